"""Fixtures of the Python tests: each test that takes `engine` runs once per
engine this machine has (HOOMD's `device` fixture), named [cpu] or [opencl]."""
import os
import pathlib

import pytest

import carom

REPOSITORY = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(params=carom.engines())
def engine(request):
    """"cpu", then "opencl" where an OpenCL device exists (its default pipeline:
    resident on a GPU, host-grid on a CPU device such as PoCL)."""
    return request.param


@pytest.fixture(scope="session")
def carom_exe():
    """The command-line program: $CAROM_EXE, else build/carom of this repository.
    Tests that compare with it fail, not skip, when it is missing."""
    path = pathlib.Path(os.environ.get("CAROM_EXE", REPOSITORY / "build" / "carom"))
    if not path.is_file():
        pytest.fail(f"the carom program is not at {path}: build it (README, Quick start) or set CAROM_EXE")
    return str(path)


@pytest.fixture(scope="session")
def scenes():
    return REPOSITORY / "scenes"
