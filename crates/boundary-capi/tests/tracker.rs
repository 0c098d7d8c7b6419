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

/// A water block over a floor of wall particles, stretched a little at every step.
fn block(step: usize) -> Vec<f64> {
    (0..300)
        .flat_map(|k| {
            let j = ((k * 7919) % 97) as f64 / 97.0 - 0.5;
            let s = 1.0 + 0.003 * step as f64;
            [
                ((k % 20) as f64 + 0.2 * j) * s,
                (k / 20) as f64 + 0.5 - 0.1 * j,
            ]
        })
        .collect()
}

/// Floor walls at height `y`, every other one shifted by `bob`.
fn floor(y: f64, bob: f64) -> Vec<f64> {
    (0..44)
        .flat_map(|k| {
            let lift = if k % 2 == 0 { bob } else { 0.0 };
            [0.5 * k as f64 - 1.0, y - 0.5 * (k / 22) as f64 + lift]
        })
        .collect()
}

/// The labels (and interface labels with phases) of a detector with `walls` and the solid
/// `solid` (or none), as `boundary_detector_detect_phases` gives them.
fn exact_in(
    xyz: &[f64],
    walls: &[f64],
    solid: Option<&str>,
    radii: Option<&[f64]>,
    phases: Option<&[u32]>,
) -> (Vec<u8>, Vec<u8>) {
    let n = xyz.len() / 2;
    let mut err = [0 as c_char; 256];
    let method = CString::new("exact").unwrap();
    let detector = unsafe {
        boundary_detector_new(
            method.as_ptr(),
            std::ptr::null(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert!(!detector.is_null(), "{}", message(&err));
    let code = unsafe {
        boundary_detector_set_walls(
            detector,
            walls.as_ptr(),
            walls.len() / 2,
            2,
            std::ptr::null(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(code, BOUNDARY_OK, "{}", message(&err));
    if let Some(solid) = solid {
        let text = CString::new(solid).unwrap();
        let code = unsafe {
            boundary_detector_add_solid(detector, text.as_ptr(), err.as_mut_ptr(), err.len())
        };
        assert_eq!(code, BOUNDARY_OK, "{}", message(&err));
    }
    let (mut labels, mut interface) = (vec![0u8; n], vec![0u8; n]);
    let code = unsafe {
        boundary_detector_detect_phases(
            detector,
            xyz.as_ptr(),
            n,
            2,
            radii.map_or(std::ptr::null(), <[f64]>::as_ptr),
            0.8,
            phases.map_or(std::ptr::null(), <[u32]>::as_ptr),
            labels.as_mut_ptr(),
            if phases.is_some() {
                interface.as_mut_ptr()
            } else {
                std::ptr::null_mut()
            },
            std::ptr::null_mut(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(code, BOUNDARY_OK, "{}", message(&err));
    unsafe { boundary_detector_free(detector) };
    (labels, interface)
}

/// Walls fixed and moving, a solid, radii and phases: the tracker's labels are those of a
/// detector with the same domain at every step, and fixed or moved walls keep the saving.
#[test]
fn tracker_in_a_domain_equals_the_detector_every_step() {
    let mut err = [0 as c_char; 256];
    let tracker = unsafe { boundary_tracker_new(0.8, 1, err.as_mut_ptr(), err.len()) };
    assert!(!tracker.is_null(), "{}", message(&err));
    let set_walls = |walls: &[f64], err: &mut [c_char; 256]| unsafe {
        boundary_tracker_set_walls(
            tracker,
            walls.as_ptr(),
            walls.len() / 2,
            2,
            std::ptr::null(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    let update = |xyz: &[f64],
                  radii: Option<&[f64]>,
                  phases: Option<&[u32]>,
                  err: &mut [c_char; 256]|
     -> (Vec<u8>, Vec<u8>, usize) {
        let n = xyz.len() / 2;
        let (mut labels, mut interface, mut recomputed) = (vec![0u8; n], vec![0u8; n], 0usize);
        let code = unsafe {
            boundary_tracker_update_domain(
                tracker,
                xyz.as_ptr(),
                n,
                2,
                std::ptr::null(),
                radii.map_or(std::ptr::null(), <[f64]>::as_ptr),
                phases.map_or(std::ptr::null(), <[u32]>::as_ptr),
                labels.as_mut_ptr(),
                if phases.is_some() {
                    interface.as_mut_ptr()
                } else {
                    std::ptr::null_mut()
                },
                &mut recomputed,
                err.as_mut_ptr(),
                err.len(),
            )
        };
        assert_eq!(code, BOUNDARY_OK, "{}", message(err));
        (labels, interface, recomputed)
    };
    // Fixed walls: set once.
    let fixed = floor(0.0, 0.0);
    assert_eq!(
        set_walls(&fixed, &mut err),
        BOUNDARY_OK,
        "{}",
        message(&err)
    );
    let mut saved = 0;
    for step in 0..5 {
        let xyz = block(step);
        let (labels, _, recomputed) = update(&xyz, None, None, &mut err);
        assert_eq!(
            labels,
            exact_in(&xyz, &fixed, None, None, None).0,
            "fixed, step {step}"
        );
        // The tank floor covers: the bottom row is interior.
        assert!(labels[..20].contains(&0), "step {step}");
        if step > 0 {
            saved += 300 - recomputed;
        }
    }
    assert!(saved > 600, "fixed walls: only {saved} saved in 4 steps");
    // Moving walls: set before each update; every other wall particle bobs.
    let mut saved = 0;
    for step in 5..10 {
        let xyz = block(step);
        let walls = floor(0.01 * step as f64, 0.005 * (step % 2) as f64);
        assert_eq!(
            set_walls(&walls, &mut err),
            BOUNDARY_OK,
            "{}",
            message(&err)
        );
        let (labels, _, recomputed) = update(&xyz, None, None, &mut err);
        assert_eq!(
            labels,
            exact_in(&xyz, &walls, None, None, None).0,
            "moving, step {step}"
        );
        saved += 300 - recomputed;
    }
    assert!(saved > 0, "moving walls: nothing saved");
    // A solid, per-particle radii and phases: the labels (and interfaces) of the detector.
    let walls = floor(0.1, 0.0);
    assert_eq!(
        set_walls(&walls, &mut err),
        BOUNDARY_OK,
        "{}",
        message(&err)
    );
    let solid = CString::new("x<0.5").unwrap();
    let code =
        unsafe { boundary_tracker_add_solid(tracker, solid.as_ptr(), err.as_mut_ptr(), err.len()) };
    assert_eq!(code, BOUNDARY_OK, "{}", message(&err));
    let radii: Vec<f64> = (0..300).map(|i| 1.0 + 0.2 * (i % 3) as f64).collect();
    let phases: Vec<u32> = (0..300).map(|i| u32::from(i % 20 >= 10)).collect();
    for step in 10..12 {
        let xyz = block(step);
        let (labels, _, _) = update(&xyz, Some(&radii), None, &mut err);
        let want = exact_in(&xyz, &walls, Some("x<0.5"), Some(&radii), None);
        assert_eq!(labels, want.0, "radii, step {step}");
        let (labels, interface, _) = update(&xyz, None, Some(&phases), &mut err);
        let want = exact_in(&xyz, &walls, Some("x<0.5"), None, Some(&phases));
        assert_eq!((labels, interface), want, "phases, step {step}");
        assert!(want.1.contains(&1), "no interface found");
    }
    // A malformed solid is a domain error; the domain stays as it was.
    let bad = CString::new("w<1").unwrap();
    let code =
        unsafe { boundary_tracker_add_solid(tracker, bad.as_ptr(), err.as_mut_ptr(), err.len()) };
    assert_eq!(code, BOUNDARY_ERR_DOMAIN);
    // Interfaces need phases.
    let xyz = block(0);
    let mut out = vec![0u8; 300];
    let code = unsafe {
        boundary_tracker_update_domain(
            tracker,
            xyz.as_ptr(),
            300,
            2,
            std::ptr::null(),
            std::ptr::null(),
            std::ptr::null(),
            out.as_mut_ptr(),
            out.as_mut_ptr(),
            std::ptr::null_mut(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(code, BOUNDARY_ERR_NULL, "{}", message(&err));
    // Repeated ids: the message says what to pass instead.
    let ids = vec![4_294_967_295u64; 300];
    let code = unsafe {
        boundary_tracker_update_ids(
            tracker,
            xyz.as_ptr(),
            300,
            2,
            ids.as_ptr(),
            out.as_mut_ptr(),
            std::ptr::null_mut(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(code, BOUNDARY_ERR_INPUT);
    assert!(
        message(&err).contains("boundary_tracker_update"),
        "{}",
        message(&err)
    );
    unsafe { boundary_tracker_free(tracker) };
}
