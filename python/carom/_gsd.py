"""GSD trajectories in HOOMD-blue's schema, written with the ``gsd`` package."""

import os
import tempfile

import gsd.hoomd
import numpy as np

from ._carom import Error, InputError
from ._world import World, _path


class GSDWriter:
    """Writes a world's state, one frame per :meth:`write`, to a GSD file in
    HOOMD-blue's schema (``gsd.hoomd``), which HOOMD, OVITO and freud read.

    ``mode`` is ``"w"`` (create, or truncate an existing file) or ``"a"``
    (append to an existing GSD file, keeping its frames, or create it).
    Every frame continues the one before it, in the file or written: the
    same number of disks and box, and a step not before its step; a write
    that does not raises :class:`carom.InputError` and writes nothing.
    A ``mode`` other than these, or a ``path`` that is a directory or whose
    folder does not exist, raises :class:`carom.InputError`; a file that
    cannot be opened for another reason raises the ``OSError`` (or, for an
    existing file that is not GSD in ``"a"`` mode, the ``RuntimeError``) of
    the ``gsd`` package.

    Use it as a context manager, or call :meth:`close` (idempotent); a write
    after closing raises :class:`carom.Error`. Each frame is flushed to disk
    when written, so a crash later keeps the frames written before it.

    Each frame holds, in carom's units (length, time, mass of the world):

    - ``configuration/step``: ``world.step_count``;
    - ``configuration/box``: ``[W, H, 0, 0, 0, 0]`` (Lz = 0) and
      ``configuration/dimensions`` = 2;
    - ``particles/N``; ``particles/position`` (N, 3) float32 with z = 0.
      carom's box is [0, W] x [0, H] and HOOMD's is centred on the origin,
      so the positions are shifted: (x - W/2, y - H/2, 0) [length];
    - ``particles/velocity`` (N, 3) float32 with z = 0 [length/time];
    - ``particles/mass`` [mass]; ``particles/diameter`` = 2 x radius [length];
    - ``particles/typeid`` (all 0) and ``particles/types`` = ``["A"]``;
    - ``particles/image`` (N, 3) int32, periodic boxes only: ``world.images``
      with z = 0, the box lengths each disk has crossed, so that
      ``position + image * (W, H, 0)`` is its unwrapped position (freud's
      ``MSD`` takes them). (The ``gsd`` package does not store a chunk equal
      to its default: a frame whose images are all 0 has no chunk, and
      readers get zeros.)
    - ``log/carom/time`` (simulated time [time], float64) and
      ``log/carom/kinetic_energy`` ([mass length^2/time^2], float64).
    """

    def __init__(self, path, mode="w"):
        if mode not in ("w", "a"):
            raise InputError(f"mode: {mode!r}; allowed: 'w', 'a'")
        path = _path("path", path)
        if os.path.isdir(path):
            raise InputError(f"path: {path!r} is a directory; allowed: a file's path")
        folder = os.path.dirname(os.path.abspath(path))
        if not os.path.isdir(folder):
            raise InputError(f"path: {path!r}: the folder {folder!r} does not exist; allowed: a path in an existing folder")
        self.path = path
        self._trajectory = _open(path, mode)
        # (step, N, box) of the last frame, which the next one must continue.
        self._last = None
        if len(self._trajectory) > 0:
            frame = self._trajectory[-1]
            self._last = (int(frame.configuration.step), int(frame.particles.N),
                          tuple(float(v) for v in frame.configuration.box[:2]))

    def write(self, world):
        """Appends one frame holding ``world``'s current state (see the class).

        Raises :class:`carom.InputError` for a world without disks and
        :class:`carom.Error` after :meth:`close`. Every field is read from the
        world before the file is touched, so a failed read writes nothing.
        """
        if self._trajectory is None:
            raise Error(f"GSDWriter({self.path!r}) is closed; open a new GSDWriter to write")
        if not isinstance(world, World):
            raise InputError(f"world: {type(world).__name__}; allowed: a carom.World")
        n = len(world.radii)
        if n == 0:
            raise InputError("world: 0 disks; allowed: a world with disks (set_disks or place first)")
        width, height = (float(v) for v in world.box)
        step = int(world.step_count)
        self._require_continues(step, n, (width, height))

        frame = gsd.hoomd.Frame()
        frame.configuration.step = step
        frame.configuration.box = [width, height, 0, 0, 0, 0]
        frame.configuration.dimensions = 2
        frame.particles.N = n
        position = np.zeros((n, 3), np.float32)
        position[:, :2] = np.asarray(world.positions, np.float64) - (width / 2, height / 2)
        frame.particles.position = position
        velocity = np.zeros((n, 3), np.float32)
        velocity[:, :2] = world.velocities
        frame.particles.velocity = velocity
        frame.particles.mass = np.array(world.masses, np.float32)
        frame.particles.diameter = 2 * np.array(world.radii, np.float32)
        frame.particles.typeid = np.zeros(n, np.uint32)
        frame.particles.types = ["A"]
        if world.boundary == "periodic":
            image = np.zeros((n, 3), np.int32)
            image[:, :2] = world.images
            frame.particles.image = image
        frame.log["carom/time"] = np.array([world.time], np.float64)
        frame.log["carom/kinetic_energy"] = np.array([world.kinetic_energy], np.float64)

        self._trajectory.append(frame)
        self._trajectory.flush()
        self._last = (step, n, (width, height))

    def _require_continues(self, step, n, box):
        if self._last is None:
            return
        last_step, last_n, last_box = self._last
        problem = None
        if n != last_n:
            problem = f"its last frame has {last_n} disks, the world {n}"
        elif box != last_box:
            problem = (f"its last frame's box is {last_box[0]:g} x {last_box[1]:g}, the world's "
                       f"{box[0]:g} x {box[1]:g}")
        elif step < last_step:
            problem = f"its last frame is at step {last_step}, after the world's step {step}"
        if problem:
            raise InputError(f"cannot append to {self.path!r}: {problem}; allowed: a frame that continues it "
                             "(the same disks and box, a step not before its last); write to another file")

    def close(self):
        """Closes the file; closing again does nothing."""
        if self._trajectory is not None:
            self._trajectory.close()
            self._trajectory = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __repr__(self):
        state = "closed" if self._trajectory is None else f"{len(self._trajectory)} frames"
        return f"GSDWriter({self.path!r}, {state})"


def _open(path, mode):
    """gsd.hoomd.open for any path: the gsd package encodes names as UTF-8, so
    one that UTF-8 cannot spell (bytes that are not UTF-8, as os.fsdecode
    gives them) is opened through a symlink in a private folder, removed once
    the file is open."""
    try:
        path.encode("utf-8")
        return gsd.hoomd.open(path, mode)
    except UnicodeEncodeError:
        pass
    with tempfile.TemporaryDirectory() as folder:
        link = os.path.join(folder, "trajectory.gsd")
        os.symlink(os.path.abspath(os.fsencode(path)), os.fsencode(link))
        return gsd.hoomd.open(link, mode)
