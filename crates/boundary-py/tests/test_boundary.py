"""Tests of the Python package `boundary` (run by `cargo xtask test`).

The reference for labels is the `boundary` command (a separate program over the same Rust
library): these tests check the translation (array layout, dimension, parameters, order of
the labels, errors), not the detectors, which the Rust tests check. The input positions are
read with NumPy's own CSV reader, not with `boundary.read`, and the CLI's output is parsed
with Python's `csv` module.

Needs: the built CLI (`BOUNDARY_CLI`, else `target/{debug,release}/boundary` of this
repository) and the public data (`BOUNDARY_DATA_DIR`, else `../shared/data`).
"""

import csv
import json
import os
import signal
import subprocess
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import boundary

REPO = Path(__file__).resolve().parents[3]
DATA = Path(os.environ.get("BOUNDARY_DATA_DIR", REPO.parent / "shared" / "data"))

# (file under the data directory, radius): a 2D and a 3D scene of fixtures/scenes.toml.
SCENES = [
    ("particles2d/sandim_vortex_spin_frame_050_1698.csv", 0.022105),
    ("particles3d/dualsphysics_dambreak3d_dp0.02_fluid.csv", 0.0346),
]


def cli_path() -> Path:
    given = os.environ.get("BOUNDARY_CLI")
    candidates = [Path(given)] if given else [
        REPO / "target" / "debug" / "boundary",
        REPO / "target" / "release" / "boundary",
    ]
    for path in candidates:
        if path.is_file():
            return path
    pytest.fail(
        "the boundary CLI is needed as the reference: build it (cargo build -p boundary-cli) "
        f"or set BOUNDARY_CLI; looked at {', '.join(map(str, candidates))}"
    )


def cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [str(cli_path()), *args], check=True, capture_output=True, text=True
    )


def load_points(relative: str) -> np.ndarray:
    path = DATA / relative
    assert path.is_file(), f"public data missing: {path}"
    table = np.genfromtxt(path, delimiter=",", names=True)
    axes = [a for a in ("x", "y", "z") if a in table.dtype.names]
    return np.ascontiguousarray(np.column_stack([table[a] for a in axes]), dtype=np.float64)


def csv_column(path: Path, name: str) -> list:
    with open(path, newline="") as f:
        return [row[name] for row in csv.DictReader(f)]


def cli_labels(relative: str, r: float, method: str, sets: list, tmp: Path) -> np.ndarray:
    out = tmp / f"{method}.csv"
    args = ["detect", str(DATA / relative), "--radius", str(r), "--method", method]
    for s in sets:
        args += ["--set", s]
    cli(*args, "--output", str(out))
    return np.array([int(v) for v in csv_column(out, "boundary")]) == 1


def jittered_ball(n_side: int, dim: int, seed: int = 7) -> np.ndarray:
    """A jittered lattice (spacing 1) clipped to a ball: an interior and a boundary."""
    rng = np.random.default_rng(seed)
    axes = [np.arange(n_side, dtype=np.float64)] * dim
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, dim)
    centre = (n_side - 1) / 2
    grid = grid[np.linalg.norm(grid - centre, axis=1) <= centre]
    return grid + rng.uniform(-0.1, 0.1, grid.shape)


# ---- labels against the CLI ------------------------------------------------------------


@pytest.mark.parametrize("relative,r", SCENES)
def test_every_method_gives_the_labels_of_the_cli(relative, r, tmp_path):
    points = load_points(relative)
    names = [m["name"] for m in boundary.methods()]
    assert {"exact", "dilts", "ia", "ge", "marrone", "muller", "hpr", "svm"} <= set(names)
    for method in names:
        ours = boundary.detect(points, r, method=method)
        assert ours.dtype == np.bool_ and ours.shape == (len(points),)
        theirs = cli_labels(relative, r, method, [], tmp_path)
        assert np.array_equal(ours, theirs), f"{method} on {relative}"


