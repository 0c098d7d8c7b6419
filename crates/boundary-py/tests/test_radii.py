"""A radius per particle from Python (`radii=`): the translation of the array, the scale
`r`, radii read back from a file, and every bad radius a ValueError naming the particle (run
by `cargo xtask test`)."""

import numpy as np
import pytest

import boundary_particles as boundary


def lattice(side: int = 5) -> np.ndarray:
    """A side^3 cubic lattice of spacing 1: at r = 1.2 its (side-2)^3 core is interior."""
    k = np.arange(side**3)
    return np.column_stack([k % side, (k // side) % side, k // side**2]).astype(np.float64)


def test_radii_of_one_scaled_by_r_give_the_uniform_labels():
    points = lattice()
    uniform = boundary.detect(points, 1.2)
    assert int(uniform.sum()) == 125 - 27
    np.testing.assert_array_equal(boundary.detect(points, 1.2, radii=np.ones(125)), uniform)
    # r defaults to 1 with radii: the radii as given.
    np.testing.assert_array_equal(boundary.detect(points, radii=np.full(125, 1.2)), uniform)
    # Any array-like: a list, float32, a strided view (converted by NumPy).
    np.testing.assert_array_equal(boundary.detect(points, 1.2, radii=[1.0] * 125), uniform)
    np.testing.assert_array_equal(
        boundary.detect(points, 2.4, radii=np.full(250, 0.5, dtype=np.float32)[::2]), uniform
    )
    labels, margin = boundary.detect(points, 1.2, radii=np.ones(125), margin=True)
    np.testing.assert_array_equal(labels, uniform)
    assert margin is not None and margin.shape == (125,)


def test_graded_radii_read_back_from_a_file_give_the_labels_of_both_exact_methods(tmp_path):
    # Radius factors 1 and 0.8 in two halves at scale 0.9, through a CSV column (what the
    # CLI's --radius-attribute reads): exact and dilts agree, ia misses no boundary particle.
    points = lattice(6)
    radii = np.where(points[:, 0] < 3, 1.0, 0.8)
    path = tmp_path / "graded.csv"
    boundary.write(path, points, point_data={"h": radii})
    back, point_data = boundary.read(path)
    np.testing.assert_array_equal(point_data["h"], radii)
    exact = boundary.detect(back, 0.9, radii=point_data["h"])
    np.testing.assert_array_equal(boundary.detect(points, 0.9, "dilts", radii=radii), exact)
    ia = boundary.detect(points, 0.9, "ia", radii=radii)
    assert not np.any(exact & ~ia)
    # Graded radii change the labels (the smaller half leaves more uncovered).
    assert not np.array_equal(exact, boundary.detect(points, 0.9))
    score = boundary.score(points, 0.9, "exact", radii=radii)
    assert (score["fp"], score["fn"]) == (0, 0)
    # score with r left to its default: method by keyword.
    assert boundary.score(points, method="exact", radii=radii)["m"] == 1.0


@pytest.mark.parametrize(
    "radii, message",
    [
        ([1.0, -1.0, 1.0], "radii: particle 1: radius must be positive and finite, got -1"),
        ([1.0, 1.0, 0.0], "radii: particle 2: radius must be positive and finite, got 0"),
        ([np.nan, 1.0, 1.0], "radii: particle 0: radius must be positive and finite, got NaN"),
        ([1.0, np.inf, 1.0], "radii: particle 1: radius must be positive and finite, got inf"),
        ([1.0, 1.0, 1e-200], "radii: particle 2: radius 1e-200 is outside the supported range"),
        ([1.0, 1.0], "radii: 2 radii for 3 particles (one radius per particle)"),
        ([[1.0], [1.0], [1.0]], "radii must be a one-dimensional array"),
        (["a", "b", "c"], "radii must be an array of reals"),
    ],
)
def test_bad_radii_raise_value_error_naming_the_particle(radii, message):
    points = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    with pytest.raises(ValueError) as info:
        boundary.detect(points, radii=radii)
    assert str(info.value).startswith(message), str(info.value)
    with pytest.raises(ValueError):
        boundary.score(points, 1.0, "ia", radii=radii)


def test_radii_out_of_range_once_scaled_and_a_missing_r_are_named():
    points = np.array([[0.0, 0.0], [1.0, 0.0]])
    with pytest.raises(ValueError, match="particle 1: radius 1e101 is outside"):
        boundary.detect(points, 100.0, radii=[1.0, 1e99])
    with pytest.raises(ValueError, match="radius must be positive"):
        boundary.detect(points, -1.0, radii=[1.0, 1.0])
    with pytest.raises(TypeError, match="missing required argument 'r'"):
        boundary.detect(points)
    with pytest.raises(TypeError, match="missing required argument 'method'"):
        boundary.score(points, radii=[1.0, 1.0])


def test_two_particles_with_radii_1_and_2_are_interior_and_boundary_with_exact():
    """p0 = (0, 0) with r0 = 1 lies inside the ball of p1 = (0.5, 0) with r1 = 2 (interior);
    S1 reaches 2.5 from p0 (boundary)."""
    points = np.array([[0.0, 0.0], [0.5, 0.0]])
    labels = boundary.detect(points, radii=[1.0, 2.0], method="exact")
    assert labels.tolist() == [False, True]
