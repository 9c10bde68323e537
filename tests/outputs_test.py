#!/usr/bin/env python3
"""`carom run`'s output files, read back by the tools users read them with.

    outputs_test.py --carom BUILD/carom --work DIR --backends cpu,opencl TEST

TEST is one of the functions named test_* below; ctest runs each as its own
test. The trajectory is read with ASE's extended XYZ reader (pip install ase,
which ./install-deps.sh --test does).
"""
import argparse
import csv
import json
import os
import re
import shutil
import signal
import stat
import struct
import subprocess
import sys
import threading
import time
import zlib

ARGS = None


def carom(*args, check=True, cwd=None):
    """Runs carom (in `cwd`); returns (stdout, stderr). Fails the test on an unexpected status."""
    done = subprocess.run([ARGS.carom, *map(str, args)], capture_output=True, text=True, timeout=600, cwd=cwd)
    if check and done.returncode != 0:
        sys.exit(f"carom {' '.join(map(str, args))} failed ({done.returncode}):\n{done.stderr}")
    return done.stdout, done.stderr


def work(name):
    """A fresh directory for one test."""
    path = os.path.join(ARGS.work, name)
    shutil.rmtree(path, ignore_errors=True)
    os.makedirs(path)
    return path


def read_bytes(path):
    with open(path, "rb") as f:
        return f.read()


def no_partial_files(directory):
    leftovers = [f for f in os.listdir(directory) if ".partial" in f]
    assert not leftovers, f"temporary files left behind: {leftovers}"


SCENE = ["--particles", 40, "--box", 30, 30, "--radius-min", 0.5, "--radius-max", 1.25,
         "--mass-min", 1, "--mass-max", 3, "--speed", 2, "--seed", 3]


def test_trajectory_reads_in_ase():
    from ase.io import read  # pip install ase

    d = work("ase")
    xyz, end = os.path.join(d, "t.xyz"), os.path.join(d, "end.csv")
    carom("run", "--backend", "cpu", *SCENE, "--steps", 50, "--every", 10, "--dt", 0.01,
          "--trajectory", xyz, "--output-state", end)
    frames = read(xyz, index=":", format="extxyz")
    assert len(frames) == 6, len(frames)
    with open(end) as f:
        final = list(csv.DictReader(f))
    for k, atoms in enumerate(frames):
        assert len(atoms) == 40
        assert atoms.info["step"] == 10 * k, atoms.info
        assert abs(atoms.info["time"] - 0.1 * k) < 1e-6, atoms.info  # dt is a float32
        assert list(atoms.pbc) == [False, False, False]
        cell = atoms.cell.array
        assert cell[0][0] == 30 and cell[1][1] == 30 and abs(cell[2][2] - 2 * max(atoms.arrays["radius"])) < 1e-6, cell
        assert (atoms.positions[:, 2] == 0).all()
        assert atoms.arrays["velo"].shape == (40, 3) and (atoms.arrays["velo"][:, 2] == 0).all()
        assert list(atoms.arrays["id"]) == list(range(40))
        masses, radii = atoms.arrays["mass"], atoms.arrays["radius"]  # OVITO's column names
        assert ((1 <= masses) & (masses <= 3)).all() and ((0.5 <= radii) & (radii <= 1.25)).all()
    last = frames[-1]
    for i, row in enumerate(final):  # the same floats, to the last bit
        assert last.positions[i][0] == float(row["x"]) and last.positions[i][1] == float(row["y"])
        assert last.arrays["velo"][i][0] == float(row["vx"]) and last.arrays["velo"][i][1] == float(row["vy"])
        assert last.arrays["mass"][i] == float(row["mass"]) and last.arrays["radius"][i] == float(row["radius"])
    no_partial_files(d)


def test_periodic_trajectory_reads_in_ase():
    from ase.io import read  # pip install ase

    d = work("ase_periodic")
    xyz = os.path.join(d, "t.xyz")
    carom("run", "--backend", "cpu", *SCENE, "--boundary", "periodic", "--steps", 2000, "--every", 100,
          "--dt", 0.01, "--trajectory", xyz)
    frames = read(xyz, index=":", format="extxyz")
    assert len(frames) == 21, len(frames)
    for atoms in frames:
        assert list(atoms.pbc) == [True, True, False], atoms.pbc  # the box repeats in x and y only
        assert atoms.arrays["image"].shape == (40, 3) and (atoms.arrays["image"][:, 2] == 0).all()
        assert list(atoms.arrays["id"]) == list(range(40))
    # The images unwrap the positions: no disk moves half a box between frames (1 time unit at speed ~2).
    unwrapped = [atoms.positions[:, :2] + 30 * atoms.arrays["image"][:, :2] for atoms in frames]
    for before, after in zip(unwrapped, unwrapped[1:]):
        assert (abs(after - before) < 15).all()
    assert (frames[-1].arrays["image"] != 0).any()  # 40 time units at speed ~2 in a box 30 wide


def test_stats_csv():
    d = work("stats")
    stats = os.path.join(d, "s.csv")
    out, _ = carom("run", "--backend", "cpu", "--particles", 300, "--packing", 0.4, "--steps", 100,
                   "--every", 25, "--stats", stats, "--json")
    summary = json.loads(out)
    with open(stats) as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0].keys()) == ["step", "time", "kinetic_energy", "momentum_x", "momentum_y",
                                    "collisions", "max_overlap", "escaped"], rows[0].keys()
    assert [int(r["step"]) for r in rows] == [0, 25, 50, 75, 100]
    collisions = [int(r["collisions"]) for r in rows]
    assert collisions == sorted(collisions) and collisions[0] == 0
    assert collisions[-1] == summary["collisions"]
    assert float(rows[0]["kinetic_energy"]) == summary["kinetic_energy"]["initial"]
    assert float(rows[-1]["kinetic_energy"]) == summary["kinetic_energy"]["final"]
    assert abs(float(rows[-1]["time"]) - 100 * 0.01) < 1e-6
    assert summary["step"] == 100 and summary["interrupted"] is False


def test_checkpoint_layout():
    d = work("layout")
    ckpt = os.path.join(d, "c.ckpt")
    for scheme, code in (("simultaneous", 0), ("pairwise", 1)):
        carom("run", "--backend", "cpu", "--particles", 5, "--box", 20, 20, "--steps", 30, "--dt", 0.02,
              "--gravity", 0, -1, "--collisions", scheme, "--checkpoint", ckpt)
        data = read_bytes(ckpt)
        magic, mark, version, count = struct.unpack_from("<8sIIQ", data, 0)
        width, height, dt, gx, gy, boundary, step, sim_time, collisions, scheme_code = \
            struct.unpack_from("<5fIQdQI", data, 24)
        assert (magic, mark, version, count) == (b"CAROMCKP", 0x01020304, 4, 5)
        assert (width, height, gx, gy, boundary, step, scheme_code) == (20, 20, 0, -1, 0, 30, code), scheme
        assert abs(dt - 0.02) < 1e-7 and abs(sim_time - 30 * dt) < 1e-12
        assert len(data) == 76 + 32 * count + 4
        assert data[76 + 24 * count:-4] == bytes(8 * count)  # the images: {0, 0} with walls
        assert struct.unpack_from("<I", data, len(data) - 4)[0] == zlib.crc32(data[:-4])


def run_with_outputs(d, backend, tag, *args):
    """carom run with every output named after `tag` in `d`; returns their paths."""
    paths = {k: os.path.join(d, f"{tag}.{k}") for k in ("xyz", "csv", "ckpt", "state")}
    carom("run", "--backend", backend, *args, "--every", 20, "--trajectory", paths["xyz"], "--stats", paths["csv"],
          "--checkpoint", paths["ckpt"], "--output-state", paths["state"], "--quiet")
    return paths


def test_resume_continues_bit_for_bit():
    """200 steps in one run equal 100 steps, a checkpoint and 100 resumed steps: the final
    state, the checkpoint, and the trajectory and statistics put end to end. The resumed run
    takes the collision scheme from the checkpoint (pairwise on the CPU backend)."""
    scene = ["--particles", 800, "--packing", 0.5, "--radius-min", 0.6, "--radius-max", 1.2,
             "--mass-min", 0.5, "--mass-max", 5, "--gravity", 0, -0.3, "--dt", 0.01]
    backends = ARGS.backends.split(",")
    pairs = [(b, b, "simultaneous") for b in backends] + \
            [(a, b, "simultaneous") for a in backends for b in backends if a != b] + [("cpu", "cpu", "pairwise")]
    for first, second, scheme in pairs:
        d = work(f"resume-{first}-{second}-{scheme}")
        whole = run_with_outputs(d, first, "whole", *scene, "--collisions", scheme, "--steps", 200)
        one = run_with_outputs(d, first, "one", *scene, "--collisions", scheme, "--steps", 100)
        two = run_with_outputs(d, second, "two", "--resume", one["ckpt"], "--steps", 100)
        label = f"{first} then {second}, {scheme}"
        assert read_bytes(whole["state"]) == read_bytes(two["state"]), label
        assert read_bytes(whole["ckpt"]) == read_bytes(two["ckpt"]), label
        assert read_bytes(whole["xyz"]) == read_bytes(one["xyz"]) + read_bytes(two["xyz"]), label
        header, rest = read_bytes(two["csv"]).split(b"\n", 1)
        assert read_bytes(whole["csv"]) == read_bytes(one["csv"]) + rest, label
        no_partial_files(d)


def checkpoint_step(path):
    """The step a checkpoint holds, 0 when there is none yet (it is replaced whole, never half-written)."""
    return struct.unpack_from("<Q", read_bytes(path), 48)[0] if os.path.exists(path) else 0


