//! The Python package `boundary`: boundary particles of meshfree particle sets from NumPy.
//!
//! This crate only translates between Python and the Rust library (the facade `boundary`,
//! `boundary-io`, `boundary-resample`): NumPy arrays in, NumPy arrays out, library errors as
//! Python exceptions with the messages the `boundary` command prints. No algorithm lives here.
//!
//! ```python
//! import numpy as np, boundary
//! points = np.random.default_rng(1).random((10_000, 3))
//! labels = boundary.detect(points, r=0.03, method="ge", depth=4)   # bool array, True = boundary
//! print(boundary.score(points, 0.03, "muller"))                    # TP, TN, FP, FN, Rec, FPR, M
//! ```
//!
//! # Conventions
//! - `points`: any `(n, 2)` or `(n, 3)` array-like of reals. A C-contiguous `float64` array is
//!   read in place (no intermediate copy; the engine's particle set is built straight from its
//!   buffer); anything else (`float32`, Fortran order, lists) is first converted by NumPy.
//! - Detection runs on a worker thread with the GIL released; rayon spreads it over all cores
//!   (or a pool of `threads`). The calling thread waits in slices of 50 ms and checks for
//!   signals between them, so Ctrl-C raises `KeyboardInterrupt` at once; the abandoned detection
//!   keeps its worker thread (and cores) busy until it finishes, and its result is dropped.
//! - `radii`: an optional `(n,)` array-like, a radius factor `s_i` per particle (adaptive
//!   resolution; converted like `points`); particle `i` then has radius `r_i = r * s_i`, and
//!   `r` defaults to 1 (the radii as given). Without `radii`, `r` is required.
//! - A domain (`walls`, `wall_radii`, `solids`, `periodic`, `phases` of `detect`) becomes the
//!   library's `Domain`, solids and periodic axes as the texts `HalfSpace::parse` and
//!   `Periodic::parse` read (`"y<0"`, `"x:0:1"`); with `phases`, `detect` also returns the
//!   interface labels.
//! - A flat `(n, 3)` set (one coordinate equal for every particle, or every particle at one
//!   place; `Flatness`) is a `ValueError` naming the 2D slice to pass: read as 3D, every
//!   particle of it would be boundary. Walls may be flat.
//! - Errors: `ValueError` for bad input (shape, NaN, a flat 3D set, `r <= 0`, a bad radius
//!   naming the particle, unknown method or parameter, malformed file), `OSError` when a file
//!   cannot be opened or written. No input panics: a panic inside the library would surface as
//!   `RuntimeError`, never abort the interpreter.
//!
//! The typed signatures and the docstrings users see are in `boundary.pyi`.

use boundary::{
    detector_with_params, methods as method_names, summary, AnyParticleSet, BoundaryDetector,
    Confusion, Detection, Domain, DomainDetection, Flatness, HalfSpace, Labels, ParticleSet,
    Periodic, Point, Radius,
};
use boundary::{Dim, SupportedDim};
use boundary_io::{AttributeValues, Column, Format, IoError, ReadOptions};
use numpy::{PyArray1, PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::exceptions::{
    PyFileNotFoundError, PyOSError, PyRuntimeError, PyTypeError, PyUserWarning, PyValueError,
};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyList, PyString, PyTuple};
use std::ffi::CString;
use std::path::PathBuf;
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::{Duration, Instant};

/// How long the calling thread waits for the worker between two signal checks.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

fn value_error(message: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(message.to_string())
}

/// A `boundary-io` error as the Python exception a user expects: `FileNotFoundError` /
/// `OSError` when the system refused the file, `ValueError` for its content.
fn io_error(err: IoError) -> PyErr {
    let message = err.to_string();
    match &err {
        IoError::Read { source, .. } | IoError::Write { source, .. } => {
            if source.kind() == std::io::ErrorKind::NotFound {
                PyFileNotFoundError::new_err(message)
            } else {
                PyOSError::new_err(message)
            }
        }
        _ => PyValueError::new_err(message),
    }
}

/// `points` as a C-contiguous `float64` NumPy array: the object itself when it already is one
/// (`numpy.ascontiguousarray` returns its argument then), else NumPy's converted copy.
fn as_f64_array<'py>(points: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let py = points.py();
    let numpy = py.import("numpy")?;
    let kwargs = PyDict::new(py);
    kwargs.set_item("dtype", numpy.getattr("float64")?)?;
    let array = numpy
        .call_method("ascontiguousarray", (points,), Some(&kwargs))
        .map_err(|e| {
            value_error(format!(
                "points must be an (n, 2) or (n, 3) array of reals: {}",
                e.value(py)
            ))
        })?;
    array
        .cast_into::<PyArrayDyn<f64>>()
        .map_err(|_| value_error("points: numpy.ascontiguousarray did not give a float64 array"))
}

/// The coordinates of `array` (checked `(n, 2)` or `(n, 3)`), as `(dim, flat slice)`.
fn coordinates<'a>(array: &'a PyReadonlyArrayDyn<'_, f64>) -> PyResult<(usize, &'a [f64])> {
    let shape = array.shape();
    if shape.len() != 2 || !(shape[1] == 2 || shape[1] == 3) {
        return Err(value_error(format!(
            "points must be an (n, 2) or (n, 3) array, got shape {}",
            shape_text(shape)
        )));
    }
    let flat = array
        .as_slice()
        .map_err(|e| value_error(format!("points: {e}")))?;
    Ok((shape[1], flat))
}

