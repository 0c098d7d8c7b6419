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
    # The first offender is named, whatever follows it.
    with pytest.raises(ValueError, match="particle 1: id -7"):
        tracker.update(points, ids=np.array([4, -7, -2], dtype=np.int64))
    # A strided view and a narrower dtype are read as the same ids.
    expected = boundary.detect(points, 1.0)
    strided = np.arange(6, dtype=np.int64)[::2]
    np.testing.assert_array_equal(tracker.update(points, ids=strided), expected)
    np.testing.assert_array_equal(tracker.update(points, ids=strided.astype(np.int32)), expected)


def tank(step: int):
    """A water block in a tank of wall particles (floor and two sides, 3 layers), the water
    stretched a little more at every step (spacing 1)."""
    rng = np.random.default_rng(11)
    k = np.arange(30 * 12)
    water = np.column_stack([k % 30 + 0.5, k // 30 + 0.5]).astype(np.float64)
    water += rng.uniform(-0.1, 0.1, water.shape)
    water[:, 0] *= 1.0 + 0.004 * step
    water[:, 1] *= 1.0 - 0.003 * step
    floor = [[x + 0.5, -0.5 - layer] for layer in range(3) for x in range(-3, 36)]
    sides = [
        [x, y + 0.5] for layer in range(3) for x in (-0.5 - layer, 35.5 + layer) for y in range(20)
    ]
    return water, np.array(floor + sides, dtype=np.float64)


def test_tracker_with_fixed_walls_gives_the_labels_of_detect():
    tracker = boundary.Tracker(1.2, threads=1, walls=tank(0)[1])
    counts = []
    for step in range(6):
        water, walls = tank(step)
        labels = tracker.update(water)
        np.testing.assert_array_equal(labels, boundary.detect(water, 1.2, walls=walls))
        counts.append(tracker.recomputed)
    # The floor covers the bottom row: not the free surface.
    assert not labels[:30].all()
    assert counts[0] == len(water)
    assert all(c < len(water) // 3 for c in counts[1:]), counts


def test_tracker_with_moving_walls_gives_the_labels_of_detect():
    tracker = boundary.Tracker(h=1.2, threads=1)
    saved = 0
    for step in range(6):
        water, walls = tank(step)
        walls = walls + np.array([0.02 * step, 0.01 * (step % 2)])
        labels = tracker.update(water, walls=walls)
        np.testing.assert_array_equal(labels, boundary.detect(water, h=1.2, walls=walls))
        if step > 0:
            saved += len(water) - tracker.recomputed
    assert saved > 0
    # Walls that did not move, passed again: nothing changes.
    labels = tracker.update(water, walls=walls)
    np.testing.assert_array_equal(labels, boundary.detect(water, h=1.2, walls=walls))
    assert tracker.recomputed < len(water) // 3
    # Another count of walls starts over.
    labels = tracker.update(water, walls=walls[:-5])
    np.testing.assert_array_equal(labels, boundary.detect(water, h=1.2, walls=walls[:-5]))
    assert tracker.recomputed == len(water)


def test_tracker_takes_the_whole_domain_of_detect():
    water, walls = tank(0)
    factors = 1.0 + 0.1 * (np.arange(len(water)) % 3)
    wall_factors = np.full(len(walls), 0.9)
    phases = (water[:, 0] > 15).astype(np.uint32)
    tracker = boundary.Tracker(
        spacing=1.0, walls=walls, wall_radii=wall_factors, solids="x<2", periodic=None
    )
    for step in range(3):
        water = tank(step)[0]
        labels = tracker.update(water, radii=factors)
        expected = boundary.detect(
            water, spacing=1.0, radii=factors, walls=walls, wall_radii=wall_factors, solids="x<2"
        )
        np.testing.assert_array_equal(labels, expected)
        labels, interface = tracker.update(water, phases=phases)
        want, want_interface = boundary.detect(
            water, spacing=1.0, walls=walls, wall_radii=wall_factors, solids="x<2", phases=phases
        )
        np.testing.assert_array_equal(labels, want)
        np.testing.assert_array_equal(interface, want_interface)
        assert interface.any()
    # Periodic axes.
    k = np.arange(400)
    points = np.column_stack([k % 20 + 0.5, k // 20]).astype(np.float64)
    points += np.random.default_rng(1).uniform(-0.1, 0.1, points.shape)
    tracker = boundary.Tracker(0.9, periodic="x:0:20")
    for step in range(3):
        moved = points.copy()
        moved[:, 1] *= 1.0 + 0.003 * step
        np.testing.assert_array_equal(
            tracker.update(moved), boundary.detect(moved, 0.9, periodic="x:0:20")
        )


def test_tracker_measures_auto_once():
    water, walls = tank(0)
    tracker = boundary.Tracker("auto", walls=walls)
    np.testing.assert_array_equal(
        tracker.update(water), boundary.detect(water, "auto", walls=walls)
    )
    r = boundary.auto_radius(water)
    assert repr(tracker) == f'Tracker(r={r}, method="exact")'
    # Later steps keep the first step's r, even where auto would measure another.
    squeezed = water * 0.9
    np.testing.assert_array_equal(
        tracker.update(squeezed), boundary.detect(squeezed, r, walls=walls)
    )


def test_tracker_reads_a_flat_3d_array_with_dim_2():
    water, walls = tank(0)
    water3 = np.column_stack([water, np.full(len(water), 0.25)])
    walls3 = np.column_stack([walls, np.full(len(walls), 0.25)])
    with pytest.raises(ValueError, match="dim=2"):
        boundary.Tracker(1.2).update(water3)
    tracker = boundary.Tracker(1.2, walls=walls3)
    expected = boundary.detect(water, 1.2, walls=walls)
    np.testing.assert_array_equal(tracker.update(water3, dim=2), expected)
    # detect takes the same flat walls beside flat points.
    np.testing.assert_array_equal(boundary.detect(water3, 1.2, dim=2, walls=walls3), expected)
    # Walls off the points' plane are refused, naming the wall particle.
    off = walls3.copy()
    off[4, 2] = 1.0
    with pytest.raises(ValueError, match="wall particle 4 has z = 1"):
        boundary.detect(water3, 1.2, dim=2, walls=off)
    # 3D walls beside 2D points say what works.
    with pytest.raises(ValueError, match="dim=2"):
        boundary.detect(water, 1.2, walls=walls3)


def test_ids_errors_say_what_to_pass_without_stable_ids():
    water, walls = tank(0)
    tracker = boundary.Tracker(1.2, walls=walls)
    unset = np.full(len(water), 4294967295, dtype=np.uint32)
    with pytest.raises(ValueError, match="pass no ids"):
        tracker.update(water, ids=unset)
    # Without ids the particles are matched by their place.
    np.testing.assert_array_equal(tracker.update(water), boundary.detect(water, 1.2, walls=walls))


def test_tracker_gives_the_labels_of_detect_on_any_thread_and_at_any_size():
    # A small set's updates run on the calling thread, a large one's (16,384 particles and
    # more) on the tracker's workers: the labels of detect either way, from whichever Python
    # thread calls.
    import threading

    rng = np.random.default_rng(9)
    for side in [40, 130]:
        k = np.arange(side * side)
        points = np.column_stack([k % side, k // side]).astype(np.float64)
        points += rng.uniform(-0.15, 0.15, points.shape)
        tracker = boundary.Tracker(0.8, threads=2)
        np.testing.assert_array_equal(tracker.update(points), boundary.detect(points, 0.8))
        got = []
        for step in range(1, 4):
            moved = points * (1.0 + 0.001 * step)
            worker = threading.Thread(target=lambda m=moved: got.append(tracker.update(m)))
            worker.start()
            worker.join()
            np.testing.assert_array_equal(got[-1], boundary.detect(moved, 0.8))
            assert tracker.recomputed < len(points) // 2, (side, step, tracker.recomputed)


def test_tracker_takes_one_array_per_coordinate():
    # A solver's structure of arrays (PySPH's fluid.x, fluid.y), contiguous or strided views:
    # the labels of the (n, d) array, and errors that say what is wrong.
    rng = np.random.default_rng(11)
    k = np.arange(900)
    points = np.column_stack([k % 30, k // 30, np.zeros(900)]).astype(np.float64)
    points[:, :2] += rng.uniform(-0.15, 0.15, (900, 2))
    flat = points[:, :2]
    by_rows = boundary.Tracker(0.8, threads=1)
    by_columns = boundary.Tracker(0.8, threads=1)
    for step in range(4):
        moved = flat * (1.0 + 0.002 * step)
        x, y = np.ascontiguousarray(moved[:, 0]), np.ascontiguousarray(moved[:, 1])
        expected = by_rows.update(moved)
        np.testing.assert_array_equal(by_columns.update(columns=(x, y)), expected)
        assert by_columns.recomputed == by_rows.recomputed
        # Strided views and a list work alike.
        np.testing.assert_array_equal(
            boundary.Tracker(0.8).update(columns=[moved[:, 0], moved[:, 1]]), expected
        )
    # Three columns: 3D, and dim=2 drops the constant one as for an (n, 3) array.
    cube = rng.uniform(0, 5, (500, 3))
    np.testing.assert_array_equal(
        boundary.Tracker(0.8).update(columns=tuple(cube.T)), boundary.detect(cube, 0.8)
    )
    x, y, z = (np.ascontiguousarray(c) for c in points.T)
    np.testing.assert_array_equal(
        boundary.Tracker(0.8).update(columns=(x, y, z), dim=2), boundary.detect(flat, 0.8)
    )
    with pytest.raises(ValueError, match=r"dim=2 \(or columns=\(x, y\)\)"):
        boundary.Tracker(0.8).update(columns=(x, y, z))
    tracker = boundary.Tracker(0.8)
    with pytest.raises(ValueError, match="got 1 array$"):
        tracker.update(columns=(x,))
    with pytest.raises(ValueError, match="columns must be a sequence"):
        tracker.update(columns={"x": x, "y": y})
    with pytest.raises(ValueError, match=r"columns\[0\] has 900 and columns\[1\] has 899"):
        tracker.update(columns=(x, y[1:]))
    with pytest.raises(ValueError, match=r"columns\[1\] must be a one-dimensional array"):
        tracker.update(columns=(x, points))
    bad = x.copy()
    bad[17] = np.inf
    with pytest.raises(ValueError, match="particle 17"):
        tracker.update(columns=(bad, y))
    with pytest.raises(TypeError, match="not both"):
        tracker.update(flat, columns=(x, y))
    with pytest.raises(TypeError, match="missing the positions"):
        tracker.update()