def test_interrupt_writes_everything():
    """Ctrl-C stops the run cleanly: status 130, every output complete, and the checkpoint
    continues exactly as an uninterrupted run would."""
    d = work("interrupt")
    ckpt, state = os.path.join(d, "c.ckpt"), os.path.join(d, "end.csv")
    scene = ["--backend", "cpu", "--particles", 500, "--packing", 0.4, "--seed", 9]
    arguments = [*scene, "--steps", 10 ** 9, "--every", 50, "--checkpoint", ckpt, "--trajectory",
                 os.path.join(d, "t.xyz"), "--stats", os.path.join(d, "s.csv"), "--output-state", state]
    process = subprocess.Popen([ARGS.carom, "run", *map(str, arguments)],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 300
    while checkpoint_step(ckpt) == 0:  # a checkpoint after step 0: the run is under way
        assert process.poll() is None and time.monotonic() < deadline, "carom wrote no checkpoint after step 0"
        time.sleep(0.05)
    process.send_signal(signal.SIGINT)
    _, err = process.communicate(timeout=300)
    assert process.returncode == 130, (process.returncode, err)
    assert "interrupted at step" in err and "carom run --resume" in err, err
    step = checkpoint_step(ckpt)
    with open(os.path.join(d, "s.csv")) as f:
        assert int(list(csv.DictReader(f))[-1]["step"]) <= step
    no_partial_files(d)

    resumed, fresh = os.path.join(d, "resumed.csv"), os.path.join(d, "fresh.csv")
    carom("run", "--backend", "cpu", "--resume", ckpt, "--steps", 30, "--output-state", resumed)
    carom("run", *scene, "--steps", step + 30, "--output-state", fresh)
    assert read_bytes(resumed) == read_bytes(fresh)
    carom("run", *scene, "--steps", step, "--output-state", fresh)
    assert read_bytes(state) == read_bytes(fresh)


def test_scene_outputs_and_overrides():
    """A scene's [output] files are written; command-line options override the scene."""
    d = work("scene")
    scene = os.path.join(d, "s.toml")
    with open(scene, "w") as f:
        f.write(f"""box = [40, 40]
collisions = "pairwise"
dt = 0.02
steps = 60
[[group]]
count = 50
temperature = 2
[output]
stats = "{os.path.join(d, 'scene.csv')}"
every = 20
""")
    out, _ = carom("run", "--backend", "cpu", "--scene", scene, "--json")
    summary = json.loads(out)
    assert (summary["steps"], summary["particles"], summary["box"]) == (60, 50, [40, 40]), summary
    assert summary["scheme"] == "pairwise", summary
    assert abs(summary["dt"] - 0.02) < 1e-7
    with open(os.path.join(d, "scene.csv")) as f:
        assert [int(r["step"]) for r in csv.DictReader(f)] == [0, 20, 40, 60]
    out, _ = carom("run", "--backend", "cpu", "--scene", scene, "--steps", 10, "--dt", 0.005, "--particles", 20,
                   "--box", 30, 50, "--collisions", "simultaneous", "--every", 5, "--stats",
                   os.path.join(d, "cli.csv"), "--json")
    summary = json.loads(out)
    assert (summary["steps"], summary["particles"], summary["box"]) == (10, 20, [30, 50]), summary
    assert summary["scheme"] == "simultaneous", summary
    assert abs(summary["dt"] - 0.005) < 1e-9
    with open(os.path.join(d, "cli.csv")) as f:
        assert [int(r["step"]) for r in csv.DictReader(f)] == [0, 5, 10]


ENERGY_WARNING = "energy changed by"


def test_energy_warning():
    """The simultaneous scheme heats a dense gas (here by 15-20 %): the run says so at its end, with
    the figure and what to do. The same gas under the pairwise scheme, and a dilute gas under the
    simultaneous one (a change of about 1e-9), get no warning."""
    dense = ["run", "--backend", "cpu", "--particles", 300, "--packing", 0.7, "--steps", 50, "--quiet"]
    out, err = carom(*dense, "--collisions", "simultaneous", "--json")
    summary = json.loads(out)
    initial, final = summary["energy"]["total"]["initial"], summary["energy"]["total"]["final"]
    change = (final - initial) / abs(initial)  # as carom computes it
    assert change > 0.05, summary["energy"]
    warning = f"the kinetic energy changed by +{100 * change:.3g} % over this run"
    assert warning in err and "--collisions pairwise, or a smaller --dt" in err, (warning, err)
    _, err = carom(*dense, "--collisions", "pairwise")
    assert ENERGY_WARNING not in err, err
    _, err = carom("run", "--backend", "cpu", "--particles", 300, "--packing", 0.1, "--steps", 50, "--quiet",
                   "--collisions", "simultaneous")
    assert ENERGY_WARNING not in err, err


def test_periodic_gravity_energy():
    """In a periodic box gravity accelerates the centre of mass forever, and -sum m g.x jumps by m g H
    whenever a disk wraps (the total changed by +173 % here, and the warning called it a bug): the
    warning judges the kinetic energy in the centre-of-mass frame, which the collisions conserve."""
    for scheme in ("pairwise", "events"):
        out, err = carom("run", "--backend", "cpu", "--boundary", "periodic", "--gravity", 0, -10, "--particles", 50,
                         "--packing", 0.05, "--steps", 300, "--collisions", scheme)
        assert ENERGY_WARNING not in err, (scheme, err)
        frame = re.search(r"in the centre-of-mass frame \(conserved: the box is periodic\) \S+ -> \S+ "
                          r"\(relative change ([-+0-9.e]+)\)", out)
        assert frame and abs(float(frame.group(1))) < 1e-3, (scheme, out)
    # The simultaneous scheme heats a dense gas in that frame too: still warned of.
    _, err = carom("run", "--backend", "cpu", "--boundary", "periodic", "--gravity", 0, -10, "--particles", 300,
                   "--packing", 0.7, "--steps", 50, "--collisions", "simultaneous")
    assert "warning: the kinetic energy in the centre-of-mass frame changed by +" in err, err


def test_blow_up_stops_cleanly():
    """A run whose state goes non-finite (the simultaneous scheme under strong gravity at a large dt)
    stops at that step with status 1 and a message naming it and the particle; no NaN reaches a
    file, the frames, rows and checkpoint before it are kept, and an existing state file is left alone."""
    d = work("blow-up")
    paths = {k: os.path.join(d, f"b.{k}") for k in ("xyz", "csv", "ckpt", "state")}
    with open(paths["state"], "w") as f:
        f.write("an earlier result\n")
    arguments = ["run", "--backend", "cpu", "--collisions", "simultaneous", "--particles", 500, "--gravity", 0, -10,
                 "--dt", 0.2, "--steps", 400, "--every", 50, "--trajectory", paths["xyz"], "--stats", paths["csv"], "--checkpoint", paths["ckpt"],
                 "--output-state", paths["state"]]
    done = subprocess.run([ARGS.carom, *map(str, arguments)], capture_output=True, text=True, timeout=600)
    assert done.returncode == 1, (done.returncode, done.stderr)
    match = re.search(r"the state went non-finite at step (\d+): particle \d+ .*smaller dt", done.stderr)
    assert match, done.stderr
    bad = int(match.group(1))
    finite = (bad - 1) // 50 * 50  # the last sample before it
    assert bad < 400 and done.stdout == "", (done.stdout, done.stderr)
    with open(paths["state"]) as f:
        assert f.read() == "an earlier result\n"
    for path in (paths["xyz"], paths["csv"]):
        with open(path) as f:
            assert "nan" not in f.read().lower(), path
    with open(paths["csv"]) as f:
        assert [int(r["step"]) for r in csv.DictReader(f)] == list(range(0, finite + 1, 50))
    assert checkpoint_step(paths["ckpt"]) == finite
    no_partial_files(d)


def test_blow_up_names_step_and_particle():
    """The issue's blow-up (2 000 disks, gravity 10, dt 0.01, simultaneous scheme) with no sample
    before the end: every backend and pipeline stops at the step it went non-finite (instead of
    running on at all-pairs cost with every NaN disk in one cell) and names that step and the
    lowest particle id; a run resumed from a checkpoint before it counts the same steps."""
    scene = ["--collisions", "simultaneous", "--gravity", 0, -10, "--particles", 2000, "--steps", 5000]
    expected = r"non-finite at step 508: particle 312 \(the lowest id of those\)"
    runs = [["--backend", "cpu"]]
    if "opencl" in ARGS.backends.split(","):
        runs += [["--backend", "opencl", "--pipeline", p] for p in ("host-grid", "resident")]
    for backend in runs:
        done = subprocess.run([ARGS.carom, "run", *map(str, scene + backend + ["--every", 5000])],
                              capture_output=True, text=True, timeout=300)
        assert done.returncode == 1 and re.search(expected, done.stderr), (backend, done.returncode, done.stderr)
    d = work("blow-up-resumed")
    ckpt = os.path.join(d, "c.ckpt")
    carom("run", *scene[:-1], 400, "--backend", "cpu", "--checkpoint", ckpt)  # by 450 the speeds leave the valid ranges
    done = subprocess.run([ARGS.carom, "run", "--resume", ckpt, "--steps", "1000", "--backend", "cpu"],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 1 and re.search(expected, done.stderr), (done.returncode, done.stderr)


def test_small_runs_start_no_thread_team():
    """A run of a few disks stays on one thread: an OpenMP team per step costs more than the step,
    and far more when other processes keep the cores busy (its threads spin at the barrier for a
    descheduled one: up to 12 s instead of 0.03 s for 1 000 steps of 2 disks). Counts the threads
    of a running carom (Linux /proc), under both schemes, with substeps for the max-speed pass."""
    if not os.path.isdir("/proc/self/task"):
        print("no /proc: skipped")
        return
    environment = dict(os.environ, OMP_NUM_THREADS="2")
    for options in (["--collisions", "simultaneous"], ["--collisions", "pairwise"],
                    ["--collisions", "simultaneous", "--dt", "auto"]):
        process = subprocess.Popen([ARGS.carom, "run", "--backend", "cpu", "--particles", "2", "--steps",
                                    "1000000000", "--quiet", *options], env=environment,
                                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            time.sleep(1.0)
            assert process.poll() is None, options
            threads = len(os.listdir(f"/proc/{process.pid}/task"))
        finally:
            process.kill()
            process.wait()
        assert threads == 1, (options, threads)


def test_json_and_quiet_print_no_progress():
    for flag in ("--json", "--quiet"):
        _, err = carom("run", "--backend", "cpu", "--particles", 100, "--steps", 20, flag)
        assert "ETA" not in err and "\r" not in err, err


def refused(*args, cwd=None):
    """Runs carom, which must refuse: a non-zero exit and nothing on stdout; returns its stderr."""
    done = subprocess.run([ARGS.carom, *map(str, args)], capture_output=True, text=True, timeout=600, cwd=cwd)
    assert done.returncode != 0 and done.stdout == "", \
        f"carom {' '.join(map(str, args))}: status {done.returncode}\n{done.stdout}{done.stderr}"
    return done.stderr


SMALL_RUN = ["run", "--backend", "cpu", "--particles", 10, "--steps", 5, "--quiet"]


def test_same_file_under_two_spellings():
    """Two outputs that are one file under two spellings ("./", "sub/..", a symlink, a hard link) or
    an output named as another's temporary file (FILE.partial) are refused before any work, naming
    both; the files already there are left as they were."""
    d = work("two-spellings")
    for name in ("c.ckpt", "a.csv"):
        with open(os.path.join(d, name), "w") as f:
            f.write("old")
    os.link(os.path.join(d, "a.csv"), os.path.join(d, "hard.csv"))
    os.symlink("a.csv", os.path.join(d, "link.csv"))
    cases = [(["--checkpoint", "c.ckpt", "--output-state", "./c.ckpt"], "--checkpoint and --output-state"),
             (["--trajectory", "t.xyz", "--stats", "./t.xyz"], "--trajectory and --stats"),
             (["--stats", "a.csv", "--output-state", "./a.csv"], "--stats and --output-state"),
             (["--stats", "a.csv", "--output-state", "hard.csv"], "--stats and --output-state"),
             (["--trajectory", "link.csv", "--checkpoint", "sub/../a.csv"], "--trajectory and --checkpoint"),
             (["--stats", "s.csv", "--trajectory", "s.csv.partial"],
              "--trajectory 's.csv.partial' is a temporary name of --stats 's.csv'"),
             (["--stats", "s.csv", "--trajectory", "s.csv.x7k2m9.partial"],
              "--trajectory 's.csv.x7k2m9.partial' is a temporary name of --stats 's.csv'"),
             (["--stats", "link.csv", "--trajectory", "a.csv.x7k2m9.partial"],  # temporaries go beside the target
              "--trajectory 'a.csv.x7k2m9.partial' is a temporary name of --stats 'link.csv'")]
    for args, message in cases:
        err = refused(*SMALL_RUN, *args, cwd=d)
        assert message in err, (args, err)
    for name in ("c.ckpt", "a.csv"):
        with open(os.path.join(d, name)) as f:
            assert f.read() == "old", name
    assert sorted(os.listdir(d)) == ["a.csv", "c.ckpt", "hard.csv", "link.csv"], os.listdir(d)


def test_outputs_never_replace_inputs():
    """An output that would replace the run's input state, resumed checkpoint or scene file is refused
    before any work, and the input is left as it was. A checkpoint resumed from and written with
    --checkpoint is the one file that may be both: it is replaced whole."""
    d = work("inputs")
    carom(*SMALL_RUN, "--box", 20, 20, "--output-state", os.path.join(d, "in.csv"), "--checkpoint",
          os.path.join(d, "c.ckpt"), cwd=d)
    scene = os.path.join(d, "s.toml")
    with open(scene, "w") as f:
        f.write('box = [20, 20]\nsteps = 5\n[[group]]\ncount = 10\ntemperature = 1\n[output]\nstate = "./s.toml"\n')
    before = {name: read_bytes(os.path.join(d, name)) for name in ("in.csv", "c.ckpt", "s.toml")}
    cases = [(["--input-state", "in.csv", "--box", 20, 20, "--output-state", "in.csv"],
              "--output-state 'in.csv' would overwrite the input --input-state 'in.csv'"),
             (["--input-state", "in.csv", "--box", 20, 20, "--stats", "./in.csv"],
              "--stats './in.csv' would overwrite the input --input-state 'in.csv'"),
             (["--resume", "c.ckpt", "--output-state", "c.ckpt"],
              "--output-state 'c.ckpt' would overwrite the input --resume 'c.ckpt'"),
             (["--scene", "s.toml"], "output.state './s.toml' would overwrite the input --scene 's.toml'")]
    for args, message in cases:
        err = refused("run", "--backend", "cpu", "--quiet", *args, cwd=d)
        assert message in err, (args, err)
    for name, content in before.items():
        assert read_bytes(os.path.join(d, name)) == content, name
    step = checkpoint_step(os.path.join(d, "c.ckpt"))
    carom("run", "--backend", "cpu", "--quiet", "--resume", "c.ckpt", "--checkpoint", "./c.ckpt", "--steps", 7, cwd=d)
    assert checkpoint_step(os.path.join(d, "c.ckpt")) == step + 7
    no_partial_files(d)


def test_resume_appends_to_its_outputs():
    """A run resumed with the same trajectory and statistics names appends to them: 100 steps and
    100 resumed steps give the very files of one 200-step run. Resuming again from the older
    checkpoint would repeat steps: refused, naming the file, its last step and the checkpoint's,
    and the files are left as they were; so is another simulation's trajectory (another number of
    disks). A resumed run creates a missing file (statistics with their header); a new run replaces
    an existing one."""
    d = work("resume-append")
    scene = ["--backend", "cpu", "--particles", 60, "--seed", 5, "--every", 20, "--quiet"]
    carom("run", *scene, "--steps", 200, "--trajectory", "whole.xyz", "--stats", "whole.csv", cwd=d)
    carom("run", *scene, "--steps", 100, "--trajectory", "t.xyz", "--stats", "s.csv", "--checkpoint", "c.ckpt", cwd=d)
    shutil.copy(os.path.join(d, "c.ckpt"), os.path.join(d, "step100.ckpt"))
    resumed = ["run", "--backend", "cpu", "--every", 20, "--quiet", "--steps", 100]
    carom(*resumed, "--resume", "c.ckpt", "--trajectory", "t.xyz", "--stats", "s.csv", "--checkpoint", "c.ckpt",
          cwd=d)
    for one, whole in (("t.xyz", "whole.xyz"), ("s.csv", "whole.csv")):
        assert read_bytes(os.path.join(d, one)) == read_bytes(os.path.join(d, whole)), one
    for name, item in (("t.xyz", "frame"), ("s.csv", "row")):
        before = read_bytes(os.path.join(d, name))
        err = refused(*resumed, "--resume", "step100.ckpt", "--trajectory" if item == "frame" else "--stats", name,
                      cwd=d)
        assert f"cannot append to '{name}': its last {item} is at step 200, after the checkpoint's step 100" in err, err
        assert read_bytes(os.path.join(d, name)) == before, name
    with open(os.path.join(d, "other.csv"), "w") as f:
        f.write("id,x,y\n")
    err = refused(*resumed, "--resume", "step100.ckpt", "--stats", "other.csv", cwd=d)
    assert "cannot append to 'other.csv': its header is 'id,x,y'" in err, err
    carom("run", "--backend", "cpu", "--particles", 30, "--steps", 20, "--every", 20, "--trajectory", "other.xyz", cwd=d)
    err = refused(*resumed, "--resume", "step100.ckpt", "--trajectory", "other.xyz", cwd=d)
    assert "cannot append to 'other.xyz': its last frame has 30 disks, the checkpoint 60" in err, err

    carom(*resumed, "--resume", "step100.ckpt", "--stats", "new.csv", cwd=d)
    with open(os.path.join(d, "new.csv")) as f:
        assert [int(r["step"]) for r in csv.DictReader(f)] == [120, 140, 160, 180, 200]
    carom("run", *scene, "--steps", 20, "--trajectory", "t.xyz", cwd=d)
    with open(os.path.join(d, "t.xyz")) as f:
        assert [int(s) for s in re.findall(r" step=(\d+)", f.read())] == [0, 20]
    no_partial_files(d)


def device_node(d, name, device):
    """A character device to write to: the system's (e.g. /dev/full) when carom cannot replace it, a
    private node of the same device when running as root (so that a regression cannot replace the
    system's), or None when root may not create one."""
    if os.geteuid() != 0:
        return device
    path = os.path.join(d, name)
    try:
        os.mknod(path, 0o666 | stat.S_IFCHR, os.stat(device).st_rdev)
    except OSError as e:
        print(f"cannot create a device node ({e}): {device} not tested")
        return None
    return path


def test_special_files():
    """A symlink is followed (the link stays, its target is replaced); a FIFO and character devices
    are written directly, never replaced by a regular file; a write error on one (/dev/full) is
    reported with its path and a non-zero exit."""
    d = work("special")
    reference = os.path.join(d, "reference.csv")
    carom(*SMALL_RUN, "--output-state", reference, "--stats", os.path.join(d, "reference-stats.csv"))

    os.makedirs(os.path.join(d, "data"))
    with open(os.path.join(d, "data", "target.csv"), "w") as f:
        f.write("old")
    os.symlink(os.path.join("data", "target.csv"), os.path.join(d, "link.csv"))
    carom(*SMALL_RUN, "--output-state", os.path.join(d, "link.csv"))
    assert os.readlink(os.path.join(d, "link.csv")) == os.path.join("data", "target.csv")
    assert read_bytes(os.path.join(d, "data", "target.csv")) == read_bytes(reference)
    no_partial_files(d)
    no_partial_files(os.path.join(d, "data"))

    fifo = os.path.join(d, "fifo")
    os.mkfifo(fifo)
    received = []
    reader = threading.Thread(target=lambda: received.append(read_bytes(fifo)), daemon=True)
    reader.start()
    carom(*SMALL_RUN, "--output-state", fifo)
    reader.join(timeout=60)
    assert received == [read_bytes(reference)], received
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)

    null = device_node(d, "null", "/dev/null")
    if null:
        carom(*SMALL_RUN, "--trajectory", null, "--stats", os.path.join(d, "stats.csv"))
        assert stat.S_ISCHR(os.stat(null).st_mode)
        assert read_bytes(os.path.join(d, "stats.csv")) == read_bytes(os.path.join(d, "reference-stats.csv"))
    full = device_node(d, "full", "/dev/full")
    if full:
        for option in ("--output-state", "--trajectory", "--stats", "--checkpoint"):
            err = refused(*SMALL_RUN, option, full)
            assert f"writing '{full}' failed: No space left on device" in err, (option, err)
            assert stat.S_ISCHR(os.stat(full).st_mode), option
    no_partial_files(d)


def test_fifo_reader_gone_keeps_the_others():
    """A FIFO output whose reader goes away fails like any write (EPIPE: carom ignores SIGPIPE,
    which would otherwise kill it with every other output lost in its .partial file): the run stops
    with status 1, names the FIFO, and keeps the statistics, the checkpoint and the final state;
    two outputs on one character device (/dev/null) are allowed."""
    d = work("fifo-reader-gone")
    fifo = os.path.join(d, "frames")
    os.mkfifo(fifo)

    def read_a_little():
        with open(fifo, "rb") as f:
            f.read(1000)

    reader = threading.Thread(target=read_a_little, daemon=True)
    reader.start()
    paths = {k: os.path.join(d, f"r.{k}") for k in ("csv", "ckpt", "state")}
    done = subprocess.run([ARGS.carom, *map(str, ["run", "--backend", "cpu", "--particles", 500, "--steps", 2000,
                                                  "--every", 10, "--trajectory", fifo, "--stats", paths["csv"],
                                                  "--checkpoint", paths["ckpt"], "--output-state", paths["state"]])],
                          capture_output=True, text=True, timeout=300)
    reader.join(timeout=60)
    assert done.returncode == 1, (done.returncode, done.stderr)
    assert f"trajectory {fifo}: FAILED: writing '{fifo}' failed: Broken pipe" in done.stderr, done.stderr
    step = check_holdings(done.stderr, paths)
    assert csv_steps(paths["csv"]) == list(range(0, step + 1, 10)), done.stderr
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)
    no_partial_files(d)
    if os.path.exists("/dev/null"):
        carom(*SMALL_RUN, "--trajectory", "/dev/null", "--stats", "/dev/null")


def test_empty_output_names_are_refused():
    """An empty output name, on the command line or in a scene's [output], is refused, not taken as
    "no output"."""
    for option in ("--output-state", "--trajectory", "--stats", "--checkpoint"):
        err = refused(*SMALL_RUN, option, "")
        assert f"{option}: an empty file name; give a path, or leave the option out" in err, err
    scene = os.path.join(work("empty-names"), "s.toml")
    for key in ("state", "trajectory", "stats", "checkpoint"):
        with open(scene, "w") as f:
            f.write(f'box = [20, 20]\nsteps = 5\n[[group]]\ncount = 10\n[output]\n{key} = ""\n')
        err = refused("run", "--backend", "cpu", "--scene", scene)
        assert f'output.{key} = "": must be a non-empty string' in err, err


def xyz_steps(path):
    """The step of each frame of an extended XYZ trajectory."""
    with open(path) as f:
        return [int(m.group(1)) for m in re.finditer(r" step=(\d+) ", f.read())]


def csv_steps(path):
    with open(path) as f:
        return [int(r["step"]) for r in csv.DictReader(f)]


def check_holdings(err, paths):
    """The message names what each output holds, and the files hold exactly that: the
    trajectory and statistics their frames and rows up to the last sample, the checkpoint
    and the final state the step the run reached. Returns the checkpoint's step."""
    if "xyz" in paths:
        frames, last = map(int, re.search(rf"trajectory {re.escape(paths['xyz'])}: (\d+) frames?, the last at step "
                                          r"(\d+)", err).groups())
        assert xyz_steps(paths["xyz"])[-1] == last and len(xyz_steps(paths["xyz"])) == frames, err
    if "csv" in paths:
        rows, last = map(int, re.search(rf"statistics {re.escape(paths['csv'])}: (\d+) rows?, the last at step (\d+)",
                                        err).groups())
        assert csv_steps(paths["csv"])[-1] == last and len(csv_steps(paths["csv"])) == rows, err
    step = int(re.search(rf"checkpoint {re.escape(paths['ckpt'])}: step (\d+)", err).group(1))
    assert checkpoint_step(paths["ckpt"]) == step, err
    if "state" in paths:
        assert re.search(rf"final state {re.escape(paths['state'])}: step {step}\b", err), err
    return step


def test_stop_signals_keep_every_output():
    """SIGTERM and SIGHUP (timeout, Slurm, docker stop, a closed terminal) stop a run as Ctrl-C
    does: status 128 + the signal, every output complete and consistent, and a message that says
    what each holds (with --every 20000 the trajectory ends at a multiple of 20000, the checkpoint
    at the step reached) and how to continue. A SIGHUP that was ignored (nohup) stays ignored."""
    stops = [(signal.SIGTERM, None), (signal.SIGINT, None)]
    if hasattr(signal, "SIGHUP"):
        stops += [(signal.SIGHUP, None), (signal.SIGTERM, signal.SIGHUP)]  # nohup: SIGHUP ignored
    for stop, ignored in stops:
        d = work(f"signal-{stop.name}-{ignored.name if ignored else 'none'}")
        paths = {k: os.path.join(d, f"s.{k}") for k in ("xyz", "csv", "ckpt", "state")}
        arguments = ["run", "--backend", "cpu", "--particles", 200, "--seed", 4, "--steps", 10 ** 9, "--every", 20000,
                     "--trajectory", paths["xyz"], "--stats", paths["csv"], "--checkpoint", paths["ckpt"],
                     "--output-state", paths["state"], "--quiet"]
        ignore = (lambda: signal.signal(ignored, signal.SIG_IGN)) if ignored else None
        process = subprocess.Popen([ARGS.carom, *map(str, arguments)], stdout=subprocess.PIPE,
                                   stderr=subprocess.PIPE, text=True, preexec_fn=ignore)
        deadline = time.monotonic() + 300
        while checkpoint_step(paths["ckpt"]) == 0:
            assert process.poll() is None and time.monotonic() < deadline, "carom wrote no checkpoint after step 0"
            time.sleep(0.05)
        if ignored:
            process.send_signal(ignored)
            time.sleep(0.5)
            assert process.poll() is None, f"an ignored {ignored.name} stopped the run"
        process.send_signal(stop)
        out, err = process.communicate(timeout=300)
        assert process.returncode == 128 + stop, (stop.name, process.returncode, err)
        match = re.search(rf"interrupted at step (\d+) of 1000000000 by {stop.name}; the outputs hold:", err)
        assert match, err
        step = check_holdings(err, paths)
        assert step == int(match.group(1)) and '"interrupted": true' not in out, err
        assert csv_steps(paths["csv"]) == list(range(0, step + 1, 20000)), err
        assert f"continue with: carom run --resume {paths['ckpt']} --steps {10 ** 9 - step} " \
               f"--checkpoint {paths['ckpt']} --trajectory {paths['xyz']} --stats {paths['csv']} --every 20000" \
               in err, err
        no_partial_files(d)


def test_two_signals_at_once_stop_the_run():
    """`timeout` sends its signal twice at once (to carom, then to its process group): two SIGTERMs
    10 ms apart (the first handled, the second while the outputs of 20 000 disks are written) still
    stop the run cleanly (status 143, every output written), not kill it; only a
    second signal a second or more after the first kills."""
    d = work("two-signals")
    ckpt = os.path.join(d, "c.ckpt")
    arguments = ["run", "--backend", "cpu", "--particles", 20000, "--steps", 10 ** 9, "--every", 100,
                 "--checkpoint", ckpt, "--output-state", os.path.join(d, "end.csv"), "--quiet"]
    process = subprocess.Popen([ARGS.carom, *map(str, arguments)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               text=True)
    deadline = time.monotonic() + 300
    while checkpoint_step(ckpt) == 0:
        assert process.poll() is None and time.monotonic() < deadline, "carom wrote no checkpoint after step 0"
        time.sleep(0.05)
    process.send_signal(signal.SIGTERM)
    time.sleep(0.01)
    process.send_signal(signal.SIGTERM)
    out, err = process.communicate(timeout=300)
    assert process.returncode == 143, (process.returncode, err)
    assert "by SIGTERM; the outputs hold:" in err and os.path.exists(os.path.join(d, "end.csv")), err
    no_partial_files(d)


def test_signal_stops_within_a_long_step():
    """A single step can take minutes (the events scheme at a high speed, a step of thousands of
    substeps): SIGTERM stops it within a second or so, not after it. The step cut short returns to
    its start, so the outputs hold step 0, complete, and the run exits with 143."""
    long_steps = [["--collisions", "events", "--speed", 1e7],  # ~6 minutes a step on a 2-core VM
                  ["--collisions", "pairwise", "--max-travel", 0.001, "--speed", 5e4]]  # ~2 minutes
    for scheme in long_steps:
        d = work(f"long-step-{scheme[1]}")
        paths = {k: os.path.join(d, f"s.{k}") for k in ("csv", "ckpt", "state")}
        arguments = ["run", "--backend", "cpu", "--particles", 2000, "--steps", 1, *scheme, "--stats", paths["csv"],
                     "--checkpoint", paths["ckpt"], "--output-state", paths["state"], "--quiet"]
        process = subprocess.Popen([ARGS.carom, *map(str, arguments)], stdout=subprocess.PIPE,
                                   stderr=subprocess.PIPE, text=True)
        try:
            time.sleep(2)  # started, and well into its one step
            assert process.poll() is None, process.communicate()
            process.send_signal(signal.SIGTERM)
            sent = time.monotonic()
            out, err = process.communicate(timeout=60)
            waited = time.monotonic() - sent
        finally:
            process.kill()
        assert process.returncode == 143, (scheme, process.returncode, err)
        assert waited < 10, (scheme, waited)  # a check every 20 ms; room for a loaded machine
        assert "interrupted at step 0 of 1 by SIGTERM; the outputs hold:" in err, err
        assert check_holdings(err, paths) == 0, err
        assert csv_steps(paths["csv"]) == [0], err
        no_partial_files(d)


def limited_run(limit, arguments):
    """carom run with a file size limit (ulimit -f) of `limit` bytes: writes past it fail (EFBIG)."""
    import resource

    def limit_file_size():
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))

    return subprocess.run([ARGS.carom, "run", *map(str, arguments)], capture_output=True, text=True, timeout=600,
                          preexec_fn=limit_file_size)