fn shape_text(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// The validated particle set of `flat` (`dim` coordinates per particle): one pass over the
/// buffer, errors naming the particle (`particle 3: coordinate 0 is not finite (NaN)`).
fn particle_set(dim: usize, flat: &[f64]) -> PyResult<AnyParticleSet> {
    fn build<const D: usize>(flat: &[f64]) -> Result<ParticleSet<D>, boundary::CoreError>
    where
        Dim<D>: SupportedDim,
    {
        ParticleSet::new(
            flat.chunks_exact(D)
                .map(Point::<D>::from_column_slice)
                .collect(),
        )
    }
    let set = if dim == 2 {
        build::<2>(flat).map(AnyParticleSet::from)
    } else {
        build::<3>(flat).map(AnyParticleSet::from)
    };
    set.map_err(value_error)
}

/// The particle set of a Python `points` argument; a flat `(n, 3)` set is a ValueError
/// (read as 3D, every particle of it would be boundary) that names the 2D slice to pass.
fn read_points(points: &Bound<'_, PyAny>) -> PyResult<AnyParticleSet> {
    let array = as_f64_array(points)?;
    let readonly = array.readonly();
    let (dim, flat) = coordinates(&readonly)?;
    let set = particle_set(dim, flat)?;
    match set.flatness() {
        None => Ok(set),
        Some(flatness @ Flatness::Plane { axis, .. }) => {
            let slice = match axis {
                2 => "points[:, :2] (x and y)",
                1 => "points[:, [0, 2]] (x and z)",
                _ => "points[:, 1:] (y and z)",
            };
            Err(value_error(format!(
                "points: {flatness}: a flat set is 2D, and as an (n, 3) array every particle \
                 would be boundary; pass {slice}"
            )))
        }
        Some(flatness) => Err(value_error(format!(
            "points: {flatness}: the set has no extent, and every particle would be boundary"
        ))),
    }
}

fn radius(r: f64) -> PyResult<Radius> {
    Radius::new(r).map_err(value_error)
}

/// `set` with the radii of a Python `radii` argument (an `(n,)` array-like of reals; a
/// C-contiguous float64 array is read in place), and the resolution: `r`, which defaults to 1
/// with radii and is required without. Errors name the particle; scaled radii out of range
/// too (`r_i = r * s_i`).
fn with_radii(
    function: &str,
    set: AnyParticleSet,
    r: Option<f64>,
    radii: Option<&Bound<'_, PyAny>>,
) -> PyResult<(AnyParticleSet, Radius)> {
    let Some(radii) = radii else {
        let r = r.ok_or_else(|| {
            PyTypeError::new_err(format!(
                "{function}() missing required argument 'r' (the resolution; optional only \
                 with radii=)"
            ))
        })?;
        return Ok((set, radius(r)?));
    };
    let r = radius(r.unwrap_or(1.0))?;
    let py = radii.py();
    let numpy = py.import("numpy")?;
    let kwargs = PyDict::new(py);
    kwargs.set_item("dtype", numpy.getattr("float64")?)?;
    let array = numpy
        .call_method("ascontiguousarray", (radii,), Some(&kwargs))
        .map_err(|e| value_error(format!("radii must be an array of reals: {}", e.value(py))))?
        .cast_into::<PyArrayDyn<f64>>()
        .map_err(|_| value_error("radii: numpy.ascontiguousarray did not give a float64 array"))?;
    let readonly = array.readonly();
    let shape = readonly.shape();
    if shape.len() != 1 {
        return Err(value_error(format!(
            "radii must be a one-dimensional array (one radius per particle), got shape {}",
            shape_text(shape)
        )));
    }
    let values = readonly
        .as_slice()
        .map_err(|e| value_error(format!("radii: {e}")))?
        .to_vec();
    let set = set
        .with_radii(values)
        .map_err(|e| value_error(format!("radii: {e}")))?;
    match &set {
        AnyParticleSet::D2(s) => s.resolved_radii(r).map(drop),
        AnyParticleSet::D3(s) => s.resolved_radii(r).map(drop),
    }
    .map_err(|e| value_error(format!("radii scaled by r = {}: {e}", r.get())))?;
    Ok((set, r))
}

/// An array-like argument `what` as a C-contiguous `float64` array (the object itself when it
/// already is one, else NumPy's converted copy).
fn float_array<'py>(
    value: &Bound<'py, PyAny>,
    what: &str,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let py = value.py();
    let numpy = py.import("numpy")?;
    let kwargs = PyDict::new(py);
    kwargs.set_item("dtype", numpy.getattr("float64")?)?;
    numpy
        .call_method("ascontiguousarray", (value,), Some(&kwargs))
        .map_err(|e| value_error(format!("{what} must be an array of reals: {}", e.value(py))))?
        .cast_into::<PyArrayDyn<f64>>()
        .map_err(|_| {
            value_error(format!(
                "{what}: numpy.ascontiguousarray did not give a float64 array"
            ))
        })
}

