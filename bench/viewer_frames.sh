#!/bin/sh
# Frame times of `carom view` against the number of disks (issue 16): headless
# frames at 1280 x 800 with the panels shown, each size run RUNS times; prints
# each run's median frame and its parts (stepping, reading back, drawing).
# The display comes from the environment: xvfb-run here, or SDL's offscreen
# driver (SDL_VIDEODRIVER=offscreen, OpenGL through EGL) on a machine without X.
#   usage: bench/viewer_frames.sh CAROM "SIZES" RUNS [carom view options...]
#   e.g.   xvfb-run -a bench/viewer_frames.sh build/carom "1000 10000 100000" 2 --backend cpu
set -eu
carom=$1 sizes=$2 runs=$3
shift 3
for n in $sizes; do
    r=1
    while [ "$r" -le "$runs" ]; do
        out=$("$carom" view --particles "$n" --frames 120 --window 1280 800 "$@")
        [ "$r" -eq 1 ] && echo "$out" | grep -o 'on .*drawn by.*' | sed "s/^/N=$n: /"
        echo "N=$n run$r: $(echo "$out" | grep -o 'median frame.*')"
        r=$((r + 1))
    done
done
