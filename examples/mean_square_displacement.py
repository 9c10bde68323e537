"""The mean-square displacement of disks in a periodic box, and their diffusion coefficient.

    python examples/mean_square_displacement.py [folder]

A periodic box wraps the positions; world.images counts the box lengths each
disk has crossed, so positions + images * box are the unwrapped centres. The
samples also go to a GSD file (folder/msd.gsd) with the images, as HOOMD
writes them; where freud (pip install freud-analysis) is installed, its MSD of
that file must equal the one computed here.
"""
import os
import sys

import numpy as np

import carom

SAMPLES, STEPS_BETWEEN = 40, 25


def main(folder="."):
    world = carom.World(box=(80, 80), boundary="periodic", dt=0.01, seed=7)
    world.place(1200, radius=0.5, temperature=1.0)
    box = np.array(world.box)
    path = os.path.join(folder, "msd.gsd")

    unwrapped = []
    with carom.GSDWriter(path) as trajectory:
        for _ in range(SAMPLES):
            unwrapped.append(world.positions + world.images * box)
            trajectory.write(world)
            world.step(STEPS_BETWEEN)
    unwrapped = np.array(unwrapped, np.float64)
    lag = np.arange(SAMPLES) * STEPS_BETWEEN * world.dt
    # From the first sample: msd[k] = <|r_i(t_k) - r_i(t_0)|^2> over the disks.
    msd = ((unwrapped - unwrapped[0]) ** 2).sum(axis=2).mean(axis=1)

    # In 2D, msd = 4 D t at long times: the slope of the second half.
    half = SAMPLES // 2
    diffusion = np.polyfit(lag[half:], msd[half:], 1)[0] / 4
    print(f"{world.n} disks, kT {world.temperature:.3f}: MSD {msd[-1]:.3f} after {lag[-1]:g} time units, "
          f"D = {diffusion:.4f}")

    try:
        import freud
        import gsd.hoomd
    except ImportError:
        print("freud is not installed: no comparison (pip install freud-analysis)")
        return msd, None
    with gsd.hoomd.open(path, "r") as frames:
        positions = np.array([f.particles.position for f in frames], np.float64)
        images = np.array([f.particles.image for f in frames])
    reference = freud.msd.MSD(freud.box.Box.from_box(box), mode="direct").compute(positions, images).msd
    assert np.allclose(msd, reference, rtol=1e-5, atol=1e-6), np.abs(msd - reference).max()
    print(f"freud's MSD agrees (largest difference {np.abs(msd - reference).max():.2g})")
    return msd, reference


if __name__ == "__main__":
    main(*sys.argv[1:])