/// The texts of a `solids` or `periodic` argument: one string, or a sequence of strings.
fn texts(value: &Bound<'_, PyAny>, what: &str, example: &str) -> PyResult<Vec<String>> {
    if let Ok(text) = value.cast::<PyString>() {
        return Ok(vec![text.to_string()]);
    }
    let bad = || {
        PyTypeError::new_err(format!(
            "{what} must be a string or a sequence of strings such as '{example}'"
        ))
    };
    let mut out = Vec::new();
    for item in value.try_iter().map_err(|_| bad())? {
        let item = item?;
        let text = item.cast::<PyString>().map_err(|_| bad())?;
        out.push(text.to_string());
    }
    Ok(out)
}

/// The phase numbers of a `phases` argument: a one-dimensional array-like of integers in
/// 0..=2^32-1, one per particle (the library checks the count).
fn phase_numbers(phases: &Bound<'_, PyAny>) -> PyResult<Vec<u32>> {
    let py = phases.py();
    let numpy = py.import("numpy")?;
    let array = numpy.call_method1("asarray", (phases,)).map_err(|e| {
        value_error(format!(
            "phases must be an array of integers: {}",
            e.value(py)
        ))
    })?;
    let shape: Vec<usize> = array.getattr("shape")?.extract()?;
    if shape.len() != 1 {
        return Err(value_error(format!(
            "phases must be a one-dimensional array (one phase number per particle), got shape {}",
            shape_text(&shape)
        )));
    }
    let kind: String = array.getattr("dtype")?.getattr("kind")?.extract()?;
    if shape[0] > 0 && !matches!(kind.as_str(), "i" | "u") {
        return Err(value_error(format!(
            "phases must be integers, got an array of dtype {}",
            array.getattr("dtype")?.str()?
        )));
    }
    if shape[0] == 0 {
        return Ok(Vec::new());
    }
    let out_of_range = |i: usize, v: &dyn std::fmt::Display| {
        value_error(format!(
            "phases: particle {i}: phase {v} is outside 0..={}",
            u32::MAX
        ))
    };
    // Every integer dtype fits in uint64 or int64 without wrapping; the values are then checked.
    if kind == "u" {
        let values: Vec<u64> = array
            .call_method1("astype", (numpy.getattr("uint64")?,))?
            .extract()?;
        values
            .into_iter()
            .enumerate()
            .map(|(i, v)| u32::try_from(v).map_err(|_| out_of_range(i, &v)))
            .collect()
    } else {
        let values: Vec<i64> = array
            .call_method1("astype", (numpy.getattr("int64")?,))?
            .extract()?;
        values
            .into_iter()
            .enumerate()
            .map(|(i, v)| u32::try_from(v).map_err(|_| out_of_range(i, &v)))
            .collect()
    }
}

/// The domain of `detect`'s keyword arguments, for particles of dimension `dim` and scale
/// `r`: walls (an `(m, dim)` array) with their optional radius factors, solid half-spaces and
/// periodic axes as texts (`"y<0"`, `"x:0:1"`), phase numbers.
fn domain(
    dim: usize,
    r: Radius,
    walls: Option<&Bound<'_, PyAny>>,
    wall_radii: Option<&Bound<'_, PyAny>>,
    solids: Option<&Bound<'_, PyAny>>,
    periodic: Option<&Bound<'_, PyAny>>,
    phases: Option<&Bound<'_, PyAny>>,
) -> PyResult<Domain> {
    let mut domain = Domain::new();
    match (walls, wall_radii) {
        (None, Some(_)) => return Err(value_error("wall_radii given without walls")),
        (None, None) => {}
        (Some(walls), wall_radii) => {
            let array = float_array(walls, "walls")?;
            let readonly = array.readonly();
            let shape = readonly.shape();
            if shape.len() != 2 || shape[1] != dim {
                return Err(value_error(format!(
                    "walls must be an (m, {dim}) array like the points, got shape {}",
                    shape_text(shape)
                )));
            }
            let flat = readonly
                .as_slice()
                .map_err(|e| value_error(format!("walls: {e}")))?;
            let mut set = particle_set(dim, flat)
                .map_err(|e| value_error(format!("walls: {}", e.value(walls.py()))))?;
            if let Some(radii) = wall_radii {
                let array = float_array(radii, "wall_radii")?;
                let readonly = array.readonly();
                let shape = readonly.shape();
                if shape.len() != 1 {
                    return Err(value_error(format!(
                        "wall_radii must be a one-dimensional array (one radius per wall \
                         particle), got shape {}",
                        shape_text(shape)
                    )));
                }
                let values = readonly
                    .as_slice()
                    .map_err(|e| value_error(format!("wall_radii: {e}")))?
                    .to_vec();
                set = set
                    .with_radii(values)
                    .map_err(|e| value_error(format!("wall_radii: {e}")))?;
                match &set {
                    AnyParticleSet::D2(s) => s.resolved_radii(r).map(drop),
                    AnyParticleSet::D3(s) => s.resolved_radii(r).map(drop),
                }
                .map_err(|e| value_error(format!("wall_radii scaled by r = {}: {e}", r.get())))?;
            }
            domain = domain.with_walls(set);
        }
    }
    if let Some(solids) = solids {
        for text in texts(solids, "solids", "y<0")? {
            domain = domain.with_solid(HalfSpace::parse(&text).map_err(value_error)?);
        }
    }
    if let Some(periodic) = periodic {
        for text in texts(periodic, "periodic", "x:0:1")? {
            domain = domain.with_periodic(Periodic::parse(&text).map_err(value_error)?);
        }
    }
    if let Some(phases) = phases {
        domain = domain.with_phases(phase_numbers(phases)?);
    }
    Ok(domain)
}

