"""carom.World: the same bits and numbers as `carom run`, views that are views,
and every refusal naming the value."""
import gc
import json
import os
import pickle
import re
import subprocess
import time

import numpy as np
import pytest

import carom


def run_cli(carom_exe, args, tmp_path):
    """`carom run ARGS --json --output-state`: the JSON summary and the final disks."""
    state = tmp_path / "final.csv"
    done = subprocess.run([carom_exe, "run", *args, "--json", "--quiet", "--output-state", str(state)],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout), carom.read_state(state)


def cli_backend(engine):
    return ["--backend", "cpu"] if engine == "cpu" else ["--backend", "opencl", "--pipeline", "host-grid"]


def assert_same_as_cli(world, summary, final):
    """The world's disks and observables are the command line's, bit for bit."""
    if not world.bitwise_reproducible:
        pytest.skip(f"{world.device_name} does not round divide and sqrt correctly: not bitwise the CPU's")
    for name in ("positions", "velocities", "masses", "radii"):
        assert np.array_equal(getattr(world, name), getattr(final, name)), name
    assert world.step_count == summary["step"]
    energy = summary["energy"]
    assert world.kinetic_energy == energy["kinetic"]["final"]
    assert world.potential_energy == energy["potential"]["final"]
    # With events, the engine's exact double state (the JSON's float samples sum to "total").
    exact = world.collision_scheme == "events"
    assert world.total_energy == energy["exact_total" if exact else "total"]["final"]
    assert list(world.momentum) == summary["momentum"]["final"]
    assert world.collisions == summary["collisions"]
    assert world.temperature == summary["temperature"]
    assert world.collision_rate == summary["collision_rate"]
    assert world.max_overlap == summary["max_overlap"]
    pressure = summary["pressure"] if world.boundary == "periodic" else summary["wall_pressure"]
    assert world.pressure == pressure["virial" if world.boundary == "periodic" else "mean"]
    assert world.compressibility == pressure["Z"]


@pytest.mark.parametrize("scene", ["ideal_gas.toml", "gravity_settle.toml", "mixture.toml"])
def test_a_scene_file_runs_as_the_command_line_runs_it(engine, carom_exe, scenes, scene, tmp_path):
    summary, final = run_cli(carom_exe, ["--scene", str(scenes / scene), "--steps", "150", *cli_backend(engine)],
                             tmp_path)
    world = carom.World.from_scene(scenes / scene, engine=engine, pipeline=None if engine == "cpu" else "host-grid")
    assert world.scene_steps > 0
    world.step(150)
    assert_same_as_cli(world, summary, final)


@pytest.mark.parametrize("boundary", ["walls", "periodic"])
@pytest.mark.parametrize("collisions", ["pairwise", "simultaneous"])
def test_a_generated_gas_runs_as_the_command_line_runs_it(engine, carom_exe, boundary, collisions, tmp_path):
    options = ["--particles", "600", "--packing", "0.45", "--radius-min", "0.5", "--radius-max", "1",
               "--mass-min", "1", "--mass-max", "3", "--speed", "2", "--seed", "5"]
    summary, final = run_cli(carom_exe, [*options, "--boundary", boundary, "--collisions", collisions, "--steps",
                                         "120", *cli_backend(engine)], tmp_path)
    scene = carom.make_scene(particles=600, packing=0.45, radius=(0.5, 1), mass=(1, 3), speed=2, seed=5)
    assert scene.box == tuple(summary["box"])
    world = carom.World(box=scene.box, boundary=boundary, collisions=collisions, engine=engine,
                        pipeline=None if engine == "cpu" else "host-grid")
    world.set_disks(scene.positions, scene.velocities, scene.masses, scene.radii, allow_overlaps=True)
    for chunk in (1, 19, 100):  # chunks change nothing
        world.step(chunk)
    assert_same_as_cli(world, summary, final)