def test_output_failure_keeps_the_others():
    """When one output cannot be written (here the trajectory, past a 64 KiB file size limit), the run
    stops with status 1, says which output failed, keeps every other (statistics and checkpoint at the
    step reached, the final state), leaves the failed output's earlier file alone, and says how to
    continue (with the run's --max-travel, which the checkpoint does not hold); the continuation
    matches an uninterrupted run bit for bit."""
    d = work("output-failure")
    paths = {k: os.path.join(d, f"f.{k}") for k in ("xyz", "csv", "ckpt", "state")}
    with open(paths["xyz"], "w") as f:
        f.write("an earlier trajectory\n")
    scene = ["--backend", "cpu", "--particles", 100, "--seed", 5, "--speed", 20, "--max-travel", 0.01]
    done = limited_run(64 * 1024, [*scene, "--steps", 2000, "--every", 100, "--trajectory", paths["xyz"], "--stats",
                                   paths["csv"], "--checkpoint", paths["ckpt"], "--output-state", paths["state"]])
    assert done.returncode == 1, (done.returncode, done.stderr)
    match = re.search(r"the run stopped at step (\d+) of 2000: writing an output failed\n"
                      rf"  trajectory {re.escape(paths['xyz'])}: FAILED: .*\nkept what could be written:", done.stderr)
    assert match and done.stdout == "", (done.stdout, done.stderr)
    step = int(match.group(1))
    assert 0 < step < 2000 and check_holdings(done.stderr, {k: paths[k] for k in ("csv", "ckpt", "state")}) == step
    assert csv_steps(paths["csv"]) == list(range(0, step + 1, 100))
    with open(paths["xyz"]) as f:
        assert f.read() == "an earlier trajectory\n"
    no_partial_files(d)

    command = re.search(r"continue with: carom run (.*)", done.stderr).group(1).split()
    resumed, fresh = os.path.join(d, "resumed.csv"), os.path.join(d, "fresh.csv")
    carom("run", *command, "--output-state", resumed)
    fresh_stats = os.path.join(d, "fresh-stats.csv")
    carom("run", *scene, "--steps", 2000, "--every", 100, "--stats", fresh_stats, "--output-state", fresh)
    assert read_bytes(resumed) == read_bytes(fresh)
    assert read_bytes(paths["csv"]) == read_bytes(fresh_stats)  # the continuation appended its rows