/// A keyword argument's value as the text `--set KEY=VALUE` would carry: `True`/`False` as
/// `true`/`false`, anything else by `str()`.
fn param_text(value: &Bound<'_, PyAny>) -> PyResult<String> {
    if let Ok(flag) = value.cast::<PyBool>() {
        return Ok(if flag.is_true() { "true" } else { "false" }.to_owned());
    }
    Ok(value.str()?.to_string())
}

/// The detector `method` with the keyword parameters `params`, in the order given.
fn detector(
    method: &str,
    params: Option<&Bound<'_, PyDict>>,
) -> PyResult<Box<dyn BoundaryDetector>> {
    let mut pairs = Vec::new();
    if let Some(params) = params {
        for (key, value) in params.iter() {
            pairs.push((key.str()?.to_string(), param_text(&value)?));
        }
    }
    detector_with_params(method, &pairs).map_err(value_error)
}

/// A rayon pool of `threads` workers, or `None` for rayon's global pool (all cores).
fn pool(threads: Option<usize>) -> PyResult<Option<rayon::ThreadPool>> {
    match threads {
        None => Ok(None),
        Some(0) => Err(value_error("threads must be at least 1")),
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map(Some)
            .map_err(|e| PyRuntimeError::new_err(format!("cannot start worker threads: {e}"))),
    }
}

/// The text of a caught panic's payload.
fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| (*s).to_owned())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".to_owned())
}

/// Runs `job` on a worker thread, with the GIL released while waiting, checking for signals
/// (Ctrl-C) every [`SIGNAL_POLL`]. On a signal the job is abandoned: its thread runs on until
/// the job ends, and the result is dropped. A panic in `job` becomes `RuntimeError`.
fn run_interruptible<T, F>(py: Python<'_>, job: F) -> PyResult<T>
where
    T: Send + 'static,
    F: FnOnce() -> T + Send + 'static,
{
    let (sender, receiver) = mpsc::channel();
    std::thread::Builder::new()
        .name("boundary-detect".to_owned())
        .spawn(move || {
            let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(job))
                .map_err(|payload| panic_text(payload.as_ref()));
            // The receiver is gone when the caller was interrupted: nothing to deliver to.
            let _ = sender.send(outcome);
        })
        .map_err(|e| PyRuntimeError::new_err(format!("cannot start a worker thread: {e}")))?;
    let mut receiver = receiver;
    loop {
        // The receiver travels into the GIL-free wait and back (it is `Send`, not `Sync`).
        let (back, received) = py.detach(move || {
            let received = receiver.recv_timeout(SIGNAL_POLL);
            (receiver, received)
        });
        receiver = back;
        match received {
            Ok(Ok(value)) => return Ok(value),
            Ok(Err(panic)) => {
                return Err(PyRuntimeError::new_err(format!(
                    "internal error (please report it): {panic}"
                )))
            }
            Err(RecvTimeoutError::Timeout) => py.check_signals()?,
            Err(RecvTimeoutError::Disconnected) => {
                return Err(PyRuntimeError::new_err(
                    "internal error (please report it): the worker thread ended without a result",
                ))
            }
        }
    }
}

/// Detection of `set` by `detector` in `domain` (the bare cloud: `Domain::new()`) in `pool`,
/// interruptible; also its wall time in seconds (the Rust call alone, for the overhead
/// measurement).
fn detect_set(
    py: Python<'_>,
    detector: Box<dyn BoundaryDetector>,
    set: AnyParticleSet,
    domain: Domain,
    r: Radius,
    threads: Option<usize>,
) -> PyResult<(DomainDetection, f64)> {
    let pool = pool(threads)?;
    let outcome = run_interruptible(py, move || {
        let run = || {
            let start = Instant::now();
            let detection = if domain.is_bare() {
                detector.detect(&set, r).map(|detection| DomainDetection {
                    detection,
                    interface: None,
                })
            } else {
                detector.detect_in(&set, &domain, r)
            };
            detection.map(|d| (d, start.elapsed().as_secs_f64()))
        };
        match &pool {
            Some(pool) => pool.install(run),
            None => run(),
        }
    })?;
    outcome.map_err(value_error)
}