def test_the_events_scheme_runs_as_the_command_line_runs_it(carom_exe, tmp_path):
    summary, final = run_cli(carom_exe, ["--particles", "300", "--packing", "0.3", "--collisions", "events",
                                         "--steps", "100", "--backend", "cpu"], tmp_path)
    scene = carom.make_scene(particles=300, packing=0.3)
    world = carom.World(box=scene.box, collisions="events")
    world.set_disks(scene.positions, scene.velocities, scene.masses, scene.radii)
    world.step(100)
    assert_same_as_cli(world, summary, final)
    assert world.event_counts()["collisions"] == summary["events"]["collisions"]
    assert world.exact_positions.dtype == np.float64
    assert np.array_equal(world.exact_positions.astype(np.float32), world.positions)


def gas(engine="cpu", collisions="pairwise", particles=400, **kwargs):
    world = carom.World(box=(60, 60), boundary="periodic", collisions=collisions, engine=engine, seed=11, **kwargs)
    world.place(particles, radius=(0.5, 1.0), speed=1.5)
    return world


def test_a_skin_changes_no_bit_and_is_refused_where_no_lists_take_it():
    expected = gas()
    expected.step(200)
    for skin in (0.01, 0.4, 3.0):
        world = gas(skin=skin)
        world.step(200)
        assert np.array_equal(world.positions, expected.positions), skin
        assert np.array_equal(world.velocities, expected.velocities), skin
        copied = pickle.loads(pickle.dumps(world))
        copied.step(10)
        world.step(10)
        assert np.array_equal(copied.positions, world.positions), skin
    assert carom.World(box=(60, 60), engine="auto", skin=0.5).engine == "cpu"
    with pytest.raises(carom.InputError, match="skin must be a finite number >= 0"):
        carom.World(box=(60, 60), skin=-1.0)
    with pytest.raises(carom.InputError, match="skin: nan is not finite"):
        carom.World(box=(60, 60), skin=float("nan"))
    with pytest.raises(carom.InputError, match="only the pairwise scheme keeps"):
        carom.World(box=(60, 60), collisions="simultaneous", skin=0.5)
    with pytest.raises(carom.InputError, match="more than 8 times the largest radius"):
        gas(skin=9.0)


def test_device_memory_counts_the_engines_buffers(engine, carom_exe, tmp_path):
    world = gas(engine)
    world.step(2)
    memory = world.device_memory
    if engine == "cpu":
        assert memory == {"bytes": 0, "peak_bytes": 0}
        return
    assert memory["bytes"] >= 400 * 100  # two 32-byte states and the tallies a disk, at least
    assert memory["peak_bytes"] >= memory["bytes"]
    summary, _ = run_cli(carom_exe, ["--particles", "400", "--steps", "2", *cli_backend(engine)], tmp_path)
    assert summary["memory"]["device_bytes_peak"] >= 400 * 100
    assert summary["memory"]["host_bytes_peak"] > 0


@pytest.mark.parametrize("collisions", ["pairwise", "simultaneous"])
def test_cpu_arrays_are_views_of_the_engines_memory(collisions):
    world = gas(collisions=collisions)
    positions, velocities = world.positions, world.velocities
    assert np.shares_memory(positions, world.positions)
    assert positions.dtype == np.float32 and positions.shape == (400, 2) and positions.strides == (32, 4)
    assert world.masses.shape == (400,) and world.radii.dtype == np.float32
    for array in (positions, velocities, world.masses, world.radii, world.ids):
        assert not array.flags.writeable
        with pytest.raises(ValueError):
            array[0] = 1
    for _ in range(3):
        world.step(2)
        assert np.shares_memory(positions, world.positions)  # the view follows the steps:
        assert np.array_equal(positions, world.copy().positions)  # it equals an independent copy
    assert np.array_equal(world.ids, np.arange(400))


def test_a_view_outlives_its_world_and_a_new_set_of_disks():
    world = gas()
    positions = world.positions
    kept = positions.copy()
    world.place(50)  # another number of disks: the view keeps the old ones
    assert not np.shares_memory(positions, world.positions)
    assert np.array_equal(positions, kept)
    velocities = world.velocities
    kept = velocities.copy()
    del world
    gc.collect()
    assert np.array_equal(velocities, kept)


