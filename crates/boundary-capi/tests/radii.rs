//! A radius per particle through the C API (`boundary_detect_radii`,
//! `boundary_detector_detect_radii`): NULL radii are the uniform call, the radii reach the
//! library's particle set (`r_i = r * s_i`), and every bad radius is `BOUNDARY_ERR_INPUT`
//! naming the particle, with the outputs untouched.

// Calling the C API means passing raw pointers (see src/lib.rs for why the crate allows it).
#![allow(unsafe_code)]
#![allow(
    clippy::undocumented_unsafe_blocks,
    clippy::multiple_unsafe_ops_per_block
)]

use boundary::{detector_by_name, methods, AnyParticleSet, ParticleSet, Radius};
use boundary_capi::*;
use std::ffi::{c_char, CStr, CString};

fn message(err: &[c_char]) -> String {
    unsafe { CStr::from_ptr(err.as_ptr()) }
        .to_string_lossy()
        .into_owned()
}

/// `boundary_detect_radii` with Rust values (`radii` `None`: NULL); returns (code, labels,
/// message).
fn detect_radii(
    xyz: &[f64],
    dim: usize,
    radii: Option<&[f64]>,
    r: f64,
    method: &str,
) -> (i32, Vec<u8>, String) {
    let n = xyz.len() / dim;
    let mut labels = vec![7u8; n];
    let mut err = [0 as c_char; 512];
    let method = CString::new(method).expect("no NUL");
    let code = unsafe {
        boundary_detect_radii(
            xyz.as_ptr(),
            n,
            dim as i32,
            radii.map_or(std::ptr::null(), <[f64]>::as_ptr),
            r,
            method.as_ptr(),
            std::ptr::null(),
            labels.as_mut_ptr(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    (code, labels, message(&err))
}

/// A 5 x 5 x 5 cubic lattice of spacing 1, flat.
fn lattice() -> Vec<f64> {
    (0..125)
        .flat_map(|k| [(k % 5) as f64, ((k / 5) % 5) as f64, (k / 25) as f64])
        .collect()
}

/// The library's labels of `xyz` with radii `radii` at `r` by `method`, as bytes.
fn library_labels(xyz: &[f64], radii: &[f64], r: f64, method: &str) -> Result<Vec<u8>, String> {
    let rows: Vec<[f64; 3]> = xyz.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    let set: AnyParticleSet = ParticleSet::<3>::from_rows(&rows)
        .and_then(|s| s.with_radii(radii.to_vec()))
        .expect("valid set")
        .into();
    detector_by_name(method)
        .expect("registered")
        .detect(&set, Radius::new(r).expect("r"))
        .map(|d| d.labels.as_slice().iter().map(|&b| u8::from(b)).collect())
        .map_err(|e| e.to_string())
}

#[test]
fn null_radii_and_radii_of_one_give_the_uniform_labels() {
    let xyz = lattice();
    let (code, uniform, err) = detect_radii(&xyz, 3, None, 1.2, "exact");
    assert_eq!(code, BOUNDARY_OK, "{err}");
    // 3 x 3 x 3 core interior at r = 1.2.
    assert_eq!(uniform.iter().filter(|&&b| b == 1).count(), 125 - 27);
    let ones = vec![1.0; 125];
    let (code, scaled, err) = detect_radii(&xyz, 3, Some(&ones), 1.2, "exact");
    assert_eq!(code, BOUNDARY_OK, "{err}");
    assert_eq!(scaled, uniform);
}

#[test]
fn every_method_through_the_c_api_gives_the_library_result_on_graded_radii() {
    // Radii 1.2 and 2.4 alternating, r = 0.5: whatever a method does with them (labels, or
    // its error for per-particle radii), the C API gives the same.
    let xyz = lattice();
    let radii: Vec<f64> = (0..125)
        .map(|k| if k % 2 == 0 { 1.2 } else { 2.4 })
        .collect();
    for method in methods() {
        let (code, labels, err) = detect_radii(&xyz, 3, Some(&radii), 0.5, method);
        match library_labels(&xyz, &radii, 0.5, method) {
            Ok(expected) => {
                assert_eq!(code, BOUNDARY_OK, "{method}: {err}");
                assert_eq!(labels, expected, "{method}");
            }
            Err(expected) => {
                assert_eq!(code, BOUNDARY_ERR_DETECT, "{method}: {err}");
                assert_eq!(err, expected, "{method}");
                assert!(labels.iter().all(|&b| b == 7), "{method}: labels written");
            }
        }
    }
}

#[test]
fn a_handle_takes_radii_and_its_margin() {
    let xyz = lattice();
    let ones = vec![1.0; 125];
    let mut err = [0 as c_char; 256];
    let handle = unsafe {
        boundary_detector_new(
            c"exact".as_ptr(),
            std::ptr::null(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert!(!handle.is_null(), "{}", message(&err));
    let run = |radii: *const f64, labels: &mut [u8], margin: &mut [f64], err: &mut [c_char]| unsafe {
        boundary_detector_detect_radii(
            handle,
            xyz.as_ptr(),
            125,
            3,
            radii,
            1.2,
            labels.as_mut_ptr(),
            margin.as_mut_ptr(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    let (mut a, mut b) = (vec![0u8; 125], vec![0u8; 125]);
    let (mut ma, mut mb) = (vec![0.0; 125], vec![0.0; 125]);
    assert_eq!(
        run(std::ptr::null(), &mut a, &mut ma, &mut err),
        BOUNDARY_OK
    );
    assert_eq!(run(ones.as_ptr(), &mut b, &mut mb, &mut err), BOUNDARY_OK);
    assert_eq!(a, b);
    // Margins are exact above -1e-6 r and upper bounds below it (exact's documented
    // margins: the uniform path's interior filter and the radii path may bound an interior
    // particle differently), so deep interior margins are compared by that band only.
    let band = -1e-6 * 1.2; // boundary_exact::INTERIOR_BAND times r
    for (i, (x, y)) in ma.iter().zip(&mb).enumerate() {
        if *x > band || *y > band {
            assert_eq!(x, y, "margin of particle {i}");
        }
    }
    assert!(ma.iter().zip(&mb).any(|(x, y)| *x <= band && *y <= band));
    let mut bad = ones.clone();
    bad[17] = -2.0;
    let (mut labels, mut margin) = (vec![9u8; 125], vec![5.0; 125]);
    assert_eq!(
        run(bad.as_ptr(), &mut labels, &mut margin, &mut err),
        BOUNDARY_ERR_INPUT
    );
    assert_eq!(
        message(&err),
        "particle 17: radius must be positive and finite, got -2"
    );
    assert!(labels.iter().all(|&b| b == 9) && margin.iter().all(|&m| m == 5.0));
    unsafe { boundary_detector_free(handle) };
    let code = unsafe {
        boundary_detector_detect_radii(
            std::ptr::null(),
            xyz.as_ptr(),
            125,
            3,
            ones.as_ptr(),
            1.0,
            labels.as_mut_ptr(),
            std::ptr::null_mut(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(code, BOUNDARY_ERR_NULL);
}

#[test]
fn bad_radii_name_the_particle_and_leave_the_labels_untouched() {
    let xyz = [0.0, 0.0, 1.0, 0.0, 0.0, 1.0];
    for (value, r, text) in [
        (
            -1.0,
            1.0,
            "particle 2: radius must be positive and finite, got -1",
        ),
        (
            0.0,
            1.0,
            "particle 2: radius must be positive and finite, got 0",
        ),
        (
            f64::NAN,
            1.0,
            "particle 2: radius must be positive and finite, got NaN",
        ),
        (
            f64::INFINITY,
            1.0,
            "particle 2: radius must be positive and finite, got inf",
        ),
        (
            1e-200,
            1.0,
            "particle 2: radius 1e-200 is outside the supported range",
        ),
        // In range alone, out of range once scaled by r.
        (
            1e99,
            100.0,
            "particle 2: radius 1e101 is outside the supported range",
        ),
    ] {
        let radii = [1.0, 1.0, value];
        let (code, labels, err) = detect_radii(&xyz, 2, Some(&radii), r, "exact");
        assert_eq!(code, BOUNDARY_ERR_INPUT, "{value}: {err}");
        assert!(err.starts_with(text), "{value}: {err}");
        assert_eq!(labels, [7, 7, 7], "{value}: labels written on error");
    }
    // Misaligned radii are refused, not read.
    let storage = [0u64; 4];
    let misaligned = unsafe { storage.as_ptr().cast::<u8>().add(1).cast::<f64>() };
    let mut labels = [7u8; 3];
    let mut err = [0 as c_char; 256];
    let code = unsafe {
        boundary_detect_radii(
            xyz.as_ptr(),
            3,
            2,
            misaligned,
            1.0,
            c"exact".as_ptr(),
            std::ptr::null(),
            labels.as_mut_ptr(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(code, BOUNDARY_ERR_SIZE, "{}", message(&err));
    assert_eq!(message(&err), "radii is not aligned for double");
    // n = 0: radii are not read.
    let code = unsafe {
        boundary_detect_radii(
            std::ptr::null(),
            0,
            3,
            misaligned,
            1.0,
            c"exact".as_ptr(),
            std::ptr::null(),
            std::ptr::null_mut(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(code, BOUNDARY_OK, "{}", message(&err));
}

/// `exact` with per-particle radii: p0 = (0, 0) with r0 = 1 lies
/// inside the ball of p1 = (0.5, 0) with r1 = 2 (interior); S1 reaches 2.5 from p0 (boundary).
#[test]
fn exact_labels_two_particles_with_radii_1_and_2_interior_and_boundary() {
    let (code, labels, err) =
        detect_radii(&[0.0, 0.0, 0.5, 0.0], 2, Some(&[1.0, 2.0]), 1.0, "exact");
    assert_eq!(code, BOUNDARY_OK, "{err}");
    assert_eq!(labels, [0, 1], "[interior, boundary]");
}
