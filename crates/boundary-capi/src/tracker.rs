//! The incremental tracker (`boundary::Tracker`) for C: `exact` labels every time step,
//! identical to `boundary_detect(..., "exact", ...)`, recomputing only the particles whose label
//! may have changed since the previous step.

use super::{
    domain_with_periodic, domain_with_solid, domain_with_walls, guarded, out_slice, particle_set,
    read_phases, refuse_flat, Failure, BOUNDARY_ERR_DETECT, BOUNDARY_ERR_DOMAIN,
    BOUNDARY_ERR_INPUT, BOUNDARY_ERR_NULL, BOUNDARY_ERR_THREADS,
};
use boundary::{DetectError, Domain, Radius, Tracker};
use std::ffi::{c_char, c_int};

/// An incremental `exact` tracker over the time steps of one particle set. Opaque: create with
/// `boundary_tracker_new`, release with `boundary_tracker_free`.
#[allow(non_camel_case_types)] // the C type's name
#[derive(Debug)]
pub struct boundary_tracker {
    tracker: Tracker,
    /// The resolution (the scale of per-particle radii).
    r: f64,
}

/// Creates a tracker at resolution `r` on `threads` worker threads (0: all cores). Returns NULL
/// on error (`r` not positive and finite, threads that cannot start), with the message in
/// `err`. Release it with `boundary_tracker_free`. An update runs on the calling thread and
/// hands only its large parts to the workers (passes over 16,384 particles and more, 128
/// evaluations and more): a small step never waits for a worker to wake.
///
/// # Safety
/// `err` is NULL or valid for writes of `err_len` bytes.
#[no_mangle]
pub unsafe extern "C" fn boundary_tracker_new(
    r: f64,
    threads: usize,
    err: *mut c_char,
    err_len: usize,
) -> *mut boundary_tracker {
    let mut handle = std::ptr::null_mut();
    let body = || {
        let r = Radius::new(r).map_err(|e| Failure::new(BOUNDARY_ERR_INPUT, e.to_string()))?;
        // The tracker builds its own pool of `threads` workers: its only failure is that they
        // cannot start.
        let threads = (threads > 0).then_some(threads);
        let tracker = Tracker::new(r, threads, Domain::new())
            .map_err(|e| Failure::new(BOUNDARY_ERR_THREADS, e.to_string()))?;
        handle = Box::into_raw(Box::new(boundary_tracker {
            tracker,
            r: r.get(),
        }));
        Ok(())
    };
    // SAFETY: forwarded from this function's contract.
    unsafe { guarded(err, err_len, body) };
    handle
}

/// Labels this step's positions of the `n` particles at `xyz` (as `boundary_detect` with
/// `"exact"`: 1 boundary, 0 interior, into `out_labels[0..n]`); the same particles in the same
/// order as at the previous step (another `n` or `dim` starts over). When `out_recomputed`
/// is not NULL, writes there how many particles this update recomputed.
///
/// # Safety
/// `handle` comes from `boundary_tracker_new` and is not freed nor used by another thread
/// during the call; `xyz` is valid for reads of `n * dim` doubles (may be NULL when `n == 0`);
/// `out_labels` valid for writes of `n` bytes; `out_recomputed` NULL or valid for one write;
/// `err` NULL or valid for writes of `err_len` bytes.
#[no_mangle]
#[allow(clippy::too_many_arguments)] // the C signature
pub unsafe extern "C" fn boundary_tracker_update(
    handle: *mut boundary_tracker,
    xyz: *const f64,
    n: usize,
    dim: c_int,
    out_labels: *mut u8,
    out_recomputed: *mut usize,
    err: *mut c_char,
    err_len: usize,
) -> c_int {
    let request = Request {
        ids: None,
        radii: std::ptr::null(),
        phases: std::ptr::null(),
        out_labels,
        out_interface: std::ptr::null_mut(),
        out_recomputed,
    };
    // SAFETY: forwarded from this function's contract; no ids.
    unsafe { update(handle, xyz, n, dim, &request, err, err_len) }
}

