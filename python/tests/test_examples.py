"""examples/mean_square_displacement.py runs, and its mean-square displacement
is right: it equals the one summed from the wrapped positions sample by
sample (each move shorter than half the box), and freud's where freud is
installed (the example compares them itself)."""
import importlib.util
import pathlib
import runpy

import gsd.hoomd
import numpy as np

EXAMPLE = pathlib.Path(__file__).resolve().parents[2] / "examples" / "mean_square_displacement.py"


def test_mean_square_displacement_example(tmp_path):
    msd, reference = runpy.run_path(str(EXAMPLE))["main"](str(tmp_path))
    assert (reference is None) == (importlib.util.find_spec("freud") is None)
    with gsd.hoomd.open(tmp_path / "msd.gsd", "r") as frames:
        box = np.array(frames[0].configuration.box[:2], np.float64)
        wrapped = np.array([f.particles.position[:, :2] for f in frames], np.float64)
        assert frames[-1].particles.image.any()  # disks crossed the box
    moves = np.diff(wrapped, axis=0)
    moves -= box * np.round(moves / box)  # each to the nearest image
    assert np.abs(moves).max() < box.min() / 4
    summed = np.concatenate([np.zeros((1, *moves.shape[1:])), np.cumsum(moves, axis=0)])
    np.testing.assert_allclose(msd, (summed ** 2).sum(axis=2).mean(axis=1), rtol=1e-4, atol=1e-6)
    assert msd[-1] > 10  # the disks went far enough for the images to matter