def test_opencl_and_events_arrays_are_fresh_copies(engine):
    worlds = [gas(collisions="events")] + ([gas(engine=engine)] if engine != "cpu" else [])
    for world in worlds:
        first = world.positions
        assert not first.flags.writeable
        assert not np.shares_memory(first, world.positions)
        world.step(1)
        assert not np.array_equal(first, world.positions)


def test_one_process_owns_every_disk(engine):
    for world in (gas(engine=engine), gas(collisions="events")):
        world.step(20)
        own = world.own_disks()
        assert np.array_equal(own.ids, np.arange(world.n, dtype=np.uint32))
        for name in ("positions", "velocities", "masses", "radii", "images"):
            assert np.array_equal(getattr(own, name), getattr(world, name)), name
        world.gather()  # nothing to gather in one process
        assert np.array_equal(own.positions, world.positions)


def test_the_opencl_pipelines_agree_bit_for_bit(engine):
    if engine == "cpu":
        pytest.skip("OpenCL only")
    host_grid = gas(engine=engine, pipeline="host-grid")
    resident = gas(engine=engine, pipeline="resident")
    cpu = gas()
    for world in (host_grid, resident, cpu):
        world.step(50)
    assert np.array_equal(host_grid.positions, resident.positions)
    if host_grid.bitwise_reproducible:
        assert np.array_equal(host_grid.velocities, cpu.velocities)


def test_the_default_pipeline_is_resident_on_a_gpu_and_host_grid_elsewhere():
    for device in carom.devices():
        world = carom.World(box=(10, 10), engine="opencl", device=device["index"])
        assert world.pipeline == ("resident" if device["type"] == "GPU" else "host-grid"), device


def test_seed_is_the_former_name_of_the_host_grid_pipeline(engine):
    if engine == "cpu":
        pytest.skip("OpenCL only")
    with pytest.warns(FutureWarning, match="pipeline='seed' is now called pipeline='host-grid'"):
        world = carom.World(box=(10, 10), engine="opencl", pipeline="seed")
    assert world.pipeline == "host-grid"


def test_a_checkpoint_continues_bit_for_bit(engine, tmp_path):
    world = gas(engine=engine)
    world.step(30)
    world.save_checkpoint(tmp_path / "w.ckpt")
    resumed = carom.World.from_checkpoint(tmp_path / "w.ckpt", engine=engine)
    assert resumed.step_count == 30 and resumed.time == world.time
    world.step(40)
    resumed.step(40)
    assert np.array_equal(world.positions, resumed.positions)
    assert np.array_equal(world.velocities, resumed.velocities)
    assert world.collisions == resumed.collisions


def test_a_copy_or_a_pickle_continues_bit_for_bit(engine):
    import copy
    import pickle
    world = gas(engine=engine)
    world.step(20)
    twins = [world.copy(), copy.deepcopy(world), pickle.loads(pickle.dumps(world))]
    world.step(30)
    for twin in twins:
        assert twin.engine == world.engine and twin.seed == world.seed and twin.step_count == 20
        twin.step(30)
        assert np.array_equal(twin.positions, world.positions)
        assert np.array_equal(twin.velocities, world.velocities)
        assert twin.collisions == world.collisions and twin.time == world.time
    empty = pickle.loads(pickle.dumps(carom.World(box=(5, 6), dt=0.02, boundary="periodic", engine=engine)))
    assert empty.box == (5, 6) and empty.dt == pytest.approx(0.02) and empty.boundary == "periodic" and len(empty) == 0


def test_a_state_written_and_read_is_the_same_bits(engine, tmp_path):
    world = gas(engine=engine)
    world.step(5)
    carom.write_state(tmp_path / "s.csv", world)
    state = carom.read_state(tmp_path / "s.csv")
    assert np.array_equal(state.positions, world.positions) and np.array_equal(state.masses, world.masses)


