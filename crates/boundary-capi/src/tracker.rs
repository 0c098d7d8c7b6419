//! The incremental tracker (`boundary::Tracker`) for C: `exact` labels every time step,
//! identical to `boundary_detect(..., "exact", ...)`, recomputing only the particles whose label
//! may have changed since the previous step.

use super::{
    guarded, out_slice, particle_set, refuse_flat, Failure, BOUNDARY_ERR_DETECT,
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
}

/// Creates a tracker at resolution `r` on `threads` worker threads (0: all cores). Returns NULL
/// on error (`r` not positive and finite, threads that cannot start), with the message in
/// `err`. Release it with `boundary_tracker_free`.
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
        handle = Box::into_raw(Box::new(boundary_tracker { tracker }));
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
    // SAFETY: forwarded from this function's contract; no ids.
    unsafe {
        update(
            handle,
            xyz,
            n,
            dim,
            None,
            out_labels,
            out_recomputed,
            err,
            err_len,
        )
    }
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
    // SAFETY: forwarded from this function's contract.
    unsafe {
        update(
            handle,
            xyz,
            n,
            dim,
            Some(ids),
            out_labels,
            out_recomputed,
            err,
            err_len,
        )
    }
}

/// Both updates: `ids` is `None` without ids, else the pointer to `n` ids.
///
/// # Safety
/// As `boundary_tracker_update_ids`.
#[allow(clippy::too_many_arguments)] // the C signature
unsafe fn update(
    handle: *mut boundary_tracker,
    xyz: *const f64,
    n: usize,
    dim: c_int,
    ids: Option<*const u64>,
    out_labels: *mut u8,
    out_recomputed: *mut usize,
    err: *mut c_char,
    err_len: usize,
) -> c_int {
    let body = || {
        // SAFETY: NULL or a live, unaliased handle (this function's contract).
        let handle = unsafe { handle.as_mut() }
            .ok_or_else(|| Failure::new(BOUNDARY_ERR_NULL, "handle is NULL"))?;
        // SAFETY: `xyz` as this function's contract says; no radii.
        let set = unsafe { particle_set(xyz, n, dim, std::ptr::null()) }?;
        refuse_flat(&set)?;
        let ids: Option<&[u64]> = match ids {
            None => None,
            Some(_) if n == 0 => Some(&[]),
            Some(p) if p.is_null() => {
                return Err(Failure::new(BOUNDARY_ERR_NULL, "ids is NULL"));
            }
            // SAFETY: `ids` valid for `n` reads (this function's contract), not NULL.
            Some(p) => Some(unsafe { std::slice::from_raw_parts(p, n) }),
        };
        // SAFETY: `out_labels` valid for `n` bytes (this function's contract).
        let out = unsafe { out_slice(out_labels, n, "out_labels") }?;
        let labels = match ids {
            Some(ids) => handle.tracker.update_with_ids(&set, ids),
            None => handle.tracker.update(&set),
        }
        .map_err(|e| {
            // Repeated ids are the caller's input; anything else is the detection's.
            let code = match e {
                DetectError::Core(_) => BOUNDARY_ERR_INPUT,
                _ => BOUNDARY_ERR_DETECT,
            };
            Failure::new(code, crate::in_c_terms(&e))
        })?;
        for (slot, i) in out.iter_mut().zip(0..n) {
            *slot = u8::from(labels.is_boundary(i));
        }
        let recomputed = handle.tracker.recomputed();
        // SAFETY: NULL or valid for one aligned write (this function's contract).
        if let Some(count) = unsafe { out_recomputed.as_mut() } {
            *count = recomputed;
        }
        Ok(())
    };
    // SAFETY: forwarded from this function's contract.
    unsafe { guarded(err, err_len, body) }
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
