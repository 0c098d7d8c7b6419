//! The compiled module `boundary_particles._native` of the Python package
//! `boundary-particles`: boundary particles of meshfree particle sets from NumPy.
//!
//! This crate only translates between Python and the Rust library (the facade `boundary`,
//! `boundary-io`, `boundary-resample`): NumPy arrays in, NumPy arrays out, library errors as
//! Python exceptions with the messages the `boundary` command prints. No algorithm lives here.
//! The public functions, their signatures and their docstrings are those of the pure-Python
//! package around this module (`python/boundary_particles/__init__.py`), which only forwards
//! to it; `python/boundary_particles/_native.pyi` types this module (checked by
//! `mypy.stubtest` in the Python tests).
//!
//! # Conventions
//! - `points`: an `(n, 2)` or `(n, 3)` array-like of reals. A C-contiguous `float64` array is
//!   read from its own buffer (no NumPy conversion); anything else (`float32`, Fortran order,
//!   lists) is first converted by NumPy. Either way the positions are then copied once into
//!   the engine's particle set, validated in the same pass.
//! - Detection runs on a rayon pool of its own (`threads` workers, default all cores) with the
//!   GIL released; the calling thread waits in slices of 50 ms and checks for signals between
//!   them. On Ctrl-C it stops the pool's workers through a `boundary::stop::StopToken` (each
//!   worker ends the particle it is classifying), waits for them, and raises
//!   `KeyboardInterrupt`: no detection keeps running in the background.
//! - The resolution, given once (the CLI's `--radius`, `--smoothing-length`, `--spacing`):
//!   `r`, a positive real or `"auto"` (the core's `auto_radius`, the CLI's `--radius auto`);
//!   `h`, the smoothing length (`r = h`; the SPH-sum methods then use `h` itself, so an
//!   `h_over_r` other than 1 is refused as the CLI refuses it); or `spacing`, the particle
//!   spacing (`r = RADIUS_PER_SPACING * spacing`, the core's `radius_from_spacing`). With
//!   `radii` (a radius factor `s_i` per particle, `r_i = r * s_i`), `r` defaults to 1. An `r`
//!   the core's `radius_concern` finds implausible for the spacing measured in the bulk
//!   (`bulk_spacing`) is a `UserWarning` with its text; the detection runs all the same.
//! - A domain (`walls`, `wall_radii`, `solids`, `periodic`, `phases`) becomes the library's
//!   `Domain`, solids and periodic axes as the texts `HalfSpace::parse` and `Periodic::parse`
//!   read (`"y<0"`, `"x:0:1"`).
//! - A flat `(n, 3)` set (one coordinate equal for every particle, or every particle at one
//!   place; `Flatness`) is a `ValueError` naming `dim=2` and the 2D slice to pass: read as 3D,
//!   every particle of it would be boundary. `dim=2` drops the constant axis (z first, then y,
//!   then x, as `boundary_io` reads a file with `dim = 2`); `dim=3` keeps such a set 3D.
//! - Errors: `ValueError` for bad input, `OSError` when a file cannot be opened or written.
//!   No input panics: a panic inside the library would surface as `RuntimeError`, never
//!   abort the interpreter.

use boundary::stop::StopToken;
use boundary::{
    auto_radius, bulk_spacing, detector_with_params, methods as method_names, radius_concern,
    radius_from_spacing, summary, AnyParticleSet, BoundaryDetector, Confusion, DetectError, Domain,
    DomainDetection, Flatness, HalfSpace, Labels, ParticleSet, Periodic, Point, Radius,
    RadiusConcern, RADIUS_PER_SPACING,
};
use boundary::{Dim, SupportedDim};
use boundary_io::{AttributeValues, Column, Format, IoError, ReadOptions};
use numpy::{
    PyArray1, PyArray2, PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods,
};
use pyo3::exceptions::{
    PyFileNotFoundError, PyKeyboardInterrupt, PyOSError, PyRuntimeError, PyTypeError,
    PyUserWarning, PyValueError,
};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyList, PyString, PyTuple};
use std::ffi::CString;
use std::path::PathBuf;
use std::sync::mpsc::{self, RecvTimeoutError};
use std::sync::Arc;
use std::time::{Duration, Instant};

mod tracker;

/// How long the calling thread waits for the workers between two signal checks.
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

/// A detection's error as a Python exception: `KeyboardInterrupt` when it was stopped,
/// `ValueError` otherwise (bad input for the method or the domain), its message in Python's
/// spelling ([`in_python_terms`]).
fn detect_error(err: DetectError) -> PyErr {
    match err {
        DetectError::Interrupted => PyKeyboardInterrupt::new_err(err.to_string()),
        other => value_error(in_python_terms(&other)),
    }
}

/// The library's names of the inputs a detection takes, with the argument of `detect` that
/// gives each. The library names inputs in its own terms; Python adds its argument after the
/// first mention of each. Solid meshes have no argument here.
const ARGUMENTS: &[(&str, &str)] = &[("half-spaces", "solids="), ("wall particles", "walls=")];

/// A detector's error message in Python's spelling: `solid half-spaces (solids=)`.
fn in_python_terms(error: &DetectError) -> String {
    let mut message = error.to_string();
    for (term, argument) in ARGUMENTS {
        if let Some(at) = message.find(term) {
            message.insert_str(at + term.len(), &format!(" ({argument})"));
        }
    }
    message
}

/// An array-like argument `what` as a C-contiguous `float64` array: the object itself when it
/// already is one (`numpy.ascontiguousarray` returns its argument then), else NumPy's
/// converted copy.
fn float_array<'py>(
    value: &Bound<'py, PyAny>,
    what: &str,
    expected: &str,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let py = value.py();
    let numpy = py.import("numpy")?;
    let kwargs = PyDict::new(py);
    kwargs.set_item("dtype", numpy.getattr("float64")?)?;
    numpy
        .call_method("ascontiguousarray", (value,), Some(&kwargs))
        .map_err(|e| value_error(format!("{what} must be {expected}: {}", e.value(py))))?
        .cast_into::<PyArrayDyn<f64>>()
        .map_err(|_| {
            value_error(format!(
                "{what}: numpy.ascontiguousarray did not give a float64 array"
            ))
        })
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

/// The validated particle set of `flat` (`stride` coordinates per particle, of which the
/// columns `kept` are taken, `D` of them): one pass over the buffer, errors naming the
/// particle (`particle 3: coordinate 0 is not finite (NaN)`).
fn particle_set<const D: usize>(
    flat: &[f64],
    stride: usize,
    kept: [usize; D],
) -> Result<ParticleSet<D>, boundary::CoreError>
where
    Dim<D>: SupportedDim,
{
    let positions = if stride == D && kept.iter().enumerate().all(|(k, &axis)| k == axis) {
        // Every column, in order: rows copied whole.
        flat.chunks_exact(D)
            .map(Point::<D>::from_column_slice)
            .collect()
    } else {
        flat.chunks_exact(stride)
            .map(|row| Point::<D>::from_fn(|k, _| row[kept[k]]))
            .collect()
    };
    ParticleSet::new(positions)
}

/// The set of `dim` columns of `flat` (rows of `stride`), without the dimension checks.
fn any_set(flat: &[f64], stride: usize) -> PyResult<AnyParticleSet> {
    if stride == 2 {
        particle_set(flat, 2, [0, 1]).map(AnyParticleSet::from)
    } else {
        particle_set(flat, 3, [0, 1, 2]).map(AnyParticleSet::from)
    }
    .map_err(value_error)
}

