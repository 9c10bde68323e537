#!/usr/bin/env bash
# The sweeps behind bench/results/: builds carom (Release), checks on the
# device that the OpenCL pipelines give the CPU backend's results bit for bit
# (both collision schemes), then runs the full `carom bench` sweep, every
# method under each scheme it runs, with a per-kernel profile.
#   bench/sweep.sh NAME OUTDIR [carom bench options, e.g. --device NVIDIA]
# writes OUTDIR/NAME.json, NAME.csv, NAME.svg and NAME.txt (the table).
# CAROM_TEST_DEVICE picks the device of the checks (as --device does);
# BUILD_DIR (default /tmp/carom-sweep-build) is reused when it exists.
set -euo pipefail
name=$1 out=$2
shift 2
build=${BUILD_DIR:-/tmp/carom-sweep-build}
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DCAROM_BUILD_VIEWER=OFF \
    ${CMAKE_PREFIX_PATH:+-DCMAKE_PREFIX_PATH=$CMAKE_PREFIX_PATH} >/dev/null
cmake --build "$build" -j"$(nproc)" --target carom carom_tests >/dev/null
"$build/tests/carom_tests" -tc='differential*,resident*,all pairs*'
mkdir -p "$out"
"$build/carom" bench --profile "$@" --json "$out/$name.json" --csv "$out/$name.csv" --plot "$out/$name.svg" |
    tee "$out/$name.txt"
