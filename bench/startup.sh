#!/usr/bin/env bash
# Start-up and long-step A/B of two carom builds, alternating, ROUNDS rounds:
#  - start-up: `carom run --particles N --packing 0.6 --steps 0` (placing,
#    checking and uploading the disks, and the summary's measurements), the
#    wall time and peak memory from /usr/bin/time;
#  - long steps a stop may cut short: 10^6 pairwise disks, dt 0.5 and
#    --max-travel 0.05 (about 36 substeps a step, 100 steps), the steps' wall time
#    from --json (carom run always sets a stop check for its signals).
#   bench/startup.sh BEFORE AFTER ROUNDS N [carom run options, e.g. --device NVIDIA --backend opencl]
# e.g. bench/startup.sh /tmp/base/carom build/carom 2 30000000 --device NVIDIA --backend opencl
set -euo pipefail
before=$1 after=$2 rounds=$3 n=$4
shift 4
steps() {
    "$@" --particles 1000000 --packing 0.3 --dt 0.5 --max-travel 0.05 --steps 100 --json 2>/dev/null |
        python3 -c "import json, sys; d = json.load(sys.stdin)
print('steps %.3f s, %d substeps, %d collisions' % (d['wall_seconds'], d['substeps'], d['collisions']))"
}
for ((r = 1; r <= rounds; ++r)); do
    for which in before after; do
        carom=$before
        [ "$which" = after ] && carom=$after
        echo "long steps, round $r, $which: $(steps "$carom" run "$@")"
    done
done
for ((r = 1; r <= rounds; ++r)); do
    for which in before after; do
        carom=$before
        [ "$which" = after ] && carom=$after
        /usr/bin/time -f "start-up of $n disks, round $r, $which: %e s, peak %M KB" \
            "$carom" run --particles "$n" --packing 0.6 --steps 0 "$@" 2>&1 >/dev/null | tail -n 1
    done
done