def test_xyz_frames_replace_or_append(engine, tmp_path):
    world = gas(engine=engine, particles=20)
    path = tmp_path / "t.xyz"
    carom.write_xyz(path, world)
    world.step(3)
    carom.write_xyz(path, world, mode="a")
    lines = path.read_text().splitlines()
    assert lines.count("20") == 2 and len(lines) == 2 * 22
    carom.write_xyz(path, world)
    assert len(path.read_text().splitlines()) == 22
    with pytest.raises(carom.InputError, match="mode: 'x'; allowed: 'w', 'a'"):
        carom.write_xyz(path, world, mode="x")
    # Appended frames continue the file: refusals speak of the world (there is no checkpoint).
    with pytest.raises(carom.InputError, match="its last frame is at step 3, after the world's step 0"):
        carom.write_xyz(path, gas(engine=engine, particles=20), mode="a")
    with pytest.raises(carom.InputError, match="its last frame has 20 disks, the world 30"):
        carom.write_xyz(path, gas(engine=engine, particles=30), mode="a")


def test_placement_is_deterministic_in_the_seed(engine):
    a, b = gas(), gas(engine=engine)
    assert np.array_equal(a.positions, b.positions) and np.array_equal(a.velocities, b.velocities)
    c = carom.World(box=(60, 60), boundary="periodic")
    assert 0 <= c.seed < 2**63  # drawn, and kept so the run can be repeated
    c.place(400, radius=(0.5, 1.0), speed=1.5)
    replay = carom.World(box=(60, 60), boundary="periodic", seed=c.seed)
    replay.place(400, radius=(0.5, 1.0), speed=1.5)
    assert np.array_equal(c.velocities, replay.velocities)
    thermal = carom.World(box=(60, 60), seed=2)
    thermal.place(2000, radius=0.3, temperature=2.0)
    assert thermal.temperature == pytest.approx(2.0, rel=0.1)


def test_energy_is_conserved_and_motion_can_change(engine):
    world = carom.World(box=(40, 40), gravity=(0, -0.5), seed=4, engine=engine)
    world.place(300, radius=0.5, speed=1.0)
    start = world.total_energy
    world.step(500)
    assert abs(world.total_energy - start) < 1e-5 * start
    world.dt = 0.005
    world.gravity = (0.0, 0.0)
    assert world.dt == pytest.approx(0.005) and world.gravity == (0.0, 0.0)
    time = world.time
    world.step(10)
    assert world.time == pytest.approx(time + 0.05)