@pytest.mark.parametrize("relative,r", SCENES)
def test_keyword_parameters_act_as_cli_set(relative, r, tmp_path):
    points = load_points(relative)
    cases = [
        ("ge", {"depth": 2}, ["depth=2"]),
        ("ia", {"depth": 3}, ["depth=3"]),
        ("hpr", {"gamma": 1.6, "cavity": False}, ["gamma=1.6", "cavity=off"]),
        ("muller", {"threshold": 0.3}, ["threshold=0.3"]),
    ]
    for method, params, sets in cases:
        ours = boundary.detect(points, r, method, **params)
        theirs = cli_labels(relative, r, method, sets, tmp_path)
        assert np.array_equal(ours, theirs), f"{method} {params} on {relative}"
    # A keyword parameter is really applied, not dropped.
    default = boundary.detect(points, r, "muller")
    assert not np.array_equal(default, boundary.detect(points, r, "muller", threshold=0.1))


def test_score_matches_the_cli_and_given_truth(tmp_path):
    relative, r = SCENES[1]
    points = load_points(relative)
    got = boundary.score(points, r, "muller")
    assert set(got) == {"TP", "TN", "FP", "FN", "Rec", "FPR", "M"}
    theirs = json.loads(
        cli("score", str(DATA / relative), "--radius", str(r), "--method", "muller", "--json").stdout
    )
    for key, cli_key in [("TP", "tp"), ("TN", "tn"), ("FP", "fp"), ("FN", "fn")]:
        assert got[key] == theirs[cli_key], key
    for key, cli_key in [("Rec", "recall"), ("FPR", "fpr"), ("M", "m")]:
        assert got[key] == pytest.approx(theirs[cli_key], rel=1e-12), key
    exact = boundary.detect(points, r)
    assert boundary.score(points, r, "muller", truth=exact) == got
    assert boundary.score(points, r, "muller", truth=exact.astype(np.int64)) == got
    perfect = boundary.score(points, r, "exact", truth=exact)
    assert perfect["FP"] == perfect["FN"] == 0 and perfect["M"] == 1.0


def test_methods_are_the_data_of_the_cli():
    theirs = json.loads(cli("methods", "--json").stdout)
    ours = boundary.methods()
    assert [m["name"] for m in ours] == [m["name"] for m in theirs]
    for a, b in zip(ours, theirs):
        assert a["summary"] == b["summary"] and a["certified"] == b["certified"]
        assert [(p["name"], p["default"]) for p in a["params"]] == [
            (p["name"], p["default"]) for p in b["params"]
        ]


def test_resample_gives_the_particles_of_the_cli(tmp_path):
    relative, r = SCENES[0]
    points = load_points(relative)
    new, feature, source = boundary.resample(points, r)
    out = tmp_path / "resampled.csv"
    cli("resample", str(DATA / relative), "--radius", str(r), "--output", str(out))
    assert np.array_equal(feature, np.array([int(v) for v in csv_column(out, "feature")]))
    assert np.array_equal(source, np.array([int(v) for v in csv_column(out, "source")]))
    xy = np.column_stack([[float(v) for v in csv_column(out, a)] for a in ("x", "y")])
    assert np.array_equal(new, xy)
    assert set(np.unique(feature)) <= set(boundary.FEATURES)
    assert boundary.FEATURES[0] == "droplet" and boundary.FEATURES[-1] == "interior"
    # Given labels instead of a method: all interior keeps every particle in place.
    kept, codes, src = boundary.resample(points, r, labels=np.zeros(len(points), bool))
    assert np.array_equal(kept, points) and (codes == -1).all()
    assert np.array_equal(src, np.arange(len(points)))


# ---- array handling ---------------------------------------------------------------------


def test_float64_c_contiguous_points_are_read_in_place():
    points = jittered_ball(10, 3)
    assert points.flags.c_contiguous and points.dtype == np.float64
    assert boundary._points_address(points) == points.ctypes.data
    # Anything else is converted first (so read elsewhere), and gives the same labels.
    as32 = points.astype(np.float32)
    fortran = np.asfortranarray(points)
    assert boundary._points_address(as32) != as32.ctypes.data
    assert boundary._points_address(fortran) != fortran.ctypes.data
    labels = boundary.detect(points, 1.0)
    assert np.array_equal(boundary.detect(fortran, 1.0), labels)
    assert np.array_equal(boundary.detect(points.tolist(), 1.0), labels)
    assert np.array_equal(
        boundary.detect(as32, 1.0), boundary.detect(as32.astype(np.float64), 1.0)
    )


