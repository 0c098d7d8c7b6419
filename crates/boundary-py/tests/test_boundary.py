"""Tests of the Python package `boundary_particles` against the installed wheel (run by
`cargo xtask test` from outside the source tree).

They check the translation (array layout, dimension, parameters, order of the labels,
errors, files) on inputs whose labels are known by construction (lattices) or on the bundled
fixture scenes (`fixtures/` of the repository, read with NumPy's own CSV reader), and the
relations the Rust tests establish between the methods (`dilts` equals `exact`; certified
methods have no false negative). They need neither the `boundary` command nor the public
data.
"""

import os
import signal
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import boundary_particles as bp

FIXTURES = Path(__file__).resolve().parents[3] / "fixtures"

# (file under fixtures/, radius of fixtures/scenes.toml): a 2D and a 3D scene.
SCENES = [("vortex2d_t1.csv", 0.0075), ("ball_bubble3d.csv", 0.15)]

# The keys of `boundary score --json` (crates/boundary-cli/src/score.rs), which Python and
# the C API (`struct boundary_confusion`) share.
CONFUSION_KEYS = {"tp", "tn", "fp", "fn", "recall", "fpr", "m", "precision", "f1"}


def load_points(name: str) -> np.ndarray:
    path = FIXTURES / name
    assert path.is_file(), f"bundled fixture missing: {path}"
    table = np.genfromtxt(path, delimiter=",", names=True)
    axes = [a for a in ("x", "y", "z") if a in table.dtype.names]
    return np.ascontiguousarray(np.column_stack([table[a] for a in axes]), dtype=np.float64)


def jittered_ball(n_side: int, dim: int, seed: int = 7) -> np.ndarray:
    """A jittered lattice (spacing 1) clipped to a ball: an interior and a boundary."""
    rng = np.random.default_rng(seed)
    axes = [np.arange(n_side, dtype=np.float64)] * dim
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, dim)
    centre = (n_side - 1) / 2
    grid = grid[np.linalg.norm(grid - centre, axis=1) <= centre]
    return grid + rng.uniform(-0.1, 0.1, grid.shape)


def lattice(side: int, dim: int, spacing: float = 1.0) -> np.ndarray:
    """A side^dim square or cubic lattice, and which of its particles are on its outer layer."""
    axes = [np.arange(side, dtype=np.float64)] * dim
    return spacing * np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, dim)


def outer_layer(points: np.ndarray, side: int, spacing: float = 1.0) -> np.ndarray:
    k = np.rint(points / spacing)
    return np.any((k == 0) | (k == side - 1), axis=1)


# ---- labels --------------------------------------------------------------------------------


@pytest.mark.parametrize("dim", [2, 3])
def test_a_lattice_is_boundary_exactly_on_its_outer_layer(dim):
    # Spacing 1 at r = 1: an inner particle's sphere is covered by its 2*dim axis neighbours'
    # balls (r >= 1/sqrt(2) in 2D, sqrt(3)/2 in 3D); an outer one has a side uncovered.
    side = 7
    points = lattice(side, dim)
    truth = outer_layer(points, side)
    labels = bp.detect(points, 1.0)
    assert labels.dtype == np.bool_ and labels.shape == (len(points),)
    np.testing.assert_array_equal(labels, truth)
    # Labels follow their particles through a permutation of the input.
    order = np.random.default_rng(3).permutation(len(points))
    np.testing.assert_array_equal(bp.detect(points[order], 1.0), truth[order])
    # Scaled lattices with the scaled radius: the same labels.
    np.testing.assert_array_equal(bp.detect(points * 0.001, 0.001), truth)


