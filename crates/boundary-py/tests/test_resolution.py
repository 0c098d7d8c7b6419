"""The resolution in a solver's terms (run by `cargo xtask test-bindings`): ``h`` (the smoothing
length, ``r = h``, as ``--smoothing-length``), ``spacing`` (``r = k * spacing``, as
``--spacing``) and ``r="auto"`` (``k`` times the spacing measured in the bulk), given once, in
``detect``, ``Detector.detect``, ``score``, ``resample`` and ``Tracker``; a ``UserWarning``
with the numbers when ``r`` is implausible for the particles' spacing."""

import warnings
from pathlib import Path

import numpy as np
import pytest

import boundary_particles as bp

FIXTURES = Path(__file__).resolve().parents[3] / "fixtures"

# The SPH-sum methods: their smoothing length is h_over_r * r.
SPH = ["marrone", "muller", "divr", "asymmetry", "randles"]

DP = 0.02


def vortex() -> np.ndarray:
    """fixtures/vortex2d_t4.csv, documented at r = 0.0075 (fixtures/scenes.toml)."""
    path = FIXTURES / "vortex2d_t4.csv"
    assert path.is_file(), f"bundled fixture missing: {path}"
    table = np.genfromtxt(path, delimiter=",", names=True)
    return np.ascontiguousarray(np.column_stack([table["x"], table["y"]]))


def jittered_disc(side: int = 30, dp: float = DP, seed: int = 3) -> np.ndarray:
    """A square lattice of spacing dp clipped to a disc, jittered by up to 10% of dp."""
    rng = np.random.default_rng(seed)
    grid = np.argwhere(np.ones((side, side))).astype(np.float64)
    centre = (side - 1) / 2
    grid = grid[np.linalg.norm(grid - centre, axis=1) <= centre]
    return dp * (grid + rng.uniform(-0.1, 0.1, grid.shape))