def test_output_failures_at_the_end_are_all_reported():
    """Every output is attempted at the end whatever happened to the others, and every failure is
    reported: with 1000 disks a 32 KiB limit fails the final state (48 KB) only, and 16 KiB also the
    checkpoint (24 KB), which then fails at step 0 (so that sample adds no row: the statistics never
    run past the checkpoint); the statistics are kept each time."""
    for limit, failed, step in ((32 * 1024, ["final state"], 200), (16 * 1024, ["checkpoint", "final state"], 0)):
        d = work(f"end-failures-{limit}")
        paths = {k: os.path.join(d, f"e.{k}") for k in ("csv", "ckpt", "state")}
        done = limited_run(limit, ["--backend", "cpu", "--particles", 1000, "--steps", 200, "--every", 100, "--stats",
                                   paths["csv"], "--checkpoint", paths["ckpt"], "--output-state", paths["state"]])
        assert done.returncode == 1, (limit, done.returncode, done.stderr)
        assert f"the run stopped at step {step} of 200: writing an output failed" in done.stderr, done.stderr
        assert re.findall(r"  (.*) \S+: FAILED", done.stderr) == failed, done.stderr
        if "checkpoint" in failed:  # a sample whose checkpoint failed adds no row: none at step 0, no file
            assert f"statistics {paths['csv']}: nothing from this run; the file, if any, is as it was" in done.stderr
            assert not os.path.exists(paths["csv"]), done.stderr
        else:
            rows = f"{step // 100 + 1} row" + ("s" if step else "")
            assert f"statistics {paths['csv']}: {rows}, the last at step {step}" in done.stderr, done.stderr
            assert csv_steps(paths["csv"]) == list(range(0, step + 1, 100))
        assert os.path.exists(paths["ckpt"]) == ("checkpoint" not in failed) and not os.path.exists(paths["state"])
        no_partial_files(d)