/// The particle set of a Python `points` argument. `dim`: `None` the array's own dimension,
/// refusing a flat `(n, 3)` set (read as 3D, every particle of it would be boundary) with a
/// message naming `dim=2` and the 2D slice; `Some(2)` drops the one constant axis of an
/// `(n, 3)` array (z first, then y, then x); `Some(3)` keeps an `(n, 3)` array 3D as it is.
fn read_points(points: &Bound<'_, PyAny>, dim: Option<usize>) -> PyResult<AnyParticleSet> {
    read_points_in(points, dim).map(|(set, _)| set)
}

/// The plane of an `(n, 3)` array read with `dim=2`: the axis dropped and its one value.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Plane {
    axis: usize,
    value: f64,
}

/// [`read_points`], and the plane it dropped when `dim=2` made an `(n, 3)` array 2D (the
/// walls beside it are then read in the same plane).
fn read_points_in(
    points: &Bound<'_, PyAny>,
    dim: Option<usize>,
) -> PyResult<(AnyParticleSet, Option<Plane>)> {
    let array = float_array(points, "points", "an (n, 2) or (n, 3) array of reals")?;
    let readonly = array.readonly();
    let (stride, flat) = coordinates(&readonly)?;
    set_of_rows(flat, stride, dim, Layout::Rows)
}

/// How a set's coordinates were given: the words of its errors.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Layout {
    /// An `(n, 2)` or `(n, 3)` array, `points`.
    Rows,
    /// Two or three arrays of `n` values, `columns`.
    Columns,
}

/// [`read_points_in`] of the rows of `flat` (`stride` coordinates each), given as `layout`.
fn set_of_rows(
    flat: &[f64],
    stride: usize,
    dim: Option<usize>,
    layout: Layout,
) -> PyResult<(AnyParticleSet, Option<Plane>)> {
    match (dim, stride) {
        (None, _) | (Some(2), 2) | (Some(3), 3) => {}
        (Some(3), _) => {
            return Err(value_error(match layout {
                Layout::Rows => "dim=3 but points is an (n, 2) array: a 2D set has no z",
                Layout::Columns => "dim=3 but columns has two arrays: a 2D set has no z",
            }))
        }
        (Some(2), _) => {
            let constant = |axis: usize| flat.chunks_exact(3).all(|row| row[axis] == flat[axis]);
            let kept = match [2, 1, 0].into_iter().find(|&axis| constant(axis)) {
                Some(2) => [0, 1],
                Some(1) => [0, 2],
                Some(_) => [1, 2],
                None => {
                    return Err(value_error(
                        "dim=2 but none of x, y, z is constant over all particles, so no \
                         axis can be dropped",
                    ))
                }
            };
            let axis = 3 - kept[0] - kept[1];
            let plane = flat.get(axis).map(|&value| Plane { axis, value });
            return particle_set(flat, 3, kept)
                .map(|set| (AnyParticleSet::from(set), plane))
                .map_err(value_error);
        }
        (Some(d), _) => return Err(value_error(format!("dim must be 2 or 3, got {d}"))),
    }
    let set = any_set(flat, stride)?;
    if dim == Some(3) {
        return Ok((set, None));
    }
    refuse_flat(set, layout).map(|set| (set, None))
}

/// `set` unless it is flat (3D with one constant axis, or without extent): read as 3D,
/// every particle of a flat set would be boundary. The error names `dim=2` and what to pass.
fn refuse_flat(set: AnyParticleSet, layout: Layout) -> PyResult<AnyParticleSet> {
    let what = match layout {
        Layout::Rows => "points",
        Layout::Columns => "columns",
    };
    match set.flatness() {
        None => Ok(set),
        Some(flatness @ Flatness::Plane { axis, .. }) => {
            let slice = match (layout, axis) {
                (Layout::Rows, 2) => "points[:, :2] (x and y)",
                (Layout::Rows, 1) => "points[:, [0, 2]] (x and z)",
                (Layout::Rows, _) => "points[:, 1:] (y and z)",
                (Layout::Columns, 2) => "columns=(x, y)",
                (Layout::Columns, 1) => "columns=(x, z)",
                (Layout::Columns, _) => "columns=(y, z)",
            };
            Err(value_error(format!(
                "{what}: {flatness}: a flat set is 2D, and read as 3D every particle would be \
                 boundary; pass dim=2 (or {slice}), or dim=3 to keep it 3D"
            )))
        }
        Some(flatness) => Err(value_error(format!(
            "{what}: {flatness}: the set has no extent, and every particle would be boundary"
        ))),
    }
}

/// The particle set of a Python `columns` argument: two or three one-dimensional arrays of
/// reals, `(x, y)` or `(x, y, z)`, one value per particle each (a solver's structure of
/// arrays), read in place when they are contiguous `float64`. `dim` as [`read_points_in`].
fn read_columns_in(
    columns: &Bound<'_, PyAny>,
    dim: Option<usize>,
) -> PyResult<(AnyParticleSet, Option<Plane>)> {
    const EXPECTED: &str = "a sequence of two or three one-dimensional arrays of reals, \
        (x, y) or (x, y, z)";
    let count = columns
        .len()
        .map_err(|_| value_error(format!("columns must be {EXPECTED}")))?;
    if !(count == 2 || count == 3) {
        return Err(value_error(format!(
            "columns must be {EXPECTED}, got {count} array{}",
            if count == 1 { "" } else { "s" }
        )));
    }
    let mut arrays = Vec::with_capacity(count);
    for k in 0..count {
        let what = format!("columns[{k}]");
        let column = columns
            .get_item(k)
            .map_err(|_| value_error(format!("columns must be {EXPECTED}")))?;
        let array = float_array(&column, &what, "a one-dimensional array of reals")?;
        if array.ndim() != 1 {
            return Err(value_error(format!(
                "{what} must be a one-dimensional array, got shape {}",
                shape_text(array.shape())
            )));
        }
        arrays.push(array.readonly());
    }
    let mut values = Vec::with_capacity(count);
    for (k, array) in arrays.iter().enumerate() {
        values.push(
            array
                .as_slice()
                .map_err(|e| value_error(format!("columns[{k}]: {e}")))?,
        );
    }
    if let Some(k) = values.iter().position(|v| v.len() != values[0].len()) {
        return Err(value_error(format!(
            "columns: every array has one value per particle, but columns[0] has {} and \
             columns[{k}] has {}",
            values[0].len(),
            values[k].len()
        )));
    }
    match (count, dim) {
        (2, None | Some(2)) => {
            let rows = values[0]
                .iter()
                .zip(values[1])
                .map(|(&x, &y)| Point::<2>::new(x, y));
            let set = ParticleSet::new(rows.collect()).map_err(value_error)?;
            Ok((set.into(), None))
        }
        (3, None | Some(3)) => {
            let rows = values[0]
                .iter()
                .zip(values[1])
                .zip(values[2])
                .map(|((&x, &y), &z)| Point::<3>::new(x, y, z));
            let set = AnyParticleSet::from(ParticleSet::new(rows.collect()).map_err(value_error)?);
            if dim == Some(3) {
                Ok((set, None))
            } else {
                refuse_flat(set, Layout::Columns).map(|set| (set, None))
            }
        }
        _ => {
            // Another `dim` (or dropping an axis): the rows' rules and messages.
            let n = values[0].len();
            let mut flat = Vec::with_capacity(n * count);
            for i in 0..n {
                flat.extend(values.iter().map(|v| v[i]));
            }
            set_of_rows(&flat, count, dim, Layout::Columns)
        }
    }
}

