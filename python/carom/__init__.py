"""carom: 2D elastic hard disks, exact and data-parallel, on CPUs and OpenCL GPUs.

    import carom
    world = carom.World(box=(100, 100), boundary="periodic", seed=1)
    world.place(1000, speed=1.0)
    world.step(1000)
    print(world.temperature, world.compressibility)

carom.World steps the disks; world.positions and friends are NumPy arrays
(views of the engine's memory on the CPU). carom.GSDWriter and
carom.write_xyz write trajectories that OVITO, freud and HOOMD read.
Every error is a carom.Error; refusals of bad input are carom.InputError,
also a ValueError, and name the value and what is allowed.
"""
from __future__ import annotations

import os
from dataclasses import dataclass
from typing import List, Optional, Tuple, Union

import numpy as np

from . import _carom
from ._carom import Error, InputError
from ._gsd import GSDWriter
from ._world import _PIPELINES, OwnDisks, World, _choice, _number, _pair, _path, _range, _whole

__version__ = _carom.VERSION
__all__ = ["World", "OwnDisks", "Scene", "make_scene", "devices", "choose_engine", "engines", "read_state",
           "write_state", "write_xyz", "GSDWriter", "Error", "InputError", "__version__"]


@dataclass(frozen=True, eq=False)
class Scene:
    """Disks placed by make_scene: the box and read-only float32 arrays in id order."""
    box: Tuple[float, float]  # (W, H) [length]
    positions: np.ndarray     # (N, 2) [length]
    velocities: np.ndarray    # (N, 2) [length/time]
    masses: np.ndarray        # (N,) [mass]
    radii: np.ndarray         # (N,) [length]


def make_scene(particles: int = 1000, packing: float = 0.3, radius=1.0, mass=1.0, speed: float = 1.0,
               seed: int = 1, box: Optional[Tuple[float, float]] = None) -> Scene:
    """N disks on a jittered hexagonal lattice, one speed in random directions:
    the scene of `carom run --particles N --packing p --seed s` and of
    `carom bench`. The box is square, sized so the disks cover `packing` of
    it, unless `box` is given. radius and mass: a value or (min, max)."""
    width, height = (0.0, 0.0) if box is None else _pair("box", box)
    width, height, arrays = _carom.make_scene(_whole("particles", particles, 1, 2**32 - 1),
                                              _number("packing", packing), width, height, _range("radius", radius),
                                              _range("mass", mass), _number("speed", speed), _whole("seed", seed))
    return Scene((width, height), *arrays)


def devices() -> List[dict]:
    """The OpenCL devices carom can run on (index, name, platform, type, version,
    memory_bytes, bitwise_reproducible); [] when there are none or this build has no OpenCL."""
    if not _carom.engine_available("opencl-host-grid"):
        return []
    try:
        return _carom.devices()
    except Error:
        return []


def choose_engine() -> dict:
    """What World(engine="auto") runs on here, and why: {"engine": "cpu" or "opencl", "pipeline": "host-grid",
    "resident" or None, "device": the OpenCL device's index or None, "reason": in words}. OpenCL on the first
    GPU, else the CPU, which outruns OpenCL on CPU devices such as PoCL (`carom run --backend auto`'s rule)."""
    name, selector, reason = _carom.choose_engine()
    pipeline = {engine: pipeline for pipeline, engine in _PIPELINES.items()}.get(name)
    return {"engine": "cpu" if name == "cpu" else "opencl", "pipeline": pipeline,
            "device": int(selector) if selector else None, "reason": reason}


def engines() -> List[str]:
    """The engines World(engine=...) can use here: "cpu", and "opencl" when a device exists."""
    return ["cpu"] + (["opencl"] if devices() else [])


def read_state(path: Union[str, os.PathLike]) -> Scene:
    """A state CSV (`carom run --output-state`, write_state): its disks, in id order.
    The box is not in the file: Scene.box is (0, 0)."""
    return Scene((0.0, 0.0), *_carom.read_state(_path("path", path)))


def write_state(path: Union[str, os.PathLike], world: World) -> None:
    """The world's disks as a state CSV (`carom run --state` reads it), bit for bit; written whole or not at all."""
    core = _world_of(world)._core
    with core.lock:
        _carom.write_state(_path("path", path), core.core)


def write_xyz(path: Union[str, os.PathLike], world: World, mode: str = "w") -> None:
    """One extended XYZ frame of the world (the format of `carom run --trajectory`,
    which OVITO and ASE read). mode "w" replaces the file; "a" appends to a
    trajectory whose last frame is at the same or an earlier step, with the
    same disk count. The file is replaced whole or not at all, so each call
    copies it: for long trajectories GSDWriter, which appends, is faster."""
    _choice("mode", mode, ("w", "a"))
    core = _world_of(world)._core
    with core.lock:
        _carom.write_xyz(_path("path", path), core.core, mode == "a")


def _world_of(world) -> World:
    if not isinstance(world, World):
        raise InputError(f"world: {type(world).__name__}; allowed: a carom.World")
    return world
