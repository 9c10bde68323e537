#!/bin/sh
# Installs what carom needs from Debian 12 packages. Idempotent.
#   ./install-deps.sh          build dependencies (compiler, CMake, OpenCL, PoCL, libraries, the viewer's SDL2/ImGui)
#   ./install-deps.sh --test   the same, plus what the tests need
set -eu
packages="cmake g++ make ocl-icd-opencl-dev opencl-headers pocl-opencl-icd clinfo
          libcli11-dev nlohmann-json3-dev libtomlplusplus-dev
          libsdl2-dev libimgui-dev libstb-dev libgl-dev"
# The viewer's tests render under Xvfb with Mesa's software OpenGL.
test_packages="doctest-dev xvfb xauth libgl1-mesa-dri libglx-mesa0"
# The fuzzers (clang's libFuzzer) and the output file tests (Python; ASE comes from PyPI below).
test_packages="$test_packages clang libclang-rt-14-dev python3 python3-pip"
[ "${1:-}" = "--test" ] && packages="$packages $test_packages"

sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
missing=""
for p in $packages; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
    echo "install-deps: installing$missing"
    $sudo apt-get update -q
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends $missing
else
    echo "install-deps: everything is installed"
fi

# ASE reads the trajectories back in tests/outputs_test.py. Debian's own
# Python refuses a plain pip install (PEP 668); a virtual environment's or
# pyenv's does not.
if [ "${1:-}" = "--test" ] && ! python3 -c "import ase" 2>/dev/null; then
    echo "install-deps: installing ase from PyPI"
    python3 -m pip install --quiet ase 2>/dev/null || python3 -m pip install --quiet --break-system-packages ase
fi