/// The resolution asked for: `r` (a positive real or the text `"auto"`), `h` (the smoothing
/// length, `r = h`) or `spacing` (the particle spacing, `r = k·spacing`).
#[derive(Debug, Clone, Copy)]
enum RadiusArg {
    Value(f64),
    Auto,
    SmoothingLength(f64),
    Spacing(f64),
}

fn radius_arg(r: Option<&Bound<'_, PyAny>>) -> PyResult<Option<RadiusArg>> {
    let Some(r) = r else { return Ok(None) };
    if let Ok(text) = r.cast::<PyString>() {
        let text = text.to_string();
        return if text.trim().eq_ignore_ascii_case("auto") {
            Ok(Some(RadiusArg::Auto))
        } else {
            Err(value_error(format!(
                "r must be a positive real or \"auto\", got {text:?}"
            )))
        };
    }
    if r.is_instance_of::<PyBool>() {
        return Err(PyTypeError::new_err(
            "r must be a positive real or \"auto\", got a bool",
        ));
    }
    r.extract::<f64>()
        .map(|v| Some(RadiusArg::Value(v)))
        .map_err(|_| {
            PyTypeError::new_err(format!(
                "r must be a positive real or \"auto\", got {}",
                type_name(r)
            ))
        })
}

fn type_name(value: &Bound<'_, PyAny>) -> String {
    value
        .get_type()
        .name()
        .map_or_else(|_| "an object".to_owned(), |n| n.to_string())
}

/// A length argument (`h`, `spacing`): a real, not a bool nor a text (checked positive and
/// finite when it is turned into `r`).
fn length_arg(value: &Bound<'_, PyAny>, name: &str, what: &str) -> PyResult<f64> {
    if value.is_instance_of::<PyBool>() || value.cast::<PyString>().is_ok() {
        return Err(PyTypeError::new_err(format!(
            "{name} must be a positive real ({what}), got {}",
            type_name(value)
        )));
    }
    value.extract::<f64>().map_err(|_| {
        PyTypeError::new_err(format!(
            "{name} must be a positive real ({what}), got {}",
            type_name(value)
        ))
    })
}

/// The resolution of the keywords `r`, `h` and `spacing` of `function`: at most one of them
/// (`None` when none is given), as the command line's `--radius`, `--smoothing-length` and
/// `--spacing`.
fn radius_input(
    function: &str,
    r: Option<&Bound<'_, PyAny>>,
    h: Option<&Bound<'_, PyAny>>,
    spacing: Option<&Bound<'_, PyAny>>,
) -> PyResult<Option<RadiusArg>> {
    let given: Vec<&str> = [
        ("r", r.is_some()),
        ("h", h.is_some()),
        ("spacing", spacing.is_some()),
    ]
    .into_iter()
    .filter_map(|(name, given)| given.then_some(name))
    .collect();
    if given.len() > 1 {
        return Err(value_error(format!(
            "{function}(): give the resolution once, as one of r, h and spacing (got {}): h is \
             the smoothing length (r = h), spacing the particle spacing (r = \
             {RADIUS_PER_SPACING} x spacing)",
            given.join(" and ")
        )));
    }
    if let Some(h) = h {
        return Ok(Some(RadiusArg::SmoothingLength(length_arg(
            h,
            "h",
            "the smoothing length, r = h",
        )?)));
    }
    if let Some(dp) = spacing {
        return Ok(Some(RadiusArg::Spacing(length_arg(
            dp,
            "spacing",
            "the particle spacing",
        )?)));
    }
    radius_arg(r)
}

fn radius(r: f64) -> PyResult<Radius> {
    Radius::new(r).map_err(|e| value_error(format!("r: {e}")))
}

/// The resolution an argument gives without looking at the particles: `r`, `r = h` or
/// `r = k·spacing`; `None` for `"auto"`.
fn fixed_radius(arg: RadiusArg) -> PyResult<Option<Radius>> {
    match arg {
        RadiusArg::Value(v) => radius(v).map(Some),
        RadiusArg::SmoothingLength(h) => Radius::new(h)
            .map(Some)
            .map_err(|e| value_error(format!("h: {e}"))),
        RadiusArg::Spacing(dp) => radius_from_spacing(dp)
            .map(Some)
            .map_err(|e| value_error(format!("spacing: {e}"))),
        RadiusArg::Auto => Ok(None),
    }
}

/// The error of a missing resolution in `function`.
fn missing_radius(function: &str) -> PyErr {
    PyTypeError::new_err(format!(
        "{function}() missing required argument 'r' (the resolution: give r, h (the smoothing \
         length, r = h) or spacing (the particle spacing), or r=\"auto\"; optional only with \
         radii=)"
    ))
}

/// The resolution of `set` for a resolution argument without radii: the value, `r = h`,
/// `r = k·spacing`, or the estimate of `"auto"`.
fn resolve_radius(function: &str, set: &AnyParticleSet, r: Option<RadiusArg>) -> PyResult<Radius> {
    let Some(arg) = r else {
        return Err(missing_radius(function));
    };
    if let Some(r) = fixed_radius(arg)? {
        return Ok(r);
    }
    auto_radius(set)
        .map_err(value_error)?
        .map(|auto| auto.radius)
        .ok_or_else(|| {
            value_error(
                "r=\"auto\" needs at least two distinct particle positions to estimate the \
                 spacing",
            )
        })
}

/// With `h` (the smoothing length), the SPH-sum methods take `h` itself as their smoothing
/// length: a parameter `h_over_r` other than 1 (which would make it a multiple of `h`) is
/// refused, as the command line refuses it with `--smoothing-length`.
fn refuse_h_over_r(detector: &dyn BoundaryDetector, arg: Option<RadiusArg>) -> PyResult<()> {
    let Some(RadiusArg::SmoothingLength(h)) = arg else {
        return Ok(());
    };
    for p in detector.describe().0 {
        let one = p.value.trim().parse::<f64>().is_ok_and(|v| v == 1.0);
        if p.name == "h_over_r" && !one {
            return Err(value_error(format!(
                "h={h} gives the SPH sums h = {h} itself; h_over_r={} would make it {} x {h}: \
                 drop h_over_r, or give r= with it",
                p.value, p.value
            )));
        }
    }
    Ok(())
}

/// Whether `r` is implausible for `set` (the core's `radius_concern` against the spacing
/// measured in its bulk). Advisory only: a set whose spacing cannot be measured gives none.
fn concern_of(set: &AnyParticleSet, r: Radius) -> Option<RadiusConcern> {
    bulk_spacing(set)
        .ok()
        .flatten()
        .and_then(|dp| radius_concern(r.get(), dp))
}

/// Whether a resolution given as `arg` (and no radii) is checked against the particles' spacing:
/// every uniform resolution but `"auto"`, which is `k` times that spacing by construction.
fn checks_plausibility(arg: Option<RadiusArg>, radii: bool) -> bool {
    !radii && !matches!(arg, None | Some(RadiusArg::Auto))
}

