"""carom.World(comm=...) under mpirun with mpi4py: every process's measurements
and process 0's files are bit for bit those of one process without a
communicator, and checkpoints move between any numbers of processes."""
import json
import os
import pathlib
import shutil
import subprocess
import sys

import pytest

import carom

pytest.importorskip("mpi4py", reason="mpi4py is not installed (./install-deps.sh --test installs it)")
MPIRUN = shutil.which("mpirun")
pytestmark = [
    pytest.mark.skipif(not carom._carom.HAVE_MPI, reason="carom was built without MPI"),
    pytest.mark.skipif(MPIRUN is None, reason="mpirun is not installed (./install-deps.sh --test installs it)"),
]
SCRIPT = pathlib.Path(__file__).with_name("mpi_world.py")


def run(tmp_path, tag, processes, arguments, resume=None):
    """mpi_world.py on `processes` (1: alone, without mpirun); returns what each process measured."""
    out = str(tmp_path / tag)
    command = [sys.executable, str(SCRIPT), out, *arguments] + ([resume] if resume else [])
    if processes > 1:
        command = [MPIRUN, "--oversubscribe", "-np", str(processes)] + command
    environment = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
                       OMP_NUM_THREADS="1")
    result = subprocess.run(command, env=environment, text=True, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            timeout=300)
    assert result.returncode == 0, f"{' '.join(command)} exited {result.returncode}:\n{result.stdout}"
    measured = []
    for rank in range(processes):
        written = json.loads((tmp_path / f"{tag}.rank{rank}.json").read_text())
        if processes > 1:  # split, not each process stepping the whole world (that too would match)
            assert f"process {rank} of {processes} (" in written["device"], written["device"]
        measured.append(written["measured"])
    return measured


def same_file(a: pathlib.Path, b: pathlib.Path) -> bool:
    return a.read_bytes() == b.read_bytes()


@pytest.mark.parametrize("collisions, boundary, gravity, processes, domains", [
    ("pairwise", "walls", -10, 2, "auto"),
    ("pairwise", "periodic", 0, 3, "3x1"),
    ("simultaneous", "walls", -10, 4, "2x2"),
])
def test_processes_match_one(tmp_path, collisions, boundary, gravity, processes, domains):
    arguments = [collisions, boundary, str(gravity)]
    one = run(tmp_path, "one", 1, arguments + ["none"])
    split = run(tmp_path, "split", processes, arguments + [domains])
    assert all(measured == one[0] for measured in split), "a process measured other values than one process"
    for suffix in (".csv", ".ckpt"):
        assert same_file(tmp_path / f"one{suffix}", tmp_path / f"split{suffix}"), f"the {suffix} files differ"
    # A checkpoint of one process resumes on several, and theirs on one.
    resumed = run(tmp_path, "resumed_split", processes, arguments + [domains], str(tmp_path / "one.ckpt"))
    assert all(measured == one[0] for measured in resumed)
    assert same_file(tmp_path / "one.csv", tmp_path / "resumed_split.csv")
    alone = run(tmp_path, "resumed_one", 1, arguments + ["none"], str(tmp_path / "split.ckpt"))
    assert alone == one
    assert same_file(tmp_path / "one.csv", tmp_path / "resumed_one.csv")


def test_own_disks_and_gathers_on_request(tmp_path):
    """With gather="on_request" each process reads its own disks between steps (each disk on exactly one
    process, as one process has it), the whole world's reads are refused until gather(), and after it are
    one process's."""
    processes = 3
    command = [MPIRUN, "--oversubscribe", "-np", str(processes), sys.executable,
               str(SCRIPT.with_name("mpi_own_disks.py")), str(tmp_path / "own")]
    environment = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
                       OMP_NUM_THREADS="1")
    result = subprocess.run(command, env=environment, text=True, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            timeout=300)
    assert result.returncode == 0, result.stdout
    read = [json.loads((tmp_path / f"own.rank{rank}.json").read_text()) for rank in range(processes)]
    one = carom.World((40.0, 30.0), boundary="periodic", dt=0.01, seed=5)
    one.place(600, radius=(0.25, 0.5), mass=(1.0, 3.0), speed=2.0)
    one.step(100)
    first = {"positions": one.positions.tobytes().hex(), "images": one.images.tobytes().hex(),
             "kinetic_energy": one.kinetic_energy, "collisions": one.collisions}
    ids = sorted(i for r in read for i in r["ids"])
    assert ids == list(range(one.n)), "the own disks are not each disk on exactly one process"
    for rank, r in enumerate(read):
        assert f"process {rank} of {processes} (" in r["device"]
        assert r["ids"] == sorted(r["ids"]) and len(r["ids"]) > 0
        assert bytes.fromhex(r["positions"]) == one.positions[r["ids"]].tobytes()
        assert bytes.fromhex(r["velocities"]) == one.velocities[r["ids"]].tobytes()
        assert bytes.fromhex(r["images"]) == one.images[r["ids"]].tobytes()
        assert "gather the whole world first" in r["refused"]
        assert r["first"] == first
    one.step(100)
    second = {"positions": one.positions.tobytes().hex(), "images": one.images.tobytes().hex(),
              "kinetic_energy": one.kinetic_energy, "collisions": one.collisions}
    assert all(r["second"] == second for r in read)


def test_refusals():
    from mpi4py import MPI
    with pytest.raises(carom.InputError, match="comm: 3; allowed: an mpi4py communicator"):
        carom.World((10, 10), comm=3)
    with pytest.raises(carom.InputError, match="domains: .* without comm"):
        carom.World((10, 10), domains=(1, 1))
    with pytest.raises(carom.InputError, match="domains"):
        carom.World((10, 10), comm=MPI.COMM_WORLD, domains=(2, 1))  # one process here
    with pytest.raises(carom.InputError, match="gather: 'sometimes'"):
        carom.World((10, 10), comm=MPI.COMM_WORLD, gather="sometimes")
    with pytest.raises(carom.InputError, match="collisions=.events. runs in one process"):
        carom.World((10, 10), collisions="events", comm=MPI.COMM_WORLD)
