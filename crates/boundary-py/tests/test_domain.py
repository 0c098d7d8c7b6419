"""A simulation's domain from Python (`walls=`, `wall_radii=`, `solids=`, `periodic=`,
`phases=` of `detect`): walls give the labels of the union's fluid part, a periodic axis those
of explicit images, a solid covers what lies in it, phases give interface labels, and every
bad domain is a ValueError (or TypeError) with the library's message (run by `cargo xtask
test`)."""

import numpy as np
import pytest

import boundary_particles as boundary


def lattice(w: int, h: int, seed: int = 7) -> np.ndarray:
    """A w x h square lattice of spacing 1 (first column at x = 0.5), jittered by up to 0.1 so
    that no two neighbours tie."""
    k = np.arange(w * h)
    points = np.column_stack([k % w + 0.5, k // w]).astype(np.float64)
    return points + np.random.default_rng(seed).uniform(-0.1, 0.1, points.shape)


@pytest.mark.parametrize("method", ["exact", "dilts", "ge"])
def test_walls_give_the_labels_of_the_unions_fluid_part(method):
    # The highest three rows of a 10 x 10 block are walls (a lid), the other seven the fluid.
    union = lattice(10, 10)
    fluid, walls = union[:70], union[70:]
    expected = boundary.detect(union, 0.9, method)[:70]
    labels = boundary.detect(fluid, 0.9, method, walls=walls)
    assert isinstance(labels, np.ndarray) and labels.dtype == np.bool_
    np.testing.assert_array_equal(labels, expected)
    # The fluid's top row is covered by the walls; without them it is boundary.
    assert boundary.detect(fluid, 0.9, method)[60:].all()
    assert not expected[60:].all()
    # Walls as a list, as float32, and no walls at all (an empty (0, 2) array).
    np.testing.assert_array_equal(
        boundary.detect(fluid, 0.9, method, walls=walls.astype(np.float32).tolist()),
        boundary.detect(fluid, 0.9, method, walls=walls.astype(np.float32)),
    )
    np.testing.assert_array_equal(
        boundary.detect(fluid, 0.9, method, walls=np.empty((0, 2))),
        boundary.detect(fluid, 0.9, method),
    )


def test_wall_radii_scale_like_the_particles_radii():
    union = lattice(10, 10)
    factors = np.where(union[:, 0] < 5, 1.0, 0.8)
    expected = boundary.detect(union, 0.9, radii=factors)[:70]
    labels = boundary.detect(
        union[:70], 0.9, radii=factors[:70], walls=union[70:], wall_radii=factors[70:]
    )
    np.testing.assert_array_equal(labels, expected)


def test_a_solid_covers_what_lies_in_it():
    # A lone particle resting on the floor y < 0 (its upper half uncovered: boundary), one
    # whose sphere lies inside the solid (interior), one whose sphere touches the floor.
    points = np.array([[0.0, 0.5], [10.0, -2.0], [20.0, 1.0]])
    assert boundary.detect(points, 1.0).tolist() == [True, True, True]
    assert boundary.detect(points, 1.0, solids=["y<0"]).tolist() == [True, False, True]
    # One string is one solid.
    assert boundary.detect(points, 1.0, solids="y < 0").tolist() == [True, False, True]
    # A small block resting on the floor: its bottom row is covered; more solid never makes a
    # particle boundary.
    block = lattice(6, 4)
    bare = boundary.detect(block, 0.9)
    floor = boundary.detect(block, 0.9, solids=["y<0"])
    higher = boundary.detect(block, 0.9, solids=["y<0", "y<0.5"])
    assert floor.sum() < bare.sum()
    assert not (floor & ~bare).any() and not (higher & ~floor).any()
    # A wall at x < 0 beside the floor covers the block's left column too.
    corner = boundary.detect(block, 0.9, solids=["y<0", "x<0"])
    assert corner.sum() < floor.sum() and not (corner & ~floor).any()


def test_a_periodic_axis_gives_the_labels_of_explicit_images():
    # An 8 x 5 strip in x in [0, 8]: its images shifted by +-8 as walls.
    strip = lattice(8, 5)
    images = np.concatenate([strip + [8.0, 0.0], strip - [8.0, 0.0]])
    for method in ["exact", "ia"]:
        labels = boundary.detect(strip, 0.9, method, periodic=["x:0:8"])
        np.testing.assert_array_equal(labels, boundary.detect(strip, 0.9, method, walls=images))
        assert labels.sum() < boundary.detect(strip, 0.9, method).sum()
        np.testing.assert_array_equal(
            boundary.detect(strip, 0.9, method, periodic="x:0:8"), labels
        )


def test_phases_give_interface_labels_beside_the_free_surface():
    # Left half phase 0, right half phase 1: the interface is where they meet.
    block = lattice(10, 8)
    phases = (np.arange(80) % 10 >= 5).astype(np.int32)
    labels, interface = boundary.detect(block, 0.9, phases=phases)
    np.testing.assert_array_equal(labels, boundary.detect(block, 0.9))
    assert interface.dtype == np.bool_ and interface.shape == (80,)
    assert interface.any() and not (interface & labels).any()
    columns = np.arange(80)[interface] % 10
    assert set(columns.tolist()) <= {4, 5}, columns
    # With margin: (labels, margin, interface).
    labels2, margin, interface2 = boundary.detect(block, 0.9, phases=phases.tolist(), margin=True)
    np.testing.assert_array_equal(labels2, labels)
    np.testing.assert_array_equal(interface2, interface)
    assert margin is not None and margin.shape == (80,)
    # One phase: no interface; unsigned phases work too.
    _, none = boundary.detect(block, 0.9, phases=np.full(80, 3, dtype=np.uint8))
    assert not none.any()


@pytest.mark.parametrize(
    "kwargs, error, message",
    [
        ({"solids": ["y<<0"]}, ValueError, "solid 'y<<0':"),
        ({"solids": ["w<0"]}, ValueError, "solid 'w<0': unknown axis"),
        ({"solids": [0]}, TypeError, "solids must be a string or a sequence of strings"),
        ({"solids": ["z<0"]}, ValueError, "solid 'z<0': a 2D set has no z axis"),
        ({"periodic": ["x:1:0"]}, ValueError, "periodic 'x:1:0':"),
        ({"periodic": ["x:0"]}, ValueError, "periodic 'x:0': not three fields"),
        ({"periodic": ["x:0:1.9"]}, ValueError, "particle 2: x = 2 lies outside"),
        ({"walls": [[0.0, 0.0, 0.0]]}, ValueError, "walls must be an (m, 2) array"),
        ({"walls": [0.0, 1.0]}, ValueError, "walls must be an (m, 2) array"),
        ({"walls": [["a", "b"]]}, ValueError, "walls must be an array of reals"),
        ({"walls": [[0.0, np.nan]]}, ValueError, "walls: particle 0: coordinate 1"),
        ({"wall_radii": [1.0]}, ValueError, "wall_radii given without walls"),
        (
            {"walls": [[0.0, -1.0]], "wall_radii": [-1.0]},
            ValueError,
            "wall_radii: particle 0: radius must be positive and finite",
        ),
        (
            {"walls": [[0.0, -1.0]], "wall_radii": [1.0, 1.0]},
            ValueError,
            "wall_radii: 2 radii for 1 particles",
        ),
        ({"phases": [0, 1]}, ValueError, "2 phase numbers for 3 particles"),
        ({"phases": [0.5, 1, 2]}, ValueError, "phases must be integers"),
        ({"phases": [0, -1, 2]}, ValueError, "phases: particle 1: phase -1 is outside"),
        ({"phases": [[0, 1, 2]]}, ValueError, "phases must be a one-dimensional array"),
        ({"method": "muller", "solids": ["y<0"]}, ValueError, "cannot honour solid"),
    ],
)
def test_bad_domains_raise_with_the_library_message(kwargs, error, message):
    points = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    with pytest.raises(error) as info:
        boundary.detect(points, 0.8, **kwargs)
    assert message in str(info.value), str(info.value)


def test_a_refused_solid_names_the_arguments_of_detect_not_the_flags_of_the_cli():
    points = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    with pytest.raises(ValueError) as info:
        boundary.detect(points, 0.8, method="muller", solids=["y<0"])
    message = str(info.value)
    assert "solid half-spaces (solids=)" in message, message
    assert "wall particles (walls=)" in message, message
    assert "--" not in message, message