REFUSALS = [
    (lambda: carom.World(box=(-1, 10)), "box width must be a finite number > 0, got -1"),
    (lambda: carom.World(box=10), "box: 10 is not a pair of numbers"),
    (lambda: carom.World(box=(10, 10), boundary="open"), "'open'"),
    (lambda: carom.World(box=(10, 10), collisions="soft"), "'soft'"),
    (lambda: carom.World(box=(10, 10), engine="cuda"), "engine: 'cuda'; allowed: 'auto', 'cpu', 'opencl'"),
    (lambda: carom.World(box=(10, 10), pipeline="resident"), "OpenCL only"),
    (lambda: carom.World(box=(10, 10), dt=0), "dt must be a finite number > 0, got 0"),
    (lambda: carom.World(box=(10, 10), seed=-2), "seed: -2 is out of range"),
    (lambda: gas().step(-1), "n: -1 is out of range; allowed: whole numbers from 0 to 18446744073709551615"),
    (lambda: gas().step(2**64), "n: 18446744073709551616 is out of range"),
    (lambda: gas().place(2**32), "count: 4294967296 is out of range; allowed: whole numbers from 1 to 4294967295"),
    (lambda: gas().place(10, temperature=0), "temperature: 0; allowed: > 0"),
    (lambda: gas().place(10, speed=2, temperature=1), "speed=2 and temperature=1; allowed: one of them"),
    (lambda: gas().place(10, radius=(2, 1)), "radius: (2, 1); allowed: (min, max) with min <= max"),
    (lambda: gas().place(10, radius=None), "radius: None is not a number"),
    (lambda: carom.World(box=(10, 10)).step(1), "step: the world has no disks yet"),
    (lambda: carom.World(box=(1e39, 10)), "box: 1e+39 is too large for a 32-bit float"),
    (lambda: carom.World(box=(10, 10), dt="x"), "dt: 'x' is not a number"),
    # carom's one reader of numbers: decimal only, and a float32 that would be another number is refused
    (lambda: carom.World(box=(10, 10), dt="0x10"), "dt: '0x10' is not a number; allowed: a finite number"),
    (lambda: carom.World(box=(10, 10), dt="+0.5"), "dt: '+0.5' is not a number"),
    (lambda: carom.World(box=(10, 10), dt=" 0.5"), "dt: ' 0.5' is not a number"),
    (lambda: carom.World(box=(10, 10), dt=1e-50), "dt: 1e-50 is too small for a 32-bit float"),
    (lambda: carom.World(box=(10, 10), gravity=(0, -1e-50)), "gravity: -1e-50 is too small for a 32-bit float"),
    (lambda: carom.World(box=(10, 10), max_travel=1e-50), "max_travel: 1e-50 is too small for a 32-bit float"),
    (lambda: gas().place(10, speed=1e-50), "speed: 1e-50 is too small for a 32-bit float and would read as 0"),
    (lambda: setattr(gas(), "gravity", (1e-50, 0)), "gravity: 1e-50 is too small"),
    (lambda: carom.World(box=(10, 10), boundary=None), "boundary: None; allowed: 'walls', 'periodic'"),
    (lambda: carom.World(box=(10, 10), max_travel=-1), "max_travel: -1; allowed: >= 0"),
    (lambda: carom.World(box=(10, 10), collisions="events", engine="opencl"),
     "collisions='events' runs on engine='cpu' only"),
    (lambda: carom.World(box=(10, 10), seed=2**64), "seed: 18446744073709551616 is out of range"),
    (lambda: setattr(gas(), "seed", -1), "seed: -1 is out of range"),
    (lambda: gas().exact_positions, "exact_positions: collisions='pairwise'; allowed: collisions='events'"),
    (lambda: gas().event_counts(), "event_counts: collisions='pairwise'"),
    (lambda: gas().set_disk(400, (1, 1), (0, 0), 1, 1), "setDisk: id 400 is not a disk; allowed: 0..399"),
    (lambda: gas().set_disk(0, (np.nan, 1), (0, 0), 1, 1), "positions[0, 0] = nan is not finite"),
    (lambda: gas().add_disks([[1, 1]], [[0, 0]], [1], [-1]), "radius must be a finite number > 0, got -1"),
    (lambda: gas().edit(velocities=np.zeros((3, 2))), "velocities: shape (3, 2); allowed: (400, 2)"),
    (lambda: gas().save_checkpoint("a.ckpt\0.txt"), "path: 'a.ckpt\\x00.txt'; allowed: a non-empty path without NUL"),
    (lambda: carom.World.from_checkpoint(carom.__file__), "__init__.py"),
    (lambda: carom.write_xyz("t.xyz", "world"), "world: str; allowed: a carom.World"),
    (lambda: carom.GSDWriter("t.gsd", mode="x"), "mode: 'x'; allowed: 'w', 'a'"),
    (lambda: gas().step(2.5), "n: 2.5 is not a whole number"),
    (lambda: gas().place(0), "count: 0 is out of range"),
    (lambda: carom.World((10, 10), gather="on_request"), "gather: 'on_request' without comm"),
    (lambda: carom.World.from_scene("no/such/scene.toml"), "no/such/scene.toml"),
    (lambda: carom.make_scene(particles=10, packing=0.95), "0.95"),
    (lambda: carom.World(box=("100", "100")), "box: '100' is not a number; allowed: a finite number"),
    (lambda: carom.World(box=(True, True)), "box: True is not a number"),
    (lambda: carom.World(box=(10, 10), dt=np.bool_(True)), "True_ is not a number"),
    (lambda: carom.World(box=(10, 10), gravity=(b"1", 0)), "gravity: b'1' is not a number"),
    (lambda: gas().place(10, radius="1"), "radius: '1' is not a number"),
    (lambda: carom.World(box=np.ma.masked_array([10, 10], mask=[0, 1])), "box[1] is masked"),
    (lambda: carom.write_state("empty.csv", carom.World(box=(10, 10))),
     "state file 'empty.csv': 0 disks; allowed: at least 1"),
    (lambda: carom.write_xyz("empty.xyz", carom.World(box=(10, 10))), "the world has no disks yet"),
]


