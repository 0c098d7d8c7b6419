"""`boundary_particles.Tracker`: the labels of `detect` at every step, with fewer particles recomputed
when the particles move a little (run by `cargo xtask test`)."""

import numpy as np
import pytest

import boundary_particles as boundary


def test_tracker_gives_the_labels_of_detect_at_every_step():
    rng = np.random.default_rng(3)
    k = np.arange(400)
    points = np.column_stack([k % 20, k // 20]).astype(np.float64)
    points += rng.uniform(-0.15, 0.15, points.shape)
    tracker = boundary.Tracker(0.8, threads=1)
    counts = []
    for step in range(8):
        moved = points * (1.0 + 0.002 * step)
        labels = tracker.update(moved)
        assert labels.dtype == np.bool_ and labels.shape == (400,)
        np.testing.assert_array_equal(labels, boundary.detect(moved, 0.8))
        counts.append(tracker.recomputed)
    assert counts[0] == 400
    assert all(c < 200 for c in counts[1:]), counts
    # 3D, and a new count starts over.
    cube = rng.uniform(0, 4, (300, 3))
    np.testing.assert_array_equal(tracker.update(cube), boundary.detect(cube, 0.8))
    assert tracker.recomputed == 300


def test_tracker_refuses_what_it_cannot_do():
    with pytest.raises(ValueError, match="has no tracker"):
        boundary.Tracker(1.0, method="ge")
    with pytest.raises(ValueError, match="tie"):
        boundary.Tracker(1.0, tie=1e-9)
    with pytest.raises(ValueError):
        boundary.Tracker(0.0)
    with pytest.raises(ValueError, match="no parameter .bogus."):
        boundary.Tracker(1.0, bogus=1)
    tracker = boundary.Tracker(1.0)
    with pytest.raises(ValueError, match="shape"):
        tracker.update(np.zeros((3, 4)))
    with pytest.raises(ValueError):
        tracker.update(np.array([[0.0, np.nan]]))
