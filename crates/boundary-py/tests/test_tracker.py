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


def test_tracker_follows_ids_through_inflow_outflow_and_reordering():
    rng = np.random.default_rng(5)
    k = np.arange(600)
    points = np.column_stack([k % 30, k // 30]).astype(np.float64)
    points += rng.uniform(-0.15, 0.15, points.shape)
    ids = np.arange(600, dtype=np.uint32)
    tracker = boundary.Tracker(0.8, threads=1)
    np.testing.assert_array_equal(tracker.update(points, ids=ids), boundary.detect(points, 0.8))
    next_id = 600
    for step in range(6):
        points[:, 0] += 0.05
        stay = points[:, 0] < 29.5
        points, ids = points[stay], ids[stay]
        if step % 2 == 0:
            column = np.column_stack([np.full(20, -0.5), np.arange(20.0)])
            points = np.vstack([points, column])
            ids = np.concatenate([ids, np.arange(next_id, next_id + 20, dtype=np.uint32)])
            next_id += 20
        order = rng.permutation(len(points))
        points, ids = points[order], ids[order]
        labels = tracker.update(points, ids=ids)
        np.testing.assert_array_equal(labels, boundary.detect(points, 0.8))
        assert tracker.recomputed < len(points) // 3, (step, tracker.recomputed)


def test_tracker_refuses_bad_ids():
    tracker = boundary.Tracker(1.0)
    points = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    with pytest.raises(ValueError, match="2 ids for 3 particles"):
        tracker.update(points, ids=[1, 2])
    with pytest.raises(ValueError, match="id 4 is given to particles 0 and 2"):
        tracker.update(points, ids=[4, 5, 4])
    with pytest.raises(ValueError, match="particle 1: id -1"):
        tracker.update(points, ids=[4, -1, 6])
    with pytest.raises(ValueError, match="integers"):
        tracker.update(points, ids=[0.5, 1.0, 2.0])
    with pytest.raises(ValueError, match="one-dimensional"):
        tracker.update(points, ids=[[1, 2, 3]])
    # Ids up to 2^64 - 1 are taken.
    big = np.array([2**64 - 1, 0, 2**63], dtype=np.uint64)
    np.testing.assert_array_equal(tracker.update(points, ids=big), boundary.detect(points, 1.0))