@pytest.mark.parametrize("make, message", REFUSALS, ids=[m for _, m in REFUSALS])
def test_bad_arguments_are_refused_naming_the_value(make, message):
    with pytest.raises(carom.InputError) as error:
        make()
    assert message in str(error.value)
    assert isinstance(error.value, ValueError) and isinstance(error.value, carom.Error)


BAD_DISKS = [
    ({"masses": np.ma.masked_array([1, 2, 3], mask=[0, 0, 1])}, "masses[2] is masked; allowed: values only"),
    ({"positions": np.ma.masked_array([[2, 2], [5, 5], [8, 8]], mask=[[0, 0], [0, 1], [0, 0]])},
     "positions[1, 1] is masked"),
    ({"positions": np.zeros((3, 3))}, "positions: shape (3, 3); allowed: (N, 2)"),
    ({"velocities": np.zeros((2, 2))}, "velocities: shape (2, 2); allowed: (3, 2)"),
    ({"masses": np.ones((3, 1))}, "masses: shape (3, 1); allowed: (3,)"),
    ({"radii": np.array(["1", "1", "1"])}, "radii: arrays of <U1 are not numbers"),
    ({"masses": np.array([1, 2j, 1])}, "masses: arrays of complex128 are not numbers"),
    ({"velocities": [[0, 0], [np.inf, 0], [0, 0]]}, "velocities[1, 0] = inf is not finite"),
    ({"masses": [1, 1, np.nan]}, "masses[2] = nan is not finite"),
    ({"masses": [1, 1e39, 1]}, "masses[1]: 1e+39 is too large for a 32-bit float"),
    ({"radii": [1, 1, 1e-46]}, "radii[2]: 1e-46 is too small for a 32-bit float"),
    ({"radii": [1, 1, 1e-40]}, "particle 2: radius 9.99995e-41 is outside [1e-18, 1e+18]"),
    ({"masses": [1, -1, 1]}, "particle 1: mass must be a finite number > 0, got -1"),
    ({"positions": [[1, 1], [5, 5], [9.5, 5]]}, "particle 2: position (9.5, 5) puts the disk outside the box"),
    ({"positions": [[2, 2], [5, 5], [5, 5]]}, "particles 1 and 2 have the same centre (5, 5)"),
    ({"positions": [[2, 2], [5, 5], [6, 5]]}, "the deepest particles 1 and 2 by 1"),
]


@pytest.mark.parametrize("change, message", BAD_DISKS, ids=[m for _, m in BAD_DISKS])
def test_bad_disks_are_refused_naming_the_index_and_value(engine, change, message):
    disks = {"positions": [[2, 2], [5, 5], [8, 8]], "velocities": np.zeros((3, 2)), "masses": np.ones(3),
             "radii": np.ones(3)}
    disks.update(change)
    world = carom.World(box=(10, 10), engine=engine)
    world.set_disks(np.array([[2.0, 2.0]]), np.zeros((1, 2)), [1.0], [1.0])
    with pytest.raises(carom.InputError) as error:
        world.set_disks(**disks)
    assert message in str(error.value)
    assert len(world) == 1  # kept as it was


def test_masked_arrays_without_masked_values_are_taken():
    world = carom.World(box=(10, 10))
    world.set_disks(np.ma.masked_array([[2, 2], [6, 6]], mask=False), np.zeros((2, 2)), [1, 1], [1, 1])
    assert world.positions[1, 0] == 6.0