/// As `boundary_tracker_update`, with a stable id per particle (`ids[0..n]`, unique): the
/// particles are matched to the previous step's by id, so they may come (inflow), go
/// (outflow) and change order without the tracker starting over. Repeated ids are an input
/// error naming both particles; after an update without ids, the tracker starts over.
///
/// # Safety
/// As `boundary_tracker_update`; `ids` is valid for reads of `n` values (may be NULL when
/// `n == 0`).
#[no_mangle]
#[allow(clippy::too_many_arguments)] // the C signature
pub unsafe extern "C" fn boundary_tracker_update_ids(
    handle: *mut boundary_tracker,
    xyz: *const f64,
    n: usize,
    dim: c_int,
    ids: *const u64,
    out_labels: *mut u8,
    out_recomputed: *mut usize,
    err: *mut c_char,
    err_len: usize,
) -> c_int {
    let request = Request {
        ids: Some(ids),
        radii: std::ptr::null(),
        phases: std::ptr::null(),
        out_labels,
        out_interface: std::ptr::null_mut(),
        out_recomputed,
    };
    // SAFETY: forwarded from this function's contract.
    unsafe { update(handle, xyz, n, dim, &request, err, err_len) }
}

/// The general update: as `boundary_tracker_update_ids` with `ids` NULL for none (the
/// particles matched by their place, as `boundary_tracker_update`), `radii` NULL or `n`
/// radius factors (`r_i = r * s_i`, as `boundary_detect_radii`), and `phases` NULL or `n`
/// phase numbers, with which `out_interface` (`n` bytes, required with phases) receives the
/// interface labels as `boundary_detector_detect_phases` writes them. The labels are those of
/// `boundary_detector_detect_phases` with `"exact"` in the tracker's domain, bit for bit.
/// Radii and phases are honoured by a full detection at every step. Nothing is written on
/// error; `out_interface` without `phases` is `BOUNDARY_ERR_NULL`.
///
/// # Safety
/// As `boundary_tracker_update_ids`, with `ids` NULL allowed; `radii` NULL or valid for reads
/// of `n` doubles; `phases` NULL or valid for reads of `n` `uint32_t`; `out_interface` NULL or
/// valid for writes of `n` bytes.
#[no_mangle]
#[allow(clippy::too_many_arguments)] // the C signature
pub unsafe extern "C" fn boundary_tracker_update_domain(
    handle: *mut boundary_tracker,
    xyz: *const f64,
    n: usize,
    dim: c_int,
    ids: *const u64,
    radii: *const f64,
    phases: *const u32,
    out_labels: *mut u8,
    out_interface: *mut u8,
    out_recomputed: *mut usize,
    err: *mut c_char,
    err_len: usize,
) -> c_int {
    let request = Request {
        ids: (!ids.is_null()).then_some(ids),
        radii,
        phases,
        out_labels,
        out_interface,
        out_recomputed,
    };
    // SAFETY: forwarded from this function's contract.
    unsafe { update(handle, xyz, n, dim, &request, err, err_len) }
}

/// What an update reads besides the positions, and where it writes.
struct Request {
    /// `None` without ids, else the pointer to `n` ids.
    ids: Option<*const u64>,
    radii: *const f64,
    phases: *const u32,
    out_labels: *mut u8,
    out_interface: *mut u8,
    out_recomputed: *mut usize,
}

