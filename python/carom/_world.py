"""carom.World: a box of disks, stepped by carom's C++ engine (carom._carom)."""
from __future__ import annotations

import operator
import os
import secrets
import tempfile
import threading
import warnings
from typing import NamedTuple, Optional, Sequence, Tuple, Union

import numpy as np

from . import _carom
from ._carom import InputError

Pair = Tuple[float, float]
Range = Union[float, Tuple[float, float]]

_FLOAT32_MAX = float(np.finfo(np.float32).max)
_PIPELINES = {"host-grid": "opencl-host-grid", "resident": "opencl-resident"}


class OwnDisks(NamedTuple):
    """The disks one process steps (World.own_disks), in id order: ids uint32 (n,), positions and velocities
    float32 (n, 2), masses and radii float32 (n,), images int32 (n, 2)."""
    ids: np.ndarray
    positions: np.ndarray
    velocities: np.ndarray
    masses: np.ndarray
    radii: np.ndarray
    images: np.ndarray


class _Serialized:
    """A _carom.World whose calls take turns, one thread at a time: its step
    releases the GIL, and another thread's call waits for the step to end
    rather than read or change the world in the middle of it."""

    __slots__ = ("core", "lock")

    def __init__(self, core: "_carom.World"):
        self.core = core
        self.lock = threading.Lock()

    def __getattr__(self, name: str):
        with self.lock:
            value = getattr(self.core, name)
        if not callable(value):
            return value

        def serialized(*args, **kwargs):
            with self.lock:
                return value(*args, **kwargs)

        return serialized


def _unmasked(name: str, value) -> None:
    """Refuses a masked array with masked values, naming the first: np.asarray would drop the mask."""
    if np.ma.is_masked(value):
        mask = np.ma.getmaskarray(value)
        where = ", ".join(str(int(i)) for i in np.unravel_index(int(np.argmax(mask)), mask.shape))
        raise InputError(f"{name}{f'[{where}]' if where else ''} is masked; allowed: values only (fill the "
                         "masked ones first: .filled(value))")


def _real_array(name: str, value, shape: tuple) -> np.ndarray:
    """`value` as a C-contiguous float32 array of `shape` (-1: any length),
    refusing what float32 cannot hold, with the index and the value."""
    _unmasked(name, value)
    array = np.asarray(value)
    if array.dtype.kind not in "fiu":
        raise InputError(f"{name}: arrays of {array.dtype} are not numbers; allowed: float or integer arrays")
    if array.ndim != len(shape) or any(want not in (-1, got) for want, got in zip(shape, array.shape)):
        wanted = "(" + ", ".join("N" if d == -1 else str(d) for d in shape) + ("," if len(shape) == 1 else "") + ")"
        raise InputError(f"{name}: shape {array.shape}; allowed: {wanted}")
    wide = array.astype(np.float64, copy=False)
    bad = ~np.isfinite(wide)
    if bad.any():
        index = np.unravel_index(int(np.argmax(bad)), bad.shape)
        raise InputError(f"{name}[{_where(index)}] = {array[index].item()!r} is not finite; allowed: finite float32 numbers")
    with np.errstate(over="ignore"):  # refused below, by name
        narrow = np.ascontiguousarray(wide, dtype=np.float32)
    changed = ((narrow == 0) & (wide != 0)) | np.isinf(narrow)
    if changed.any():  # _carom.to_float refuses it, naming why
        index = np.unravel_index(int(np.argmax(changed)), changed.shape)
        _carom.to_float(f"{name}[{_where(index)}]", float(wide[index]))
    return narrow


def _where(index: tuple) -> str:
    return ", ".join(str(int(i)) for i in index)


def _disk_arrays(positions, velocities, masses, radii):
    positions = _real_array("positions", positions, (-1, 2))
    n = len(positions)
    return (positions, _real_array("velocities", velocities, (n, 2)),
            _real_array("masses", masses, (n,)), _real_array("radii", radii, (n,)))


def _number(name: str, value) -> float:
    """A finite number that float32 holds (the engine's precision), refused naming the value otherwise.
    Text and booleans are not numbers, though float() reads them."""
    _unmasked(name, value)
    if isinstance(value, (str, bytes, bool, np.bool_)):
        raise InputError(f"{name}: {value!r} is not a number; allowed: a finite number")
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name}: {value!r} is not a number; allowed: a finite number") from None
    return _finite(name, value, _carom.to_float(name, number))