/// Warns (`UserWarning`, attributed to the caller of the package's function) that `r` looks
/// wrong for the particles, with the numbers.
fn warn_concern(py: Python<'_>, concern: Option<RadiusConcern>) -> PyResult<()> {
    let Some(concern) = concern else {
        return Ok(());
    };
    let text = CString::new(concern.to_string().replace('\0', " ")).unwrap_or_default();
    PyErr::warn(py, &py.get_type::<PyUserWarning>(), &text, 2)
}

/// One radius factor per particle from an `(n,)` array-like `values` (`what` in messages).
fn radius_factors(values: &Bound<'_, PyAny>, what: &str, per: &str) -> PyResult<Vec<f64>> {
    let array = float_array(values, what, "an array of reals")?;
    let readonly = array.readonly();
    let shape = readonly.shape();
    if shape.len() != 1 {
        return Err(value_error(format!(
            "{what} must be a one-dimensional array (one radius per {per}), got shape {}",
            shape_text(shape)
        )));
    }
    Ok(readonly
        .as_slice()
        .map_err(|e| value_error(format!("{what}: {e}")))?
        .to_vec())
}

/// `set` with radius factors `values` (`what` in messages), checked at scale `r`.
fn attach_radii(
    set: AnyParticleSet,
    values: Vec<f64>,
    r: Radius,
    what: &str,
) -> PyResult<AnyParticleSet> {
    let set = set
        .with_radii(values)
        .map_err(|e| value_error(format!("{what}: {e}")))?;
    match &set {
        AnyParticleSet::D2(s) => s.resolved_radii(r).map(drop),
        AnyParticleSet::D3(s) => s.resolved_radii(r).map(drop),
    }
    .map_err(|e| value_error(format!("{what} scaled by r = {}: {e}", r.get())))?;
    Ok(set)
}

/// `set` with the radii of a Python `radii` argument, and the resolution: `r` (or `h`,
/// `spacing`), which defaults to 1 with radii (the scale of the factors) and is required
/// without (a value, `"auto"`, `h` or `spacing`).
fn with_radii(
    function: &str,
    set: AnyParticleSet,
    r: Option<RadiusArg>,
    radii: Option<&Bound<'_, PyAny>>,
) -> PyResult<(AnyParticleSet, Radius)> {
    let Some(radii) = radii else {
        let r = resolve_radius(function, &set, r)?;
        return Ok((set, r));
    };
    let r = match r {
        None => radius(1.0)?,
        Some(arg) => fixed_radius(arg)?.ok_or_else(|| {
            value_error(
                "r=\"auto\" estimates one uniform resolution; with radii= give r as the scale \
                 of the radius factors (default 1)",
            )
        })?,
    };
    let values = radius_factors(radii, "radii", "particle")?;
    Ok((attach_radii(set, values, r, "radii")?, r))
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
    let values = whole_numbers(phases, "phases", "phase", u64::from(u32::MAX))?;
    // In range: checked against u32::MAX.
    Ok(values.into_iter().map(|v| v as u32).collect())
}

/// A one-dimensional array-like of integers in 0..=`max`, one per particle: the `name`
/// argument, each value a `what` (named with its particle in the errors).
fn whole_numbers(arg: &Bound<'_, PyAny>, name: &str, what: &str, max: u64) -> PyResult<Vec<u64>> {
    let py = arg.py();
    let numpy = py.import("numpy")?;
    let array = numpy.call_method1("asarray", (arg,)).map_err(|e| {
        value_error(format!(
            "{name} must be an array of integers: {}",
            e.value(py)
        ))
    })?;
    let shape: Vec<usize> = array.getattr("shape")?.extract()?;
    if shape.len() != 1 {
        return Err(value_error(format!(
            "{name} must be a one-dimensional array (one {what} per particle), got shape {}",
            shape_text(&shape)
        )));
    }
    let kind: String = array.getattr("dtype")?.getattr("kind")?.extract()?;
    if shape[0] > 0 && !matches!(kind.as_str(), "i" | "u") {
        return Err(value_error(format!(
            "{name} must be integers, got an array of dtype {}",
            array.getattr("dtype")?.str()?
        )));
    }
    if shape[0] == 0 {
        return Ok(Vec::new());
    }
    let out_of_range = |i: usize, v: &dyn std::fmt::Display| {
        value_error(format!(
            "{name}: particle {i}: {what} {v} is outside 0..={max}"
        ))
    };
    // Every integer dtype fits in uint64 or int64 without wrapping; the values are then
    // checked. A contiguous array of that dtype is read in place, any other converted to one.
    let contiguous = |dtype: &str| -> PyResult<Bound<'_, PyAny>> {
        let kwargs = PyDict::new(py);
        kwargs.set_item("dtype", numpy.getattr(dtype)?)?;
        numpy.call_method("ascontiguousarray", (&array,), Some(&kwargs))
    };
    if kind == "u" {
        let values = contiguous("uint64")?;
        let values: numpy::PyReadonlyArray1<'_, u64> = values.extract()?;
        let values = values.as_slice()?;
        if let Some((i, v)) = values.iter().enumerate().find(|(_, &v)| v > max) {
            return Err(out_of_range(i, v));
        }
        Ok(values.to_vec())
    } else {
        let values = contiguous("int64")?;
        let values: numpy::PyReadonlyArray1<'_, i64> = values.extract()?;
        let values = values.as_slice()?;
        // The range first, in one branch-free pass (a solver hands its ids every step); the
        // particle and value are looked up only when something is out of range.
        let (low, high) = values
            .iter()
            .fold((i64::MAX, i64::MIN), |(lo, hi), &v| (lo.min(v), hi.max(v)));
        if low < 0 || u64::try_from(high).is_ok_and(|high| high > max) {
            let bad = |&v: &i64| u64::try_from(v).map_or(true, |v| v > max);
            if let Some((i, v)) = values.iter().enumerate().find(|(_, v)| bad(v)) {
                return Err(out_of_range(i, v));
            }
        }
        // Non-negative: the same value as a u64.
        Ok(values.iter().map(|&v| v as u64).collect())
    }
}

/// The domain of `detect`'s keyword arguments, for particles of dimension `dim` and scale
/// `r`: walls (an `(m, dim)` array) with their optional radius factors, solid half-spaces and
/// periodic axes as texts (`"y<0"`, `"x:0:1"`), phase numbers.
fn domain(
    dim: usize,
    plane: Option<Plane>,
    r: Radius,
    args: &DomainArgs<'_, '_>,
) -> PyResult<Domain> {
    let mut domain = Domain::new();
    if let Some(walls) = Walls::read(args.walls, args.wall_radii, Some(dim))? {
        domain = domain.with_walls(walls.set(dim, plane, r)?);
    }
    for solid in solids(args.solids)? {
        domain = domain.with_solid(solid);
    }
    for axis in periodic_axes(args.periodic)? {
        domain = domain.with_periodic(axis);
    }
    if let Some(phases) = args.phases {
        domain = domain.with_phases(phase_numbers(phases)?);
    }
    Ok(domain)
}