def test_stdout_write_errors_are_reported():
    """A summary, JSON or listing that cannot reach stdout (here /dev/full) is an error, not a silent
    exit 0, for every subcommand; with the reason when the failed write came in the final flush (the
    outputs up to stdio's buffer, 4 KiB)."""
    if not os.path.exists("/dev/full"):
        return
    for arguments in (["run", "--backend", "cpu", "--particles", 10, "--steps", 10, "--json"],
                      ["run", "--backend", "cpu", "--particles", 10, "--steps", 10], ["devices"],
                      ["bench", "--list"], ["--help"], ["run", "--help"]):
        with open("/dev/full", "w") as full:
            done = subprocess.run([ARGS.carom, *map(str, arguments)], stdout=full, stderr=subprocess.PIPE, text=True,
                                  timeout=600)
        assert done.returncode == 1, (arguments, done.returncode, done.stderr)
        reason = ": No space left on device" if arguments != ["run", "--help"] else ""
        assert f"writing to standard output failed{reason}" in done.stderr, (arguments, done.stderr)


def test_empty_numbers_are_refused():
    """An empty value is not 0, for every numeric option of every subcommand."""
    run = ["run", "--backend", "cpu", "--particles", 10, "--steps", 1]
    cases = [(run, "--seed"), (run, "--speed"), (run, "--max-travel"), (run, "--every"), (run, "--packing"),
             (run, "--radius"), (run, "--mass"), (["run", "--backend", "cpu", "--particles", 10], "--steps"),
             (["run", "--backend", "cpu", "--steps", 1], "--particles"),
             (["bench", "--quick", "--methods", "cpu"], "--seed"), (["bench", "--quick", "--methods", "cpu"], "--dt"),
             (["bench", "--quick", "--methods", "cpu"], "--samples"), (["validate", "--quick"], "--seed"),
             (["validate", "--quick"], "--particles")]
    for args, option in cases:
        done = subprocess.run([ARGS.carom, *map(str, args), option, ""], capture_output=True, text=True, timeout=60)
        assert done.returncode != 0, f"{option} '' was accepted: {done.stdout}"
        assert re.search(f"{option}: '' is not a (whole )?number", done.stderr), done.stderr


def csv_rows(n):
    return "id,x,y,vx,vy,mass,radius\n" + "".join(f"{i},{3 * i + 2},5,0.5,0,1,1\n" for i in range(n))


def test_input_state_fifo():
    """A FIFO with a writer is read (also process substitution); one nobody writes to is refused, not waited on."""
    d = work("fifo")
    fifo = os.path.join(d, "in.csv")
    os.mkfifo(fifo)
    run = ["run", "--backend", "cpu", "--steps", 5, "--box", 40, 10, "--json", "--input-state"]
    started = time.monotonic()
    done = subprocess.run([ARGS.carom, *map(str, run), fifo], capture_output=True, text=True, timeout=60)
    waited = time.monotonic() - started
    assert done.returncode != 0 and "is a FIFO (named pipe) that no program wrote to within 10 s" in done.stderr, \
        done.stderr
    assert waited < 30, f"waited {waited:.0f} s"

    reader = subprocess.Popen([ARGS.carom, *map(str, run), fifo], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              text=True)
    time.sleep(0.5)
    with open(fifo, "w") as writer:
        writer.write(csv_rows(5))
    out, err = reader.communicate(timeout=60)
    assert reader.returncode == 0, err
    assert json.loads(out)["particles"] == 5

    state = os.path.join(d, "state.csv")
    with open(state, "w") as f:
        f.write(csv_rows(4))
    command = " ".join(map(str, [ARGS.carom, *run])) + f" <(cat {state})"
    done = subprocess.run(["bash", "-c", command], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout)["particles"] == 4


def test_synced_before_rename():
    """Each output file is synced to the disk (fsync of FILE.XXXXXX.partial) before it is renamed into place,
    and its folder after the rename, so that a power loss leaves the old file or the complete new one
    under the name, never an empty one. fsync and rename are logged by tests/fsync_spy.cpp."""
    d = work("synced")
    log = os.path.join(d, "calls.log")
    paths = [os.path.join(d, name) for name in ("t.xyz", "s.csv", "c.ckpt", "end.csv")]
    env = dict(os.environ, LD_PRELOAD=ARGS.spy, CAROM_SPY_LOG=log)
    arguments = ["run", "--backend", "cpu", "--particles", 50, "--steps", 20, "--every", 10, "--trajectory", paths[0],
                 "--stats", paths[1], "--checkpoint", paths[2], "--output-state", paths[3]]
    done = subprocess.run([ARGS.carom, *map(str, arguments)], capture_output=True, text=True, timeout=120, env=env)
    assert done.returncode == 0, done.stderr
    with open(log) as f:
        calls = [tuple(line.rstrip("\n").split(" ", 1)) for line in f]
    folder = os.path.realpath(d)
    for path in paths:
        temporary = re.compile(re.escape(os.path.join(folder, os.path.basename(path))) + r"\.[0-9a-z]{6}\.partial")
        renames = [i for i, (call, name) in enumerate(calls) if call == "rename" and temporary.fullmatch(name)]
        assert renames, (path, calls)
        for i in renames:
            partial = calls[i][1]  # each write its own temporary name
            assert ("fsync", partial) in calls[:i], (path, "not synced", calls)
            assert ("fsync", folder) in calls[i + 1:i + 3], (path, "folder not synced", calls)


def skipped_under_sanitizer():
    """True (and says so) where carom is built with AddressSanitizer, which cannot start under an
    address-space limit (ulimit -v): it reserves terabytes for its shadow memory."""
    if ARGS.sanitized:
        print("skipped: AddressSanitizer cannot run under ulimit -v")
    return ARGS.sanitized


def test_resume_forged_count_allocates_nothing():
    """A checkpoint header claiming 3 * 10^7 particles, in a sparse file of the size they need, with no valid
    checksum: refused by the checksum (or the memory check) without allocating what the header claims, which
    the address-space limit here would turn into "out of memory"."""
    import resource

    if skipped_under_sanitizer():
        return
    d = work("forged")
    good = os.path.join(d, "good.ckpt")
    carom("run", "--backend", "cpu", "--particles", 10, "--steps", 1, "--checkpoint", good)
    header = bytearray(read_bytes(good)[:76])
    count = 30_000_000
    header[16:24] = struct.pack("<Q", count)
    forged = os.path.join(d, "forged.ckpt")
    with open(forged, "wb") as f:
        f.write(header)
        f.truncate(76 + 32 * count + 4)

    def limit_memory():
        resource.setrlimit(resource.RLIMIT_AS, (512 << 20, 512 << 20))

    done = subprocess.run([ARGS.carom, "run", "--backend", "cpu", "--resume", forged, "--steps", "1"],
                          capture_output=True, text=True, timeout=120, preexec_fn=limit_memory)
    assert done.returncode != 0, done.stdout
    assert "out of memory" not in done.stderr, done.stderr
    assert re.search("checksum mismatch|particles need about", done.stderr), done.stderr


