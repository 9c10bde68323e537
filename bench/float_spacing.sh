#!/bin/sh
# The README's float-spacing table (Limits): one disk at 0.9 x the box side,
# moving at speed 1 along x for 1000 steps of dt 0.01, and the error of the
# distance it covered against the exact 10. Boxes carom refuses (the step
# below one float spacing) say so.
#   bench/float_spacing.sh [CAROM]    (default build/carom)
set -eu
carom=${1:-build/carom}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "box,error_percent"
for box in 1000 8192 32768 65536 131072 150000 1000000; do
    x0=$(awk -v b="$box" 'BEGIN { printf "%.9g", 0.9 * b }')
    printf 'id,x,y,vx,vy,mass,radius\n0,%s,%s,1,0,1,1\n' "$x0" "$((box / 2))" > "$work/start.csv"
    if "$carom" run --backend cpu --box "$box" "$box" --input-state "$work/start.csv" \
            --steps 1000 --dt 0.01 --output-state "$work/end.csv" --quiet > /dev/null 2> "$work/err"; then
        awk -F, -v x0="$x0" -v box="$box" 'NR == 2 { printf "%s,%+.2f\n", box, 100 * (($2 - x0) / 10 - 1) }' \
            "$work/end.csv"
    else
        echo "$box,refused: $(head -c 120 "$work/err")"
    fi
done