/// The solid half-spaces of a `solids` argument (`"y<0"`, or a sequence of such texts).
fn solids(value: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<HalfSpace>> {
    let Some(value) = value else {
        return Ok(Vec::new());
    };
    texts(value, "solids", "y<0")?
        .iter()
        .map(|text| HalfSpace::parse(text).map_err(value_error))
        .collect()
}

/// The periodic axes of a `periodic` argument (`"x:0:1"`, or a sequence of such texts).
fn periodic_axes(value: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<Periodic>> {
    let Some(value) = value else {
        return Ok(Vec::new());
    };
    texts(value, "periodic", "x:0:1")?
        .iter()
        .map(|text| Periodic::parse(text).map_err(value_error))
        .collect()
}

/// A `walls` argument (with its `wall_radii`), copied out of Python: the coordinates, their
/// number of columns, and the radius factors. The particle set is made for the points beside
/// it ([`Walls::set`]).
#[derive(Debug, Clone, PartialEq)]
struct Walls {
    flat: Vec<f64>,
    columns: usize,
    radii: Option<Vec<f64>>,
}

impl Walls {
    /// The walls of the arguments, or `None` without walls; `dim`, when known, is that of
    /// the points (for the messages).
    fn read(
        walls: Option<&Bound<'_, PyAny>>,
        wall_radii: Option<&Bound<'_, PyAny>>,
        dim: Option<usize>,
    ) -> PyResult<Option<Walls>> {
        let walls = match (walls, wall_radii) {
            (None, Some(_)) => return Err(value_error("wall_radii given without walls")),
            (None, None) => return Ok(None),
            (Some(walls), _) => walls,
        };
        let array = float_array(walls, "walls", "an array of reals")?;
        let readonly = array.readonly();
        let shape = readonly.shape();
        if shape.len() != 2 || !(shape[1] == 2 || shape[1] == 3) {
            let columns = dim.map_or("2 or 3".to_owned(), |d| d.to_string());
            return Err(value_error(format!(
                "walls must be an (m, {columns}) array like the points, got shape {}",
                shape_text(shape)
            )));
        }
        let flat = readonly
            .as_slice()
            .map_err(|e| value_error(format!("walls: {e}")))?
            .to_vec();
        let radii = wall_radii
            .map(|radii| radius_factors(radii, "wall_radii", "wall particle"))
            .transpose()?;
        Ok(Some(Walls {
            flat,
            columns: shape[1],
            radii,
        }))
    }

    /// The walls as the particle set beside points of dimension `dim` at scale `r`: `(m, 3)`
    /// walls beside `(n, 3)` points read with `dim=2` lie in the points' `plane`, which is
    /// dropped from both.
    fn set(&self, dim: usize, plane: Option<Plane>, r: Radius) -> PyResult<AnyParticleSet> {
        let set = match (self.columns, dim, plane) {
            (2, 2, _) => particle_set(&self.flat, 2, [0, 1]).map(AnyParticleSet::from),
            (3, 3, _) => particle_set(&self.flat, 3, [0, 1, 2]).map(AnyParticleSet::from),
            (3, 2, Some(plane)) => {
                let axis_name = ["x", "y", "z"][plane.axis];
                if let Some(k) = self
                    .flat
                    .chunks_exact(3)
                    .position(|row| row[plane.axis] != plane.value)
                {
                    return Err(value_error(format!(
                        "walls: wall particle {k} has {axis_name} = {}, off the plane                          {axis_name} = {} of the points (dim=2 drops {axis_name} from both)",
                        self.flat[3 * k + plane.axis], plane.value
                    )));
                }
                let kept = match plane.axis {
                    2 => [0, 1],
                    1 => [0, 2],
                    _ => [1, 2],
                };
                particle_set(&self.flat, 3, kept).map(AnyParticleSet::from)
            }
            (columns, dim, _) => {
                return Err(value_error(format!(
                    "walls must be an (m, {dim}) array like the points, got shape ({}, {columns}){}",
                    self.flat.len() / columns,
                    if columns == 3 {
                        ": pass dim=2 with (n, 3) points in the walls' plane, or walls[:, :2]"
                    } else {
                        ""
                    }
                )))
            }
        }
        .map_err(|e| value_error(format!("walls: {e}")))?;
        match &self.radii {
            Some(values) => attach_radii(set, values.clone(), r, "wall_radii"),
            None => Ok(set),
        }
    }
}

/// The domain arguments of `Detector.detect`, as given.
struct DomainArgs<'a, 'py> {
    walls: Option<&'a Bound<'py, PyAny>>,
    wall_radii: Option<&'a Bound<'py, PyAny>>,
    solids: Option<&'a Bound<'py, PyAny>>,
    periodic: Option<&'a Bound<'py, PyAny>>,
    phases: Option<&'a Bound<'py, PyAny>>,
}

/// A parameter's value as the text `--set KEY=VALUE` would carry: `True`/`False` as
/// `true`/`false`, anything else by `str()`.
fn param_text(value: &Bound<'_, PyAny>) -> PyResult<String> {
    if let Ok(flag) = value.cast::<PyBool>() {
        return Ok(if flag.is_true() { "true" } else { "false" }.to_owned());
    }
    Ok(value.str()?.to_string())
}

/// The `(key, text)` pairs of a parameter dict, in the order given.
fn param_pairs(params: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<(String, String)>> {
    let mut pairs = Vec::new();
    if let Some(params) = params {
        for (key, value) in params.iter() {
            pairs.push((key.str()?.to_string(), param_text(&value)?));
        }
    }
    Ok(pairs)
}

/// The detector `method` with the parameters `pairs`, through the facade's registry.
fn detector(method: &str, pairs: &[(String, String)]) -> PyResult<Arc<dyn BoundaryDetector>> {
    detector_with_params(method, pairs)
        .map(Arc::from)
        .map_err(value_error)
}

/// The text of a caught panic's payload.
fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| (*s).to_owned())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".to_owned())
}

/// Runs `job` on a rayon pool of `threads` workers (all cores when `None`) built for this
/// call, with the GIL released while waiting, checking for signals (Ctrl-C) every
/// [`SIGNAL_POLL`]. On a signal the pool's stop token is stopped, so the workers leave their
/// remaining particles; the call waits for them to end (within one particle's work) and then
/// raises the signal's exception. A panic in `job` becomes `RuntimeError`.
fn run_interruptible<T, F>(py: Python<'_>, threads: Option<usize>, job: F) -> PyResult<T>
where
    T: Send + 'static,
    F: FnOnce() -> T + Send + 'static,
{
    let (token, pool) = interruptible_pool(threads)?;
    run_on(py, &token, &pool, job)
}

/// A rayon pool of `threads` workers (all cores when `None`) that stop when its token is
/// stopped ([`run_on`]).
fn interruptible_pool(threads: Option<usize>) -> PyResult<(StopToken, rayon::ThreadPool)> {
    if threads == Some(0) {
        return Err(value_error("threads must be at least 1"));
    }
    let token = StopToken::new();
    let pool = token
        .pool_builder()
        .num_threads(threads.unwrap_or(0))
        .thread_name(|k| format!("boundary-{k}"))
        .build()
        .map_err(|e| PyRuntimeError::new_err(format!("cannot start worker threads: {e}")))?;
    Ok((token, pool))
}

/// Runs `job` on `pool` (from [`interruptible_pool`], with its `token`) as
/// [`run_interruptible`] does. After a signal the token stays stopped: the pool is not to be
/// used again.
fn run_on<T, F>(py: Python<'_>, token: &StopToken, pool: &rayon::ThreadPool, job: F) -> PyResult<T>
where
    T: Send + 'static,
    F: FnOnce() -> T + Send + 'static,
{
    let (sender, receiver) = mpsc::channel();
    pool.spawn(move || {
        let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(job))
            .map_err(|payload| panic_text(payload.as_ref()));
        // The receiver outlives the job (the caller waits for it even when interrupted).
        let _ = sender.send(outcome);
    });
    let mut receiver = receiver;
    let mut interrupted: Option<PyErr> = None;
    let outcome = loop {
        // The receiver travels into the GIL-free wait and back (it is `Send`, not `Sync`).
        let (back, received) = py.detach(move || {
            let received = receiver.recv_timeout(SIGNAL_POLL);
            (receiver, received)
        });
        receiver = back;
        match received {
            Ok(outcome) => break outcome,
            Err(RecvTimeoutError::Timeout) => {
                if interrupted.is_none() {
                    if let Err(signal) = py.check_signals() {
                        token.stop();
                        interrupted = Some(signal);
                    }
                }
            }
            Err(RecvTimeoutError::Disconnected) => {
                break Err("the worker ended without a result".to_owned())
            }
        }
    };
    if let Some(signal) = interrupted {
        return Err(signal);
    }
    outcome.map_err(|panic| {
        PyRuntimeError::new_err(format!("internal error (please report it): {panic}"))
    })
}

/// What [`detect_set`] returns: the detection, its wall time in seconds (the Rust call
/// alone), and what looks wrong about `r` when it was checked.
type Detected = (DomainDetection, f64, Option<RadiusConcern>);

/// Detection of `set` by `detector` in `domain` (the bare cloud: `Domain::new()`) on
/// `threads` workers, interruptible; also its wall time in seconds (the Rust call alone) and,
/// when `check`, whether `r` is implausible for the set's spacing ([`concern_of`]).
fn detect_set(
    py: Python<'_>,
    detector: Arc<dyn BoundaryDetector>,
    set: AnyParticleSet,
    domain: Domain,
    r: Radius,
    threads: Option<usize>,
    check: bool,
) -> PyResult<Detected> {
    let outcome = run_interruptible(py, threads, move || {
        let concern = if check { concern_of(&set, r) } else { None };
        let start = Instant::now();
        let detection = if domain.is_bare() {
            detector.detect(&set, r).map(|detection| DomainDetection {
                detection,
                interface: None,
            })
        } else {
            detector.detect_in(&set, &domain, r)
        };
        detection.map(|d| (d, start.elapsed().as_secs_f64(), concern))
    })?;
    outcome.map_err(detect_error)
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

/// A method with its parameters and thread count, built once through the facade's registry
/// (`boundary::detector_with_params`) and used for any number of detections.
#[pyclass(module = "boundary_particles._native", frozen)]
struct Detector {
    method: String,
    threads: Option<usize>,
    detector: Arc<dyn BoundaryDetector>,
}

#[pymethods]
impl Detector {
    #[new]
    #[pyo3(signature = (method = "exact", threads = None, params = None))]
    fn new(
        method: &str,
        threads: Option<usize>,
        params: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        if threads == Some(0) {
            return Err(value_error("threads must be at least 1"));
        }
        let pairs = param_pairs(params)?;
        let detector = detector(method, &pairs)?;
        Ok(Self {
            method: method.to_owned(),
            threads,
            detector,
        })
    }

    /// The method's name.
    #[getter]
    fn method(&self) -> &str {
        &self.method
    }

    /// The worker threads (`None`: all cores).
    #[getter]
    fn threads(&self) -> Option<usize> {
        self.threads
    }

    /// Every parameter of the method with its value in this detector, as `(key, text)` pairs
    /// (the listing `boundary methods` prints).
    fn settings(&self) -> Vec<(String, String)> {
        self.detector
            .describe()
            .0
            .into_iter()
            .map(|p| (p.name.to_owned(), p.value))
            .collect()
    }

    /// Whether the method never misses a boundary particle.
    #[getter]
    fn certified(&self) -> bool {
        self.detector.certified()
    }

    /// The method's label, `name (key=value, ...)`.
    fn label(&self) -> String {
        self.detector.to_string()
    }

    #[pyo3(signature = (
        points, r = None, margin = false, radii = None, walls = None, wall_radii = None,
        solids = None, periodic = None, phases = None, dim = None, *, h = None, spacing = None
    ))]
    #[allow(clippy::too_many_arguments)] // the Python signature: keyword arguments with defaults
    fn detect<'py>(
        &self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
        r: Option<&Bound<'py, PyAny>>,
        margin: bool,
        radii: Option<&Bound<'py, PyAny>>,
        walls: Option<&Bound<'py, PyAny>>,
        wall_radii: Option<&Bound<'py, PyAny>>,
        solids: Option<&Bound<'py, PyAny>>,
        periodic: Option<&Bound<'py, PyAny>>,
        phases: Option<&Bound<'py, PyAny>>,
        dim: Option<usize>,
        h: Option<&Bound<'py, PyAny>>,
        spacing: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let arg = radius_input("detect", r, h, spacing)?;
        refuse_h_over_r(self.detector.as_ref(), arg)?;
        let check = checks_plausibility(arg, radii.is_some());
        let (set, plane) = read_points_in(points, dim)?;
        let (set, r) = with_radii("detect", set, arg, radii)?;
        let args = DomainArgs {
            walls,
            wall_radii,
            solids,
            periodic,
            phases,
        };
        let domain = domain(set.dim(), plane, r, &args)?;
        let with_phases = domain.phases().is_some();
        let (found, _, concern) = detect_set(
            py,
            self.detector.clone(),
            set,
            domain,
            r,
            self.threads,
            check,
        )?;
        warn_concern(py, concern)?;
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

    /// `detect` on the bare cloud that also returns the seconds the Rust detection took
    /// (the overhead measurement of `bench/overhead.py`).
    #[pyo3(signature = (points, r))]
    fn _detect_timed<'py>(
        &self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
        r: f64,
    ) -> PyResult<(Bound<'py, PyArray1<bool>>, f64)> {
        let r = radius(r)?;
        let set = read_points(points, None)?;
        let (found, seconds, _) = detect_set(
            py,
            self.detector.clone(),
            set,
            Domain::new(),
            r,
            self.threads,
            false,
        )?;
        Ok((bool_array(py, found.detection.labels.into_vec()), seconds))
    }
}

