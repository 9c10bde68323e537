"""GSD trajectories in HOOMD-blue's schema, written with the ``gsd`` package."""

import os

import gsd.hoomd
import numpy as np

from ._carom import Error, InputError
from ._world import World, _path


class GSDWriter:
    """Writes a world's state, one frame per :meth:`write`, to a GSD file in
    HOOMD-blue's schema (``gsd.hoomd``), which HOOMD, OVITO and freud read.

    ``mode`` is ``"w"`` (create, or truncate an existing file) or ``"a"``
    (append to an existing GSD file, keeping its frames, or create it).
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
    - ``particles/image`` (N, 3) int32, periodic boxes only: ALWAYS ZERO.
      carom wraps positions into the box and does not count the box lengths
      a disk has crossed, so the true images are unknown; the positions of a
      periodic box are wrapped and cannot be unwrapped from this file. (The
      ``gsd`` package does not store a chunk equal to its default, so the
      file has no ``particles/image`` chunk; readers get zeros either way.)
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
        self._trajectory = gsd.hoomd.open(path, mode)

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

        frame = gsd.hoomd.Frame()
        frame.configuration.step = int(world.step_count)
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
            frame.particles.image = np.zeros((n, 3), np.int32)
        frame.log["carom/time"] = np.array([world.time], np.float64)
        frame.log["carom/kinetic_energy"] = np.array([world.kinetic_energy], np.float64)

        self._trajectory.append(frame)
        self._trajectory.flush()

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