def test_memory_check_uses_available_memory():
    """--particles needing more than MemAvailable, but less than the total memory, is refused before
    allocating, naming what is available. The address-space limit (ulimit -v) is set between the two,
    so a check against the total would fail to allocate ("out of memory") and one against the limit
    would name it; and a limit below MemAvailable is the figure named, as a container's would be."""
    import resource

    if skipped_under_sanitizer():
        return
    def refusal(particles, limit):
        def limit_memory():
            resource.setrlimit(resource.RLIMIT_AS, (limit, limit))

        done = subprocess.run([ARGS.carom, "run", "--backend", "cpu", "--steps", "1", "--particles", str(particles)],
                              capture_output=True, text=True, timeout=120, preexec_fn=limit_memory)
        assert done.returncode != 0, done.stdout
        match = re.search(f"--particles: {particles} particles need about [0-9]+ MiB of memory, more than the "
                          "([0-9]+) MiB available", done.stderr)
        assert match, done.stderr
        return int(match.group(1))

    assert refusal(8_000_000, 1 << 30) == 1024  # 2 GB asked, ulimit -v 1 GiB
    try:
        with open("/proc/meminfo") as f:
            info = {line.split(":")[0]: int(line.split()[1]) * 1024 for line in f}
    except OSError:
        print("skipped MemAvailable: no /proc/meminfo")
        return
    total, available = info["MemTotal"], info["MemAvailable"]
    if total - available < 1 << 30:
        print("skipped MemAvailable: available memory is within 1 GiB of the total")
        return
    named = refusal(min((total + available) // 2 // 256, 500_000_000), available + (total - available) // 4)
    assert abs(named - (available >> 20)) < 0.05 * (available >> 20), (named, available >> 20)


# --- The events scheme (--collisions events, issue 12) ---

EVENTS_DISKS = ["--particles", 300, "--packing", 0.45, "--radius-min", 0.5, "--radius-max", 1.2,
                "--mass-min", 0.5, "--mass-max", 4, "--speed", 1.5, "--seed", 7, "--dt", 0.01,
                "--collisions", "events"]
EVENTS_SCENES = {"periodic": [*EVENTS_DISKS, "--boundary", "periodic"],
                 "walls-gravity": [*EVENTS_DISKS, "--boundary", "walls", "--gravity", 0, -0.5]}


def reseal(data):
    """The bytes with their trailing CRC-32 rewritten, as carom would have written them."""
    return data[:-4] + struct.pack("<I", zlib.crc32(data[:-4]))


def test_events_checkpoint_layout():
    """An events run's checkpoint is format version 4 with scheme code 2 and holds, after the float32
    particles and their images, the engine's time and 64 bytes per disk (checkpoint.h): each disk's double state at its
    own time, projected to the engine's time, is the float32 particle; every event is pending (at or
    after that time) and names a kind of event or another disk; no event means an infinite time."""
    d = work("events-layout")
    ckpt = os.path.join(d, "c.ckpt")
    n, dt, steps, gravity = 60, 0.02, 30, -1.0
    carom("run", "--backend", "cpu", "--particles", n, "--box", 40, 40, "--radius-min", 0.5, "--radius-max", 1.5,
          "--steps", steps, "--dt", dt, "--gravity", 0, gravity, "--collisions", "events", "--checkpoint", ckpt)
    data = read_bytes(ckpt)
    magic, mark, version, count = struct.unpack_from("<8sIIQ", data, 0)
    assert (magic, mark, version, count) == (b"CAROMCKP", 0x01020304, 4, n)
    step, sim_time, _, scheme_code = struct.unpack_from("<QdQI", data, 48)
    assert (step, scheme_code) == (steps, 2)
    assert len(data) == 76 + 32 * n + 8 + 64 * n + 4
    assert struct.unpack_from("<I", data, len(data) - 4)[0] == zlib.crc32(data[:-4])
    (now,) = struct.unpack_from("<d", data, 76 + 32 * n)
    assert abs(now - sim_time) < 1e-9, (now, sim_time)
    for i in range(n):
        x, y, vx, vy, t, event_time, event, _, _, _ = struct.unpack_from("<6di3I", data, 84 + 32 * n + 64 * i)
        px, py, pvx, pvy = struct.unpack_from("<4f", data, 76 + 24 * i)
        s = now - t
        assert 0 <= s, (i, t, now)
        projected = (x + vx * s, y + vy * s + 0.5 * gravity * s * s, vx, vy + gravity * s)
        for got, want in zip((px, py, pvx, pvy), projected):
            assert abs(got - want) <= 1e-5 * max(1.0, abs(want)), (i, got, want)
        assert -9 <= event < n and event != i, (i, event)
        assert (event == -1) == (event_time == float("inf")), (i, event, event_time)
        assert event_time >= now, (i, event_time, now)


def test_events_resume_continues_bit_for_bit():
    """200 steps of the events scheme in one run equal 100 steps and 100 resumed from the checkpoint
    (the checkpoint keeps the engine's exact state), periodic and with walls and gravity: the final
    state and checkpoint, and the trajectory and statistics the resumed run appends to, byte for byte."""
    for name, scene in EVENTS_SCENES.items():
        d = work(f"events-resume-{name}")
        whole = run_with_outputs(d, "cpu", "whole", *scene, "--steps", 200)
        one = run_with_outputs(d, "cpu", "one", *scene, "--steps", 100)
        two_state = os.path.join(d, "two.state")
        out, _ = carom("run", "--backend", "cpu", "--resume", one["ckpt"], "--steps", 100, "--every", 20,
                       "--trajectory", one["xyz"], "--stats", one["csv"], "--checkpoint", one["ckpt"],
                       "--output-state", two_state, "--quiet")
        assert "  scheme       events (" in out, out
        assert read_bytes(whole["state"]) == read_bytes(two_state), name
        for kind in ("ckpt", "xyz", "csv"):
            assert read_bytes(whole[kind]) == read_bytes(one[kind]), (name, kind)
        with open(whole["csv"]) as f:
            assert [int(r["step"]) for r in csv.DictReader(f)] == list(range(0, 201, 20)), name
        no_partial_files(d)


def test_events_json_and_summary():
    """--json reports the scheme, the engine's event counts (its collisions are the run's) and the
    change of the total energy of its double state, within 1e-12 relative over the run, where the
    float32 samples only show their rounding; the text summary prints the same figures; no energy
    warning."""
    for name, scene in EVENTS_SCENES.items():
        args = ["run", "--backend", "cpu", *scene, "--steps", 100, "--quiet"]
        out, err = carom(*args, "--json")
        summary = json.loads(out)
        assert summary["scheme"] == "events", summary
        events = summary["events"]
        assert set(events) == {"collisions", "wall_bounces", "cell_crossings", "stale", "overlapping"}, events
        assert events["collisions"] == summary["collisions"] > 0, (events, summary["collisions"])
        assert events["cell_crossings"] > 0, events
        assert (events["wall_bounces"] > 0) == (name == "walls-gravity"), (name, events)
        energy = summary["energy"]
        exact = energy["exact_total"]
        change = energy["exact_relative_change"]
        assert change == (exact["final"] - exact["initial"]) / abs(exact["initial"]), energy
        assert abs(change) < 1e-12, (name, change)
        for moment in ("initial", "final"):  # the same energy, from float32 samples
            assert abs(exact[moment] - energy["total"][moment]) < 1e-5 * abs(exact[moment]), (name, energy)
        assert ENERGY_WARNING not in err, err

        text, _ = carom(*args)
        expected = (f"  scheme       events ({events['collisions']} collisions, {events['wall_bounces']} wall "
                    f"bounces, {events['cell_crossings']} cell crossings; {events['stale']} stale and "
                    f"{events['overlapping']} overlapping events)")
        assert expected in text, (expected, text)
        total = "total" if name == "walls-gravity" else "kinetic"
        assert f"               {total} in double, the engine's state: " in text, text
        assert f"(relative change {change:+.2e})" in text, (change, text)


def test_events_resume_refusals():
    """Resuming an events checkpoint with substeps (--max-travel) or on OpenCL is refused, naming what
    to use; so is a checkpoint whose engine state is forged (valid checksum): an unknown event code by
    the reader, a cell outside the grid by the engine; and one cut short. Nothing is written."""
    d = work("events-refusals")
    ckpt, state = os.path.join(d, "c.ckpt"), os.path.join(d, "end.csv")
    n = 50
    carom("run", "--backend", "cpu", "--particles", n, "--steps", 10, "--collisions", "events", "--checkpoint", ckpt)
    resume = ["run", "--backend", "cpu", "--steps", 10, "--output-state", state]
    err = refused(*resume, "--resume", ckpt, "--max-travel", 0.3)
    assert "--max-travel 0.3 splits steps into substeps, but the events scheme has no steps to split" in err, err
    if "opencl" in ARGS.backends.split(","):
        err = refused("run", "--backend", "opencl", "--steps", 10, "--resume", ckpt, "--output-state", state)
        assert "--collisions events runs on the CPU only (one thread, double precision): use --backend cpu" in err

    data = bytearray(read_bytes(ckpt))
    disks = 84 + 32 * n
    forged = os.path.join(d, "forged.ckpt")
    for offset, value, message in ((disks + 48, -12, r"events state: disk 0: event code -12 is unknown; allowed: "
                                                     r"-9 to -1 \(kinds of event\) or a partner id from 0 to 49"),
                                   (disks + 64 * 3 + 60, 1 << 30, r"checkpoint '.*forged.ckpt': .*cell")):
        changed = bytearray(data)
        struct.pack_into("<i", changed, offset, value)
        with open(forged, "wb") as f:
            f.write(reseal(bytes(changed)))
        err = refused(*resume, "--resume", forged)
        assert re.search(message, err), (message, err)
    with open(forged, "wb") as f:
        f.write(reseal(bytes(data[:-68]) + bytes(4)))  # a disk short
    err = refused(*resume, "--resume", forged)
    assert f"but {n} particles and their events state need {len(data)}" in err, err
    assert not os.path.exists(state)
    no_partial_files(d)


# ---------------------------------------------------------------------------
# Every subcommand's files: one check before any work, temporaries removed on
# every exit path, signals honoured from the start.

def has_viewer():
    """Whether this carom has `carom view` (built with SDL2, OpenGL and Dear ImGui); says so if not."""
    done = subprocess.run([ARGS.carom, "view", "--help"], capture_output=True, text=True, timeout=60)
    if "--frames" not in done.stdout:
        print("skipped: this carom has no viewer")
    return "--frames" in done.stdout


def snapshot_files(d):
    """Every file under `d` with its bytes, to check that a refusal changed nothing."""
    found = {}
    for root, _, names in os.walk(d):
        for name in names:
            path = os.path.join(root, name)
            found[os.path.relpath(path, d)] = None if stat.S_ISFIFO(os.lstat(path).st_mode) else read_bytes(path)
    return found


def test_every_subcommand_checks_its_files_first():
    """view, bench and validate refuse, before any work and naming both options, what run refuses:
    an output over an input (the scene, the input state, the events script), two outputs that are
    one file, an output among the files of a folder output (validate's report, view's --record),
    a folder output that is a file, and an output in a missing folder. Nothing is written."""
    d = work("plan")
    with open(os.path.join(d, "sc.toml"), "w") as f:
        f.write("box = [20, 20]\nsteps = 5\n[[group]]\ncount = 10\n")
    with open(os.path.join(d, "in.csv"), "w") as f:
        f.write(csv_rows(3))
    with open(os.path.join(d, "ev.txt"), "w") as f:
        f.write("1 key space\n")
    with open(os.path.join(d, "x.png"), "w") as f:
        f.write("an earlier screenshot")
    os.makedirs(os.path.join(d, "vr"))
    with open(os.path.join(d, "vr", "README.md"), "w") as f:
        f.write("an earlier report")
    before = snapshot_files(d)
    view = ["view", "--backend", "cpu", "--frames", 2, "--window", 64, 64]
    cases = [
        (["bench", "--methods", "cpu", "--sizes", 100, "--json", "x.out", "--csv", "./x.out"],
         "--json and --csv name the same file ('x.out' and './x.out')"),
        (["bench", "--methods", "cpu", "--sizes", 100, "--plot", "x.svg", "--csv", "x.svg.abc123.partial"],
         "--csv 'x.svg.abc123.partial' is a temporary name of --plot 'x.svg'"),
        (["bench", "--methods", "cpu", "--sizes", 100, "--json", "no-such-folder/b.json"],
         "--json 'no-such-folder/b.json': the folder"),
        (["validate", "--quick", "--report", "vr", "--json", "vr/README.md"],
         "--json 'vr/README.md' is one of the files --report 'vr' writes"),
        (["validate", "--quick", "--report", "x.png"], "--report 'x.png' is a file; give a folder"),
        (["validate", "--quick", "--report", "vr", "--json", "vr/../vr"], "--json 'vr/../vr' is a folder"),
    ]
    if has_viewer():
        cases += [
            ([*view, "--scene", "sc.toml", "--output-state", "./sc.toml"],
             "--output-state './sc.toml' would overwrite the input --scene 'sc.toml'"),
            ([*view, "--box", 20, 20, "--input-state", "in.csv", "--output-state", "in.csv"],
             "--output-state 'in.csv' would overwrite the input --input-state 'in.csv'"),
            ([*view, "--events", "ev.txt", "--screenshot", "./ev.txt"],
             "--screenshot './ev.txt' would overwrite the input --events 'ev.txt'"),
            ([*view, "--screenshot", "x.png", "--output-state", "./x.png"],
             "--screenshot and --output-state name the same file ('x.png' and './x.png')"),
            ([*view, "--record", "rec", "--screenshot", "rec/frame_00001.png"],
             "--screenshot 'rec/frame_00001.png' is one of the files --record 'rec' writes"),
            ([*view, "--record", "x.png"], "--record 'x.png' is a file; give a folder"),
            ([*view, "--screenshot", "no-such-folder/x.png"], "--screenshot 'no-such-folder/x.png': the folder"),
        ]
    for args, message in cases:
        err = refused(*args, cwd=d)
        assert message in err, (args, err)
        assert snapshot_files(d) == before, (args, "changed the files")


def test_empty_file_names_are_refused():
    """An empty name for any file option of any subcommand, input or output, is refused naming the
    option, never taken as "not given": `--resume ""` does not start a fresh scene whose --checkpoint
    would replace the run it meant to continue."""
    d = work("empty-file-names")
    carom(*SMALL_RUN, "--checkpoint", "keep.ckpt", cwd=d)
    kept = read_bytes(os.path.join(d, "keep.ckpt"))
    cases = [["run", "--resume", "", "--checkpoint", "keep.ckpt"], ["run", "--scene", ""],
             ["run", "--box", 20, 20, "--input-state", ""], ["bench", "--sizes", 100, "--json", ""],
             ["bench", "--sizes", 100, "--csv", ""], ["bench", "--sizes", 100, "--plot", ""],
             ["validate", "--quick", "--json", ""], ["validate", "--quick", "--report", ""]]
    if has_viewer():
        cases += [["view", "--frames", 1, option, ""]
                  for option in ("--scene", "--input-state", "--events", "--screenshot", "--record", "--output-state")]
    for args in cases:
        option = next(a for a, b in zip(args, args[1:]) if b == "")
        err = refused(*args, cwd=d)
        assert f"{option}: an empty file name; give a path, or leave the option out" in err, (args, err)
    assert read_bytes(os.path.join(d, "keep.ckpt")) == kept
    assert sorted(os.listdir(d)) == ["keep.ckpt"], os.listdir(d)


def test_failed_first_sample_keeps_earlier_files():
    """An output that took no sample (the checkpoint fails at the first one, so no frame or row follows
    it) is not committed: the earlier trajectory and statistics stay as they were, in a new run and in
    a resumed one, and the message says so."""
    d = work("first-sample")
    full = device_node(d, "full", "/dev/full")
    if not full:
        return
    carom(*SMALL_RUN, "--every", 1, "--trajectory", "t.xyz", "--stats", "s.csv", "--checkpoint", "c.ckpt", cwd=d)
    before = {name: read_bytes(os.path.join(d, name)) for name in ("t.xyz", "s.csv")}
    for resume in ([], ["--resume", "c.ckpt"]):
        args = ["run", "--backend", "cpu", "--steps", 5, "--every", 1, "--quiet", "--trajectory", "t.xyz", "--stats",
                "s.csv", "--checkpoint", full, *(resume or ["--particles", 10])]
        err = refused(*args, cwd=d)
        assert f"checkpoint {full}: FAILED: writing '{full}' failed: No space left on device" in err, err
        for name, item in (("t.xyz", "trajectory"), ("s.csv", "statistics")):
            assert f"{item} {name}: nothing from this run; the file, if any, is as it was" in err, err
            assert read_bytes(os.path.join(d, name)) == before[name], (resume, name)
        no_partial_files(d)


def test_same_file_through_a_symlinked_folder():
    """An output in a folder and another in a symlink to that folder are one file, although it does
    not exist yet."""
    d = work("symlinked-folder")
    os.makedirs(os.path.join(d, "real"))
    os.symlink("real", os.path.join(d, "alias"))
    err = refused(*SMALL_RUN, "--checkpoint", "real/c.ckpt", "--output-state", "alias/c.ckpt", cwd=d)
    assert "--checkpoint and --output-state name the same file ('real/c.ckpt' and 'alias/c.ckpt')" in err, err
    assert os.listdir(os.path.join(d, "real")) == []


def test_same_file_through_a_bind_mount():
    """The same with a bind mount of the folder (the two folders are one by device and inode, as a
    symlink cannot show), in a private mount namespace; skipped where one cannot be made (not root)."""
    d = work("bind-mount")
    os.makedirs(os.path.join(d, "real"))
    os.makedirs(os.path.join(d, "alias"))
    script = (f"mount --bind real alias && exec {ARGS.carom} run --backend cpu --particles 10 --steps 5 --quiet "
              "--checkpoint real/c.ckpt --output-state alias/c.ckpt")
    try:
        done = subprocess.run(["unshare", "-m", "--propagation", "private", "sh", "-c", script], capture_output=True,
                              text=True, timeout=120, cwd=d)
    except FileNotFoundError:
        print("skipped: no unshare here to make a bind mount")
        return
    if "unshare:" in done.stderr or "mount:" in done.stderr:
        print(f"skipped: cannot make a bind mount here ({done.stderr.strip()})")
        return
    assert done.returncode == 1 and "--checkpoint and --output-state name the same file" in done.stderr, done.stderr
    assert os.listdir(os.path.join(d, "real")) == []


def test_resume_refuses_a_gap_or_another_simulation():
    """A resumed run appends only to files whose last frame or row is the last sample up to the
    checkpoint's step (no gap) and of the same simulation (disk count, box, boundary, radii, masses,
    time, collisions); otherwise it is refused and the file left as it was."""
    d = work("gap")
    scene = ["--backend", "cpu", "--particles", 30, "--box", 30, 30, "--seed", 4, "--every", 100, "--quiet"]
    carom("run", *scene, "--steps", 500, "--trajectory", "t.xyz", "--stats", "s.csv", "--checkpoint", "c500.ckpt",
          cwd=d)
    carom("run", "--resume", "c500.ckpt", "--steps", 600, "--every", 100, "--checkpoint", "c1100.ckpt", cwd=d)
    resumed = ["run", "--backend", "cpu", "--every", 100, "--quiet", "--steps", 100]
    for option, name, item in (("--trajectory", "t.xyz", "frame"), ("--stats", "s.csv", "row")):
        before = read_bytes(os.path.join(d, name))
        err = refused(*resumed, "--resume", "c1100.ckpt", option, name, cwd=d)
        assert f"cannot append to '{name}': its last {item} is at step 500, but sampling every 100 steps up to the " \
               "checkpoint's step 1100 reaches step 1100, so the samples in between would be missing" in err, err
        assert read_bytes(os.path.join(d, name)) == before

    # Another simulation with as many disks, up to step 500: another box, other masses.
    others = [(["--box", 40, 40, "--seed", 4], "has another cell or other columns than the checkpoint's box"),
              (["--box", 30, 30, "--seed", 5, "--mass-min", 1, "--mass-max", 2], "has disk 0 as ")]
    for k, (world, message) in enumerate(others):
        trajectory, stats = f"other{k}.xyz", f"other{k}.csv"
        carom("run", "--backend", "cpu", "--particles", 30, "--every", 100, "--quiet", *world, "--steps", 500,
              "--trajectory", trajectory, "--stats", stats, cwd=d)
        before = read_bytes(os.path.join(d, trajectory))
        err = refused(*resumed, "--resume", "c500.ckpt", "--trajectory", trajectory, cwd=d)
        assert f"cannot append to '{trajectory}': its last frame {message}" in err, err
        assert "so it is another simulation's trajectory" in err, err
        assert read_bytes(os.path.join(d, trajectory)) == before
        err = refused(*resumed, "--resume", "c500.ckpt", "--stats", stats, cwd=d)
        assert f"cannot append to '{stats}': its last row, at step 500, " in err, err
        assert "so it is another simulation's statistics" in err, err
    # The files of this simulation, resumed where they end, still take the samples after.
    carom(*resumed, "--resume", "c500.ckpt", "--trajectory", "t.xyz", "--stats", "s.csv", cwd=d)
    assert xyz_steps(os.path.join(d, "t.xyz")) == list(range(0, 601, 100))
    no_partial_files(d)


def test_output_that_is_standard_output_or_error():
    """An output that is the regular file carom's standard output or error goes to (under any name:
    /dev/stdout, or the file itself) is refused before any work: replacing it would lose the summary
    and messages printed there. A pipe or a terminal as /dev/stdout is written directly."""
    d = work("own-stdout")
    for args, stream, redirect in ((["--output-state", "/dev/stdout"], "standard output", "stdout"),
                                   (["--stats", "out.txt"], "standard output", "stdout"),
                                   (["--trajectory", "/dev/stderr"], "standard error", "stderr")):
        path = os.path.join(d, "out.txt")
        with open(path, "w") as f:
            f.write("kept\n")
        inode = os.stat(path).st_ino
        with open(path, "a") as f:
            streams = {"stdout": f, "stderr": subprocess.PIPE} if redirect == "stdout" else \
                      {"stdout": subprocess.PIPE, "stderr": f}
            done = subprocess.run([ARGS.carom, *map(str, SMALL_RUN), *args], text=True, timeout=120, cwd=d, **streams)
        assert done.returncode == 1 and os.stat(path).st_ino == inode, args
        with open(path) as f:
            text = f.read()
        message = text if redirect == "stderr" else done.stderr
        assert f"is the file carom's {stream} goes to" in message, (args, message)
        assert text.startswith("kept\n"), text
    done = subprocess.run(f"{ARGS.carom} run --backend cpu --particles 3 --box 10 10 --steps 1 --quiet "
                          "--output-state /dev/stdout | cat", shell=True, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0 and done.stdout.startswith("id,x,y,vx,vy,mass,radius\n"), done.stderr


def test_huge_last_line_is_refused_at_once():
    """A file of one 100 MB line (no newline) given to a resumed run to append to is refused at once,
    naming it, not read whole (which took minutes)."""
    d = work("huge-line")
    carom(*SMALL_RUN, "--checkpoint", "c.ckpt", cwd=d)
    for option, name in (("--trajectory", "t.xyz"), ("--stats", "s.csv")):
        with open(os.path.join(d, name), "wb") as f:
            if name == "s.csv":
                f.write(b"step,time,kinetic_energy,momentum_x,momentum_y,collisions,max_overlap,escaped\n")
            f.write(b"x" * (100 << 20))
        done = subprocess.run([ARGS.carom, "run", "--resume", "c.ckpt", "--steps", "5", "--quiet", option, name],
                              capture_output=True, text=True, timeout=60, cwd=d)
        assert done.returncode == 1 and "has a line longer than 65536 bytes" in done.stderr, done.stderr
        os.remove(os.path.join(d, name))
    no_partial_files(d)


def test_signal_at_start_up_ends_at_once():
    """SIGTERM while the run starts (here waiting for a FIFO output's reader, which never comes) ends
    it at once with 143, every file as it was and no temporary file left."""
    d = work("start-up-signal")
    os.mkfifo(os.path.join(d, "frames"))
    with open(os.path.join(d, "s.csv"), "w") as f:
        f.write("an earlier file\n")
    process = subprocess.Popen([ARGS.carom, *map(str, SMALL_RUN), "--stats", "s.csv", "--trajectory", "frames"],
                               cwd=d, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    time.sleep(1)
    assert process.poll() is None, "carom did not wait for the FIFO's reader"
    process.send_signal(signal.SIGTERM)
    _, err = process.communicate(timeout=60)
    assert process.returncode == 143, (process.returncode, err)
    assert "carom run: interrupted by SIGTERM before writing any output; every file is as it was" in err, err
    with open(os.path.join(d, "s.csv")) as f:
        assert f.read() == "an earlier file\n"
    no_partial_files(d)


def test_bench_and_validate_stop_on_signals():
    """carom validate and carom bench stop at once on SIGINT or SIGTERM, exit 128 + the signal, write
    no file (what they measured is on stderr) and leave no temporary file."""
    d = work("bench-validate-signals")
    for stop, args in ((signal.SIGINT, ["validate", "--report", "vr", "--json", "v.json"]),
                       (signal.SIGTERM, ["bench", "--methods", "cpu", "--sizes", "1e5", "--samples", 1000,
                                         "--json", "b.json", "--csv", "b.csv", "--plot", "b.svg"])):
        process = subprocess.Popen([ARGS.carom, *map(str, args)], cwd=d, stdout=subprocess.PIPE,
                                   stderr=subprocess.PIPE, text=True)
        time.sleep(2)
        assert process.poll() is None, process.communicate()
        process.send_signal(stop)
        _, err = process.communicate(timeout=60)
        assert process.returncode == 128 + stop, (args[0], process.returncode, err)
        assert f"carom {args[0]}: interrupted by {stop.name} before writing any output" in err, err
        for folder in (d, os.path.join(d, "vr")):
            if os.path.isdir(folder):
                no_partial_files(folder)
                assert not [f for f in os.listdir(folder) if f.endswith((".json", ".csv", ".svg", ".md"))]


def test_second_signal_removes_temporary_files():
    """A second signal, a second after the first, ends the run at once (here blocked writing a
    trajectory to a FIFO nobody reads any more), and removes its temporary files: no .partial is left."""
    d = work("second-signal")
    fifo = os.path.join(d, "frames")
    os.mkfifo(fifo)
    arguments = ["run", "--backend", "cpu", "--particles", 2000, "--steps", 10 ** 9, "--every", 1, "--quiet",
                 "--trajectory", fifo, "--stats", "s.csv", "--checkpoint", "c.ckpt"]
    process = subprocess.Popen([ARGS.carom, *map(str, arguments)], cwd=d, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    reader = open(fifo, "rb")  # never read: the pipe fills and carom blocks in a write
    deadline = time.monotonic() + 120
    while not os.path.exists(os.path.join(d, "c.ckpt")):
        assert process.poll() is None and time.monotonic() < deadline, process.communicate()
        time.sleep(0.05)
    time.sleep(0.5)
    assert any(".partial" in f for f in os.listdir(d)), os.listdir(d)
    process.send_signal(signal.SIGTERM)
    time.sleep(1.5)
    process.send_signal(signal.SIGTERM)
    process.communicate(timeout=60)
    reader.close()
    assert process.returncode == -signal.SIGTERM, process.returncode
    no_partial_files(d)


def test_append_copy_failure_is_named():
    """The copy a resumed run appends to is made before any work; when it fails (past a file size
    limit here, a full disk in the next test) the message says why, the partial copy is removed and
    the file is unchanged."""
    d = work("append-copy")
    carom("run", "--backend", "cpu", "--particles", 200, "--steps", 100, "--every", 10, "--quiet", "--trajectory",
          "t.xyz", "--checkpoint", "c.ckpt", cwd=d)
    before = read_bytes(os.path.join(d, "t.xyz"))
    done = limited_run(len(before) // 2, ["--backend", "cpu", "--resume", os.path.join(d, "c.ckpt"), "--steps", 10, "--every", 10, "--quiet",
                                          "--trajectory", os.path.join(d, "t.xyz")])
    assert done.returncode == 1, done.stderr
    assert re.search(r"cannot append to '.*t.xyz': copying it to '.*t.xyz.[0-9a-z]{6}.partial' failed: File too "
                     r"large; the file is unchanged", done.stderr), done.stderr
    assert read_bytes(os.path.join(d, "t.xyz")) == before
    no_partial_files(d)


def test_append_copy_on_a_full_disk():
    """A full disk while copying for an append says "No space left on device" and removes the partial
    copy (a 1 MiB tmpfs in a private mount namespace; skipped where one cannot be made)."""
    d = work("append-full-disk")
    os.makedirs(os.path.join(d, "small"))
    carom("run", "--backend", "cpu", "--particles", 2000, "--steps", 50, "--every", 10, "--quiet", "--trajectory",
          "t.xyz", "--checkpoint", "c.ckpt", cwd=d)
    size = os.path.getsize(os.path.join(d, "t.xyz"))
    assert 600 * 1024 < size < 1024 * 1024, size  # one copy fits in 1 MiB, two do not
    script = (f"mount -t tmpfs -o size=1m tmpfs small && cp t.xyz small/ && "
              f"{ARGS.carom} run --resume c.ckpt --steps 10 --every 10 --quiet --trajectory small/t.xyz; "
              "echo status $?; cmp t.xyz small/t.xyz && echo unchanged; ls small")
    try:
        done = subprocess.run(["unshare", "-m", "--propagation", "private", "sh", "-c", script], capture_output=True,
                              text=True, timeout=120, cwd=d)
    except FileNotFoundError:
        print("skipped: no unshare here to mount a small file system")
        return
    if "unshare:" in done.stderr or "mount:" in done.stderr:
        print(f"skipped: cannot mount a small file system here ({done.stderr.strip()})")
        return
    assert "status 1\nunchanged\nt.xyz\n" in done.stdout, (done.stdout, done.stderr)
    assert "failed: No space left on device; the file is unchanged" in done.stderr, done.stderr


def test_signal_ends_the_wait_for_a_fifo_reader():
    """A checkpoint written to a FIFO is opened anew each time; when its reader has gone, the first
    SIGTERM ends the wait for another (it was ignored: the open blocked): the run stops at once, names
    the FIFO, and keeps the other outputs."""
    d = work("fifo-wait")
    fifo = os.path.join(d, "c.fifo")
    os.mkfifo(fifo)
    reader = threading.Thread(target=lambda: read_bytes(fifo), daemon=True)  # some checkpoints, then gone
    reader.start()
    # Samples far apart (about 0.2 s): the next checkpoint's open comes after the reader has closed the
    # FIFO, not between its end of file and its close (where the open would succeed and the write fail).
    process = subprocess.Popen([ARGS.carom, *map(str, ["run", "--backend", "cpu", "--particles", 10, "--steps",
                                                       10 ** 9, "--every", 200000, "--quiet", "--checkpoint", fifo,
                                                       "--stats", "s.csv"])],
                               cwd=d, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    reader.join(timeout=60)
    time.sleep(1)
    assert process.poll() is None, process.communicate()
    process.send_signal(signal.SIGTERM)
    _, err = process.communicate(timeout=60)
    assert process.returncode == 1, (process.returncode, err)
    assert f"checkpoint {fifo}: FAILED: cannot write '{fifo}': no reader opened the FIFO before carom was asked " \
           "to stop" in err, err
    step = int(re.search(rf"checkpoint {re.escape(fifo)}: step (\d+)", err).group(1))  # the reader's last
    assert csv_steps(os.path.join(d, "s.csv"))[-1] == step, err
    no_partial_files(d)


def main():
    global ARGS
    parser = argparse.ArgumentParser()
    parser.add_argument("--carom", required=True)
    parser.add_argument("--work", required=True)
    parser.add_argument("--backends", default="cpu")
    parser.add_argument("--sanitized", action="store_true", help="carom is built with AddressSanitizer")
    parser.add_argument("--spy", help="the fsync_spy library, preloaded by test_synced_before_rename")
    parser.add_argument("test")
    ARGS = parser.parse_args()
    globals()["test_" + ARGS.test]()
    print(f"outputs_test.py {ARGS.test}: passed")


if __name__ == "__main__":
    main()
