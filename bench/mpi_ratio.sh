#!/usr/bin/env bash
# One process against the same world split among processes under mpirun: the
# table of docs/mpi.md ("What it costs").
#   bench/mpi_ratio.sh CAROM PROCESSES RUNS [N ...]
#       for each N (default 100000 1000000) and each stepped scheme, RUNS runs taken
#       in turns of `carom run --backend cpu --packing 0.5 --steps 100` in one
#       process of PROCESSES threads and under `mpirun -np PROCESSES` (a thread
#       each); prints each run's wall_seconds, the medians and their ratio
# CAROM is the carom binary (e.g. build/carom). Python 3 reads the JSON.
set -euo pipefail
carom=$1 processes=$2 runs=$3
shift 3
sizes=${*:-100000 1000000}

seconds() { python3 -c 'import json, sys; print(json.load(sys.stdin)["wall_seconds"])'; }
median() { printf '%s\n' "$@" | sort -g | awk '{ v[NR] = $1 } END { print (NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2) }'; }

for n in $sizes; do
    for scheme in pairwise simultaneous; do
        options=(run --backend cpu --particles "$n" --packing 0.5 --steps 100 --collisions "$scheme" --json)
        one=() split=()
        for _ in $(seq "$runs"); do
            one+=("$(OMP_NUM_THREADS=$processes "$carom" "${options[@]}" | seconds)")
            split+=("$(mpirun -np "$processes" -x OMP_NUM_THREADS=1 "$carom" "${options[@]}" | seconds)")
        done
        a=$(median "${one[@]}") b=$(median "${split[@]}")
        echo "N $n $scheme: one process ${one[*]} s, $processes processes ${split[*]} s;" \
             "medians $a / $b s, ratio $(python3 -c "print(round($b / $a, 2))")"
    done
done
