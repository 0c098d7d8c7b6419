"""`examples/pysph/dam_break_2d.py`: PySPH's dam break with a tracker in its time loop, run for
a few steps where PySPH is installed (skipped, saying how to install it, where it is not). The
labels PySPH saved with its output are those of `detect` on the saved positions and walls (run
by `cargo xtask test`)."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import boundary_particles as boundary

EXAMPLE = Path(__file__).resolve().parents[3] / "examples" / "pysph" / "dam_break_2d.py"
INSTALL = "pip install pysph (it compiles with Cython and a C compiler)"

try:
    from pysph.examples.dam_break_2d import h as SMOOTHING_LENGTH
    from pysph.solver.utils import get_files, load
except ImportError:
    get_files = load = None


def test_the_pysph_example_labels_every_step(tmp_path):
    if load is None:
        print(f"SKIPPED: PySPH is not installed: {INSTALL}")
        pytest.skip(f"PySPH is not installed: {INSTALL}")
    out = subprocess.run(
        [sys.executable, str(EXAMPLE), "--max-steps", "6", "--pfreq", "3", "-d", str(tmp_path)],
        capture_output=True,
        text=True,
        timeout=1800,
    )
    assert out.returncode == 0, out.stdout[-3000:] + out.stderr[-3000:]
    assert "ratio" in out.stdout, out.stdout[-3000:]
    assert "command:" in (tmp_path / "boundary_tracker_cost.txt").read_text()
    files = get_files(str(tmp_path))
    assert len(files) >= 2, files
    data = load(files[-1])
    fluid, walls = data["arrays"]["fluid"], data["arrays"]["boundary"]
    labels = fluid.get("boundary_label").astype(bool)
    points = np.column_stack([fluid.get("x"), fluid.get("y")])
    # The example's r: PySPH's initial smoothing length (the default --h-factor 1).
    h = SMOOTHING_LENGTH
    expected = boundary.detect(
        points, h=h, walls=np.column_stack([walls.get("x"), walls.get("y")])
    )
    np.testing.assert_array_equal(labels, expected)
    # The tank's floor and walls cover: fewer boundary particles than without them.
    assert labels.sum() < boundary.detect(points, h=h).sum()


def test_the_pysph_example_takes_mass_and_smoothing_length_from_dx(tmp_path):
    if load is None:
        print(f"SKIPPED: PySPH is not installed: {INSTALL}")
        pytest.skip(f"PySPH is not installed: {INSTALL}")
    dx = 0.06
    out = subprocess.run(
        [sys.executable, str(EXAMPLE), "--dx", str(dx), "--max-steps", "4", "--pfreq", "2",
         "-d", str(tmp_path)],
        capture_output=True,
        text=True,
        timeout=1800,
    )
    assert out.returncode == 0, out.stdout[-3000:] + out.stderr[-3000:]
    data = load(get_files(str(tmp_path))[-1])
    fluid, walls = data["arrays"]["fluid"], data["arrays"]["boundary"]
    # PySPH's own example would keep h = 1.3 * 0.03 and m = 0.03^2 * 1000 here. The scheme
    # updates h from the density as it runs: within 1e-6 after a few steps.
    for array in (fluid, walls):
        np.testing.assert_allclose(array.get("h"), 1.3 * dx, rtol=1e-6)
        np.testing.assert_allclose(array.get("m"), dx**2 * 1000.0, rtol=1e-12)
    points = np.column_stack([fluid.get("x"), fluid.get("y")])
    expected = boundary.detect(
        points, h=1.3 * dx, walls=np.column_stack([walls.get("x"), walls.get("y")])
    )
    np.testing.assert_array_equal(fluid.get("boundary_label").astype(bool), expected)
