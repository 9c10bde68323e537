#!/usr/bin/env bash
# One process on one GPU against two processes under mpirun sharing it: the
# GPU table of docs/mpi.md ("What it costs").
#   bench/mpi_gpu.sh CAROM RUNS [N]
#       for each stepped scheme, RUNS runs taken in turns of `carom run
#       --backend opencl --pipeline resident --packing 0.5 --steps 100` with
#       N disks (default 16000000), in one process and under `mpirun -np 2
#       --bind-to none`; prints each run's wall_seconds, the medians, and the
#       two processes' costs of the last run (the JSON's `processes`)
# CAROM is the carom binary (e.g. build/carom). Python 3 reads the JSON.
set -euo pipefail
carom=$1 runs=$2 n=${3:-16000000}

seconds() { python3 -c 'import json, sys; print(json.load(sys.stdin)["wall_seconds"])'; }
median() { printf '%s\n' "$@" | sort -g | awk '{ v[NR] = $1 } END { print (NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2) }'; }
costs=$(mktemp)
trap 'rm -f "$costs"' EXIT

for scheme in pairwise simultaneous; do
    options=(run --backend opencl --pipeline resident --particles "$n" --packing 0.5 --steps 100
             --collisions "$scheme" --json)
    one=() split=()
    for _ in $(seq "$runs"); do
        one+=("$("$carom" "${options[@]}" | seconds)")
        mpirun -np 2 --bind-to none "$carom" "${options[@]}" > "$costs"
        split+=("$(seconds < "$costs")")
    done
    echo "N $n $scheme: one process ${one[*]} s, 2 processes ${split[*]} s;" \
         "medians $(median "${one[@]}") / $(median "${split[@]}") s"
    python3 -c 'import json, sys
for p in json.load(open(sys.argv[1]))["processes"]:
    print("  costs of the last run: substeps", p["substeps"], "bytes", p["bytes"], "halo copies", p["halo_copies"],
          {k: round(v, 3) for k, v in p["seconds"].items()})' "$costs"
done