@pytest.mark.parametrize("name,r", SCENES)
def test_every_method_runs_on_the_fixtures_with_the_relations_of_the_library(name, r):
    points = load_points(name)
    names = [m["name"] for m in bp.methods()]
    assert {"exact", "dilts", "ia", "ge", "marrone", "muller", "hpr", "svm"} <= set(names)
    exact = bp.detect(points, r)
    assert 0 < exact.sum() < len(points)
    for info in bp.methods():
        detector = bp.Detector(info["name"])
        labels = detector.detect(points, r)
        assert labels.dtype == np.bool_ and labels.shape == (len(points),), info["name"]
        # The same detector again, and the one-call form: the same labels.
        np.testing.assert_array_equal(detector.detect(points, r), labels)
        np.testing.assert_array_equal(bp.detect(points, r, info["name"]), labels)
        assert detector.certified == info["certified"]
        if info["certified"]:
            assert not np.any(exact & ~labels), f"{info['name']} missed a boundary particle"
    np.testing.assert_array_equal(bp.detect(points, r, "dilts"), exact)


def test_keyword_parameters_reach_the_method():
    points = load_points(SCENES[1][0])
    r = SCENES[1][1]
    ge = bp.Detector("ge", depth=2)
    assert ge.settings()["depth"] == "2" and ge.params == {"depth": 2}
    assert bp.Detector("ge").settings()["depth"] != "2"
    np.testing.assert_array_equal(ge.detect(points, r), bp.detect(points, r, "ge", depth=2))
    hpr = bp.Detector("hpr", gamma=1.6, cavity=False)
    assert hpr.settings()["cavity"] in ("false", "off")
    # A parameter changes the labels: it is applied, not dropped.
    default = bp.detect(points, r, "muller")
    assert not np.array_equal(default, bp.detect(points, r, "muller", threshold=0.1))
    assert repr(ge) == "Detector('ge', depth=2)" and str(ge) == "ge (depth=2)"
    assert bp.Detector("exact", threads=2).threads == 2


def test_methods_list_their_parameters_as_their_detectors_have_them():
    for info in bp.methods():
        assert info["summary"] and isinstance(info["certified"], bool)
        settings = bp.Detector(info["name"]).settings()
        assert [p["name"] for p in info["params"]] == list(settings)
        assert [p["default"] for p in info["params"]] == list(settings.values())
        assert all(p["description"] for p in info["params"])


def test_r_auto_is_k_times_the_spacing_measured_in_the_bulk():
    points = lattice(30, 2, spacing=0.5)
    assert abs(bp.bulk_spacing(points) / 0.5 - 1) < 0.05
    r = bp.auto_radius(points)
    assert r == bp.RADIUS_PER_SPACING * bp.bulk_spacing(points)
    np.testing.assert_array_equal(bp.detect(points, "auto"), bp.detect(points, r))
    np.testing.assert_array_equal(bp.detect(points, r="AUTO"), bp.detect(points, r))
    ball = jittered_ball(12, 3)
    np.testing.assert_array_equal(
        bp.detect(ball, "auto", "ge"), bp.detect(ball, bp.auto_radius(ball), "ge")
    )
    with pytest.raises(ValueError, match="two distinct particle positions"):
        bp.detect([[1.0, 1.0], [1.0, 1.0]], "auto")
    with pytest.raises(ValueError, match='r must be a positive real or "auto"'):
        bp.detect(points, "big")
    with pytest.raises(TypeError, match='r must be a positive real or "auto"'):
        bp.detect(points, [1.0])
    with pytest.raises(ValueError, match="with radii= give r as the scale"):
        bp.detect(points, "auto", radii=np.ones(len(points)))


# ---- scores ------------------------------------------------------------------------------


def test_confusion_scores_given_labels_with_the_keys_of_the_cli():
    predicted = np.array([1, 1, 1, 0, 0, 0, 0, 0], dtype=bool)
    truth = np.array([1, 1, 0, 1, 0, 0, 0, 0], dtype=bool)
    c = bp.confusion(predicted, truth)
    assert set(c) == CONFUSION_KEYS
    assert (c["tp"], c["fp"], c["fn"], c["tn"]) == (2, 1, 1, 4)
    assert c["recall"] == pytest.approx(2 / 3) and c["fpr"] == pytest.approx(1 / 5)
    assert c["m"] == pytest.approx(2 / 3 * 4 / 5)
    assert c["precision"] == pytest.approx(2 / 3) and c["f1"] == pytest.approx(2 / 3)
    # 0/1 integers and lists are labels too.
    assert bp.confusion(predicted.astype(np.int64).tolist(), truth.astype(np.uint8)) == c
    with pytest.raises(ValueError, match="predicted has 8 labels and truth 3"):
        bp.confusion(predicted, truth[:3])
    with pytest.raises(ValueError, match="truth: particle 2: a label must be 0 or 1"):
        bp.confusion([0, 0, 0], [0, 1, 2])
    with pytest.raises(ValueError, match="one-dimensional"):
        bp.confusion([[0, 1]], [[0, 1]])


