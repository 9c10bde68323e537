"""carom.GSDWriter: frames in HOOMD's GSD schema, read back with gsd.hoomd."""

import os
import re

import gsd.fl
import gsd.hoomd
import numpy as np
import pytest

import carom

BOX = (20.0, 16.0)


def make_world(engine, boundary="walls", count=12):
    world = carom.World(box=BOX, boundary=boundary, engine=engine, seed=3)
    world.place(count, radius=0.5, speed=2.0)
    return world


def snapshot(world):
    """Copies of what a frame holds (views of the CPU engine change as it steps)."""
    return dict(
        step=world.step_count,
        time=world.time,
        kinetic_energy=world.kinetic_energy,
        positions=np.array(world.positions),
        velocities=np.array(world.velocities),
        masses=np.array(world.masses),
        radii=np.array(world.radii),
    )


def chunk_names(path, frame):
    with gsd.fl.open(path, "r") as f:
        return {name for name in f.find_matching_chunk_names("") if f.chunk_exists(frame, name)}


@pytest.mark.parametrize("boundary", ["walls", "periodic"])
def test_round_trip(engine, boundary, tmp_path):
    path = tmp_path / "t.gsd"
    world = make_world(engine, boundary)
    expected = []
    with carom.GSDWriter(path) as writer:
        for steps in (0, 5, 40):
            if steps:
                world.step(steps)
            writer.write(world)
            expected.append(snapshot(world))

    with gsd.hoomd.open(path, "r") as traj:
        assert len(traj) == 3
        for frame, want in zip(traj, expected):
            n = len(want["radii"])
            assert frame.configuration.step == want["step"]
            np.testing.assert_array_equal(frame.configuration.box, [*BOX, 0, 0, 0, 0])
            assert frame.configuration.dimensions == 2
            assert frame.particles.N == n
            pos = frame.particles.position
            assert pos.dtype == np.float32 and pos.shape == (n, 3)
            np.testing.assert_array_equal(pos[:, 2], 0)
            assert np.all(np.abs(pos[:, :2]) <= np.array(BOX) / 2)
            np.testing.assert_allclose(pos[:, :2] + np.array(BOX) / 2, want["positions"], rtol=0, atol=1e-5)
            np.testing.assert_array_equal(frame.particles.velocity[:, :2], want["velocities"])
            np.testing.assert_array_equal(frame.particles.velocity[:, 2], 0)
            np.testing.assert_array_equal(frame.particles.mass, want["masses"])
            np.testing.assert_array_equal(frame.particles.diameter, 2 * want["radii"])
            np.testing.assert_array_equal(frame.particles.typeid, np.zeros(n))
            assert frame.particles.types == ["A"]
            assert frame.log["carom/time"][0] == want["time"]
            assert frame.log["carom/kinetic_energy"][0] == want["kinetic_energy"]
    assert expected[-1]["step"] == 45


def test_image_periodic_only(engine, tmp_path):
    """A periodic frame holds the world's images, which unwrap its positions;
    a walls frame has none (gsd stores no chunk, readers get zeros)."""
    path = tmp_path / "periodic.gsd"
    world = make_world(engine, "periodic")
    with carom.GSDWriter(path) as writer:
        for _ in range(30):
            writer.write(world)
            world.step(10)  # 0.1 time units at speed ~2: far less than half a box
    with gsd.hoomd.open(path, "r") as traj:
        image = traj[-1].particles.image
        assert image.shape == (len(world), 3) and image.dtype == np.int32
        np.testing.assert_array_equal(image[:, 2], 0)
        assert image.any()  # 3 time units at speed 2 in a box 20 x 16: some disks crossed
        box = np.array([*BOX, 0])
        unwrapped = [f.particles.position + f.particles.image * box for f in traj]
        for before, after in zip(unwrapped, unwrapped[1:]):
            assert (np.abs(after - before) < 1).all()

    path = tmp_path / "walls.gsd"
    world = make_world(engine, "walls")
    world.step(20)
    with carom.GSDWriter(path) as writer:
        writer.write(world)
    with gsd.hoomd.open(path, "r") as traj:
        assert not traj[0].particles.image.any()
    assert "particles/image" not in chunk_names(path, 0)