def test_empty_sets_and_2d_lists_work():
    assert boundary.detect(np.zeros((0, 3)), 1.0).shape == (0,)
    square = [[x, y] for y in range(6) for x in range(6)]
    labels = boundary.detect(square, 0.8)
    # A 6 x 6 lattice of spacing 1 at r = 0.8: the 4 x 4 core is interior.
    assert labels.sum() == 36 - 16


def test_margin_is_returned_when_the_method_has_one():
    points = jittered_ball(8, 2)
    labels, margin = boundary.detect(points, 1.0, margin=True)
    assert margin is not None and margin.shape == labels.shape
    assert np.array_equal(labels, boundary.detect(points, 1.0))
    # exact: the margin leans boundary exactly where the label is boundary (no tie here).
    assert np.array_equal(labels, margin > 0)
    for m in boundary.methods():
        got_labels, got_margin = boundary.detect(points, 1.0, m["name"], margin=True)
        assert got_margin is None or got_margin.shape == got_labels.shape


def test_threads_do_not_change_the_labels():
    points = jittered_ball(14, 3)
    assert np.array_equal(
        boundary.detect(points, 1.0, "ia", threads=1), boundary.detect(points, 1.0, "ia")
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
        boundary.detect(points, r, method, **params)


def flat_grid(axis, value):
    """A 10 x 10 square lattice of spacing 1 as an (100, 3) array, coordinate axis = value."""
    grid = np.array([[x, y] for y in range(10) for x in range(10)], dtype=np.float64)
    return np.insert(grid, axis, value, axis=1)


@pytest.mark.parametrize(
    "axis,value,message,flat_slice",
    [
        (2, 0.0, r"all 100 particles have z = 0: a flat set is 2D.*pass points\[:, :2\] \(x and y\)", np.s_[:, :2]),
        (1, -2.5, r"all 100 particles have y = -2.5: .*pass points\[:, \[0, 2\]\] \(x and z\)", np.s_[:, [0, 2]]),
        (0, 3.0, r"all 100 particles have x = 3: .*pass points\[:, 1:\] \(y and z\)", np.s_[:, 1:]),
    ],
)
def test_a_flat_3d_set_raises_naming_the_axis_and_the_slice(axis, value, message, flat_slice):
    points = flat_grid(axis, value)
    with pytest.raises(ValueError, match=message):
        boundary.detect(points, 1.0)
    with pytest.raises(ValueError, match=message):
        boundary.score(points, 1.0, "ia")
    with pytest.raises(ValueError, match=message):
        boundary.resample(points, 1.0)
    # The slice it names is the 2D set: the 8 x 8 inner particles are interior at r = 1.
    assert boundary.detect(points[flat_slice], 1.0).sum() == 36


def test_particles_all_at_one_place_raise_but_one_particle_does_not():
    with pytest.raises(ValueError, match=r"all 3 particles are at \(1, 2, 3\): the set has no extent"):
        boundary.detect([[1.0, 2.0, 3.0]] * 3, 1.0)
    assert boundary.detect([[1.0, 2.0, 3.0]], 1.0).tolist() == [True]
    # Flat walls are fine: a wall is often one plane of particles.
    block = np.array([[x, y, z] for z in range(1, 4) for y in range(3) for x in range(3)], float)
    floor = flat_grid(2, 0.0)
    assert boundary.detect(block, 1.0, walls=floor).shape == (27,)


def test_bad_threads_truth_and_files_raise_clear_errors(tmp_path):
    points = jittered_ball(6, 2)
    with pytest.raises(ValueError, match="threads must be at least 1"):
        boundary.detect(points, 1.0, threads=0)
    with pytest.raises(ValueError, match=r"truth: 3 labels for \d+ particles"):
        boundary.score(points, 1.0, "ia", truth=[True, False, True])
    with pytest.raises(ValueError, match="truth: particle 0: boundary must be 0 or 1, got 2"):
        boundary.score(points, 1.0, "ia", truth=np.full(len(points), 2))
    with pytest.raises(FileNotFoundError, match="cannot read .*missing.csv"):
        boundary.read(tmp_path / "missing.csv")
    bad = tmp_path / "bad.csv"
    bad.write_text("x,y\n0,0\n1,oops\n")
    with pytest.raises(ValueError, match="bad.csv"):
        boundary.read(bad)
    with pytest.raises(ValueError, match="unknown particle file format"):
        boundary.write(tmp_path / "out.unknown", points)
    with pytest.raises(ValueError, match=r"column \"pressure\""):
        boundary.write(tmp_path / "out.csv", points, pressure=np.zeros(3))


# ---- files ------------------------------------------------------------------------------


@pytest.mark.parametrize("suffix", [".csv", ".vtu", ".vtk", ".ply", ".bgeo"])
def test_write_then_read_keeps_points_labels_and_attributes(suffix, tmp_path):
    points = jittered_ball(7, 3)
    labels = boundary.detect(points, 1.0)
    pressure = np.linspace(0.0, 1.0, len(points))
    ids = np.arange(len(points), dtype=np.int32)
    path = tmp_path / f"frame{suffix}"
    boundary.write(path, points, boundary=labels, pressure=pressure, ids=ids)
    back, attributes = boundary.read(path)
    assert back.shape == points.shape
    assert np.allclose(back, points, rtol=0, atol=1e-6 * np.abs(points).max())
    assert np.array_equal(attributes["boundary"] == 1, labels)
    assert np.allclose(attributes["pressure"], pressure, rtol=1e-6, atol=1e-12)
    assert np.array_equal(attributes["ids"], ids)


def test_write_is_atomic_a_failed_write_leaves_no_file(tmp_path):
    points = jittered_ball(5, 3)
    # A folder where the file should go: the rename into place fails, naming the file, and
    # the temporary file written beside it is removed.
    taken = tmp_path / "taken.csv"
    taken.mkdir()
    with pytest.raises(OSError, match="taken.csv"):
        boundary.write(taken, points)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["taken.csv"]
    with pytest.raises(FileNotFoundError, match="missing"):
        boundary.write(tmp_path / "missing" / "out.csv", points)
    # Writing over the file the points were read from replaces it whole.
    path = tmp_path / "frame.csv"
    boundary.write(path, points)
    back, _ = boundary.read(path)
    boundary.write(path, back, boundary=np.ones(len(back), dtype=bool))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["frame.csv", "taken.csv"]
    assert np.all(boundary.read(path)[1]["boundary"] == 1)


def test_read_gives_the_positions_of_the_file():
    for relative, _ in SCENES:
        points, attributes = boundary.read(DATA / relative)
        assert np.array_equal(points, load_points(relative))
        assert attributes == {}


# ---- the GIL and Ctrl-C -----------------------------------------------------------------


def test_the_gil_is_released_during_detection():
    points = jittered_ball(36, 3)
    started = threading.Event()

    def work():
        started.set()
        boundary.detect(points, 1.0, "exact", threads=1)

    worker = threading.Thread(target=work)
    worker.start()
    started.wait()
    spins = 0
    while worker.is_alive():
        spins += 1
    worker.join()
    # With the GIL held for the whole detection this loop could not run during it.
    assert spins > 10_000, spins


def test_ctrl_c_interrupts_a_long_detection():
    # About 170k particles at r = 1.8 (spacing 1: about 190 neighbours within 2r): over a
    # second on one thread, far longer than the timer's delay.
    points = jittered_ball(70, 3)
    # Python installs its Ctrl-C handler only if SIGINT was not ignored when it started, and a
    # shell starting a job in the background ignores it (a CI dry run under nohup did not
    # raise): install it for this test, as an interactive interpreter has it.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.1, lambda: os.kill(os.getpid(), signal.SIGINT))
    try:
        timer.start()
        start = time.monotonic()
        with pytest.raises(KeyboardInterrupt):
            boundary.detect(points, 1.8, "exact", threads=1)
        interrupted_after = time.monotonic() - start
        timer.join()
    finally:
        signal.signal(signal.SIGINT, previous)
    # The package still works after an interrupt.
    assert boundary.detect([[0.0, 0.0], [1.0, 0.0]], 1.0).all()
    print(f"interrupted after {interrupted_after:.3f} s")