def test_score_is_the_confusion_of_the_method_against_exact():
    name, r = SCENES[1]
    points = load_points(name)
    exact = bp.detect(points, r)
    muller = bp.detect(points, r, "muller")
    got = bp.score(points, r, "muller")
    assert got == bp.confusion(muller, exact)
    assert bp.score(points, r, "muller", truth=exact.astype(np.int64)) == got
    perfect = bp.score(points, r, "exact", truth=exact)
    assert perfect["fp"] == perfect["fn"] == 0 and perfect["m"] == 1.0
    with pytest.raises(ValueError, match=r"truth: 3 labels for \d+ particles|predicted has"):
        bp.score(points, r, "ia", truth=[True, False, True])


# ---- resampling --------------------------------------------------------------------------


def test_resample_keeps_interior_particles_and_names_its_features():
    name, r = SCENES[0]
    points = load_points(name)
    labels = bp.detect(points, r)
    new, feature, source = bp.resample(points, r)
    assert new.shape[1] == 2 and len(new) == len(feature) == len(source)
    assert set(np.unique(feature)) <= set(bp.FEATURES)
    assert bp.FEATURES[0] == "droplet" and bp.FEATURES[-1] == "interior"
    assert source.min() >= 0 and source.max() < len(points)
    # Interior particles stay where they were; boundary ones get a feature.
    interior = feature == -1
    np.testing.assert_array_equal(new[interior], points[source[interior]])
    assert not labels[source[interior]].any()
    assert labels[source[~interior]].all()
    # The same from the given labels.
    again = bp.resample(points, r, labels=labels)
    for a, b in zip(again, (new, feature, source)):
        np.testing.assert_array_equal(a, b)
    # All interior keeps every particle in place.
    kept, codes, src = bp.resample(points, r, labels=np.zeros(len(points), bool))
    assert np.array_equal(kept, points) and (codes == -1).all()
    assert np.array_equal(src, np.arange(len(points)))


# ---- array handling ---------------------------------------------------------------------


def test_float64_c_contiguous_points_are_read_in_place():
    points = jittered_ball(10, 3)
    assert points.flags.c_contiguous and points.dtype == np.float64
    assert bp._native._points_address(points) == points.ctypes.data
    # Anything else is converted first (so read elsewhere), and gives the same labels.
    as32 = points.astype(np.float32)
    fortran = np.asfortranarray(points)
    assert bp._native._points_address(as32) != as32.ctypes.data
    assert bp._native._points_address(fortran) != fortran.ctypes.data
    labels = bp.detect(points, 1.0)
    assert np.array_equal(bp.detect(fortran, 1.0), labels)
    assert np.array_equal(bp.detect(points.tolist(), 1.0), labels)
    assert np.array_equal(
        bp.detect(as32, 1.0), bp.detect(as32.astype(np.float64), 1.0)
    )


def test_empty_sets_and_2d_lists_work():
    assert bp.detect(np.zeros((0, 3)), 1.0).shape == (0,)
    square = [[x, y] for y in range(6) for x in range(6)]
    labels = bp.detect(square, 0.8)
    # A 6 x 6 lattice of spacing 1 at r = 0.8: the 4 x 4 core is interior.
    assert labels.sum() == 36 - 16


def test_margin_is_returned_when_the_method_has_one():
    points = jittered_ball(8, 2)
    labels, margin = bp.detect(points, 1.0, margin=True)
    assert margin is not None and margin.shape == labels.shape
    assert np.array_equal(labels, bp.detect(points, 1.0))
    # exact: the margin leans boundary exactly where the label is boundary (no tie here).
    assert np.array_equal(labels, margin > 0)
    for m in bp.methods():
        got_labels, got_margin = bp.detect(points, 1.0, m["name"], margin=True)
        assert got_margin is None or got_margin.shape == got_labels.shape