def test_a_frame_must_continue_the_file(engine, tmp_path):
    """A frame of earlier steps, another box or another number of disks is refused, in "a" mode against
    the file's last frame and in either mode against the frame written before; nothing is written."""
    path = tmp_path / "c.gsd"
    world = make_world(engine)
    world.step(5)
    with carom.GSDWriter(path) as writer:
        writer.write(world)
        with pytest.raises(carom.InputError, match="its last frame is at step 5, after the world's step 0"):
            writer.write(make_world(engine))
    wider = carom.World(box=(30, 16), engine=engine)
    wider.place(12, radius=0.5)
    more = make_world(engine, count=13)
    wider.step(5)
    more.step(5)
    for other, message in ((make_world(engine), "its last frame is at step 5, after the world's step 0"),
                           (wider, "its last frame's box is 20 x 16, the world's 30 x 16"),
                           (more, "its last frame has 12 disks, the world 13")):
        with carom.GSDWriter(path, mode="a") as writer:
            with pytest.raises(carom.InputError, match=re.escape(f"cannot append to {str(path)!r}: {message}")):
                writer.write(other)
    with gsd.hoomd.open(path, "r") as traj:
        assert len(traj) == 1


def test_append_keeps_frames(engine, tmp_path):
    path = tmp_path / "a.gsd"
    world = make_world(engine)
    with carom.GSDWriter(path, mode="w") as writer:
        writer.write(world)
        world.step(3)
        writer.write(world)
    world.step(4)
    with carom.GSDWriter(path, mode="a") as writer:
        writer.write(world)
    with gsd.hoomd.open(path, "r") as traj:
        assert [f.configuration.step for f in traj] == [0, 3, 7]
    with carom.GSDWriter(path, mode="w") as writer:  # "w" truncates
        writer.write(world)
    with gsd.hoomd.open(path, "r") as traj:
        assert len(traj) == 1


def test_frames_flushed_before_close(engine, tmp_path):
    path = tmp_path / "f.gsd"
    world = make_world(engine)
    writer = carom.GSDWriter(path)
    writer.write(world)
    world.step(2)
    writer.write(world)
    with gsd.hoomd.open(path, "r") as traj:
        assert len(traj) == 2
    writer.close()


def test_close_is_idempotent_and_final(engine, tmp_path):
    world = make_world(engine)
    writer = carom.GSDWriter(tmp_path / "c.gsd")
    writer.close()
    writer.close()
    with pytest.raises(carom.Error, match="closed"):
        writer.write(world)


@pytest.mark.parametrize("mode", ["r", "x", "r+", "wb", ""])
def test_refuses_mode(mode, tmp_path):
    with pytest.raises(carom.InputError, match=re.escape(f"mode: '{mode}'; allowed: 'w', 'a'")):
        carom.GSDWriter(tmp_path / "m.gsd", mode=mode)
    assert not (tmp_path / "m.gsd").exists()


def test_a_path_that_is_not_utf8(engine, tmp_path):
    """A name of bytes that are not UTF-8 (as os.fsdecode gives them) is written under those bytes."""
    name = os.fsdecode(bytes(tmp_path) + b"/caf\xe9.gsd")
    world = make_world(engine)
    with carom.GSDWriter(name) as writer:
        writer.write(world)
    world.step(1)
    with carom.GSDWriter(name, mode="a") as writer:
        writer.write(world)
    assert os.listdir(bytes(tmp_path)) == [b"caf\xe9.gsd"]
    os.symlink(name, tmp_path / "link.gsd")
    with gsd.hoomd.open(tmp_path / "link.gsd", "r") as traj:
        assert [f.configuration.step for f in traj] == [0, 1]


def test_refuses_directory_and_missing_folder(tmp_path):
    with pytest.raises(carom.InputError, match="is a directory") as info:
        carom.GSDWriter(tmp_path)
    assert str(tmp_path) in str(info.value)
    missing = tmp_path / "nowhere" / "t.gsd"
    with pytest.raises(carom.InputError, match="does not exist") as info:
        carom.GSDWriter(missing, mode="a")
    assert str(tmp_path / "nowhere") in str(info.value)


def test_refuses_world_without_disks(engine, tmp_path):
    path = tmp_path / "e.gsd"
    with carom.GSDWriter(path) as writer:
        with pytest.raises(carom.InputError, match="0 disks"):
            writer.write(carom.World(box=BOX, engine=engine))
        writer.write(make_world(engine))  # the refusal wrote nothing
    with gsd.hoomd.open(path, "r") as traj:
        assert len(traj) == 1