def no_warning(call):
    """`call()`, failing on any warning."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return call()


def test_h_gives_the_labels_of_r_equal_h_everywhere():
    points = jittered_disc()
    h = 1.5 * DP
    for method in ["exact", "ge", *SPH]:
        np.testing.assert_array_equal(
            bp.detect(points, h=h, method=method), bp.detect(points, h, method), method
        )
    detector = bp.Detector("muller", threads=2)
    np.testing.assert_array_equal(detector.detect(points, h=h), detector.detect(points, r=h))
    # The README's example scene.
    points = vortex()
    labels = no_warning(lambda: bp.detect(points, h=0.0075))
    np.testing.assert_array_equal(labels, bp.detect(points, r=0.0075))
    assert 0 < labels.sum() < len(labels)
    assert bp.score(points, h=0.0075, method="muller") == bp.score(points, 0.0075, "muller")
    tracker = bp.Tracker(h=0.0075)
    np.testing.assert_array_equal(tracker.update(points), labels)
    for a, b in zip(bp.resample(points, h=0.0075), bp.resample(points, 0.0075)):
        np.testing.assert_array_equal(a, b)


def test_h_refuses_an_h_over_r_other_than_1_as_the_command_line_does():
    points = jittered_disc()
    h = 1.5 * DP
    for method in SPH:
        with pytest.raises(ValueError, match=r"h_over_r=2 would make it 2 x 0\.03"):
            bp.detect(points, h=h, method=method, h_over_r=2)
        # h_over_r = 1 is h itself; with r, any h_over_r is the user's own choice.
        np.testing.assert_array_equal(
            bp.detect(points, h=h, method=method, h_over_r=1.0), bp.detect(points, h, method)
        )
        bp.detect(points, h, method, h_over_r=2)
    with pytest.raises(ValueError, match=r"h=0\.03 gives the SPH sums h = 0\.03 itself"):
        bp.Detector("marrone", h_over_r=1.5).detect(points, h=h)
    with pytest.raises(ValueError, match="drop h_over_r, or give r= with it"):
        bp.score(points, h=h, method="divr", h_over_r=2)
    with pytest.raises(ValueError, match="h_over_r=3"):
        bp.resample(points, h=h, method="muller", h_over_r=3)
    # resample with labels given runs no method: nothing to refuse.
    labels = bp.detect(points, h)
    bp.resample(points, h=h, method="muller", h_over_r=3, labels=labels)


def test_spacing_gives_the_labels_of_r_k_times_the_spacing():
    assert bp.RADIUS_PER_SPACING == 1.45
    points = jittered_disc()
    r = 1.45 * DP
    for method in ["exact", "muller"]:
        np.testing.assert_array_equal(
            no_warning(lambda: bp.detect(points, spacing=DP, method=method)),
            bp.detect(points, r, method),
            method,
        )
    np.testing.assert_array_equal(bp.Detector().detect(points, spacing=DP), bp.detect(points, r))
    assert bp.score(points, spacing=DP, method="ia") == bp.score(points, r, "ia")
    np.testing.assert_array_equal(bp.Tracker(spacing=DP).update(points), bp.detect(points, r))
    # With radii, the spacing gives the scale of the factors as r does.
    radii = np.ones(len(points))
    np.testing.assert_array_equal(
        bp.detect(points, spacing=DP, radii=radii), bp.detect(points, r, radii=radii)
    )


def test_the_resolution_is_given_once_and_checked():
    points = jittered_disc()
    once = r"give the resolution once, as one of r, h and spacing \(got {}\)"
    for kwargs, got in [
        ({"r": 0.03, "h": 0.03}, "r and h"),
        ({"r": 0.03, "spacing": DP}, "r and spacing"),
        ({"h": 0.03, "spacing": DP}, "h and spacing"),
        ({"r": "auto", "h": 0.03}, "r and h"),
        ({"r": 0.03, "h": 0.03, "spacing": DP}, "r and h and spacing"),
    ]:
        with pytest.raises(ValueError, match=once.format(got)):
            bp.detect(points, **kwargs)
        with pytest.raises(ValueError, match=once.format(got)):
            bp.Detector().detect(points, **kwargs)
    with pytest.raises(ValueError, match=once.format("r and h")):
        bp.detect(points, 0.03, h=0.03)
    with pytest.raises(ValueError, match=once.format("r and spacing")):
        bp.score(points, 0.03, "ge", spacing=DP)
    with pytest.raises(ValueError, match=once.format("r and h")):
        bp.resample(points, 0.03, h=0.03)
    with pytest.raises(ValueError, match=once.format("r and h")):
        bp.Tracker(0.03, h=0.03)
    # None of them: the missing argument, naming the three.
    for call in [lambda: bp.detect(points), lambda: bp.resample(points), lambda: bp.Tracker()]:
        with pytest.raises(TypeError, match=r"missing required argument 'r' .*give r, h .* or spacing"):
            call()
    # Bad values: a ValueError naming the keyword, or a TypeError for what is no number.
    for kwargs, message in [
        ({"h": -1.0}, "h: radius must be positive"),
        ({"h": float("nan")}, "h: radius must be positive"),
        ({"h": 0.0}, "h: radius must be positive"),
        ({"spacing": 0.0}, "spacing: particle spacing must be positive and finite, got 0"),
        ({"spacing": -DP}, "spacing: particle spacing must be positive and finite"),
        ({"spacing": float("inf")}, "spacing: particle spacing must be positive and finite"),
        ({"spacing": 1e300}, "spacing: radius .* is outside the supported range"),
    ]:
        with pytest.raises(ValueError, match=message):
            bp.detect(points, **kwargs)
        with pytest.raises(ValueError, match=message):
            bp.Tracker(**kwargs)
    for kwargs in [{"h": "0.03"}, {"h": True}, {"spacing": [DP]}, {"spacing": "auto"}]:
        with pytest.raises(TypeError, match=r"(h|spacing) must be a positive real"):
            bp.detect(points, **kwargs)
    # The tracker measures "auto" on its first update's particles, and keeps that r.
    np.testing.assert_array_equal(bp.Tracker("auto").update(points), bp.detect(points, "auto"))


def test_r_auto_is_k_times_the_bulk_spacing_and_close_to_the_documented_r():
    points = vortex()
    r = bp.auto_radius(points)
    assert 0.6 * 0.0075 <= r <= 1.67 * 0.0075, r
    dp = bp.bulk_spacing(points)
    assert r == bp.RADIUS_PER_SPACING * dp
    labels = no_warning(lambda: bp.detect(points, "auto"))
    np.testing.assert_array_equal(labels, bp.detect(points, r))
    np.testing.assert_array_equal(labels, bp.detect(points, spacing=dp))
    np.testing.assert_array_equal(labels, bp.Detector("exact").detect(points, r="Auto"))
    # On a jittered lattice the measured spacing is the lattice's.
    assert abs(bp.bulk_spacing(jittered_disc()) / DP - 1) < 0.1
    flat = np.column_stack([jittered_disc(), np.zeros(len(jittered_disc()))])
    assert bp.bulk_spacing(flat, dim=2) == bp.bulk_spacing(jittered_disc())
    with pytest.raises(ValueError, match="pass dim=2"):
        bp.bulk_spacing(flat)
    for few in [[[1.0, 1.0]], [[1.0, 1.0], [1.0, 1.0]], np.zeros((0, 3))]:
        with pytest.raises(ValueError, match="two distinct particle positions"):
            bp.bulk_spacing(few)
        with pytest.raises(ValueError, match="two distinct particle positions"):
            bp.auto_radius(few)
    with pytest.raises(ValueError, match="not finite"):
        bp.bulk_spacing([[0.0, 0.0], [np.nan, 1.0]])


def test_an_implausible_r_warns_with_the_numbers_and_still_detects():
    points = vortex()
    with pytest.warns(UserWarning, match=r"r = 7\.5 is [0-9.]+ x the particle spacing [0-9.]+ measured in the bulk \(above 4\)") as record:
        labels = bp.detect(points, 7.5)
    # Attributed to the caller's line, not the package's.
    assert [w.filename for w in record] == [__file__]
    assert labels.shape == (len(points),)
    with pytest.warns(UserWarning, match=r"\(below 0\.75\): almost every particle will be boundary"):
        assert bp.detect(points, 0.001).mean() > 0.9
    with pytest.warns(UserWarning, match="above 4"):
        bp.detect(points, h=1.0, method="muller")
    with pytest.warns(UserWarning, match="above 4"):
        bp.Detector("ge").detect(points, spacing=0.1)
    small = jittered_disc()
    with pytest.warns(UserWarning, match="above 4"):
        bp.resample(small, 5 * DP)
    # The tracker checks its r at the first update only.
    tracker = bp.Tracker(r=5 * DP)
    with pytest.warns(UserWarning, match="above 4") as record:
        tracker.update(small)
    assert [w.filename for w in record] == [__file__]
    no_warning(lambda: tracker.update(small + 1e-5))
    # Plausible resolutions, "auto" and radii (r is their scale) say nothing.
    for call in [
        lambda: bp.detect(points, 0.0075),
        lambda: bp.detect(points, h=0.0075),
        lambda: bp.detect(points, spacing=0.005),
        lambda: bp.detect(points, "auto"),
        lambda: bp.detect(small, 100.0, radii=np.full(len(small), 0.0003)),
    ]:
        no_warning(call)
    # Warnings as errors stop the call with the warning, and nothing crashes.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(UserWarning, match="above 4"):
            bp.detect(points, 7.5)