/// Every update.
///
/// # Safety
/// As `boundary_tracker_update_domain`, the pointers of `request` as its arguments.
unsafe fn update(
    handle: *mut boundary_tracker,
    xyz: *const f64,
    n: usize,
    dim: c_int,
    request: &Request,
    err: *mut c_char,
    err_len: usize,
) -> c_int {
    let body = || {
        // SAFETY: NULL or a live, unaliased handle (this function's contract).
        let handle = unsafe { handle.as_mut() }
            .ok_or_else(|| Failure::new(BOUNDARY_ERR_NULL, "handle is NULL"))?;
        // SAFETY: `xyz` and `radii` as this function's contract says.
        let set = unsafe { particle_set(xyz, n, dim, request.radii) }?;
        refuse_flat(&set)?;
        let ids: Option<&[u64]> = match request.ids {
            None => None,
            Some(_) if n == 0 => Some(&[]),
            Some(p) if p.is_null() => {
                return Err(Failure::new(BOUNDARY_ERR_NULL, "ids is NULL"));
            }
            // SAFETY: `ids` valid for `n` reads (this function's contract), not NULL.
            Some(p) => Some(unsafe { std::slice::from_raw_parts(p, n) }),
        };
        // SAFETY: `phases` as this function's contract says; `n` doubles fit (checked above).
        let phases = unsafe { read_phases(request.phases, n) }?;
        // SAFETY: `out_labels` valid for `n` bytes (this function's contract).
        let out = unsafe { out_slice(request.out_labels, n, "out_labels") }?;
        let interface = match (&phases, request.out_interface.is_null()) {
            (None, true) => None,
            (None, false) => {
                return Err(Failure::new(
                    BOUNDARY_ERR_NULL,
                    "out_interface is given but phases is NULL (interfaces need phases)",
                ))
            }
            // SAFETY: forwarded from this function's contract.
            (Some(_), _) => Some(unsafe { out_slice(request.out_interface, n, "out_interface") }?),
        };
        if let (Some(r), Some(_)) = (Radius::new(handle.r).ok(), set.radii()) {
            // Scaled radii out of range name the particle (an input error).
            let resolved = match &set {
                boundary::AnyParticleSet::D2(s) => s.resolved_radii(r).map(drop),
                boundary::AnyParticleSet::D3(s) => s.resolved_radii(r).map(drop),
            };
            resolved.map_err(|e| Failure::new(BOUNDARY_ERR_INPUT, e.to_string()))?;
        }
        handle.tracker.set_phases(phases);
        match ids {
            Some(ids) => handle.tracker.update_with_ids(&set, ids).map(drop),
            None => handle.tracker.update(&set).map(drop),
        }
        .map_err(|e| {
            // Repeated ids are the caller's input; anything else is the detection's.
            let code = match e {
                DetectError::Core(_) => BOUNDARY_ERR_INPUT,
                DetectError::Domain(_) => BOUNDARY_ERR_DOMAIN,
                _ => BOUNDARY_ERR_DETECT,
            };
            let message = match e {
                DetectError::Core(boundary::CoreError::RepeatedId { .. }) => format!(
                    "{e}; pass the solver's stable particle id, or, for a solver without one, \
                     boundary_tracker_update (the particles matched by their place in xyz, \
                     right while the solver keeps their order; a new n starts over)"
                ),
                _ => crate::in_c_terms(&e),
            };
            Failure::new(code, message)
        })?;
        if let (Some(out), Some(found)) = (interface, handle.tracker.interface()) {
            for (slot, &b) in out.iter_mut().zip(found.as_slice()) {
                *slot = u8::from(b);
            }
        }
        let labels = handle.tracker.labels();
        for (slot, i) in out.iter_mut().zip(0..n) {
            *slot = u8::from(labels.is_boundary(i));
        }
        let recomputed = handle.tracker.recomputed();
        // SAFETY: NULL or valid for one aligned write (this function's contract).
        if let Some(count) = unsafe { request.out_recomputed.as_mut() } {
            *count = recomputed;
        }
        Ok(())
    };
    // SAFETY: forwarded from this function's contract.
    unsafe { guarded(err, err_len, body) }
}