fn bool_array(py: Python<'_>, labels: Vec<bool>) -> Bound<'_, PyArray1<bool>> {
    PyArray1::from_vec(py, labels)
}

/// `(n, dim)` float64 array of the positions of `set`.
fn points_array<'py>(py: Python<'py>, set: &AnyParticleSet) -> PyResult<Bound<'py, PyAny>> {
    let dim = set.dim();
    let n = set.len();
    let mut flat = Vec::with_capacity(n * dim);
    for i in 0..n {
        flat.extend_from_slice(set.coords(i));
    }
    Ok(PyArray1::from_vec(py, flat).reshape([n, dim])?.into_any())
}

/// Labels every particle: True on the boundary, False inside.
///
/// Particle i is interior iff its sphere of radius r is covered by the balls of radius r of
/// the other particles within 2r (Sandim, Paiva & Figueiredo, J. Comput. Phys. 2020).
///
/// points: (n, 2) or (n, 3) array-like of reals (a C-contiguous float64 array is read in
///     place); r: the particle resolution (> 0); method: a name from methods() (default
///     "exact", the reference labels); threads: worker threads (default: all cores);
///     margin: also return the method's per-particle margin (None if it has none);
///     radii: optional (n,) radius factors s_i, one per particle: r_i = r * s_i, r then
///     defaulting to 1; walls: optional (m, dim) covering-only particles, with optional
///     wall_radii (m,); solids: "y<0" or a list of such closed solid half-spaces; periodic:
///     "x:0:1" or a list of such periodic axes; phases: optional (n,) integer phase numbers;
///     **params: the method's parameters, as `--set KEY=VALUE` (depth=4, gamma=1.3, ...).
///
/// Returns a bool array of length n, or (labels, margin) with margin=True; with phases, the
/// interface labels are appended: (labels, interface) or (labels, margin, interface). Raises
/// ValueError on bad input (shape, NaN, a flat (n, 3) set: the message names the 2D slice to
/// pass, r <= 0, a bad radius, a bad domain, a method that
/// cannot honour a solid, unknown method or parameter); Ctrl-C raises KeyboardInterrupt (the
/// detection finishes in the background and is discarded).
#[pyfunction]
#[pyo3(signature = (
    points, r = None, method = "exact", threads = None, margin = false, radii = None,
    walls = None, wall_radii = None, solids = None, periodic = None, phases = None, **params
))]
#[allow(clippy::too_many_arguments)] // the Python signature: keyword arguments with defaults
fn detect<'py>(
    py: Python<'py>,
    points: &Bound<'py, PyAny>,
    r: Option<f64>,
    method: &str,
    threads: Option<usize>,
    margin: bool,
    radii: Option<&Bound<'py, PyAny>>,
    walls: Option<&Bound<'py, PyAny>>,
    wall_radii: Option<&Bound<'py, PyAny>>,
    solids: Option<&Bound<'py, PyAny>>,
    periodic: Option<&Bound<'py, PyAny>>,
    phases: Option<&Bound<'py, PyAny>>,
    params: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    let detector = detector(method, params)?;
    let set = read_points(points)?;
    let (set, r) = with_radii("detect", set, r, radii)?;
    let domain = domain(set.dim(), r, walls, wall_radii, solids, periodic, phases)?;
    let with_phases = domain.phases().is_some();
    let (found, _) = detect_set(py, detector, set, domain, r, threads)?;
    let labels = bool_array(py, found.detection.labels.into_vec()).into_any();
    let mut out = vec![labels];
    if margin {
        out.push(match found.detection.margin {
            Some(m) => PyArray1::from_vec(py, m).into_any(),
            None => py.None().into_bound(py),
        });
    }
    if with_phases {
        let interface = found.interface.map(Labels::into_vec).ok_or_else(|| {
            PyRuntimeError::new_err(
                "internal error (please report it): no interface labels with phases",
            )
        })?;
        out.push(bool_array(py, interface).into_any());
    }
    match out.len() {
        1 => Ok(out.remove(0)),
        _ => Ok(PyTuple::new(py, out)?.into_any()),
    }
}

/// `detect` that also returns the seconds the Rust detection took (overhead measurement).
#[pyfunction]
#[pyo3(signature = (points, r, method = "exact", threads = None, **params))]
fn _detect_timed<'py>(
    py: Python<'py>,
    points: &Bound<'py, PyAny>,
    r: f64,
    method: &str,
    threads: Option<usize>,
    params: Option<&Bound<'py, PyDict>>,
) -> PyResult<(Bound<'py, PyArray1<bool>>, f64)> {
    let detector = detector(method, params)?;
    let r = radius(r)?;
    let set = read_points(points)?;
    let (found, seconds) = detect_set(py, detector, set, Domain::new(), r, threads)?;
    Ok((bool_array(py, found.detection.labels.into_vec()), seconds))
}

/// The address of the buffer `detect` reads `points` from (the zero-copy test compares it with
/// the array's own data pointer).
#[pyfunction]
fn _points_address(points: &Bound<'_, PyAny>) -> PyResult<usize> {
    let array = as_f64_array(points)?;
    let readonly = array.readonly();
    let (_, flat) = coordinates(&readonly)?;
    Ok(flat.as_ptr() as usize)
}

