#!/bin/sh
# Installs what carom needs from Debian 12 packages. Idempotent.
#   ./install-deps.sh          build dependencies (compiler, CMake, OpenCL, PoCL, libraries, the viewer's SDL2/ImGui,
#                              Open MPI for mpirun)
#   ./install-deps.sh --test   the same, plus what the tests need, and .venv: a virtual
#                              environment with the Python tests' packages (PyPI)
#   ./install-deps.sh --python the build dependencies, plus Python's headers and venv,
#                              for `pip install .` (docs/python.md)
#   ./install-deps.sh --docs   the build dependencies, Python's, Doxygen, and .venv with
#                              Sphinx and its extensions (docs/requirements.txt), to build
#                              the documentation (docs/building.md)
#   ./install-deps.sh --web    the build dependencies and emscripten, for the browser page (docs/web.md)
set -eu
packages="cmake g++ make ocl-icd-opencl-dev opencl-headers pocl-opencl-icd clinfo
          libcli11-dev nlohmann-json3-dev libtomlplusplus-dev
          libsdl2-dev libimgui-dev libstb-dev libgl-dev
          libopenmpi-dev openmpi-bin"
# The viewer's tests render under Xvfb with Mesa's software OpenGL.
test_packages="doctest-dev xvfb xauth libgl1-mesa-dri libglx-mesa0"
# The fuzzers (clang's libFuzzer), the formatting check (clang-format) and the output
# file tests (Python; ASE comes from PyPI below).
test_packages="$test_packages clang clang-format libclang-rt-14-dev python3 python3-pip"
# The Python package (pip install .): Python's headers, venv and pip.
python_packages="python3-dev python3-venv python3-pip"
# The documentation: Doxygen reads the public headers for the C++ reference.
docs_packages="doxygen"
# The browser page: emscripten builds it; its tests drive Debian's headless Chromium.
web_packages="emscripten"
test_packages="$test_packages $web_packages chromium chromium-driver"
[ "${1:-}" = "--test" ] && packages="$packages $test_packages $python_packages $docs_packages"
[ "${1:-}" = "--python" ] && packages="$packages $python_packages"
[ "${1:-}" = "--docs" ] && packages="$packages $python_packages $docs_packages"
[ "${1:-}" = "--web" ] && packages="$packages $web_packages"

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

# The Python tests (docs/python.md): pytest, gsd, nbclient and the
# notebook's kernel and plots, mpi4py (its wheel uses Debian's Open MPI)
# for the tests under mpirun, and Selenium for the browser tests (it drives
# Debian's Chromium: no browser is downloaded), in .venv, where `pip install .` puts carom;
# and the documentation's Sphinx, whose build the tests run too.
if [ "${1:-}" = "--test" ] || [ "${1:-}" = "--docs" ]; then
    [ -x .venv/bin/python ] || python3 -m venv .venv
    .venv/bin/python -m pip install --quiet --upgrade pip
fi
if [ "${1:-}" = "--test" ]; then
    echo "install-deps: the Python test packages in .venv (PyPI)"
    .venv/bin/python -m pip install --quiet numpy gsd pytest nbclient nbformat ipykernel matplotlib mpi4py selenium
fi
if [ "${1:-}" = "--test" ] || [ "${1:-}" = "--docs" ]; then
    echo "install-deps: Sphinx and its extensions in .venv (PyPI, docs/requirements.txt)"
    .venv/bin/python -m pip install --quiet -r docs/requirements.txt
fi