/// The resolution `auto` would use on `points`: the core's `auto_radius` (`k` times the
/// spacing measured in the bulk).
#[pyfunction]
#[pyo3(signature = (points, dim = None))]
fn auto_radius_of(py: Python<'_>, points: &Bound<'_, PyAny>, dim: Option<usize>) -> PyResult<f64> {
    let set = read_points(points, dim)?;
    py.detach(|| resolve_radius("auto_radius", &set, Some(RadiusArg::Auto)))
        .map(|r| r.get())
}

/// The particle spacing of `points` as a solver defines it: the core's `bulk_spacing` (the
/// side of the volume per particle in the bulk).
#[pyfunction]
#[pyo3(signature = (points, dim = None))]
fn bulk_spacing_of(py: Python<'_>, points: &Bound<'_, PyAny>, dim: Option<usize>) -> PyResult<f64> {
    let set = read_points(points, dim)?;
    py.detach(|| bulk_spacing(&set))
        .map_err(value_error)?
        .ok_or_else(|| {
            value_error(
                "bulk_spacing needs at least two distinct particle positions to measure the                  spacing",
            )
        })
}

/// The address of the buffer `detect` reads `points` from (the no-conversion test compares it
/// with the array's own data pointer).
#[pyfunction]
fn _points_address(points: &Bound<'_, PyAny>) -> PyResult<usize> {
    let array = float_array(points, "points", "an (n, 2) or (n, 3) array of reals")?;
    let readonly = array.readonly();
    let (_, flat) = coordinates(&readonly)?;
    Ok(flat.as_ptr() as usize)
}