def test_threads_do_not_change_the_labels():
    points = jittered_ball(14, 3)
    assert np.array_equal(
        bp.detect(points, 1.0, "ia", threads=1), bp.detect(points, 1.0, "ia")
    )


# ---- errors -----------------------------------------------------------------------------


@pytest.mark.parametrize(
    "points,r,method,params,message",
    [
        ([[0.0, 0.0], [float("nan"), 1.0]], 1.0, "exact", {}, r"particle 1: coordinate 0 is not finite \(NaN\)"),
        ([[0.0, 0.0, float("inf")]], 1.0, "exact", {}, r"particle 0: coordinate 2 is not finite"),
        (np.zeros((5, 4)), 1.0, "exact", {}, r"\(n, 2\) or \(n, 3\) array, got shape \(5, 4\)"),
        (np.zeros(6), 1.0, "exact", {}, r"got shape \(6,\)"),
        (np.zeros((2, 2, 2)), 1.0, "exact", {}, r"got shape \(2, 2, 2\)"),
        ([["a", "b"]], 1.0, "exact", {}, r"array of reals"),
        ([[0.0, 0.0]], 0.0, "exact", {}, r"radius must be positive and finite, got 0"),
        ([[0.0, 0.0]], -1.0, "exact", {}, r"radius must be positive and finite, got -1"),
        ([[0.0, 0.0]], float("nan"), "exact", {}, r"radius must be positive and finite, got NaN"),
        ([[0.0, 0.0]], 1.0, "nope", {}, r"unknown method 'nope' \(available: exact, "),
        ([[0.0, 0.0]], 1.0, "exact", {"depth": 3}, r"method 'exact' has no parameter 'depth'"),
        ([[0.0, 0.0]], 1.0, "ge", {"depth": "deep"}, r"method 'ge': invalid value 'deep' for 'depth'"),
    ],
)
def test_bad_input_raises_value_error_with_the_cli_message(points, r, method, params, message):
    with pytest.raises(ValueError, match=message):
        bp.detect(points, r, method, **params)


def flat_grid(axis, value):
    """A 10 x 10 square lattice of spacing 1 as an (100, 3) array, coordinate axis = value."""
    grid = np.array([[x, y] for y in range(10) for x in range(10)], dtype=np.float64)
    return np.insert(grid, axis, value, axis=1)


@pytest.mark.parametrize(
    "axis,value,message,flat_slice",
    [
        (2, 0.0, r"all 100 particles have z = 0: a flat set is 2D.*pass dim=2 \(or points\[:, :2\] \(x and y\)", np.s_[:, :2]),
        (1, -2.5, r"all 100 particles have y = -2.5: .*pass dim=2 \(or points\[:, \[0, 2\]\] \(x and z\)", np.s_[:, [0, 2]]),
        (0, 3.0, r"all 100 particles have x = 3: .*pass dim=2 \(or points\[:, 1:\] \(y and z\)", np.s_[:, 1:]),
    ],
)
def test_a_flat_3d_set_raises_naming_dim_2_the_axis_and_the_slice(axis, value, message, flat_slice):
    points = flat_grid(axis, value)
    for call in [
        lambda: bp.detect(points, 1.0),
        lambda: bp.detect(points, "auto"),
        lambda: bp.score(points, 1.0, "ia"),
        lambda: bp.resample(points, 1.0),
    ]:
        with pytest.raises(ValueError, match=message) as info:
            call()
        assert "pass dim=2" in str(info.value), str(info.value)
    # The slice it names is the 2D set: the 8 x 8 inner particles are interior at r = 1.
    assert bp.detect(points[flat_slice], 1.0).sum() == 36
    # dim=2 drops the constant axis: the same labels; dim=3 keeps it 3D (all boundary).
    np.testing.assert_array_equal(bp.detect(points, 1.0, dim=2), bp.detect(points[flat_slice], 1.0))
    assert bp.detect(points, 1.0, dim=3).all()
    with pytest.raises(ValueError, match="dim=2 but none of x, y, z is constant"):
        bp.detect(jittered_ball(6, 3), 1.0, dim=2)
    with pytest.raises(ValueError, match="dim=3 but points is an \\(n, 2\\) array"):
        bp.detect(points[flat_slice], 1.0, dim=3)