/// Truth labels from an array-like of booleans or 0/1 values, one per particle.
fn truth_labels(truth: &Bound<'_, PyAny>, n: usize) -> PyResult<Vec<bool>> {
    let py = truth.py();
    let numpy = py.import("numpy")?;
    let kwargs = PyDict::new(py);
    kwargs.set_item("dtype", numpy.getattr("float64")?)?;
    let array = numpy
        .call_method("ascontiguousarray", (truth,), Some(&kwargs))
        .map_err(|e| value_error(format!("truth: {}", e.value(py))))?
        .cast_into::<PyArrayDyn<f64>>()
        .map_err(|_| value_error("truth must be an array of booleans"))?;
    let readonly = array.readonly();
    let shape = readonly.shape();
    if shape.len() != 1 {
        return Err(value_error(format!(
            "truth must be a one-dimensional array, got shape {}",
            shape_text(shape)
        )));
    }
    let values = readonly
        .as_slice()
        .map_err(|e| value_error(format!("truth: {e}")))?;
    if values.len() != n {
        return Err(value_error(format!(
            "truth: {} labels for {n} particles",
            values.len()
        )));
    }
    values
        .iter()
        .enumerate()
        .map(|(i, &v)| {
            if v == 0.0 {
                Ok(false)
            } else if v == 1.0 {
                Ok(true)
            } else {
                Err(value_error(format!(
                    "truth: particle {i}: boundary must be 0 or 1, got {v}"
                )))
            }
        })
        .collect()
}

/// Scores `method` against the truth: a dict with TP, TN, FP, FN, Rec, FPR, M.
///
/// Boundary is the positive class: Rec = TP/(TP+FN), FPR = FP/(FP+TN), M = Rec*(1-FPR)
/// (J. Comput. Phys. 2020, Sec. 4). truth: one bool (or 0/1) per particle; default: the
/// labels of "exact" (with the same radii). Other arguments as detect(); method is required
/// (`score(points, method="ia", radii=h)` when r is left to its default).
#[pyfunction]
#[pyo3(signature = (points, r = None, method = None, truth = None, threads = None, radii = None, **params))]
#[allow(clippy::too_many_arguments)] // the Python signature: keyword arguments with defaults
fn score<'py>(
    py: Python<'py>,
    points: &Bound<'py, PyAny>,
    r: Option<f64>,
    method: Option<&str>,
    truth: Option<&Bound<'py, PyAny>>,
    threads: Option<usize>,
    radii: Option<&Bound<'py, PyAny>>,
    params: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let method =
        method.ok_or_else(|| PyTypeError::new_err("score() missing required argument 'method'"))?;
    let detector = detector(method, params)?;
    let set = read_points(points)?;
    let (set, r) = with_radii("score", set, r, radii)?;
    let n = set.len();
    let truth = match truth {
        Some(t) => Some(truth_labels(t, n)?),
        None => None,
    };
    let (predicted, truth) = match truth {
        Some(truth) => (
            detect_set(py, detector, set, Domain::new(), r, threads)?
                .0
                .detection,
            truth,
        ),
        None => {
            let exact = self::detector("exact", None)?;
            let shared = std::sync::Arc::new(set);
            let pool = pool(threads)?;
            let (a, b) = (shared.clone(), shared);
            run_interruptible(py, move || {
                let run = || -> Result<(Detection, Detection), boundary::DetectError> {
                    Ok((detector.detect(&a, r)?, exact.detect(&b, r)?))
                };
                match &pool {
                    Some(pool) => pool.install(run),
                    None => run(),
                }
            })?
            .map(|(d, e)| (d, e.labels.into_vec()))
            .map_err(value_error)?
        }
    };
    let c = Confusion::from_labels(predicted.labels.as_slice(), &truth).map_err(value_error)?;
    let dict = PyDict::new(py);
    dict.set_item("TP", c.tp)?;
    dict.set_item("TN", c.tn)?;
    dict.set_item("FP", c.fp)?;
    dict.set_item("FN", c.fn_)?;
    dict.set_item("Rec", c.recall())?;
    dict.set_item("FPR", c.fpr())?;
    dict.set_item("M", c.m())?;
    Ok(dict)
}

/// Every method: a list of dicts with name, summary (with the paper), certified and params
/// (name, default, description each); the data of `boundary methods --json`.
#[pyfunction]
fn methods(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let list = PyList::empty(py);
    for name in method_names() {
        let d = detector(name, None)?;
        let entry = PyDict::new(py);
        entry.set_item("name", name)?;
        entry.set_item("summary", summary(name).unwrap_or(""))?;
        entry.set_item("certified", d.certified())?;
        let params = PyList::empty(py);
        for p in d.params().0 {
            let param = PyDict::new(py);
            param.set_item("name", p.name)?;
            param.set_item("default", p.default)?;
            param.set_item("description", p.description)?;
            params.append(param)?;
        }
        entry.set_item("params", params)?;
        list.append(entry)?;
    }
    Ok(list)
}

fn format_arg(format: Option<&str>) -> PyResult<Option<Format>> {
    format
        .map(|f| f.parse::<Format>().map_err(value_error))
        .transpose()
}

