//! The tracker through the C API: the labels of `boundary_detect` with "exact" at every step,
//! fewer particles recomputed after a small move, errors as codes with messages.

#![allow(clippy::unwrap_used)]
// test code: a failed unwrap is a failed test

// Calling the C API means passing raw pointers (see src/lib.rs for why the crate allows it).
#![allow(unsafe_code)]
#![allow(
    clippy::undocumented_unsafe_blocks,
    clippy::multiple_unsafe_ops_per_block
)]

use boundary_capi::*;
use std::ffi::{c_char, CStr, CString};

fn message(err: &[c_char]) -> String {
    // SAFETY: the API writes a NUL-terminated message into `err`.
    unsafe { CStr::from_ptr(err.as_ptr()) }
        .to_string_lossy()
        .into_owned()
}

fn exact(xyz: &[f64], dim: usize, r: f64) -> Vec<u8> {
    let n = xyz.len() / dim;
    let mut labels = vec![0u8; n];
    let mut err = [0 as c_char; 256];
    let (method, params) = (CString::new("exact").unwrap(), CString::new("").unwrap());
    // SAFETY: buffers of the stated sizes; strings NUL-terminated.
    let code = unsafe {
        boundary_detect(
            xyz.as_ptr(),
            n,
            dim as i32,
            r,
            method.as_ptr(),
            params.as_ptr(),
            labels.as_mut_ptr(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(code, BOUNDARY_OK, "{}", message(&err));
    labels
}

#[test]
fn tracker_labels_equal_exact_detection_every_step() {
    let mut err = [0 as c_char; 256];
    // SAFETY: `err` is valid for its length.
    let tracker = unsafe { boundary_tracker_new(0.8, 1, err.as_mut_ptr(), err.len()) };
    assert!(!tracker.is_null(), "{}", message(&err));
    let mut xyz: Vec<f64> = (0..400)
        .flat_map(|k| {
            let j = ((k * 7919) % 97) as f64 / 97.0 - 0.5;
            [(k % 20) as f64 + 0.2 * j, (k / 20) as f64 - 0.1 * j]
        })
        .collect();
    let mut counts = vec![];
    for step in 0..5 {
        if step > 0 {
            xyz.iter_mut().for_each(|x| *x *= 1.002);
        }
        let mut labels = vec![0u8; 400];
        let mut recomputed = usize::MAX;
        // SAFETY: a live handle; buffers of the stated sizes.
        let code = unsafe {
            boundary_tracker_update(
                tracker,
                xyz.as_ptr(),
                400,
                2,
                labels.as_mut_ptr(),
                &mut recomputed,
                err.as_mut_ptr(),
                err.len(),
            )
        };
        assert_eq!(code, BOUNDARY_OK, "{}", message(&err));
        assert_eq!(labels, exact(&xyz, 2, 0.8), "step {step}");
        counts.push(recomputed);
    }
    assert_eq!(counts[0], 400);
    assert!(counts[1..].iter().all(|&c| c < 200), "{counts:?}");
    // A non-finite coordinate: an input error naming the particle; nothing written.
    xyz[7] = f64::NAN;
    let mut labels = vec![7u8; 400];
    // SAFETY: as above; `out_recomputed` may be NULL.
    let code = unsafe {
        boundary_tracker_update(
            tracker,
            xyz.as_ptr(),
            400,
            2,
            labels.as_mut_ptr(),
            std::ptr::null_mut(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(code, BOUNDARY_ERR_INPUT);
    assert!(message(&err).contains('3'), "{}", message(&err));
    assert!(labels.iter().all(|&l| l == 7));
    // SAFETY: the handle from `boundary_tracker_new`, released once; NULL is ignored.
    unsafe {
        boundary_tracker_free(tracker);
        boundary_tracker_free(std::ptr::null_mut());
    }
}

#[test]
fn bad_arguments_are_error_codes() {
    let mut err = [0 as c_char; 256];
    // SAFETY: `err` is valid for its length.
    let tracker = unsafe { boundary_tracker_new(-1.0, 0, err.as_mut_ptr(), err.len()) };
    assert!(tracker.is_null());
    assert!(!message(&err).is_empty());
    let mut labels = [0u8; 1];
    let xyz = [0.0, 0.0];
    // SAFETY: a NULL handle is reported, not dereferenced.
    let code = unsafe {
        boundary_tracker_update(
            std::ptr::null_mut(),
            xyz.as_ptr(),
            1,
            2,
            labels.as_mut_ptr(),
            std::ptr::null_mut(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(code, BOUNDARY_ERR_NULL);
    // SAFETY: `err` is valid for its length.
    let tracker = unsafe { boundary_tracker_new(1.0, 0, err.as_mut_ptr(), err.len()) };
    // SAFETY: a live handle; `dim` 4 is refused before any read.
    let code = unsafe {
        boundary_tracker_update(
            tracker,
            xyz.as_ptr(),
            1,
            4,
            labels.as_mut_ptr(),
            std::ptr::null_mut(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(code, BOUNDARY_ERR_SIZE);
    // SAFETY: released once.
    unsafe { boundary_tracker_free(tracker) };
}

/// One `boundary_tracker_update_ids` call: the code, the labels and the recomputed count.
fn update_ids(
    tracker: *mut boundary_tracker,
    xyz: &[f64],
    ids: &[u64],
    err: &mut [c_char],
) -> (i32, Vec<u8>, usize) {
    let n = xyz.len() / 2;
    let mut labels = vec![0u8; n];
    let mut recomputed = usize::MAX;
    // SAFETY: a live handle; buffers of the stated sizes (`ids` as long as it is: the test
    // passes `n` only when it has `n` ids).
    let code = unsafe {
        boundary_tracker_update_ids(
            tracker,
            xyz.as_ptr(),
            n,
            2,
            ids.as_ptr(),
            labels.as_mut_ptr(),
            &mut recomputed,
            err.as_mut_ptr(),
            err.len(),
        )
    };
    (code, labels, recomputed)
}

/// With ids, particles that leave and arrive keep the saving; the labels stay exact's; bad ids
/// are input errors naming the particles.
#[test]
fn tracker_with_ids_follows_inflow_and_outflow() {
    let mut err = [0 as c_char; 256];
    // SAFETY: `err` is valid for its length.
    let tracker = unsafe { boundary_tracker_new(0.8, 1, err.as_mut_ptr(), err.len()) };
    assert!(!tracker.is_null(), "{}", message(&err));
    // A 20 × 20 block; each step the last row leaves and a new one enters below, listed first.
    let mut particles: Vec<([f64; 2], u64)> = (0..400u64)
        .map(|k| {
            let j = ((k * 7919) % 97) as f64 / 97.0 - 0.5;
            ([(k % 20) as f64 + 0.2 * j, (k / 20) as f64], k)
        })
        .collect();
    let mut counts = vec![];
    for step in 0..4u64 {
        if step > 0 {
            particles.retain(|(p, _)| p[1] < (19 - step) as f64 + 0.5);
            let row: Vec<([f64; 2], u64)> = (0..20)
                .map(|k| ([k as f64, -(step as f64)], 1000 * step + k))
                .collect();
            particles.splice(0..0, row);
        }
        let xyz: Vec<f64> = particles.iter().flat_map(|(p, _)| *p).collect();
        let ids: Vec<u64> = particles.iter().map(|(_, id)| *id).collect();
        let (code, labels, recomputed) = update_ids(tracker, &xyz, &ids, &mut err);
        assert_eq!(code, BOUNDARY_OK, "{}", message(&err));
        assert_eq!(labels, exact(&xyz, 2, 0.8), "step {step}");
        counts.push(recomputed);
    }
    assert_eq!(counts[0], 400);
    assert!(counts[1..].iter().all(|&c| c < 120), "{counts:?}");
    let xyz = [0.0, 0.0, 1.0, 0.0];
    let (code, _, _) = update_ids(tracker, &xyz, &[5, 5], &mut err);
    assert_eq!(code, BOUNDARY_ERR_INPUT);
    assert!(
        message(&err).contains("id 5 is given to particles 0 and 1"),
        "{}",
        message(&err)
    );
    let mut labels = [0u8; 2];
    // SAFETY: NULL ids with n > 0 are reported, not read.
    let code = unsafe {
        boundary_tracker_update_ids(
            tracker,
            xyz.as_ptr(),
            2,
            2,
            std::ptr::null(),
            labels.as_mut_ptr(),
            std::ptr::null_mut(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(code, BOUNDARY_ERR_NULL);
    assert!(message(&err).contains("ids"), "{}", message(&err));
    // SAFETY: the handle from `boundary_tracker_new`, released once.
    unsafe { boundary_tracker_free(tracker) };
}
