#!/usr/bin/env bash
# Timing-only builds of carom with one constant or one pass changed, for the
# A/B figures of bench/results/nvidia-h200-group-rounds.txt and
# bench/results/nvidia-h200-small-system.txt ("Where a small step's time
# goes"). Each variant is built from a copy of this source tree in
# OUT/src-NAME, so the checkout is never edited; the binary lands in
# OUT/carom-NAME. Then every binary (and BASE, a build of an earlier commit,
# when given) runs `carom bench` ROUNDS times in turn, alternating, with the
# arguments after `--`. The nogrid and nostep variants compute wrong physics:
# only their times mean anything.
#   bench/build_variants.sh OUT ROUNDS "VARIANT..." [BASE|-] -- BENCH-ARGS...
# Variants: main (the tree as it is), launchedN (kLaunchedRoundLength = N),
# scan8 (8 counts per work-item in the small system's scan), nogrid (no grid
# build in stepSmallSystem), nostep (no carom_step_slot in stepSmallSystem).
# e.g. on the GPU machine (../shared/device/README.md has the OpenCL setup):
#   bench/build_variants.sh /tmp/v 2 "main launched1024 launched4096 launched1073741824" /tmp/base/carom -- \
#       --device NVIDIA --methods opencl-resident --collisions pairwise --sizes 1e3,1e4,1e5,1e6,1.6e7 --samples 5
#   bench/build_variants.sh /tmp/v 2 "main scan8 nogrid nostep" - -- \
#       --device NVIDIA --methods opencl-resident --collisions simultaneous --sizes 1e3,2e3 --samples 5
set -euo pipefail
out=$1 rounds=$2 variants=$3 base=$4
shift 4
[ "${1:-}" = "--" ] && shift
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"

edit() {  # FILE OLD NEW: replace the text OLD (it may span lines), or fail
    python3 - "$@" <<'EOF'
import sys
path, old, new = sys.argv[1:]
text = open(path).read()
if old not in text:
    sys.exit("build_variants: %r not found in %s" % (old, path))
open(path, "w").write(text.replace(old, new, 1))
EOF
}

for v in $variants; do
    src=$out/src-$v
    rm -rf "$src"
    mkdir -p "$src"
    tar -C "$here" --exclude=./.git --exclude='./build*' --exclude=./.venv -cf - . | tar -C "$src" -xf -
    case $v in
        main) ;;
        launched*)
            edit "$src/backends/opencl/pairwise.cpp" "constexpr cl_uint kLaunchedRoundLength = 256;" \
                "constexpr cl_uint kLaunchedRoundLength = ${v#launched};" ;;
        scan8)
            edit "$src/kernels/small_system.cl" "#define CAROM_SMALL_SYSTEM_SCAN_ITEMS 4" "#define CAROM_SMALL_SYSTEM_SCAN_ITEMS 8"
            edit "$src/backends/opencl/small_system.cpp" "kSmallSystemScanItems = 4;" "kSmallSystemScanItems = 8;" ;;
        nogrid)
            edit "$src/kernels/small_system.cl" "        carom_build_grid_in_group(step.count, cellCount, counts, cells, cellOf, rankInCell, ids, cellOrder, sortedIds,
                                  counts, tile, runSums);" "" ;;
        nostep)
            edit "$src/kernels/small_system.cl" "            carom_step_slot(k, state" \
                "            if (step.count == 0) carom_step_slot(k, state" ;;
        *) echo "build_variants: unknown variant '$v'" >&2; exit 1 ;;
    esac
    cmake -S "$src" -B "$src/build" -DCMAKE_BUILD_TYPE=Release -DCAROM_BUILD_TESTS=OFF -DCAROM_BUILD_VIEWER=OFF \
        ${CMAKE_PREFIX_PATH:+-DCMAKE_PREFIX_PATH=$CMAKE_PREFIX_PATH} > "$out/build-$v.log" 2>&1
    cmake --build "$src/build" -j"$(nproc)" --target carom >> "$out/build-$v.log" 2>&1
    cp "$src/build/carom" "$out/carom-$v"
done

binaries=""
[ "$base" != "-" ] && binaries="$base"
for v in $variants; do binaries="$binaries $out/carom-$v"; done
for ((r = 1; r <= rounds; ++r)); do
    for b in $binaries; do
        echo "== $b round $r"
        "$b" bench "$@" | grep -E '^(method|opencl|cpu|naive)'
    done
done