def test_particles_all_at_one_place_raise_but_one_particle_does_not():
    with pytest.raises(ValueError, match=r"all 3 particles are at \(1, 2, 3\): the set has no extent"):
        bp.detect([[1.0, 2.0, 3.0]] * 3, 1.0)
    assert bp.detect([[1.0, 2.0, 3.0]], 1.0).tolist() == [True]
    # Flat walls are fine: a wall is often one plane of particles.
    block = np.array([[x, y, z] for z in range(1, 4) for y in range(3) for x in range(3)], float)
    floor = flat_grid(2, 0.0)
    assert bp.detect(block, 1.0, walls=floor).shape == (27,)


def test_bad_threads_and_truth_raise_clear_errors():
    points = jittered_ball(6, 2)
    with pytest.raises(ValueError, match="threads must be at least 1"):
        bp.detect(points, 1.0, threads=0)
    with pytest.raises(ValueError, match="threads must be at least 1"):
        bp.Detector("exact", threads=0)
    with pytest.raises(ValueError, match=r"predicted has \d+ labels and truth 3"):
        bp.score(points, 1.0, "ia", truth=[True, False, True])
    with pytest.raises(ValueError, match="truth: particle 0: a label must be 0 or 1"):
        bp.score(points, 1.0, "ia", truth=np.full(len(points), 2))
    with pytest.raises(ValueError, match=r"unknown method 'nope'"):
        bp.Detector("nope")


# ---- files ------------------------------------------------------------------------------


@pytest.mark.parametrize("suffix", [".csv", ".vtu", ".vtk", ".ply", ".bgeo"])
def test_write_then_read_keeps_points_labels_and_point_data(suffix, tmp_path):
    points = jittered_ball(7, 3)
    labels = bp.detect(points, 1.0)
    n = len(points)
    pressure = np.linspace(0.0, 1.0, n)
    ids = np.arange(n, dtype=np.int32)
    velocity = np.column_stack([pressure, -pressure, 2 * pressure])
    path = tmp_path / f"frame{suffix}"
    # Names that are keywords of `write` are attributes like any other.
    point_data = {"pressure": pressure, "ids": ids, "format": ids * 2, "velocity": velocity}
    bp.write(path, points, boundary=labels, point_data=point_data)
    back, data = bp.read(path)
    assert back.shape == points.shape
    assert np.allclose(back, points, rtol=0, atol=1e-6 * np.abs(points).max())
    if suffix == ".ply":
        # PLY property names are identifiers: a vector's components are written (and read
        # back) as the scalar properties velocity_0, velocity_1, velocity_2.
        components = {f"velocity_{k}" for k in range(3)}
        assert set(data) == {"boundary", "pressure", "ids", "format"} | components
        for k in range(3):
            assert np.allclose(data[f"velocity_{k}"], velocity[:, k], rtol=1e-6, atol=1e-12)
    else:
        assert set(data) == {"boundary"} | set(point_data)
    assert np.array_equal(data["boundary"] == 1, labels)
    assert np.allclose(data["pressure"], pressure, rtol=1e-6, atol=1e-12)
    assert np.array_equal(data["ids"], ids) and data["ids"].dtype == np.int64
    assert np.array_equal(data["format"], ids * 2)
    if suffix == ".ply":
        return
    # A vector attribute comes back as an (n, k) array, as meshio gives it.
    assert data["velocity"].shape == (n, 3)
    assert np.allclose(data["velocity"], velocity, rtol=1e-6, atol=1e-12)


def test_read_gives_the_positions_of_the_bundled_files():
    for name, _ in SCENES:
        points, point_data = bp.read(FIXTURES / name)
        assert np.array_equal(points, load_points(name))
        assert point_data == {}