/// Labels from an array-like of booleans or 0/1 values (`what` in messages), `n` of them
/// when `n` is given.
fn bool_labels(values: &Bound<'_, PyAny>, what: &str, n: Option<usize>) -> PyResult<Vec<bool>> {
    let array = float_array(values, what, "an array of booleans or 0/1")?;
    let readonly = array.readonly();
    let shape = readonly.shape();
    if shape.len() != 1 {
        return Err(value_error(format!(
            "{what} must be a one-dimensional array, got shape {}",
            shape_text(shape)
        )));
    }
    let values = readonly
        .as_slice()
        .map_err(|e| value_error(format!("{what}: {e}")))?;
    if let Some(n) = n {
        if values.len() != n {
            return Err(value_error(format!(
                "{what}: {} labels for {n} particles",
                values.len()
            )));
        }
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
                    "{what}: particle {i}: a label must be 0 or 1 (or a bool), got {v}"
                )))
            }
        })
        .collect()
}

/// The confusion counts of `predicted` against `truth` (boundary is the positive class),
/// with the keys of `boundary score --json`: tp, tn, fp, fn, recall, fpr, m, precision, f1.
#[pyfunction]
fn confusion<'py>(
    py: Python<'py>,
    predicted: &Bound<'py, PyAny>,
    truth: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyDict>> {
    let predicted = bool_labels(predicted, "predicted", None)?;
    let truth = bool_labels(truth, "truth", None)?;
    if predicted.len() != truth.len() {
        return Err(value_error(format!(
            "predicted has {} labels and truth {}: one label per particle in both",
            predicted.len(),
            truth.len()
        )));
    }
    let c = Confusion::from_labels(&predicted, &truth).map_err(value_error)?;
    let dict = PyDict::new(py);
    dict.set_item("tp", c.tp)?;
    dict.set_item("tn", c.tn)?;
    dict.set_item("fp", c.fp)?;
    dict.set_item("fn", c.fn_)?;
    dict.set_item("recall", c.recall())?;
    dict.set_item("fpr", c.fpr())?;
    dict.set_item("m", c.m())?;
    dict.set_item("precision", c.precision())?;
    dict.set_item("f1", c.f1())?;
    Ok(dict)
}

/// Every method: a list of dicts with name, summary (with the paper), certified and params
/// (name, default, description each); the data of `boundary methods --json`.
#[pyfunction]
fn methods(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let list = PyList::empty(py);
    for name in method_names() {
        let d = detector(name, &[])?;
        let entry = PyDict::new(py);
        entry.set_item("name", name)?;
        entry.set_item("summary", summary(name).unwrap_or(""))?;
        entry.set_item("certified", d.certified())?;
        let params = PyList::empty(py);
        for p in d.describe().0 {
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

/// The component index of a column name `base:k` (`k` decimal), with its base.
fn component(name: &str) -> Option<(&str, usize)> {
    let (base, k) = name.rsplit_once(':')?;
    if base.is_empty() || k.is_empty() || !k.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    Some((base, k.parse().ok()?))
}

/// Reads a particle file: `(points, point_data)`, each attribute a `(n,)` array, or `(n, k)`
/// for the `k` columns `name:0 .. name:k-1` of one vector attribute (consecutive, of one type).
#[pyfunction]
#[pyo3(signature = (path, dim = None, format = None, array = None))]
fn read<'py>(
    py: Python<'py>,
    path: PathBuf,
    dim: Option<usize>,
    format: Option<&str>,
    array: Option<&str>,
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
        .detach(|| match array {
            Some(array) => boundary_io::read_particle_array(&path, array, &options),
            None => boundary_io::read_particle_file(&path, &options),
        })
        .map_err(io_error)?;
    for skipped in &file.skipped {
        let text = format!("{}: attribute not read: {skipped}", path.display());
        let text = CString::new(text.replace('\0', " ")).unwrap_or_default();
        PyErr::warn(py, &py.get_type::<PyUserWarning>(), &text, 1)?;
    }
    let n = file.set.len();
    let point_data = PyDict::new(py);
    let attributes = file.attributes;
    let mut a = 0;
    while a < attributes.len() {
        // A run `base:0, base:1, ...` of one value type is one (n, k) array.
        let mut k = 0;
        if let Some((base, 0)) = component(&attributes[a].name) {
            let same_kind = |x: &AttributeValues| {
                matches!(
                    (x, &attributes[a].values),
                    (AttributeValues::Int(_), AttributeValues::Int(_))
                        | (AttributeValues::Float(_), AttributeValues::Float(_))
                )
            };
            while a + k < attributes.len()
                && component(&attributes[a + k].name) == Some((base, k))
                && same_kind(&attributes[a + k].values)
            {
                k += 1;
            }
            if k >= 2 && !point_data.contains(base)? {
                let columns = &attributes[a..a + k];
                let value = match &columns[0].values {
                    AttributeValues::Int(_) => {
                        let rows: Vec<Vec<i64>> = (0..n)
                            .map(|i| {
                                columns
                                    .iter()
                                    .map(|c| match &c.values {
                                        AttributeValues::Int(v) => v[i],
                                        AttributeValues::Float(_) => 0,
                                    })
                                    .collect()
                            })
                            .collect();
                        vector_array(py, rows, k)?
                    }
                    AttributeValues::Float(_) => {
                        let rows: Vec<Vec<f64>> = (0..n)
                            .map(|i| {
                                columns
                                    .iter()
                                    .map(|c| match &c.values {
                                        AttributeValues::Float(v) => v[i],
                                        AttributeValues::Int(_) => 0.0,
                                    })
                                    .collect()
                            })
                            .collect();
                        vector_array(py, rows, k)?
                    }
                };
                point_data.set_item(base, value)?;
                a += k;
                continue;
            }
        }
        let attribute = &attributes[a];
        let values = match &attribute.values {
            AttributeValues::Int(v) => PyArray1::from_slice(py, v).into_any(),
            AttributeValues::Float(v) => PyArray1::from_slice(py, v).into_any(),
        };
        point_data.set_item(&attribute.name, values)?;
        a += 1;
    }
    Ok((points_array(py, &file.set)?, point_data))
}

/// An `(n, k)` array of `rows` (each of length `k`; an `(0, k)` array when empty).
fn vector_array<'py, T: numpy::Element + Copy>(
    py: Python<'py>,
    rows: Vec<Vec<T>>,
    k: usize,
) -> PyResult<Bound<'py, PyAny>> {
    let n = rows.len();
    let flat: Vec<T> = rows.into_iter().flatten().collect();
    let array: Bound<'py, PyArray2<T>> = PyArray1::from_vec(py, flat).reshape([n, k])?;
    Ok(array.into_any())
}

/// One column given to `write`: integers stay integers (NumPy kinds `b`, `i`, `u`), anything
/// else is written as reals.
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