def _finite(name: str, value, number: float) -> float:
    if not (abs(number) <= _FLOAT32_MAX):
        raise InputError(f"{name}: {value!r} is not finite; allowed: finite numbers within +-{_FLOAT32_MAX:.4g}")
    return number


def _range(name: str, value: Range) -> Pair:
    """A value, or (min, max) of a uniform draw."""
    if np.ndim(value) == 0:
        number = _number(name, value)
        return number, number
    low, high = _pair(name, value)
    if low > high:
        raise InputError(f"{name}: ({low:g}, {high:g}); allowed: (min, max) with min <= max")
    return low, high


def _pair(name: str, value) -> Pair:
    _unmasked(name, value)
    try:
        x, y = value
    except (TypeError, ValueError):
        raise InputError(f"{name}: {value!r} is not a pair of numbers; allowed: (x, y)") from None
    return _number(name, x), _number(name, y)


def _whole(name: str, value, minimum: int = 0, maximum: int = 2**64 - 1) -> int:
    allowed = f"allowed: whole numbers from {minimum} to {maximum}"
    if isinstance(value, bool):
        raise InputError(f"{name}: {value!r} is not a whole number; {allowed}")
    try:
        number = operator.index(value)
    except TypeError:
        raise InputError(f"{name}: {value!r} is not a whole number; {allowed}") from None
    if not minimum <= number <= maximum:
        raise InputError(f"{name}: {number} is out of range; {allowed}")
    return number


def _choice(name: str, value, allowed: Sequence[str]) -> str:
    if value not in allowed:
        raise InputError(f"{name}: {value!r}; allowed: " + ", ".join(repr(a) for a in allowed))
    return value


def _path(name: str, value) -> str:
    try:
        path = os.fspath(value)
    except TypeError:
        raise InputError(f"{name}: {value!r} is not a path; allowed: str or os.PathLike") from None
    if isinstance(path, bytes):
        path = os.fsdecode(path)
    if "\0" in path or path == "":
        raise InputError(f"{name}: {path!r}; allowed: a non-empty path without NUL characters")
    return path


def _split(comm, domains, gather: str) -> Tuple[Optional[int], Tuple[int, int], str]:
    """The Fortran handle of the mpi4py communicator `comm` (None: none), the domains across and up, and `gather`."""
    _choice("gather", gather, ("each_step", "on_request"))
    if comm is None:
        if domains is not None:
            raise InputError(f"domains: {domains!r} without comm; allowed: None, or domains with a communicator")
        if gather != "each_step":
            raise InputError(f"gather: {gather!r} without comm; allowed: 'each_step', or 'on_request' with a "
                             "communicator")
        return None, (0, 0), gather
    if not callable(getattr(comm, "py2f", None)) or not callable(getattr(comm, "Get_size", None)):
        raise InputError(f"comm: {comm!r}; allowed: an mpi4py communicator (such as mpi4py.MPI.COMM_WORLD) or None")
    if not _carom.HAVE_MPI:
        raise InputError("comm: this carom was built without MPI; allowed: None (docs/mpi.md says how to build "
                         "with it)")
    if domains is None:
        return comm.py2f(), (0, 0), gather
    _unmasked("domains", domains)
    try:
        across, up = domains
    except (TypeError, ValueError):
        raise InputError(f"domains: {domains!r} is not a pair of whole numbers; allowed: (across, up), "
                         "whose product is comm's number of processes") from None
    size = comm.Get_size()
    return comm.py2f(), (_whole("domains", across, 1, size), _whole("domains", up, 1, size)), gather


def _engine_name(engine: str, device, pipeline: Optional[str], cpu_only: bool = False) -> Tuple[str, str]:
    """The C++ engine name and device selector for `engine`, `device` and `pipeline` (and, for engine="auto",
    whether the world asks for what only the CPU has: the events scheme, a skin)."""
    _choice("engine", engine, ("auto", "cpu", "opencl"))
    if device is not None and (isinstance(device, bool) or not isinstance(device, (int, str))):
        raise InputError(f"device: {device!r}; allowed: an index of carom.devices(), part of a name, or None")
    selector = "" if device is None else str(device)
    if engine == "auto":
        if device is not None or pipeline is not None:  # they ask for OpenCL, as on the command line
            engine = "opencl"
        elif cpu_only:
            return "cpu", ""
        else:
            name, selector, _ = _carom.choose_engine()
            return name, selector
    if engine == "cpu":
        if device is not None or pipeline is not None:
            raise InputError("device and pipeline: OpenCL only; allowed with engine='opencl'")
        return "cpu", ""
    if pipeline == "seed":  # host-grid's former name
        warnings.warn("pipeline='seed' is now called pipeline='host-grid'; the old name still works, for now",
                      FutureWarning, stacklevel=3)
        pipeline = "host-grid"
    if pipeline is None:  # as the command line's --pipeline auto
        return _carom.opencl_engine_for(selector), selector
    return _PIPELINES[_choice("pipeline", pipeline, ("host-grid", "resident", None))], selector