def test_read_takes_any_particle_array_of_a_pysph_file():
    # PySPH's dam break (fixtures/pysph): `fluid` by default, `boundary` when named, each as
    # PySPH's own loader exported it; an array the file lacks, or one asked of a format
    # without named arrays, is a ValueError naming it.
    pysph = FIXTURES / "pysph"
    hdf5 = pysph / "dam_break_2d_00010.hdf5"
    arrays = [
        (None, "fluid_loaded.csv"),
        ("fluid", "fluid_loaded.csv"),
        ("boundary", "boundary_loaded.csv"),
    ]
    for array, loaded in arrays:
        points, point_data = bp.read(hdf5, array=array)
        expected, _ = bp.read(pysph / loaded, dim=2)
        np.testing.assert_array_equal(points, expected)
        assert "gid" in point_data
    npz_points, _ = bp.read(pysph / "dam_break_2d_00010.npz", array="boundary")
    np.testing.assert_array_equal(npz_points, bp.read(hdf5, array="boundary")[0])
    with pytest.raises(ValueError, match='"solid"'):
        bp.read(hdf5, array="solid")
    with pytest.raises(ValueError, match="only PySPH files"):
        bp.read(pysph / "fluid_loaded.csv", array="fluid")


def test_write_is_atomic_a_failed_write_leaves_no_file(tmp_path):
    points = jittered_ball(5, 3)
    # A folder where the file should go: the rename into place fails, naming the file, and
    # the temporary file written beside it is removed.
    taken = tmp_path / "taken.csv"
    taken.mkdir()
    with pytest.raises(OSError, match="taken.csv"):
        bp.write(taken, points)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["taken.csv"]
    with pytest.raises(FileNotFoundError, match="missing"):
        bp.write(tmp_path / "missing" / "out.csv", points)
    # Writing over the file the points were read from replaces it whole.
    path = tmp_path / "frame.csv"
    bp.write(path, points)
    back, _ = bp.read(path)
    bp.write(path, back, boundary=np.ones(len(back), dtype=bool))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["frame.csv", "taken.csv"]
    assert np.all(bp.read(path)[1]["boundary"] == 1)


def test_read_refuses_a_misspelt_z_and_a_file_of_no_particle(tmp_path):
    # `x,y,zz` would silently be 2D: a ValueError naming the file, the column and the fix,
    # the text of `boundary detect`'s error.
    typo = tmp_path / "typo.csv"
    typo.write_text("x,y,zz\n0,0,0\n1,0,1\n0,1,2\n")
    with pytest.raises(ValueError) as error:
        bp.read(typo)
    assert str(error.value) == (
        f'column "zz" in {typo} line 1 column 3 looks like a misspelt z, and without a z the '
        "file would be read as 2D from x, y: rename it to z, or pass --dim 2 (Python: dim=2) "
        "to read it as 2D on purpose"
    )
    # 2D on purpose: x and y; the other column is point data.
    points, point_data = bp.read(typo, dim=2)
    assert points.shape == (3, 2)
    assert np.array_equal(point_data["zz"], [0, 1, 2])
    # A header without rows is no empty set.
    header_only = tmp_path / "header.csv"
    header_only.write_text("x,y,z\n")
    with pytest.raises(ValueError) as error:
        bp.read(header_only)
    assert str(error.value) == (
        f"no particles in {header_only}: the header on line 1 (x, y, z) is followed by no "
        "data row"
    )
    empty = tmp_path / "empty.xyz"
    empty.write_text("")
    with pytest.raises(ValueError, match=r"no particles in .*empty\.xyz: .*\(empty file\)"):
        bp.read(empty)


