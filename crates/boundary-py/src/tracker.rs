//! `boundary_particles.Tracker`: the library's incremental tracker (`boundary::Tracker`) for Python.
//! Translation only: arguments checked and converted as `detect` does, the update run on a
//! worker thread with the GIL released and Ctrl-C honoured.

use super::{
    bool_array, detector, param_pairs, radius, read_points, run_interruptible, value_error,
    whole_numbers,
};
use boundary::{Domain, Radius, Tracker};
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Labels the particles of successive time steps, each as `detect(points, r)` would, while
/// recomputing only the particles whose label may have changed since the previous step.
///
/// Tracker(r, method="exact", threads=None, **params): r, the particle resolution (> 0);
/// method: "exact" (the only method with a tracker); threads: worker threads (default: all
/// cores); **params: the method's parameters (exact: tie must stay 0, the exact labels).
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
    /// How many particles the last update recomputed.
    #[pyo3(get)]
    recomputed: usize,
}

#[pymethods]
impl PyTracker {
    #[new]
    #[pyo3(signature = (r, method = "exact", threads = None, **params))]
    fn new(
        r: f64,
        method: &str,
        threads: Option<usize>,
        params: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let r = radius(r)?;
        // Unknown methods and parameters fail with the registry's messages.
        let configured = detector(method, &param_pairs(params)?)?;
        if method != "exact" {
            return Err(value_error(format!(
                "Tracker: method '{method}' has no tracker; use method=\"exact\""
            )));
        }
        if configured.params().0.iter().any(|p| p.value != p.default) {
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
        let (tracker, outcome) = run_interruptible(py, self.threads, move || {
            let outcome = match &ids {
                Some(ids) => tracker.update_with_ids(&set, ids),
                None => tracker.update(&set),
            }
            .map(|labels| labels.as_slice().to_vec());
            (tracker, outcome)
        })?;
        let labels = outcome.map_err(value_error)?;
        self.recomputed = tracker.recomputed();
        self.tracker = Some(tracker);
        Ok(bool_array(py, labels))
    }

    fn __repr__(&self) -> String {
        format!("Tracker(r={}, method=\"exact\")", self.r.get())
    }
}
