#!/usr/bin/env bash
# Two carom binaries against pymunk, quiet and beside one busy process, in
# alternating runs so that drift in the machine's speed falls on both: the
# figures of the README's "Threads under load" (issue 15).
#   bench/peers/alternate.sh BEFORE AFTER RUNS OUTDIR [pymunk_peer.py options]
# e.g. bench/peers/alternate.sh /tmp/old/carom build/carom 5 /tmp/meas
# (default options: --particles 10000 --packing 0.3 --collisions pairwise).
# Writes OUTDIR/{before,after}-load{0,1}-run{R}.json and prints each run's
# ratio; PYTHON (default python3) must have pymunk.
set -euo pipefail
before=$1 after=$2 runs=$3 out=$4
shift 4
[ $# -gt 0 ] || set -- --particles 10000 --packing 0.3 --collisions pairwise
mkdir -p "$out"
here=$(dirname "$0")
for ((r = 1; r <= runs; ++r)); do
    for load in 0 1; do
        for which in before after; do
            carom=$before
            [ "$which" = after ] && carom=$after
            file="$out/$which-load$load-run$r"
            "${PYTHON:-python3}" "$here/pymunk_peer.py" --carom "$carom" --carom-bench --busy-loops "$load" \
                --json "$file.json" "$@" > "$file.txt" 2>&1
            echo "$which, $load busy, run $r: $(tail -1 "$file.txt")"
        done
    done
done