def test_images_unwrap_the_positions(engine, tmp_path):
    """world.images: int32 (N, 2), read-only; positions + images * box is the unwrapped centre. Kept by
    copies, pickles and checkpoints; edits keep them, added disks start at 0, set_disks restarts them."""
    import pickle

    world = carom.World(box=(20, 10), boundary="periodic", engine=engine, collisions="simultaneous")
    world.set_disks([[5, 5], [13, 5]], [[7, -2.6], [7, -2.6]], [1, 1], [0.5, 0.5])  # side by side, 8 apart
    world.step(1000)  # 10 time units: at (75, -21) and (83, -21)
    images = world.images
    assert images.dtype == np.int32 and images.shape == (2, 2) and not images.flags.writeable
    np.testing.assert_array_equal(images, [[3, -3], [4, -3]])
    unwrapped = world.positions + images * np.array(world.box)
    np.testing.assert_allclose(unwrapped, [[75, -21], [83, -21]], atol=1e-2)
    world.save_checkpoint(tmp_path / "w.ckpt")
    for twin in (world.copy(), pickle.loads(pickle.dumps(world)),
                 carom.World.from_checkpoint(tmp_path / "w.ckpt", engine=engine)):
        np.testing.assert_array_equal(twin.images, images)
    world.add_disks([[1, 1]], [[0, 0]], [1], [0.5])
    np.testing.assert_array_equal(world.images, [[3, -3], [4, -3], [0, 0]])
    world.set_disks([[5, 5]], [[1, 0]], [1], [0.5])
    np.testing.assert_array_equal(world.images, [[0, 0]])
    assert carom.World(box=(20, 10)).images.shape == (0, 2)


def test_pickle_keeps_scene_steps(scenes):
    import pickle

    world = carom.World.from_scene(scenes / "ideal_gas.toml")
    assert pickle.loads(pickle.dumps(world)).scene_steps == world.scene_steps


def test_paths_that_are_not_utf8(engine, tmp_path):
    """Names of bytes that are not UTF-8 (as os.fsdecode gives them) reach the files, and messages show
    their bytes as \\xNN."""
    world = carom.World(box=(20, 20), engine=engine, seed=1)
    world.place(10, radius=0.5)
    folder = bytes(tmp_path)
    for name in (os.fsdecode(folder + b"/caf\xe9.ckpt"), folder + b"/caf\xe9.ckpt"):
        world.save_checkpoint(name)
        assert carom.World.from_checkpoint(name, engine=engine).step_count == 0
    carom.write_state(os.fsdecode(folder + b"/caf\xe9.csv"), world)
    np.testing.assert_array_equal(carom.read_state(os.fsdecode(folder + b"/caf\xe9.csv")).positions,
                                  world.positions)
    carom.write_xyz(os.fsdecode(folder + b"/caf\xe9.xyz"), world)
    assert sorted(os.listdir(folder)) == [b"caf\xe9.ckpt", b"caf\xe9.csv", b"caf\xe9.xyz"]
    with pytest.raises(carom.InputError, match=re.escape("no-such-caf\\xe9.ckpt")):
        carom.World.from_checkpoint(os.fsdecode(folder + b"/no-such-caf\xe9.ckpt"))


def test_deep_overlaps_are_allowed_on_request_with_a_warning():
    world = carom.World(box=(10, 10))
    world.set_disks([[5, 5], [6, 5]], np.zeros((2, 2)), [1, 1], [1, 1], allow_overlaps=True)
    assert "particles 0 and 1 by 1" in world.warnings[0]


def test_coincident_disks_are_refused_in_seconds():
    """10^5 disks on one centre took 42 s to refuse (all pairs checked): the check sorts them."""
    world = carom.World(box=(1000, 1000))
    n = 100_000
    start = time.perf_counter()
    with pytest.raises(carom.InputError) as error:
        world.set_disks(np.full((n, 2), 500.0), np.zeros((n, 2)), np.ones(n), np.ones(n))
    assert time.perf_counter() - start < 5
    assert "particles 0 and 1 have the same centre (500, 500)" in str(error.value)
    assert f"{n * (n - 1) // 2} such pair(s)" in str(error.value)


