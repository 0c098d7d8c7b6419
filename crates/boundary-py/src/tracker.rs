//! `boundary_particles.Tracker`: the library's incremental tracker (`boundary::Tracker`) for Python.
//! Translation only: arguments checked and converted as `detect` does, the update run with the
//! GIL released: a small set's on the calling thread (the tracker hands its large parts to
//! the tracker's own worker pool), a large set's on that pool with Ctrl-C honoured.

use super::{
    attach_radii, bool_array, checks_plausibility, concern_of, detector, fixed_radius,
    interruptible_pool, panic_text, param_pairs, periodic_axes, phase_numbers, radius_factors,
    radius_input, read_columns_in, read_points_in, refuse_h_over_r, resolve_radius, run_on,
    value_error, warn_concern, whole_numbers, Plane, RadiusArg, Walls,
};
use boundary::stop::StopToken;
use boundary::{Domain, HalfSpace, Periodic, Radius, Tracker};
use pyo3::exceptions::{PyRuntimeError, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use std::sync::Arc;

/// Updates of fewer particles run on the calling thread: the longest of them (a first update,
/// every particle evaluated) takes some tens of milliseconds, the longest a Ctrl-C waits;
/// handing a few-thousand-particle update to a worker and back cost as much as the update.
/// Larger sets run on the worker pool, interruptible.
const CALLING_THREAD_BELOW: usize = 16_384;

/// What to say when ids are missing or unusable: the solver's own stable id, or none.
pub(crate) const IDS_GUIDANCE: &str = "ids are one unique whole number per particle that \
    follows the particle when the solver reorders: the solver's own stable id, or an id \
    property given to the particles when they are created (0 .. n-1), which the solver \
    permutes with the others; without either (PySPH's serial gid is 4294967295 for every \
    particle), pass no ids: the particles are then matched by their place in the array, right \
    while the solver keeps their order, and a new count starts over";

/// Labels the particles of successive time steps, each as `detect(points, r, ...)` would in
/// the same domain, while recomputing only the particles whose label may have changed since
/// the previous step.
///
/// Tracker(r=None, method="exact", threads=None, *, h=None, spacing=None, walls=None,
/// wall_radii=None, solids=None, periodic=None, **params): the resolution as one of r (> 0 or
/// "auto": measured at the first update, then kept), h and spacing (with radii at the updates
/// it is their scale, default 1); the domain as `detect` takes it (the walls fixed until an
/// update passes others).
///
/// update(points=None, ids=None, *, columns=None, radii=None, walls=None, wall_radii=None,
/// phases=None, dim=None) -> labels, or (labels, interface) with phases: the positions as
/// `points`, an (n, 2) or (n, 3) array, or as `columns=(x, y)` or `(x, y, z)`, one array per
/// coordinate (a solver's own arrays, read in place when contiguous float64). An update of
/// fewer than 16,384 particles runs on the calling thread (its large parts on the `threads`
/// workers), Ctrl-C seen when it returns; a larger one on the workers, interruptible.
/// recomputed: how many particles the last update recomputed.
#[derive(Debug)]
#[pyclass(name = "Tracker", module = "boundary_particles._native")]
pub struct PyTracker {
    /// The resolution as given.
    arg: RadiusArg,
    /// The resolution, once known (at construction, or at the first update for `"auto"`).
    r: Option<Radius>,
    threads: Option<usize>,
    /// The worker pool of the updates and its stop token, built at the first update and kept
    /// (a new one after an interrupted update); the tracker holds the pool too.
    pool: Option<(StopToken, Arc<rayon::ThreadPool>)>,
    /// `None` before the first update and after an interrupted one (the abandoned one keeps
    /// it): the next update starts over with a new tracker.
    tracker: Option<Tracker>,
    /// The walls of the constructor, or of the last update that passed walls.
    walls: Option<Walls>,
    /// The dimension and plane the tracker's walls were made for.
    walls_made_for: Option<(usize, Option<Plane>)>,
    solids: Vec<HalfSpace>,
    periodic: Vec<Periodic>,
    /// Whether `r` is still to be checked against the particles' spacing (at the first update).
    check: bool,
    /// How many particles the last update recomputed.
    #[pyo3(get)]
    recomputed: usize,
}

#[pymethods]
impl PyTracker {
    #[new]
    #[pyo3(signature = (
        r = None, method = "exact", threads = None, *, h = None, spacing = None, walls = None,
        wall_radii = None, solids = None, periodic = None, **params
    ))]
    #[allow(clippy::too_many_arguments)] // the Python signature: keyword arguments with defaults
    fn new(
        r: Option<&Bound<'_, PyAny>>,
        method: &str,
        threads: Option<usize>,
        h: Option<&Bound<'_, PyAny>>,
        spacing: Option<&Bound<'_, PyAny>>,
        walls: Option<&Bound<'_, PyAny>>,
        wall_radii: Option<&Bound<'_, PyAny>>,
        solids: Option<&Bound<'_, PyAny>>,
        periodic: Option<&Bound<'_, PyAny>>,
        params: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let arg = radius_input("Tracker", r, h, spacing)?.ok_or_else(|| {
            PyTypeError::new_err(
                "Tracker() missing required argument 'r' (the resolution: give r, h (the \
                 smoothing length, r = h) or spacing (the particle spacing), or r=\"auto\"; with \
                 radii at the updates, r is their scale, e.g. r=1)",
            )
        })?;
        let fixed = fixed_radius(arg)?;
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
            arg,
            r: fixed,
            threads,
            pool: None,
            tracker: None,
            walls: Walls::read(walls, wall_radii, None)?,
            walls_made_for: None,
            solids: super::solids(solids)?,
            periodic: periodic_axes(periodic)?,
            check: checks_plausibility(Some(arg), false),
            recomputed: 0,
        })
    }

    /// The labels of this step's positions (an (n, 2) or (n, 3) array-like of reals, or one
    /// array per coordinate), the particles matched by `ids` when given, in the tracker's
    /// domain.
    #[pyo3(signature = (
        points = None, ids = None, *, columns = None, radii = None, walls = None,
        wall_radii = None, phases = None, dim = None
    ))]
    #[allow(clippy::too_many_arguments)] // the Python signature: keyword arguments with defaults
    fn update<'py>(
        &mut self,
        py: Python<'py>,
        points: Option<&Bound<'py, PyAny>>,
        ids: Option<&Bound<'py, PyAny>>,
        columns: Option<&Bound<'py, PyAny>>,
        radii: Option<&Bound<'py, PyAny>>,
        walls: Option<&Bound<'py, PyAny>>,
        wall_radii: Option<&Bound<'py, PyAny>>,
        phases: Option<&Bound<'py, PyAny>>,
        dim: Option<usize>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (set, plane) = match (points, columns) {
            (Some(points), None) => read_points_in(points, dim)?,
            (None, Some(columns)) => read_columns_in(columns, dim)?,
            (Some(_), Some(_)) => {
                return Err(PyTypeError::new_err(
                    "Tracker.update() takes the positions as points or as columns, not both",
                ))
            }
            (None, None) => {
                return Err(PyTypeError::new_err(
                    "Tracker.update() missing the positions: points (an (n, 2) or (n, 3) \
                     array) or columns=(x, y) / (x, y, z) (one array per coordinate)",
                ))
            }
        };
        let ids = ids
            .map(|ids| whole_numbers(ids, "ids", "id", u64::MAX))
            .transpose()
            .map_err(|e| value_error(format!("{}; {IDS_GUIDANCE}", e.value(py))))?;
        let phases = phases.map(phase_numbers).transpose()?;
        let r = match (self.r, radii) {
            (Some(r), _) => r,
            (None, Some(_)) => {
                return Err(value_error(
                    "r=\"auto\" estimates one uniform resolution; with radii= give r as the \
                     scale of the radius factors (e.g. r=1)",
                ))
            }
            (None, None) => resolve_radius("Tracker", &set, Some(self.arg))?,
        };
        let set = match radii {
            Some(radii) => {
                attach_radii(set, radius_factors(radii, "radii", "particle")?, r, "radii")?
            }
            None => set,
        };
        let new_walls = Walls::read(walls, wall_radii, Some(set.dim()))?;
        let (token, pool) = match self.pool.take() {
            Some(pool) => pool,
            None => {
                let (token, pool) = interruptible_pool(self.threads)?;
                // A new pool (the first update, or after an interrupt): a new tracker on it.
                self.tracker = None;
                (token, Arc::new(pool))
            }
        };
        let mut tracker = match self.tracker.take() {
            Some(t) => t,
            None => {
                self.walls_made_for = None;
                let mut domain = Domain::new();
                for &solid in &self.solids {
                    domain = domain.with_solid(solid);
                }
                for &axis in &self.periodic {
                    domain = domain.with_periodic(axis);
                }
                // The tracker's large parts run on the interruptible pool of `threads` workers.
                Tracker::with_pool(r, Arc::clone(&pool), domain)
            }
        };
        // Walls given to this update replace the tracker's (the same walls change nothing);
        // the walls are made again for points of another dimension or plane.
        let made_for = (set.dim(), plane);
        let changed = new_walls.is_some() && new_walls != self.walls;
        if changed {
            self.walls = new_walls;
        }
        if changed || self.walls_made_for != Some(made_for) {
            if let Some(walls) = &self.walls {
                tracker
                    .move_walls(walls.set(set.dim(), plane, r)?)
                    .map_err(value_error)?;
            }
            self.walls_made_for = Some(made_for);
        }
        let with_phases = phases.is_some();
        tracker.set_phases(phases);
        let check = self.check && radii.is_none();
        let inline = set.len() < CALLING_THREAD_BELOW;
        let job = move || {
            let concern = if check { concern_of(&set, r) } else { None };
            let outcome = match &ids {
                Some(ids) => tracker.update_with_ids(&set, ids),
                None => tracker.update(&set),
            }
            .map(|labels| labels.as_slice().to_vec());
            (tracker, outcome, concern)
        };
        let (tracker, outcome, concern) = if inline {
            py.detach(move || std::panic::catch_unwind(std::panic::AssertUnwindSafe(job)))
                .map_err(|payload| {
                    PyRuntimeError::new_err(format!(
                        "internal error (please report it): {}",
                        panic_text(payload.as_ref())
                    ))
                })?
        } else {
            run_on(py, &token, &pool, job)?
        };
        if !token.is_stopped() {
            self.pool = Some((token, pool));
        }
        self.recomputed = tracker.recomputed();
        let interface = tracker.interface().map(|i| i.as_slice().to_vec());
        self.tracker = Some(tracker);
        let labels = outcome.map_err(|e| {
            let text = e.to_string();
            if ids_error(&e) {
                value_error(format!("{text}; {IDS_GUIDANCE}"))
            } else {
                value_error(text)
            }
        })?;
        self.r = Some(r);
        self.check = false;
        warn_concern(py, concern)?;
        let labels = bool_array(py, labels).into_any();
        match (with_phases, interface) {
            (false, _) => Ok(labels),
            (true, Some(interface)) => {
                Ok(PyTuple::new(py, [labels, bool_array(py, interface).into_any()])?.into_any())
            }
            (true, None) => Err(value_error(
                "internal error (please report it): no interface labels with phases",
            )),
        }
    }

    fn __repr__(&self) -> String {
        match self.r {
            Some(r) => format!("Tracker(r={}, method=\"exact\")", r.get()),
            None => "Tracker(method=\"exact\")".to_owned(),
        }
    }
}

/// Whether `err` is about the ids (their count or a repeated id).
fn ids_error(err: &boundary::DetectError) -> bool {
    matches!(
        err,
        boundary::DetectError::Core(
            boundary::CoreError::IdsLengthMismatch { .. } | boundary::CoreError::RepeatedId { .. }
        )
    )
}