/// The columns of one `point_data` entry: a `(n,)` array is the column `name`, a `(n, k)`
/// array the columns `name:0 .. name:k-1` (which VTK XML and BGEO write as one vector
/// attribute, and PLY as the properties `name_0 .. name_k-1`).
fn owned_columns(name: &str, values: &Bound<'_, PyAny>) -> PyResult<Vec<(String, OwnedColumn)>> {
    let py = values.py();
    let numpy = py.import("numpy")?;
    let array = numpy
        .call_method1("asarray", (values,))
        .map_err(|e| value_error(format!("point_data {name:?}: {}", e.value(py))))?;
    let shape: Vec<usize> = array.getattr("shape")?.extract()?;
    let kind: String = array.getattr("dtype")?.getattr("kind")?.extract()?;
    let integer = matches!(kind.as_str(), "b" | "i" | "u");
    if kind == "u" && shape.iter().product::<usize>() > 0 {
        // uint64 beyond i64::MAX would wrap in astype: refuse it instead.
        let max: u64 = array.call_method0("max")?.extract()?;
        if max > i64::MAX as u64 {
            return Err(value_error(format!(
                "point_data {name:?}: value {max} does not fit a signed 64-bit integer"
            )));
        }
    }
    let column = |values: Bound<'_, PyAny>| -> PyResult<OwnedColumn> {
        let dtype = if integer { "int64" } else { "float64" };
        let converted = values
            .call_method1("astype", (numpy.getattr(dtype)?,))
            .map_err(|e| value_error(format!("point_data {name:?}: {}", e.value(py))))?;
        Ok(if integer {
            OwnedColumn::Int(converted.extract()?)
        } else {
            OwnedColumn::Float(converted.extract()?)
        })
    };
    match shape.as_slice() {
        [_] => Ok(vec![(name.to_owned(), column(array)?)]),
        [_, k] => (0..*k)
            .map(|j| {
                let item = array.get_item((pyo3::types::PySlice::full(py), j))?;
                Ok((format!("{name}:{j}"), column(item)?))
            })
            .collect(),
        _ => Err(value_error(format!(
            "point_data {name:?}: expected an (n,) or (n, k) array (one value or one vector \
             per particle), got shape {}",
            shape_text(&shape)
        ))),
    }
}

/// Writes points with an optional `boundary` column (0/1) and the `point_data` columns, in
/// the format of the extension or `format`; atomic.
#[pyfunction]
#[pyo3(signature = (path, points, boundary = None, point_data = None, format = None, dim = None))]
fn write(
    py: Python<'_>,
    path: PathBuf,
    points: &Bound<'_, PyAny>,
    boundary: Option<&Bound<'_, PyAny>>,
    point_data: Option<&Bound<'_, PyAny>>,
    format: Option<&str>,
    dim: Option<usize>,
) -> PyResult<()> {
    let set = read_points(points, dim)?;
    let format = format_arg(format)?;
    let mut owned: Vec<(String, OwnedColumn)> = Vec::new();
    if let Some(labels) = boundary {
        let labels = bool_labels(labels, "boundary", Some(set.len()))?;
        owned.push((
            "boundary".to_owned(),
            OwnedColumn::Int(labels.iter().map(|&b| i64::from(b)).collect()),
        ));
    }
    if let Some(point_data) = point_data {
        let items = point_data
            .call_method0("items")
            .map_err(|_| PyTypeError::new_err("point_data must be a mapping of names to arrays"))?;
        for item in items.try_iter()? {
            let (key, values): (Bound<'_, PyAny>, Bound<'_, PyAny>) = item?.extract()?;
            let name = key
                .cast::<PyString>()
                .map_err(|_| PyTypeError::new_err("point_data: every name must be a string"))?
                .to_string();
            owned.extend(owned_columns(&name, &values)?);
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

/// Classifies boundary particles by feature and resamples thin features (`boundary-resample`).
#[pyfunction]
#[pyo3(signature = (
    points, r, detector, k = 4, alpha = 0.2, shift = 0.5, labels = None, *, h = None,
    spacing = None
))]
#[allow(clippy::too_many_arguments)] // the Python signature: keyword arguments with defaults
fn resample<'py>(
    py: Python<'py>,
    points: &Bound<'py, PyAny>,
    r: Option<&Bound<'py, PyAny>>,
    detector: &Detector,
    k: usize,
    alpha: f64,
    shift: f64,
    labels: Option<&Bound<'py, PyAny>>,
    h: Option<&Bound<'py, PyAny>>,
    spacing: Option<&Bound<'py, PyAny>>,
) -> PyResult<ResampledArrays<'py>> {
    let arg = radius_input("resample", r, h, spacing)?;
    if labels.is_none() {
        refuse_h_over_r(detector.detector.as_ref(), arg)?;
    }
    let check = checks_plausibility(arg, false);
    let set = read_points(points, None)?;
    let r = resolve_radius("resample", &set, arg)?;
    let config = boundary_resample::ResampleConfig {
        k,
        alpha,
        shift,
        ..boundary_resample::ResampleConfig::default()
    };
    let given = match labels {
        Some(l) => Some(Labels::new(bool_labels(l, "labels", Some(set.len()))?)),
        None => None,
    };
    let method = detector.detector.clone();
    let outcome = run_interruptible(py, detector.threads, move || -> Result<_, DetectError> {
        let concern = if check { concern_of(&set, r) } else { None };
        let labels = match given {
            Some(l) => l,
            None => method.detect(&set, r)?.labels,
        };
        let resampled = match &set {
            AnyParticleSet::D2(s) => boundary_resample::resample(s, r, &labels, &config)
                .map(|o| (o.set.into(), o.feature, o.source)),
            AnyParticleSet::D3(s) => boundary_resample::resample(s, r, &labels, &config)
                .map(|o| (o.set.into(), o.feature, o.source)),
        }
        .map_err(|e| DetectError::Method {
            method: "resample",
            message: e.to_string(),
        })?;
        Ok((resampled, concern))
    })?;
    let ((out, feature, source), concern): ((AnyParticleSet, Vec<i8>, Vec<usize>), _) =
        outcome.map_err(detect_error)?;
    warn_concern(py, concern)?;
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

/// The compiled part of `boundary_particles`; see the package for the documented API.
#[pymodule]
#[pyo3(name = "_native")]
fn boundary_py(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<Detector>()?;
    m.add_function(wrap_pyfunction!(confusion, m)?)?;
    m.add_class::<tracker::PyTracker>()?;
    m.add_function(wrap_pyfunction!(methods, m)?)?;
    m.add_function(wrap_pyfunction!(read, m)?)?;
    m.add_function(wrap_pyfunction!(write, m)?)?;
    m.add_function(wrap_pyfunction!(resample, m)?)?;
    m.add_function(wrap_pyfunction!(auto_radius_of, m)?)?;
    m.add_function(wrap_pyfunction!(bulk_spacing_of, m)?)?;
    m.add("RADIUS_PER_SPACING", RADIUS_PER_SPACING)?;
    m.add_function(wrap_pyfunction!(_points_address, m)?)?;
    let features = PyDict::new(py);
    features.set_item(boundary_resample::INTERIOR_CODE, "interior")?;
    for (f, name) in [
        (boundary_resample::Feature::Droplet, "droplet"),
        (boundary_resample::Feature::Ligament, "ligament"),
        (boundary_resample::Feature::Sheet, "sheet"),
        (boundary_resample::Feature::Regular, "regular"),
    ] {
        features.set_item(f.code(), name)?;
    }
    m.add("FEATURES", features)?;
    Ok(())
}