class World:
    """A box of disks that steps forward in time: carom's C++ engine.

    Units are yours (length, mass, time); the box is [0, W] x [0, H].

    box: (W, H), the box's sides [length].
    boundary: "walls" (reflecting) or "periodic".
    dt: the time step [time].
    gravity: (gx, gy) [length/time^2].
    collisions: "pairwise" (default: binary elastic collisions at their exact
        times, energy conserved to rounding), "simultaneous" (the seed's
        scheme, heats dense gases) or "events" (exact event-driven dynamics in
        double, CPU only; dt only says when to sample).
    engine: "cpu" (OpenMP), "opencl", or "auto": OpenCL on the first GPU,
        else the CPU (faster than OpenCL on CPU devices such as PoCL), as
        carom.choose_engine() says; a device or pipeline asks for OpenCL,
        collisions="events" for the CPU.
    device: OpenCL only, an index of carom.devices() or part of a device name;
        None: the first GPU, else the first device.
    pipeline: OpenCL only, "host-grid" (the host builds the grid, best on CPU
        devices) or "resident" (state and grid stay on the device, best on
        GPUs); None: resident on a GPU, host-grid otherwise. Both give the
        same bits. "seed", host-grid's former name, still works with a
        FutureWarning.
    max_travel: > 0 splits each step so no disk moves more than this fraction
        of the smallest radius per substep; 0 = off.
    skin: the CPU engine's neighbour lists (pairwise scheme): each disk lists
        the disks within contact plus this distance, again once the disks
        have moved about half of it; 0 = automatic (about the largest radius),
        else at most 8 largest radii. Changes the speed, never a result.
    seed: the random seed of place(); None draws one from the OS, kept in
        world.seed so that the run can be repeated (with comm, process 0's).
    comm: an mpi4py communicator (run under mpirun): the world is split into
        rectangular domains, one per process, and every process steps its
        own; the results are bit for bit those of one process. Every process
        makes the same world and calls step and the edits in the same order;
        after each step every process holds the whole world, so the reads
        (disks, observables, measurements) are the whole world's. The
        pairwise or simultaneous scheme; engine="auto" chooses the CPU;
        docs/mpi.md.
    domains: with comm, (across, up), whose product is the number of
        processes; None: as square as the box allows.
    gather: with comm, when every process receives the whole world:
        "each_step" (after every step call), or "on_request": only at
        gather(), so that a process that reads its own disks between steps
        (own_disks()) pays nothing for the others'; the whole world's reads
        and the edits raise carom.Error until every process calls gather().

    Every refusal of bad input raises carom.InputError (a ValueError) naming
    the value and what is allowed. A World is not thread-safe.
    """

    def __init__(self, box: Sequence[float], boundary: str = "walls", dt: float = 0.01,
                 gravity: Sequence[float] = (0.0, 0.0), collisions: str = "pairwise", engine: str = "cpu",
                 device: Union[int, str, None] = None, pipeline: Optional[str] = None, max_travel: float = 0.0,
                 skin: float = 0.0, seed: Optional[int] = None, comm=None,
                 domains: Optional[Tuple[int, int]] = None, gather: str = "each_step"):
        width, height = _pair("box", box)
        _choice("boundary", boundary, ("walls", "periodic"))
        _choice("collisions", collisions, ("pairwise", "simultaneous", "events"))
        if collisions == "events" and engine == "opencl":
            raise InputError(f"collisions='events' runs on engine='cpu' only (one thread, in double); got engine={engine!r}")
        if collisions == "events" and comm is not None:
            raise InputError("collisions='events' runs in one process; allowed with comm: 'pairwise', 'simultaneous'")
        skin = _number("skin", skin)
        # engine="auto" with comm: the CPU, on which the processes step their domains.
        engine_name, selector = _engine_name(engine, device, pipeline,
                                             collisions == "events" or skin > 0 or comm is not None)
        travel = _number("max_travel", max_travel)
        if not travel >= 0:
            raise InputError(f"max_travel: {max_travel!r}; allowed: >= 0 (0 = off)")
        handle, split, gather = _split(comm, domains, gather)
        core = _carom.World(width, height, _number("dt", dt), _pair("gravity", gravity), boundary, collisions,
                            engine_name, selector, travel, skin, handle, split, gather)
        if seed is None and comm is not None:  # place() must draw the same disks on every process
            seed = comm.bcast(secrets.randbits(63), root=0)
        self._adopt(core, selector, seed)

    def _adopt(self, core: "_carom.World", device: str, seed: Optional[int]) -> None:
        self._core = _Serialized(core)
        self._device = device  # the selector asked for, which a copy asks for again
        self.seed = secrets.randbits(63) if seed is None else seed
        self._ids = np.zeros(0, dtype=np.uint32)

    @property
    def seed(self) -> int:
        """The random seed of place(), 0 <= seed < 2**64; settable."""
        return self._seed

    @seed.setter
    def seed(self, value: int) -> None:
        self._seed = _whole("seed", value)

    @classmethod
    def _from_core(cls, core: "_carom.World", device: str, seed: Optional[int] = None) -> "World":
        world = cls.__new__(cls)
        world._adopt(core, device, seed)
        return world

    # Copies (a snapshot, World::restore) and pickles (a checkpoint in memory)
    # continue bit for bit on the same engine; their measurements' interval restarts.

    def __getstate__(self) -> dict:
        core = self._core
        state = {"engine": core.engine, "device": self._device, "max_travel": core.max_travel, "skin": core.skin,
                 "seed": self.seed,
                 "world": (core.width, core.height, core.dt, tuple(core.gravity), core.boundary,
                           core.collision_scheme)}
        if hasattr(self, "scene_steps"):
            state["scene_steps"] = self.scene_steps
        if core.disk_count > 0:
            with tempfile.TemporaryDirectory() as folder:
                path = os.path.join(folder, "world.ckpt")
                core.save_checkpoint(path)
                with open(path, "rb") as file:
                    state["checkpoint"] = file.read()
        return state

    def __setstate__(self, state: dict) -> None:
        if "checkpoint" not in state:
            width, height, dt, gravity, boundary, collisions = state["world"]
            core = _carom.World(width, height, dt, gravity, boundary, collisions, state["engine"], state["device"],
                                state["max_travel"], state.get("skin", 0.0))
        else:
            with tempfile.TemporaryDirectory() as folder:
                path = os.path.join(folder, "world.ckpt")
                with open(path, "wb") as file:
                    file.write(state["checkpoint"])
                core = _carom.World.from_checkpoint(path, state["engine"], state["device"], state["max_travel"],
                                                    state.get("skin", 0.0))
        self._adopt(core, state["device"], state["seed"])
        if "scene_steps" in state:
            self.scene_steps = state["scene_steps"]

    def copy(self) -> "World":
        """An independent world in the same state, on the same engine: both continue bit for bit alike."""
        duplicate = type(self)._from_core(self._core.copy(), self._device, self.seed)
        if hasattr(self, "scene_steps"):
            duplicate.scene_steps = self.scene_steps
        return duplicate

    __copy__ = copy

    def __deepcopy__(self, memo) -> "World":
        return self.copy()

    @classmethod
    def from_scene(cls, path: Union[str, os.PathLike], engine: str = "cpu", device: Union[int, str, None] = None,
                   pipeline: Optional[str] = None, max_travel: Optional[float] = None, skin: float = 0.0,
                   comm=None, domains: Optional[Tuple[int, int]] = None, gather: str = "each_step") -> "World":
        """The world of a scene file, its disks placed as `carom run --scene path` places them.
        max_travel: None keeps the file's (its max_travel, or dt = "auto").
        comm, domains, gather: as World's.
        world.scene_steps is the number of steps `carom run` would take."""
        skin = _number("skin", skin)
        engine_name, selector = _engine_name(engine, device, pipeline, skin > 0)
        travel = None if max_travel is None else _number("max_travel", max_travel)
        handle, split, gather = _split(comm, domains, gather)
        core, steps = _carom.World.from_scene_file(_path("path", path), engine_name, selector, travel, skin, handle,
                                                   split, gather)
        world = cls._from_core(core, selector, None if comm is None else comm.bcast(secrets.randbits(63), root=0))
        world.scene_steps = steps
        return world

    @classmethod
    def from_checkpoint(cls, path: Union[str, os.PathLike], engine: str = "cpu", device: Union[int, str, None] = None,
                        pipeline: Optional[str] = None, max_travel: float = 0.0, skin: float = 0.0,
                        comm=None, domains: Optional[Tuple[int, int]] = None, gather: str = "each_step") -> "World":
        """The world a checkpoint holds (save_checkpoint, `carom run --checkpoint`), continuing bit for bit.
        A checkpoint does not hold max_travel, the skin or the engine: pass the saved world's to continue
        its substeps alike (copy() and pickle keep them). comm, domains, gather: as World's; a checkpoint saved by
        any number of processes resumes on any other."""
        skin = _number("skin", skin)
        engine_name, selector = _engine_name(engine, device, pipeline, skin > 0)
        handle, split, gather = _split(comm, domains, gather)
        core = _carom.World.from_checkpoint(_path("path", path), engine_name, selector,
                                            _number("max_travel", max_travel), skin, handle, split, gather)
        return cls._from_core(core, selector, None if comm is None else comm.bcast(secrets.randbits(63), root=0))

    def save_checkpoint(self, path: Union[str, os.PathLike]) -> None:
        """Writes everything the world needs to continue bit for bit (`carom run --resume` reads it too);
        the file is replaced whole or not at all. With comm, every process holds the whole world: call it
        on one process (say rank 0), not on all of them at once."""
        self._core.save_checkpoint(_path("path", path))

    # The disks.

    def set_disks(self, positions, velocities, masses, radii, allow_overlaps: bool = False) -> None:
        """Replaces every disk: arrays of shape (N, 2), (N, 2), (N,), (N,), of any
        real dtype (stored as float32). Disk i gets id i; the step count, the
        time and the measurements restart. Refuses (carom.InputError, naming
        the index and the value, the disks kept as they were) values that are
        not finite or out of range, disks outside the box, coincident centres,
        and disks overlapping deeper than a step closes unless allow_overlaps.
        """
        arrays = _disk_arrays(positions, velocities, masses, radii)
        try:
            self._core.set_disks(*arrays, refuse_deep_overlaps=not allow_overlaps)
        except InputError as error:
            if "more than a step closes" not in str(error):
                raise
            raise InputError(f"{error}; set_disks(..., allow_overlaps=True) accepts deeper ones") from None

    # Edits between steps keep the step count, the time and the collision
    # count (the measurements' interval restarts). They check ranges and the
    # box, not overlaps: overlapping disks separate as they move apart, but two
    # disks with the same centre never collide.

    def edit(self, positions=None, velocities=None, masses=None, radii=None) -> None:
        """Replaces the given arrays of every disk at once (the others stay),
        e.g. world.edit(velocities=2 * world.velocities). Shapes as set_disks."""
        current = [positions, velocities, masses, radii]
        kept = self._core.disk_arrays()
        arrays = _disk_arrays(*(kept[i] if given is None else given for i, given in enumerate(current)))
        if len(arrays[0]) != self.n:
            raise InputError(f"positions: {len(arrays[0])} disks; allowed: {self.n} (an edit keeps the number of "
                             "disks: add_disks adds, set_disks replaces)")
        self._core.edit_disks(*arrays)

    def add_disks(self, positions, velocities, masses, radii) -> None:
        """Appends disks (ids N, N+1, ...) between steps; arrays as set_disks."""
        self._core.add_disks(*_disk_arrays(positions, velocities, masses, radii))

    def set_disk(self, id: int, position: Sequence[float], velocity: Sequence[float], mass: float,
                 radius: float) -> None:
        """Replaces disk `id` between steps (a drag, a throw)."""
        arrays = _disk_arrays([position], [velocity], [mass], [radius])
        position, velocity, mass, radius = (a.ravel().tolist() for a in arrays)
        self._core.set_disk(_whole("id", id), position, velocity, mass[0], radius[0])

    def place(self, count: int, radius: Range = 1.0, mass: Range = 1.0, speed: Optional[float] = None,
              temperature: Optional[float] = None) -> None:
        """Replaces the disks with `count` disks on a jittered hexagonal lattice
        filling the box, as a scene file's [[group]] places them: radius and mass
        fixed or uniform in (min, max); one speed (default 1) in random
        directions, or Maxwell-Boltzmann velocities at kT = temperature (> 0),
        not both. Random from world.seed."""
        if temperature is not None and speed is not None:
            raise InputError(f"speed={speed!r} and temperature={temperature!r}; allowed: one of them")
        kt = 0.0 if temperature is None else _number("temperature", temperature)
        if temperature is not None and not kt > 0:
            raise InputError(f"temperature: {temperature!r}; allowed: > 0 (kT), or None for one speed")
        self._core.place(_whole("count", count, 1, 2**32 - 1), _range("radius", radius), _range("mass", mass),
                         _number("speed", 1.0 if speed is None else speed), kt, self.seed)

    def __len__(self) -> int:
        return self._core.disk_count

    @property
    def n(self) -> int:
        """The number of disks."""
        return self._core.disk_count

    @property
    def positions(self) -> np.ndarray:
        """Centres, float32 (N, 2), read-only, row i = disk i [length]. On the CPU
        engine (pairwise, simultaneous) a view of the engine's own memory: no
        copy, it follows the steps and edits (keep a .copy() to compare with
        later); after set_disks or add_disks change N it keeps the old disks.
        On OpenCL and with collisions="events" a fresh copy."""
        return self._core.disk_arrays()[0]

    @property
    def velocities(self) -> np.ndarray:
        """Velocities, float32 (N, 2), read-only [length/time]; a view or a copy as positions."""
        return self._core.disk_arrays()[1]

    @property
    def masses(self) -> np.ndarray:
        """Masses, float32 (N,), read-only [mass]; a view or a copy as positions."""
        return self._core.disk_arrays()[2]

    @property
    def radii(self) -> np.ndarray:
        """Radii, float32 (N,), read-only [length]; a view or a copy as positions."""
        return self._core.disk_arrays()[3]

    @property
    def ids(self) -> np.ndarray:
        """Disk ids, uint32 (N,), read-only: rows are always in id order, so ids[i] == i."""
        if len(self._ids) != self.n:
            self._ids = np.arange(self.n, dtype=np.uint32)
            self._ids.flags.writeable = False
        return self._ids

    def own_disks(self) -> OwnDisks:
        """The disks this process steps, in id order, as an OwnDisks (ids, positions, velocities, masses,
        radii, images; read-only copies): with comm, those whose centres lie in its domain (each disk on
        exactly one process), every disk otherwise. Not collective: it reads no other process's disks."""
        ids, (positions, velocities, masses, radii), images = self._core.own_disks()
        return OwnDisks(ids, positions, velocities, masses, radii, images)

    def gather(self) -> None:
        """With comm and gather="on_request", collective: brings the whole world to every process, for the
        reads until the next step. Nothing to do otherwise."""
        self._core.gather()

    @property
    def images(self) -> np.ndarray:
        """Periodic images, int32 (N, 2), read-only, row i = disk i: the box
        widths and heights each disk has crossed since set_disks or place (+1
        each time it left by the right or top side, -1 by the left or bottom),
        so that positions + images * box is its unwrapped centre, for
        mean-square displacements. All 0 with walls. Edits keep them (added
        disks start at 0); copies, pickles and checkpoints keep them. A copy."""
        return self._core.images()

    @property
    def exact_positions(self) -> np.ndarray:
        """collisions="events" only: the centres in double, as the engine holds them (float64 (N, 2), a copy)."""
        self._events_only("exact_positions")
        return self._core.exact_positions()

    def _events_only(self, what: str) -> None:
        if self.collision_scheme != "events":
            raise InputError(f"{what}: collisions={self.collision_scheme!r}; allowed: collisions='events'")

    # Time.

    def step(self, n: int = 1) -> None:
        """Advances n steps of dt, letting other threads run meanwhile. Ctrl-C
        stops it within about 0.1 s, even within a long step, with the world
        at the last step it completed (a step cut short returns to its start). Raises
        carom.InputError when a step leaves a disk non-finite or needs too many
        substeps (the world keeps the step it reached)."""
        n = _whole("n", n)
        if self.n == 0 and n > 0:
            raise InputError("step: the world has no disks yet; allowed after set_disks or place")
        self._core.step(n)

    @property
    def step_count(self) -> int:
        """Steps taken since set_disks (or the scene a checkpoint continues)."""
        return self._core.step_count

    @property
    def time(self) -> float:
        """Simulated time [time]: the sum of the steps' dt."""
        return self._core.time

    @property
    def dt(self) -> float:
        """The time step [time]; settable between steps."""
        return self._core.dt

    @dt.setter
    def dt(self, value: float) -> None:
        self._core.set_motion(_number("dt", value), self._core.gravity)

    @property
    def gravity(self) -> Pair:
        """(gx, gy) [length/time^2]; settable between steps."""
        return tuple(self._core.gravity)

    @gravity.setter
    def gravity(self, value: Sequence[float]) -> None:
        self._core.set_motion(self._core.dt, _pair("gravity", value))

    @property
    def box(self) -> Pair:
        """(W, H) [length]."""
        return self._core.width, self._core.height

    @property
    def boundary(self) -> str:
        return self._core.boundary

    @property
    def collision_scheme(self) -> str:
        """"pairwise", "simultaneous" or "events"."""
        return self._core.collision_scheme

    @property
    def engine(self) -> str:
        """"cpu" or "opencl"."""
        return "cpu" if self._core.engine == "cpu" else "opencl"

    @property
    def pipeline(self) -> Optional[str]:
        """OpenCL's pipeline, "host-grid" or "resident"; None on the CPU."""
        return {engine: pipeline for pipeline, engine in _PIPELINES.items()}.get(self._core.engine)

    @property
    def device_name(self) -> str:
        return self._core.device_name

    @property
    def device_memory(self) -> dict:
        """The engine's buffers on its device [bytes]: {"bytes": alive now,
        "peak_bytes": the most alive at once}; zeros on the CPU, whose memory
        is the host's."""
        return dict(self._core.device_memory)

    @property
    def bitwise_reproducible(self) -> bool:
        """Whether results are bitwise the CPU engine's (always on the CPU; on
        OpenCL devices that round divide and sqrt correctly)."""
        return self._core.bitwise_reproducible

    @property
    def warnings(self) -> list:
        """What the last set_disks found less accurate or slower than usual, though allowed."""
        return list(self._core.warnings)

    # Observables: the numbers of `carom run --json`.

    @property
    def kinetic_energy(self) -> float:
        """sum m v^2 / 2, in double [mass length^2/time^2]."""
        return self._core.kinetic_energy

    @property
    def potential_energy(self) -> float:
        """-sum m g.x in the world's gravity (0 without)."""
        return self._core.potential_energy

    @property
    def total_energy(self) -> float:
        """kinetic + potential; with collisions="events", of the engine's exact double state."""
        return self._core.total_energy

    @property
    def momentum(self) -> Pair:
        """sum m v [mass length/time]."""
        return tuple(self._core.momentum)

    @property
    def temperature(self) -> float:
        """kT (k = 1): E_kin / N with walls; (E_kin - P^2/2M) / (N - 1) in a periodic box."""
        return self._core.temperature

    @property
    def collisions(self) -> int:
        """Pairs that received an impulse since the scene began, each pair once."""
        return self._core.collision_count

    @property
    def max_overlap(self) -> float:
        """The deepest overlap of two disks, 0 if none [length]."""
        return self._core.max_overlap

    def measurements(self) -> dict:
        """Collisions, pressure, Z and more over the interval since set_disks or
        reset_measurements() (carom/world.h, Measurements)."""
        return self._core.measurements()

    def reset_measurements(self) -> None:
        """Starts a new interval for pressure, compressibility and collision_rate."""
        self._core.reset_measurements()

    @property
    def pressure(self) -> float:
        """Over the measurements' interval [mass/time^2]: from the collision virial
        in a periodic box, from the walls' momentum otherwise."""
        return self._core.measurements()["pressure"]

    @property
    def compressibility(self) -> float:
        """Z = P A / (N kT) over the measurements' interval."""
        return self._core.measurements()["compressibility"]

    @property
    def collision_rate(self) -> float:
        """Collisions per disk per unit time over the measurements' interval [1/time]."""
        return self._core.measurements()["collision_rate"]

    def event_counts(self) -> dict:
        """collisions="events" only: collisions, wall bounces, cell crossings, stale and overlapping events."""
        self._events_only("event_counts")
        return self._core.event_counts()

    def __repr__(self) -> str:
        w, h = self.box
        return (f"carom.World(box=({w:g}, {h:g}), boundary={self.boundary!r}, collisions={self.collision_scheme!r}, "
                f"engine={self.engine!r}, disks={self.n}, step={self.step_count})")
