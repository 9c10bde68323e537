#!/bin/sh
# Installs what carom needs from Debian 12 packages. Idempotent.
#   ./install-deps.sh          build dependencies (compiler, CMake, OpenCL, PoCL, libraries)
#   ./install-deps.sh --test   the same, plus what the tests need
set -eu
packages="cmake g++ make ocl-icd-opencl-dev opencl-headers pocl-opencl-icd clinfo
          libcli11-dev nlohmann-json3-dev"
test_packages="doctest-dev"
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