/// Reads a particle file: (points, attributes).
///
/// CSV (header x,y[,z]), XYZ, PLY, legacy VTK, VTK XML .vtu/.vtp, Houdini .bgeo[.gz], by
/// extension or `format`. points: (n, dim) float64; attributes: every other per-particle
/// attribute (a vector as name:0, name:1, ...) as an int64 or float64 array. dim=2 drops the
/// constant axis of a 3D file. Unreadable attributes give a UserWarning.
#[pyfunction]
#[pyo3(signature = (path, dim = None, format = None))]
fn read<'py>(
    py: Python<'py>,
    path: PathBuf,
    dim: Option<usize>,
    format: Option<&str>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyDict>)> {
    if let Some(d) = dim {
        if d != 2 && d != 3 {
            return Err(value_error(format!("dim must be 2 or 3, got {d}")));
        }
    }
    let options = ReadOptions {
        dim,
        format: format_arg(format)?,
    };
    let file = py
        .detach(|| boundary_io::read_particle_file(&path, &options))
        .map_err(io_error)?;
    for skipped in &file.skipped {
        let text = format!("{}: attribute not read: {skipped}", path.display());
        let text = CString::new(text.replace('\0', " ")).unwrap_or_default();
        PyErr::warn(py, &py.get_type::<PyUserWarning>(), &text, 1)?;
    }
    let attributes = PyDict::new(py);
    for attribute in file.attributes {
        let values = match attribute.values {
            AttributeValues::Int(v) => PyArray1::from_vec(py, v).into_any(),
            AttributeValues::Float(v) => PyArray1::from_vec(py, v).into_any(),
        };
        attributes.set_item(attribute.name, values)?;
    }
    Ok((points_array(py, &file.set)?, attributes))
}

/// One attribute column given to `write`: integers stay integers (NumPy kinds `b`, `i`, `u`),
/// anything else is written as reals.
enum OwnedColumn {
    Int(Vec<i64>),
    Float(Vec<f64>),
}

impl OwnedColumn {
    fn column(&self) -> Column<'_> {
        match self {
            OwnedColumn::Int(v) => Column::Int(v),
            OwnedColumn::Float(v) => Column::Float(v),
        }
    }
}

fn owned_column(name: &str, values: &Bound<'_, PyAny>) -> PyResult<OwnedColumn> {
    let py = values.py();
    let numpy = py.import("numpy")?;
    let array = numpy
        .call_method1("asarray", (values,))
        .map_err(|e| value_error(format!("column {name:?}: {}", e.value(py))))?;
    let shape: Vec<usize> = array.getattr("shape")?.extract()?;
    if shape.len() != 1 {
        return Err(value_error(format!(
            "column {name:?}: expected one value per particle (a one-dimensional array), got shape {}",
            shape_text(&shape)
        )));
    }
    let kind: String = array.getattr("dtype")?.getattr("kind")?.extract()?;
    let as_type = |dtype: &str| -> PyResult<Bound<'_, PyAny>> {
        array
            .call_method1("astype", (numpy.getattr(dtype)?,))
            .map_err(|e| value_error(format!("column {name:?}: {}", e.value(py))))
    };
    if matches!(kind.as_str(), "b" | "i" | "u") {
        if kind == "u" {
            // uint64 beyond i64::MAX would wrap in astype: refuse it instead.
            let max: u64 = array.call_method0("max").map_or(Ok(0), |m| m.extract())?;
            if shape[0] > 0 && max > i64::MAX as u64 {
                return Err(value_error(format!(
                    "column {name:?}: value {max} does not fit a signed 64-bit integer"
                )));
            }
        }
        Ok(OwnedColumn::Int(as_type("int64")?.extract()?))
    } else {
        Ok(OwnedColumn::Float(as_type("float64")?.extract()?))
    }
}

/// Writes points with an optional `boundary` column (0/1) and one column per keyword
/// attribute (integer arrays stay integers, others are written as reals), in the format of
/// the extension or `format`. Atomic: the file appears whole or not at all (a failed write
/// leaves no file, and a file already at `path` stays as it was).
#[pyfunction]
#[pyo3(signature = (path, points, boundary = None, format = None, **attributes))]
fn write(
    py: Python<'_>,
    path: PathBuf,
    points: &Bound<'_, PyAny>,
    boundary: Option<&Bound<'_, PyAny>>,
    format: Option<&str>,
    attributes: Option<&Bound<'_, PyDict>>,
) -> PyResult<()> {
    let set = read_points(points)?;
    let format = format_arg(format)?;
    let mut owned: Vec<(String, OwnedColumn)> = Vec::new();
    if let Some(labels) = boundary {
        let labels = truth_labels(labels, set.len())
            .map_err(|e| value_error(e.value(py).to_string().replacen("truth", "boundary", 1)))?;
        owned.push((
            "boundary".to_owned(),
            OwnedColumn::Int(labels.iter().map(|&b| i64::from(b)).collect()),
        ));
    }
    if let Some(attributes) = attributes {
        for (key, values) in attributes.iter() {
            let name = key.cast::<PyString>()?.to_string();
            let column = owned_column(&name, &values)?;
            owned.push((name, column));
        }
    }
    let columns: Vec<(&str, Column<'_>)> = owned
        .iter()
        .map(|(name, c)| (name.as_str(), c.column()))
        .collect();
    py.detach(|| boundary_io::write_particles(&path, format, &set, &columns))
        .map_err(io_error)
}

/// What `resample` returns: the new points, their feature codes, their source indices.
type ResampledArrays<'py> = (
    Bound<'py, PyAny>,
    Bound<'py, PyArray1<i8>>,
    Bound<'py, PyArray1<i64>>,
);