def test_auto_engine_follows_the_command_lines_rule():
    """engine="auto" is carom::chooseEngine's choice, as `carom run --backend auto`'s: OpenCL on a GPU (a
    doctest), else the CPU, as on this machine, which has no GPU; a device asks for OpenCL, events for the CPU."""
    choice = carom.choose_engine()
    assert choice["engine"] == "cpu" and choice["device"] is None and choice["pipeline"] is None
    assert choice["reason"].startswith(("no OpenCL", "this carom was built without OpenCL"))
    assert carom.World(box=(10, 10), engine="auto").engine == "cpu"
    assert carom.World(box=(10, 10), engine="auto", collisions="events").engine == "cpu"
    if carom.devices():
        assert carom.World(box=(10, 10), engine="auto", device=0).engine == "opencl"


def test_any_float_dtype_is_taken():
    for dtype in (np.float16, np.float32, np.float64, np.int32):
        world = carom.World(box=(10, 10))
        world.set_disks(np.array([[2, 2], [6, 6]], dtype=dtype), np.zeros((2, 2), dtype=dtype),
                        np.ones(2, dtype=dtype), np.ones(2, dtype=dtype))
        assert world.positions[1, 0] == 6.0


def test_a_failed_step_names_the_step_and_keeps_the_world(engine):
    world = carom.World(box=(100, 100), gravity=(0, -1e15), dt=1.0, max_travel=0.5, engine=engine)
    world.set_disks([[50, 50], [20, 20]], [[1, 0], [0, 1]], [1, 1], [1, 1])
    with pytest.raises(carom.InputError, match="would need .* substeps"):
        world.step(10)
    assert world.step_count == 0  # the step it reached


def test_an_edit_keeps_the_clock_and_a_view_follows_it(engine):
    world = gas(engine=engine)
    world.step(10)
    collisions, doubled = world.collisions, 2 * world.velocities
    view = world.velocities
    world.edit(velocities=doubled)
    assert world.step_count == 10 and world.time == pytest.approx(0.1) and world.collisions == collisions
    assert np.array_equal(world.velocities, doubled)
    if engine != "cpu":
        return  # OpenCL hands out copies
    assert np.shares_memory(view, world.velocities)  # the same memory, rewritten
    assert np.array_equal(view, world.velocities)
    replacement = carom.World(box=(60, 60), boundary="periodic", seed=12)
    replacement.place(400, radius=(0.5, 1.0), speed=1.5)
    world.set_disks(replacement.positions, replacement.velocities, replacement.masses, replacement.radii)
    assert np.shares_memory(view, world.velocities) and np.array_equal(view, replacement.velocities)


def test_a_scene_with_max_travel_runs_as_the_command_line_runs_it(carom_exe, tmp_path):
    scene = tmp_path / "travel.toml"
    scene.write_text('box = [200.0, 200.0]\ndt = "auto"\nsteps = 40\nseed = 3\n'
                     '[[group]]\ncount = 30\nradius = 3.0\nspeed = 5.0\n'
                     '[[group]]\ncount = 200\nradius = 0.2\nspeed = 5.0\n')
    summary, final = run_cli(carom_exe, ["--scene", str(scene), "--backend", "cpu"], tmp_path)
    world = carom.World.from_scene(scene)
    world.step(world.scene_steps)
    assert world.measurements()["substeps"] == summary["substeps"] > 40
    assert_same_as_cli(world, summary, final)


def test_devices_and_version():
    assert carom.__version__.count(".") == 2
    for device in carom.devices():
        assert {"index", "name", "type", "bitwise_reproducible"} <= device.keys()
    assert carom.engines()[0] == "cpu"


def test_a_signal_stops_a_long_step_between_two_steps():
    import signal

    class Stop(Exception):
        pass

    def stop(*_):
        raise Stop

    world = gas(particles=100)
    previous = signal.signal(signal.SIGALRM, stop)
    signal.setitimer(signal.ITIMER_REAL, 0.3)
    try:
        with pytest.raises(Stop):
            world.step(10**7)  # minutes of steps, were the signal not seen
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
    assert 0 < world.step_count < 10**7
    assert world.time == pytest.approx(world.step_count * world.dt)
    world.step(1)  # the world goes on from the step it reached