def test_bad_files_and_point_data_raise_clear_errors(tmp_path):
    points = jittered_ball(6, 2)
    with pytest.raises(FileNotFoundError, match="cannot read .*missing.csv"):
        bp.read(tmp_path / "missing.csv")
    bad = tmp_path / "bad.csv"
    bad.write_text("x,y\n0,0\n1,oops\n")
    with pytest.raises(ValueError, match="bad.csv"):
        bp.read(bad)
    with pytest.raises(ValueError, match="unknown particle file format"):
        bp.write(tmp_path / "out.unknown", points)
    with pytest.raises(ValueError, match=r"column \"pressure\""):
        bp.write(tmp_path / "out.csv", points, point_data={"pressure": np.zeros(3)})
    with pytest.raises(ValueError, match=r"point_data \"cube\": expected an \(n,\) or \(n, k\)"):
        bp.write(tmp_path / "out.csv", points, point_data={"cube": np.zeros((len(points), 2, 2))})
    with pytest.raises(TypeError, match="point_data must be a mapping"):
        bp.write(tmp_path / "out.csv", points, point_data=[1, 2])  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="boundary: 3 labels for"):
        bp.write(tmp_path / "out.csv", points, boundary=[True, False, True])
    assert not (tmp_path / "out.csv").exists()


# ---- the GIL and Ctrl-C -----------------------------------------------------------------


def test_the_gil_is_released_during_detection():
    points = jittered_ball(36, 3)
    started = threading.Event()

    def work():
        started.set()
        bp.detect(points, 1.0, "exact", threads=1)

    worker = threading.Thread(target=work)
    worker.start()
    started.wait()
    spins = 0
    while worker.is_alive():
        spins += 1
    worker.join()
    # With the GIL held for the whole detection this loop could not run during it.
    assert spins > 10_000, spins


def worker_threads() -> list:
    """The detection workers alive in this process (Linux: the names of its threads; the
    package names its workers `boundary-K`)."""
    tasks = Path("/proc/self/task")
    assert tasks.is_dir(), "this test reads the thread names of /proc (Linux)"
    names = []
    for task in tasks.iterdir():
        try:
            names.append((task / "comm").read_text().strip())
        except OSError:  # the thread ended meanwhile
            pass
    return [n for n in names if n.startswith("boundary-")]


def test_ctrl_c_stops_the_workers_not_only_the_wait():
    # About 380k particles at r = 2.5 (spacing 1: about 520 neighbours within 2r): several
    # seconds on two threads, far longer than the timer's delay.
    points = jittered_ball(90, 3)
    # Python installs its Ctrl-C handler only if SIGINT was not ignored when it started, and a
    # shell starting a job in the background ignores it: install it for this test, as an
    # interactive interpreter has it.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    try:
        timer.start()
        with pytest.raises(KeyboardInterrupt):
            bp.detect(points, 2.5, "exact", threads=2)
        timer.join()
    finally:
        signal.signal(signal.SIGINT, previous)
    # When KeyboardInterrupt is raised the workers have left their loops; their threads end
    # as the pool is dropped (asynchronously: wait for them, a few seconds at most).
    deadline = time.monotonic() + 5.0
    while worker_threads() and time.monotonic() < deadline:
        time.sleep(0.01)
    assert worker_threads() == [], "detection workers still alive after Ctrl-C"
    # Nothing computes in the background: the process uses no CPU while this thread sleeps
    # (a detection left running would use up to two cores' worth).
    cpu = time.process_time()
    time.sleep(0.5)
    assert time.process_time() - cpu < 0.2
    # The package still works after an interrupt.
    assert bp.detect([[0.0, 0.0], [1.0, 0.0]], 1.0).all()


def test_the_stop_leaves_the_workers_of_other_detections_alone():
    # A detection on a worker thread of its own runs to its end while the main thread
    # interrupts (and recovers from) another one.
    points = jittered_ball(60, 3)
    expected = bp.detect(points, 1.8)
    got = []
    other = threading.Thread(target=lambda: got.append(bp.detect(points, 1.8)))
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.2, lambda: os.kill(os.getpid(), signal.SIGINT))
    try:
        other.start()
        timer.start()
        with pytest.raises(KeyboardInterrupt):
            bp.detect(jittered_ball(90, 3), 2.5, threads=1)
        timer.join()
    finally:
        signal.signal(signal.SIGINT, previous)
    other.join()
    assert len(got) == 1
    np.testing.assert_array_equal(got[0], expected)
