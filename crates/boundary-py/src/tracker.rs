//! `boundary_particles.Tracker`: the library's incremental tracker (`boundary::Tracker`) for Python.
//! Translation only: arguments checked and converted as `detect` does, the update run on a
//! worker thread with the GIL released and Ctrl-C honoured.

use super::{
    bool_array, checks_plausibility, concern_of, detector, fixed_radius, param_pairs, radius_input,
    read_points, refuse_h_over_r, run_interruptible, value_error, warn_concern, whole_numbers,
    RadiusArg,
};
use boundary::{Domain, Radius, Tracker};
use numpy::PyArray1;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Labels the particles of successive time steps, each as `detect(points, r)` would, while
/// recomputing only the particles whose label may have changed since the previous step.
///
/// Tracker(r=None, method="exact", threads=None, *, h=None, spacing=None, **params): the
/// resolution as one of r (> 0), h (the smoothing length, r = h) and spacing (the particle
/// spacing, r = k * spacing); method: "exact" (the only method with a tracker); threads: worker
/// threads (default: all cores); **params: the method's parameters (exact: tie must stay 0, the
/// exact labels). An r implausible for the spacing of the first update's particles warns
/// (`UserWarning`), once.
///
/// update(points, ids=None) -> bool array of length n (True = boundary): the labels of this
/// step's positions, the same particles in the same order as before (another count starts
/// over), or, with ids (one whole number per particle, unique), matched to the last update's
/// particles by id: particles may come, go and reorder.
/// recomputed: how many particles the last update recomputed.
#[derive(Debug)]
#[pyclass(name = "Tracker", module = "boundary_particles._native")]
pub struct PyTracker {
    r: Radius,
    threads: Option<usize>,
    /// `None` after an interrupted update (the abandoned one keeps it): the next update starts
    /// over with a new tracker.
    tracker: Option<Tracker>,
    /// Whether `r` is still to be checked against the particles' spacing (at the first update).
    check: bool,
    /// How many particles the last update recomputed.
    #[pyo3(get)]
    recomputed: usize,
}

#[pymethods]
impl PyTracker {
    #[new]
    #[pyo3(signature = (r = None, method = "exact", threads = None, *, h = None, spacing = None, **params))]
    fn new(
        r: Option<&Bound<'_, PyAny>>,
        method: &str,
        threads: Option<usize>,
        h: Option<&Bound<'_, PyAny>>,
        spacing: Option<&Bound<'_, PyAny>>,
        params: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let missing = || {
            PyTypeError::new_err(
                "Tracker() missing required argument 'r' (the resolution: give r, h (the \
                 smoothing length, r = h) or spacing (the particle spacing))",
            )
        };
        let arg = radius_input("Tracker", r, h, spacing)?.ok_or_else(missing)?;
        if matches!(arg, RadiusArg::Auto) {
            return Err(value_error(
                "Tracker: r=\"auto\" is not supported (the resolution must be the same at \
                 every step): give r, h or spacing, e.g. r=bp.auto_radius(first_points)",
            ));
        }
        let r = fixed_radius(arg)?.ok_or_else(missing)?;
        // Unknown methods and parameters fail with the registry's messages.
        let configured = detector(method, &param_pairs(params)?)?;
        refuse_h_over_r(configured.as_ref(), Some(arg))?;
        if method != "exact" {
            return Err(value_error(format!(
                "Tracker: method '{method}' has no tracker; use method=\"exact\""
            )));
        }
        if configured.describe().0.iter().any(|p| p.value != p.default) {
            return Err(value_error(format!(
                "Tracker: {configured} is not supported: the tracker gives the exact labels \
                 (tie = 0)"
            )));
        }
        if threads == Some(0) {
            return Err(value_error("threads must be at least 1"));
        }
        Ok(PyTracker {
            r,
            threads,
            tracker: None,
            check: checks_plausibility(Some(arg), false),
            recomputed: 0,
        })
    }

    /// The labels of this step's positions (an (n, 2) or (n, 3) array-like of reals), the
    /// particles matched by `ids` when given.
    #[pyo3(signature = (points, ids = None))]
    fn update<'py>(
        &mut self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
        ids: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray1<bool>>> {
        let set = read_points(points, None)?;
        let ids = ids
            .map(|ids| whole_numbers(ids, "ids", "id", u64::MAX))
            .transpose()?;
        let mut tracker = match self.tracker.take() {
            Some(t) => t,
            // The update runs on the interruptible pool of `threads` workers.
            None => Tracker::new(self.r, None, Domain::new()).map_err(value_error)?,
        };
        let (check, r) = (self.check, self.r);
        let (tracker, outcome, concern) = run_interruptible(py, self.threads, move || {
            let concern = if check { concern_of(&set, r) } else { None };
            let outcome = match &ids {
                Some(ids) => tracker.update_with_ids(&set, ids),
                None => tracker.update(&set),
            }
            .map(|labels| labels.as_slice().to_vec());
            (tracker, outcome, concern)
        })?;
        let labels = outcome.map_err(value_error)?;
        self.recomputed = tracker.recomputed();
        self.tracker = Some(tracker);
        self.check = false;
        warn_concern(py, concern)?;
        Ok(bool_array(py, labels))
    }

    fn __repr__(&self) -> String {
        format!("Tracker(r={}, method=\"exact\")", self.r.get())
    }
}
