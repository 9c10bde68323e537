#!/bin/sh
# The README's "One cell size for all disks" figures: the step-time ratio of
# tests/data/large_radius.toml (one disk of radius 20 beside 1 500 of radius
# 0.5) to the same scene without the large disk, per collision scheme, the
# median of RUNS runs of STEPS steps each; and the estimate carom warns with.
#   bench/large_radius.sh [CAROM] [RUNS] [STEPS]   (default build/carom 3 200)
set -eu
carom=${1:-build/carom} runs=${2:-3} steps=${3:-200}
here=$(dirname "$0")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
with="$here/../tests/data/large_radius.toml"
sed '/^\[\[disk\]\]/,$d' "$with" > "$work/without.toml"
seconds() {  # SCENE SCHEME: the median wall time of RUNS runs
    for r in $(seq "$runs"); do
        "$carom" run --backend cpu --scene "$1" --collisions "$2" --steps "$steps" --json 2> /dev/null |
            sed -n 's/.*"wall_seconds": \([0-9.e+-]*\).*/\1/p'
    done | sort -g | awk '{ t[NR] = $1 } END { print t[int((NR + 1) / 2)] }'
}
"$carom" run --backend cpu --scene "$with" --steps 0 2>&1 >/dev/null | grep -o 'costs about [0-9]* times' || true
for scheme in simultaneous pairwise; do
    a=$(seconds "$with" "$scheme")
    b=$(seconds "$work/without.toml" "$scheme")
    awk -v s="$scheme" -v a="$a" -v b="$b" 'BEGIN { printf "%s: %.4f s / %.4f s = %.0f times\n", s, a, b, a / b }'
done