/// Classifies boundary particles by feature and resamples thin features (Sandim 2020
/// thesis Sec. 2.6, Eq. 2.4-2.5; Computers & Graphics 2019).
///
/// Boundary particles come from `method` (with **params) or from `labels`. k, alpha, shift:
/// K and alpha of Eq. 2.5 and the shift in units of r. Returns (points, feature, source):
/// the new set, each new particle's feature code (FEATURES: -1 interior, 0 droplet,
/// 1 ligament, 2 sheet, 3 regular) and the input index it comes from.
#[pyfunction]
#[pyo3(signature = (points, r, method = "exact", k = 4, alpha = 0.2, shift = 0.5, labels = None, threads = None, **params))]
#[allow(clippy::too_many_arguments)] // the Python signature: keyword arguments with defaults
fn resample<'py>(
    py: Python<'py>,
    points: &Bound<'py, PyAny>,
    r: f64,
    method: &str,
    k: usize,
    alpha: f64,
    shift: f64,
    labels: Option<&Bound<'py, PyAny>>,
    threads: Option<usize>,
    params: Option<&Bound<'py, PyDict>>,
) -> PyResult<ResampledArrays<'py>> {
    let detector = detector(method, params)?;
    let r = radius(r)?;
    let set = read_points(points)?;
    let config = boundary_resample::ResampleConfig {
        k,
        alpha,
        shift,
        ..boundary_resample::ResampleConfig::default()
    };
    let given = match labels {
        Some(l) => Some(boundary::Labels::new(truth_labels(l, set.len()).map_err(
            |e| value_error(e.value(py).to_string().replacen("truth", "labels", 1)),
        )?)),
        None => None,
    };
    let pool = pool(threads)?;
    let outcome = run_interruptible(py, move || {
        let run = || -> Result<(AnyParticleSet, Vec<i8>, Vec<usize>), String> {
            let labels = match given {
                Some(l) => l,
                None => detector.detect(&set, r).map_err(|e| e.to_string())?.labels,
            };
            match &set {
                AnyParticleSet::D2(s) => boundary_resample::resample(s, r, &labels, &config)
                    .map(|o| (o.set.into(), o.feature, o.source)),
                AnyParticleSet::D3(s) => boundary_resample::resample(s, r, &labels, &config)
                    .map(|o| (o.set.into(), o.feature, o.source)),
            }
            .map_err(|e| e.to_string())
        };
        match &pool {
            Some(pool) => pool.install(run),
            None => run(),
        }
    })?;
    let (out, feature, source) = outcome.map_err(value_error)?;
    let source: Vec<i64> = source
        .into_iter()
        .map(|i| i64::try_from(i).unwrap_or(i64::MAX))
        .collect();
    Ok((
        points_array(py, &out)?,
        PyArray1::from_vec(py, feature),
        PyArray1::from_vec(py, source),
    ))
}

/// Boundary particles of meshfree particle sets (SPH, PBF, FLIP/APIC, MPS).
///
/// Particle i at p_i with resolution r is interior iff its sphere of radius r is covered by
/// the closed balls of radius r of the other particles within 2r; otherwise boundary (Sandim,
/// Paiva & Figueiredo, J. Comput. Phys. 2020). Methods: exact, dilts (Dilts 2000; Haque &
/// Dilts 2007), ia and ge (JCP 2020 Sec. 3), marrone (Marrone et al. 2010), muller (Mueller
/// et al. 2003), hpr and svm (Sandim 2020 thesis, ch. 2 and 3). See detect(), score(),
/// methods(), read(), write(), resample().
#[pymodule]
#[pyo3(name = "boundary")]
fn boundary_py(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(detect, m)?)?;
    m.add_function(wrap_pyfunction!(score, m)?)?;
    m.add_function(wrap_pyfunction!(methods, m)?)?;
    m.add_function(wrap_pyfunction!(read, m)?)?;
    m.add_function(wrap_pyfunction!(write, m)?)?;
    m.add_function(wrap_pyfunction!(resample, m)?)?;
    m.add_function(wrap_pyfunction!(_detect_timed, m)?)?;
    m.add_function(wrap_pyfunction!(_points_address, m)?)?;
    let features = PyDict::new(py);
    features.set_item(boundary_resample::INTERIOR_CODE, "interior")?;
    for f in [
        boundary_resample::Feature::Droplet,
        boundary_resample::Feature::Ligament,
        boundary_resample::Feature::Sheet,
        boundary_resample::Feature::Regular,
    ] {
        let name = match f {
            boundary_resample::Feature::Droplet => "droplet",
            boundary_resample::Feature::Ligament => "ligament",
            boundary_resample::Feature::Sheet => "sheet",
            boundary_resample::Feature::Regular => "regular",
        };
        features.set_item(f.code(), name)?;
    }
    m.add("FEATURES", features)?;
    Ok(())
}
