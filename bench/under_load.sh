#!/usr/bin/env bash
# carom's CPU backend beside other work, the figures of the README's "Threads
# under load": RUNS runs of a small `carom run` while BUSY busy loops keep the
# cores occupied; prints each run's wall time, then the median and the worst.
#   bench/under_load.sh CAROM RUNS BUSY [carom run options]
# e.g. bench/under_load.sh build/carom 15 2 --collisions simultaneous
# (default options: --particles 2 --steps 1000). CAROM is the carom binary;
# the busy loops are ended when the script ends.
set -uo pipefail
carom=$1 runs=$2 busy=$3
shift 3
[ $# -gt 0 ] || set -- --particles 2 --steps 1000
[[ "$*" == *--particles* ]] || set -- --particles 2 "$@"
[[ "$*" == *--steps* ]] || set -- --steps 1000 "$@"

loops=()
trap 'kill "${loops[@]}" 2>/dev/null' EXIT
for ((b = 0; b < busy; ++b)); do
    sh -c 'while :; do :; done' &
    loops+=($!)
done

times=()
for ((r = 0; r < runs; ++r)); do
    start=$(date +%s.%N)
    "$carom" run --backend cpu "$@" --quiet > /dev/null || exit 1
    end=$(date +%s.%N)
    times+=("$(echo "$end - $start" | bc -l)")
done
printf '%s\n' "${times[@]}" | sort -g | awk -v options="$*" -v busy="$busy" '
    { t[NR] = $1; printf "%.3f s\n", $1 }
    END { printf "carom run %s beside %d busy loops, %d runs: median %.3f s, worst %.3f s\n",
                 options, busy, NR, (NR % 2 ? t[(NR + 1) / 2] : (t[NR / 2] + t[NR / 2 + 1]) / 2), t[NR] }'