/// Runs `change` on the tracker's domain, reporting through `err`.
///
/// # Safety
/// `handle` is NULL or comes from `boundary_tracker_new`, not freed nor used by another
/// thread during the call; `err` NULL or valid for writes of `err_len` bytes.
unsafe fn change_domain(
    handle: *mut boundary_tracker,
    err: *mut c_char,
    err_len: usize,
    change: impl FnOnce(Domain) -> Result<Domain, Failure>,
) -> c_int {
    let body = || {
        // SAFETY: NULL or a live, unaliased handle (the caller's contract).
        let handle = unsafe { handle.as_mut() }
            .ok_or_else(|| Failure::new(BOUNDARY_ERR_NULL, "handle is NULL"))?;
        // On error the domain stays as it was.
        let domain = change(handle.tracker.domain().clone())?;
        handle
            .tracker
            .set_domain(domain)
            .map_err(|e| Failure::new(BOUNDARY_ERR_DOMAIN, e.to_string()))
    };
    // SAFETY: forwarded from the caller's contract.
    unsafe { guarded(err, err_len, body) }
}

/// Sets the walls of the tracker: `m` covering-only particles at `xyz` (`m * dim` doubles),
/// with `radii` NULL or `m` radius factors, as `boundary_detector_set_walls`. Call it once
/// for fixed walls: walls that are never set again cost nothing per update after the first.
/// Call it before an update to move them: walls equal to the current ones bit for bit change
/// nothing (one comparison), moved walls keep the saving (their movement counts like the
/// particles'), another `m` starts over; `m == 0` removes them.
///
/// # Safety
/// As `boundary_detector_set_walls`, with a handle from `boundary_tracker_new`.
#[no_mangle]
#[allow(clippy::too_many_arguments)] // the C signature
pub unsafe extern "C" fn boundary_tracker_set_walls(
    handle: *mut boundary_tracker,
    xyz: *const f64,
    m: usize,
    dim: c_int,
    radii: *const f64,
    err: *mut c_char,
    err_len: usize,
) -> c_int {
    // SAFETY: forwarded from this function's contract.
    let change = |domain: Domain| unsafe { domain_with_walls(&domain, xyz, m, dim, radii) };
    // SAFETY: forwarded from this function's contract.
    unsafe { change_domain(handle, err, err_len, change) }
}

/// Adds a closed solid half-space to the tracker's domain (`"y<0"`), as
/// `boundary_detector_add_solid`.
///
/// # Safety
/// As `boundary_detector_add_solid`, with a handle from `boundary_tracker_new`.
#[no_mangle]
pub unsafe extern "C" fn boundary_tracker_add_solid(
    handle: *mut boundary_tracker,
    text: *const c_char,
    err: *mut c_char,
    err_len: usize,
) -> c_int {
    // SAFETY: forwarded from this function's contract.
    let change = |domain: Domain| unsafe { domain_with_solid(domain, text) };
    // SAFETY: forwarded from this function's contract.
    unsafe { change_domain(handle, err, err_len, change) }
}

/// Adds a periodic axis to the tracker's domain (`"x:0:1.5"`), as
/// `boundary_detector_add_periodic`.
///
/// # Safety
/// As `boundary_detector_add_periodic`, with a handle from `boundary_tracker_new`.
#[no_mangle]
pub unsafe extern "C" fn boundary_tracker_add_periodic(
    handle: *mut boundary_tracker,
    text: *const c_char,
    err: *mut c_char,
    err_len: usize,
) -> c_int {
    // SAFETY: forwarded from this function's contract.
    let change = |domain: Domain| unsafe { domain_with_periodic(domain, text) };
    // SAFETY: forwarded from this function's contract.
    unsafe { change_domain(handle, err, err_len, change) }
}

/// Releases a tracker from `boundary_tracker_new`; NULL is ignored.
///
/// # Safety
/// `handle` is NULL or comes from `boundary_tracker_new` and is not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn boundary_tracker_free(handle: *mut boundary_tracker) {
    if handle.is_null() {
        return;
    }
    let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        // SAFETY: `handle` came from `Box::into_raw` in `boundary_tracker_new` and is
        // released once (this function's contract).
        drop(unsafe { Box::from_raw(handle) });
    }));
}
