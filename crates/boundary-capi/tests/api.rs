//! The C API from Rust, through the same `extern "C"` functions a C program calls: labels
//! equal the library's for every method, in 2D and 3D; every documented error code comes with
//! its message and leaves the outputs untouched.

// Calling the C API means passing raw pointers (see src/lib.rs for why the crate allows it).
#![allow(unsafe_code)]
#![allow(
    clippy::undocumented_unsafe_blocks,
    clippy::multiple_unsafe_ops_per_block
)]

use boundary::{detector_by_name, methods, BoundaryDetector, Radius};
use boundary_capi::*;
use boundary_scenes::{shared_set, SHARED_SCENES};
use std::ffi::{c_char, CStr, CString};

/// Flat coordinates of a shared scene, its radius and its exact boundary count (manifest);
/// `None` when the data is missing and `BOUNDARY_ALLOW_MISSING_DATA=1` (a skip).
fn scene(name: &str) -> Option<(Vec<f64>, usize, f64, usize, boundary::AnyParticleSet)> {
    let &(_, dim, file, r, n, boundary, _) = SHARED_SCENES
        .iter()
        .find(|s| s.0 == name)
        .expect("scene in the manifest");
    let set: boundary::AnyParticleSet = if dim == 2 {
        shared_set::<2>(file).expect("shared data")?.into()
    } else {
        shared_set::<3>(file).expect("shared data")?.into()
    };
    assert_eq!(set.len(), n);
    let flat: Vec<f64> = (0..n).flat_map(|i| set.coords(i).to_vec()).collect();
    Some((flat, dim, r, boundary, set))
}

fn message(err: &[c_char]) -> String {
    unsafe { CStr::from_ptr(err.as_ptr()) }
        .to_string_lossy()
        .into_owned()
}

/// `boundary_detect` with Rust strings; returns (code, labels, message).
fn detect(xyz: &[f64], dim: usize, r: f64, method: &str, params: &str) -> (i32, Vec<u8>, String) {
    let n = xyz.len() / dim;
    let mut labels = vec![7u8; n];
    let mut err = [0 as c_char; 512];
    let method = CString::new(method).expect("no NUL");
    let params = CString::new(params).expect("no NUL");
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
    (code, labels, message(&err))
}

#[test]
fn every_method_through_the_c_api_gives_the_library_labels_in_2d_and_3d() {
    for name in ["sandim_vortex_050", "dualsphysics_dambreak3d"] {
        let Some((xyz, dim, r, exact_count, set)) = scene(name) else {
            continue;
        };
        for method in methods() {
            let (code, labels, err) = detect(&xyz, dim, r, method, "");
            assert_eq!(code, BOUNDARY_OK, "{name} {method}: {err}");
            assert_eq!(err, "", "no message on success");
            let expected = detector_by_name(method)
                .expect("registered")
                .detect(&set, Radius::new(r).expect("r > 0"))
                .expect("detects");
            let expected: Vec<u8> = expected
                .labels
                .as_slice()
                .iter()
                .map(|&b| u8::from(b))
                .collect();
            assert_eq!(labels, expected, "{name} {method}");
            if method == "exact" {
                let count = labels.iter().filter(|&&b| b == 1).count();
                assert_eq!(count, exact_count, "{name}: the manifest's exact count");
            }
        }
    }
}

#[test]
fn a_handle_is_reused_across_steps_with_its_params_and_margin() {
    let Some((xyz, dim, r, _, set)) = scene("sandim_vortex_001") else {
        return;
    };
    let n = xyz.len() / dim;
    let mut err = [0 as c_char; 256];
    let handle = unsafe {
        boundary_detector_new(
            c"muller".as_ptr(),
            c"threshold=0.3".as_ptr(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert!(!handle.is_null(), "{}", message(&err));
    let muller = boundary::MullerDetector::try_new(boundary::MullerParams {
        threshold: 0.3,
        ..Default::default()
    })
    .expect("threshold 0.3");
    let expected = muller
        .detect(&set, Radius::new(r).expect("r"))
        .expect("detects");
    assert_eq!(
        unsafe { boundary_detector_set_threads(handle, 1, err.as_mut_ptr(), err.len()) },
        BOUNDARY_OK
    );
    for _step in 0..2 {
        let mut labels = vec![0u8; n];
        let mut margin = vec![0.0f64; n];
        let code = unsafe {
            boundary_detector_detect(
                handle,
                xyz.as_ptr(),
                n,
                dim as i32,
                r,
                labels.as_mut_ptr(),
                margin.as_mut_ptr(),
                err.as_mut_ptr(),
                err.len(),
            )
        };
        assert_eq!(code, BOUNDARY_OK, "{}", message(&err));
        let want: Vec<u8> = expected
            .labels
            .as_slice()
            .iter()
            .map(|&b| u8::from(b))
            .collect();
        assert_eq!(labels, want);
        assert_eq!(Some(margin), expected.margin.clone());
    }
    unsafe { boundary_detector_free(handle) };
}

#[test]
fn a_method_without_margin_refuses_out_margin_and_writes_nothing() {
    let xyz = [0.0, 0.0, 1.0, 0.0];
    let mut err = [0 as c_char; 256];
    let handle = unsafe {
        boundary_detector_new(
            c"ge".as_ptr(),
            std::ptr::null(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert!(!handle.is_null(), "{}", message(&err));
    let mut labels = [9u8; 2];
    let mut margin = [5.0f64; 2];
    let code = unsafe {
        boundary_detector_detect(
            handle,
            xyz.as_ptr(),
            2,
            2,
            1.0,
            labels.as_mut_ptr(),
            margin.as_mut_ptr(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(code, BOUNDARY_ERR_NO_MARGIN);
    assert!(message(&err).contains("no margin"), "{}", message(&err));
    assert_eq!(labels, [9, 9]);
    assert_eq!(margin, [5.0, 5.0]);
    unsafe { boundary_detector_free(handle) };
}

#[test]
fn bad_input_gives_its_code_and_the_cli_message_and_leaves_labels_untouched() {
    let good = [0.0, 0.0, 1.0, 0.0, 0.0, 1.0];
    // (what, xyz, dim, r, method, params, expected code, part of the message)
    type Case = (
        &'static str,
        Vec<f64>,
        usize,
        f64,
        &'static str,
        &'static str,
        i32,
        &'static str,
    );
    let cases: Vec<Case> = vec![
        (
            "nan",
            vec![0.0, 0.0, f64::NAN, 1.0],
            2,
            1.0,
            "exact",
            "",
            BOUNDARY_ERR_INPUT,
            "particle 1: coordinate 0 is not finite",
        ),
        (
            "r = 0",
            good.to_vec(),
            2,
            0.0,
            "exact",
            "",
            BOUNDARY_ERR_INPUT,
            "radius must be positive",
        ),
        (
            "r = -1",
            good.to_vec(),
            2,
            -1.0,
            "exact",
            "",
            BOUNDARY_ERR_INPUT,
            "radius must be positive",
        ),
        (
            "flat",
            vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0],
            3,
            1.0,
            "exact",
            "",
            BOUNDARY_ERR_INPUT,
            "all 3 particles have z = 0: a flat set is 2D, and with dim = 3 every particle \
             would be boundary; pass dim = 2 with the x and y coordinates",
        ),
        (
            "flat in y",
            vec![0.0, 2.0, 0.0, 1.0, 2.0, 0.0, 0.0, 2.0, 1.0],
            3,
            1.0,
            "exact",
            "",
            BOUNDARY_ERR_INPUT,
            "all 3 particles have y = 2: a flat set is 2D",
        ),
        (
            "one place",
            vec![1.0, 2.0, 3.0, 1.0, 2.0, 3.0],
            3,
            1.0,
            "exact",
            "",
            BOUNDARY_ERR_INPUT,
            "all 2 particles are at (1, 2, 3): the set has no extent",
        ),
        (
            "dim 4",
            good.to_vec(),
            4,
            1.0,
            "exact",
            "",
            BOUNDARY_ERR_SIZE,
            "dim must be 2 or 3",
        ),
        (
            "method",
            good.to_vec(),
            2,
            1.0,
            "nope",
            "",
            BOUNDARY_ERR_METHOD,
            "unknown method 'nope'",
        ),
        (
            "param key",
            good.to_vec(),
            2,
            1.0,
            "ge",
            "gamma=2",
            BOUNDARY_ERR_PARAM,
            "has no parameter 'gamma'",
        ),
        (
            "param value",
            good.to_vec(),
            2,
            1.0,
            "ge",
            "depth=-3",
            BOUNDARY_ERR_PARAM,
            "invalid value '-3'",
        ),
        (
            "param syntax",
            good.to_vec(),
            2,
            1.0,
            "ge",
            "depth",
            BOUNDARY_ERR_PARAM,
            "expected KEY=VALUE",
        ),
    ];
    for (what, xyz, dim, r, method, params, code, text) in cases {
        let n = xyz.len() / dim.clamp(2, 3);
        let mut labels = vec![7u8; n];
        let mut err = [0 as c_char; 512];
        let method = CString::new(method).expect("no NUL");
        let params = CString::new(params).expect("no NUL");
        let got = unsafe {
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
        assert_eq!(got, code, "{what}: {}", message(&err));
        assert!(message(&err).contains(text), "{what}: {}", message(&err));
        assert!(
            labels.iter().all(|&b| b == 7),
            "{what}: labels written on error"
        );
    }
}

#[test]
fn null_pointers_are_errors_unless_there_is_nothing_to_read() {
    let mut err = [0 as c_char; 256];
    let mut labels = [0u8; 3];
    let xyz = [0.0; 6];
    let call = |xyz: *const f64,
                n: usize,
                method: *const c_char,
                labels: *mut u8,
                err: &mut [c_char]| unsafe {
        boundary_detect(
            xyz,
            n,
            2,
            1.0,
            method,
            std::ptr::null(),
            labels,
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(
        call(
            std::ptr::null(),
            3,
            c"exact".as_ptr(),
            labels.as_mut_ptr(),
            &mut err
        ),
        BOUNDARY_ERR_NULL
    );
    assert_eq!(message(&err), "xyz is NULL");
    assert_eq!(
        call(
            xyz.as_ptr(),
            3,
            c"exact".as_ptr(),
            std::ptr::null_mut(),
            &mut err
        ),
        BOUNDARY_ERR_NULL
    );
    assert_eq!(message(&err), "out_labels is NULL");
    assert_eq!(
        call(
            xyz.as_ptr(),
            3,
            std::ptr::null(),
            labels.as_mut_ptr(),
            &mut err
        ),
        BOUNDARY_ERR_NULL
    );
    assert_eq!(message(&err), "method is NULL");
    // n = 0: nothing to read or write, so NULL buffers are fine.
    assert_eq!(
        call(
            std::ptr::null(),
            0,
            c"exact".as_ptr(),
            std::ptr::null_mut(),
            &mut err
        ),
        BOUNDARY_OK
    );
    // A NULL error buffer is allowed.
    let code = unsafe {
        boundary_detect(
            std::ptr::null(),
            3,
            2,
            1.0,
            c"exact".as_ptr(),
            std::ptr::null(),
            labels.as_mut_ptr(),
            std::ptr::null_mut(),
            0,
        )
    };
    assert_eq!(code, BOUNDARY_ERR_NULL);
    let mut labels = [0u8; 1];
    let code = unsafe {
        boundary_detector_detect(
            std::ptr::null(),
            xyz.as_ptr(),
            1,
            2,
            1.0,
            labels.as_mut_ptr(),
            std::ptr::null_mut(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(code, BOUNDARY_ERR_NULL);
    assert_eq!(message(&err), "handle is NULL");
    unsafe { boundary_detector_free(std::ptr::null_mut()) };
    let handle = unsafe {
        boundary_detector_new(
            c"nope".as_ptr(),
            std::ptr::null(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert!(handle.is_null());
    assert!(
        message(&err).starts_with("unknown method 'nope'"),
        "{}",
        message(&err)
    );
}

#[test]
fn invalid_utf8_and_overflowing_sizes_are_refused() {
    let mut err = [0 as c_char; 256];
    let mut labels = [0u8; 1];
    let xyz = [0.0; 2];
    let bad = [0xffu8 as c_char, 0];
    let code = unsafe {
        boundary_detect(
            xyz.as_ptr(),
            1,
            2,
            1.0,
            bad.as_ptr(),
            std::ptr::null(),
            labels.as_mut_ptr(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(code, BOUNDARY_ERR_UTF8, "{}", message(&err));
    let code = unsafe {
        boundary_detect(
            xyz.as_ptr(),
            usize::MAX / 2,
            3,
            1.0,
            c"exact".as_ptr(),
            std::ptr::null(),
            labels.as_mut_ptr(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(code, BOUNDARY_ERR_SIZE, "{}", message(&err));
    assert!(message(&err).contains("too many"), "{}", message(&err));
}

#[test]
fn the_error_message_is_cut_to_the_buffer_and_nul_terminated() {
    let mut err = [b'#' as c_char; 8];
    let mut labels = [0u8; 1];
    let xyz = [0.0; 2];
    let code = unsafe {
        boundary_detect(
            xyz.as_ptr(),
            1,
            2,
            1.0,
            c"nope".as_ptr(),
            std::ptr::null(),
            labels.as_mut_ptr(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(code, BOUNDARY_ERR_METHOD);
    assert_eq!(message(&err), "unknown");
    assert_eq!(err[7], 0);
}

#[test]
fn the_thread_count_does_not_change_the_labels() {
    let Some((xyz, dim, r, _, _)) = scene("sandim_vortex_100") else {
        return;
    };
    let (code, all_cores, err) = detect(&xyz, dim, r, "ia", "depth=4");
    assert_eq!(code, BOUNDARY_OK, "{err}");
    let mut buf = [0 as c_char; 128];
    assert_eq!(
        unsafe { boundary_set_threads(1, buf.as_mut_ptr(), buf.len()) },
        BOUNDARY_OK
    );
    let (code, one_thread, err) = detect(&xyz, dim, r, "ia", "depth=4");
    assert_eq!(
        unsafe { boundary_set_threads(0, buf.as_mut_ptr(), buf.len()) },
        BOUNDARY_OK
    );
    assert_eq!(code, BOUNDARY_OK, "{err}");
    assert_eq!(all_cores, one_thread);
}

#[test]
fn the_version_is_the_crate_version() {
    let version = unsafe { CStr::from_ptr(boundary_version()) };
    assert_eq!(version.to_str(), Ok(env!("CARGO_PKG_VERSION")));
}

#[test]
fn confusion_scores_given_labels_with_the_keys_of_the_cli() {
    let predicted = [1u8, 1, 1, 0, 0, 0, 0, 0];
    let truth = [1u8, 1, 0, 1, 0, 0, 0, 0];
    let mut out = boundary_confusion::default();
    let mut err = [0 as c_char; 256];
    let code = unsafe {
        boundary_confusion_from_labels(
            predicted.as_ptr(),
            truth.as_ptr(),
            predicted.len(),
            &mut out,
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(code, BOUNDARY_OK, "{}", message(&err));
    assert_eq!((out.tp, out.fp, out.r#fn, out.tn), (2, 1, 1, 4));
    assert!((out.recall - 2.0 / 3.0).abs() < 1e-15);
    assert!((out.fpr - 0.2).abs() < 1e-15);
    assert!((out.m - 2.0 / 3.0 * 0.8).abs() < 1e-15);
    assert!((out.precision - 2.0 / 3.0).abs() < 1e-15 && (out.f1 - 2.0 / 3.0).abs() < 1e-15);
    // The same numbers as the library's `Confusion`, which `boundary score` prints.
    let bools = |v: &[u8]| v.iter().map(|&b| b == 1).collect::<Vec<_>>();
    let c = boundary::Confusion::from_labels(&bools(&predicted), &bools(&truth)).expect("n each");
    assert_eq!(
        (c.tp, c.tn, c.fp, c.fn_),
        (out.tp, out.tn, out.fp, out.r#fn)
    );
    assert_eq!((c.recall(), c.fpr(), c.m()), (out.recall, out.fpr, out.m));

    // A label other than 0/1 is named, and the output stays as it was.
    let bad = [0u8, 2, 0, 0, 0, 0, 0, 0];
    let before = out;
    let code = unsafe {
        boundary_confusion_from_labels(
            predicted.as_ptr(),
            bad.as_ptr(),
            bad.len(),
            &mut out,
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(code, BOUNDARY_ERR_INPUT);
    assert_eq!(
        message(&err),
        "truth: particle 1: a label must be 0 or 1, got 2"
    );
    assert_eq!(out, before);
    let code = unsafe {
        boundary_confusion_from_labels(
            std::ptr::null(),
            truth.as_ptr(),
            truth.len(),
            &mut out,
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(
        (code, message(&err).as_str()),
        (BOUNDARY_ERR_NULL, "predicted is NULL")
    );
    let code = unsafe {
        boundary_confusion_from_labels(
            std::ptr::null(),
            std::ptr::null(),
            0,
            std::ptr::null_mut(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(
        (code, message(&err).as_str()),
        (BOUNDARY_ERR_NULL, "out is NULL")
    );
}

// ---- the resolution in a solver's terms: h, the spacing, auto --------------------------------

/// A `side`^2 lattice of spacing `dp` clipped to a disc, jittered by up to 10% of `dp` (a
/// deterministic LCG): an interior and a free surface.
fn jittered_disc(side: usize, dp: f64) -> Vec<f64> {
    let mut state = 11u64;
    let mut next = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let centre = (side - 1) as f64 / 2.0;
    let mut xyz = Vec::new();
    for i in 0..side {
        for j in 0..side {
            let (x, y) = (i as f64 - centre, j as f64 - centre);
            if x.hypot(y) <= centre {
                xyz.push(dp * (x + 0.1 * (2.0 * next() - 1.0)));
                xyz.push(dp * (y + 0.1 * (2.0 * next() - 1.0)));
            }
        }
    }
    xyz
}

/// `boundary_detect_h` with Rust strings; returns (code, labels, message).
fn detect_h(xyz: &[f64], h: f64, method: &str, params: &str) -> (i32, Vec<u8>, String) {
    let n = xyz.len() / 2;
    let mut labels = vec![7u8; n];
    let mut err = [0 as c_char; 512];
    let method = CString::new(method).expect("no NUL");
    let params = CString::new(params).expect("no NUL");
    let code = unsafe {
        boundary_detect_h(
            xyz.as_ptr(),
            n,
            2,
            h,
            method.as_ptr(),
            params.as_ptr(),
            labels.as_mut_ptr(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    (code, labels, message(&err))
}

#[test]
fn the_smoothing_length_gives_the_labels_of_r_equal_h_and_refuses_another_h_over_r() {
    let dp = 0.02;
    let xyz = jittered_disc(30, dp);
    let h = 1.5 * dp;
    for method in [
        "exact",
        "marrone",
        "muller",
        "divr",
        "asymmetry",
        "randles",
        "ge",
    ] {
        let (code, labels, text) = detect_h(&xyz, h, method, "");
        assert_eq!(code, BOUNDARY_OK, "{method}: {text}");
        let (code, expected, text) = detect(&xyz, 2, h, method, "");
        assert_eq!(code, BOUNDARY_OK, "{method}: {text}");
        assert_eq!(labels, expected, "{method}");
        assert!(labels.contains(&0) && labels.contains(&1), "{method}");
        // h_over_r = 1 is h itself; anything else would make the SPH sums' h another one.
        if method != "exact" && method != "ge" {
            let (code, labels, _) = detect_h(&xyz, h, method, "h_over_r=1.0");
            assert_eq!((code, &labels), (BOUNDARY_OK, &expected), "{method}");
            let (code, labels, text) = detect_h(&xyz, h, method, "h_over_r=2");
            assert_eq!(code, BOUNDARY_ERR_PARAM, "{method}: {text}");
            assert!(
                text.contains("h_over_r=2 would make it 2 x 0.03"),
                "{method}: {text}"
            );
            assert!(labels.iter().all(|&b| b == 7), "{method}: labels written");
        }
    }
    // The handle: the same labels as boundary_detector_detect with r = h, in its domain.
    let mut err = [0 as c_char; 512];
    let n = xyz.len() / 2;
    for (params, code_expected) in [("", BOUNDARY_OK), ("h_over_r=1.5", BOUNDARY_ERR_PARAM)] {
        let params = CString::new(params).expect("no NUL");
        let handle = unsafe {
            boundary_detector_new(
                c"muller".as_ptr(),
                params.as_ptr(),
                err.as_mut_ptr(),
                err.len(),
            )
        };
        assert!(!handle.is_null(), "{}", message(&err));
        let mut labels = vec![7u8; n];
        let code = unsafe {
            boundary_detector_detect_h(
                handle,
                xyz.as_ptr(),
                n,
                2,
                h,
                labels.as_mut_ptr(),
                std::ptr::null_mut(),
                err.as_mut_ptr(),
                err.len(),
            )
        };
        assert_eq!(code, code_expected, "{}", message(&err));
        if code == BOUNDARY_OK {
            let mut expected = vec![7u8; n];
            let code = unsafe {
                boundary_detector_detect(
                    handle,
                    xyz.as_ptr(),
                    n,
                    2,
                    h,
                    expected.as_mut_ptr(),
                    std::ptr::null_mut(),
                    err.as_mut_ptr(),
                    err.len(),
                )
            };
            assert_eq!(code, BOUNDARY_OK, "{}", message(&err));
            assert_eq!(labels, expected);
        } else {
            assert!(message(&err).contains("h_over_r=1.5"), "{}", message(&err));
            assert!(labels.iter().all(|&b| b == 7));
        }
        // A bad h is an input error, never a crash; nothing is written.
        for bad in [f64::NAN, -h, 0.0, f64::INFINITY] {
            let code = unsafe {
                boundary_detector_detect_h(
                    handle,
                    xyz.as_ptr(),
                    n,
                    2,
                    bad,
                    labels.as_mut_ptr(),
                    std::ptr::null_mut(),
                    err.as_mut_ptr(),
                    err.len(),
                )
            };
            assert_eq!(code, BOUNDARY_ERR_INPUT, "h = {bad}");
            assert!(
                message(&err).starts_with("smoothing length h: "),
                "{}",
                message(&err)
            );
        }
        unsafe { boundary_detector_free(handle) };
    }
    let code = unsafe {
        boundary_detector_detect_h(
            std::ptr::null(),
            xyz.as_ptr(),
            n,
            2,
            h,
            std::ptr::null_mut(),
            std::ptr::null_mut(),
            std::ptr::null_mut(),
            0,
        )
    };
    assert_eq!(code, BOUNDARY_ERR_NULL);
    for bad in [f64::NAN, -1.0, 0.0, f64::INFINITY, 1e300] {
        let (code, labels, text) = detect_h(&xyz, bad, "exact", "");
        assert_eq!(code, BOUNDARY_ERR_INPUT, "h = {bad}: {text}");
        assert!(labels.iter().all(|&b| b == 7));
    }
    let (code, _, text) = detect_h(&[0.0, f64::NAN], h, "exact", "");
    assert_eq!(code, BOUNDARY_ERR_INPUT, "{text}");
    let mut labels = [7u8; 3];
    let code = unsafe {
        boundary_detect_h(
            std::ptr::null(),
            3,
            2,
            h,
            c"exact".as_ptr(),
            std::ptr::null(),
            labels.as_mut_ptr(),
            std::ptr::null_mut(),
            0,
        )
    };
    assert_eq!(code, BOUNDARY_ERR_NULL);
}

#[test]
fn the_spacing_gives_r_k_dp_and_the_bulk_spacing_reads_a_jittered_lattice() {
    assert_eq!(BOUNDARY_RADIUS_PER_SPACING, boundary::RADIUS_PER_SPACING);
    let mut err = [0 as c_char; 512];
    let mut r = -7.0;
    let code = unsafe { boundary_radius_from_spacing(0.02, &mut r, err.as_mut_ptr(), err.len()) };
    assert_eq!(code, BOUNDARY_OK, "{}", message(&err));
    assert_eq!(r, BOUNDARY_RADIUS_PER_SPACING * 0.02);
    assert_eq!(r, boundary::radius_from_spacing(0.02).expect("valid").get());

    // The labels of r = k dp.
    let dp = 0.02;
    let xyz = jittered_disc(30, dp);
    let n = xyz.len() / 2;
    let (code, labels, text) = detect(&xyz, 2, r, "exact", "");
    assert_eq!(code, BOUNDARY_OK, "{text}");
    let set = boundary::AnyParticleSet::from(
        boundary::ParticleSet::from_rows(
            &xyz.chunks_exact(2)
                .map(|p| [p[0], p[1]])
                .collect::<Vec<_>>(),
        )
        .expect("finite"),
    );
    let expected = detector_by_name("exact")
        .expect("exact")
        .detect(&set, Radius::new(1.45 * dp).expect("valid"))
        .expect("detects");
    let expected: Vec<u8> = expected
        .labels
        .as_slice()
        .iter()
        .map(|&b| u8::from(b))
        .collect();
    assert_eq!(labels, expected);

    // The spacing measured in the bulk, and auto's r from it: the library's numbers.
    let mut spacing = -7.0;
    let code = unsafe {
        boundary_bulk_spacing(
            xyz.as_ptr(),
            n,
            2,
            &mut spacing,
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(code, BOUNDARY_OK, "{}", message(&err));
    assert_eq!(
        Some(spacing),
        boundary::bulk_spacing(&set).expect("measures")
    );
    assert!((spacing / dp - 1.0).abs() < 0.1, "{spacing}");
    let (mut auto_r, mut auto_dp) = (-7.0, -7.0);
    let code = unsafe {
        boundary_auto_radius(
            xyz.as_ptr(),
            n,
            2,
            &mut auto_r,
            &mut auto_dp,
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(code, BOUNDARY_OK, "{}", message(&err));
    assert_eq!(
        (auto_dp, auto_r),
        (spacing, BOUNDARY_RADIUS_PER_SPACING * spacing)
    );
    let mut only_r = -7.0;
    let code = unsafe {
        boundary_auto_radius(
            xyz.as_ptr(),
            n,
            2,
            &mut only_r,
            std::ptr::null_mut(),
            std::ptr::null_mut(),
            0,
        )
    };
    assert_eq!((code, only_r), (BOUNDARY_OK, auto_r));
}

#[test]
fn bad_spacings_and_sets_are_errors_and_write_nothing() {
    let mut err = [0 as c_char; 512];
    for bad in [
        f64::NAN,
        -0.02,
        0.0,
        f64::INFINITY,
        f64::NEG_INFINITY,
        1e300,
    ] {
        let mut r = -7.0;
        let code =
            unsafe { boundary_radius_from_spacing(bad, &mut r, err.as_mut_ptr(), err.len()) };
        assert_eq!(code, BOUNDARY_ERR_INPUT, "dp = {bad}");
        assert!(message(&err).starts_with("spacing: "), "{}", message(&err));
        assert_eq!(r, -7.0);
    }
    let code = unsafe {
        boundary_radius_from_spacing(0.02, std::ptr::null_mut(), err.as_mut_ptr(), err.len())
    };
    assert_eq!(
        (code, message(&err).as_str()),
        (BOUNDARY_ERR_NULL, "out_r is NULL")
    );
    let code = unsafe {
        boundary_radius_from_spacing(f64::NAN, std::ptr::null_mut(), std::ptr::null_mut(), 0)
    };
    assert_ne!(code, BOUNDARY_OK);

    // (what, xyz, n, dim, code, part of the message) for both bulk_spacing and auto_radius.
    let one = [0.5, 0.5];
    let twins = [0.5, 0.5, 0.5, 0.5];
    let nan = [0.0, 0.0, f64::NAN, 1.0];
    let flat = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let square = [0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 1.0];
    let cases: Vec<(&str, *const f64, usize, i32, i32, &str)> = vec![
        (
            "empty",
            std::ptr::null(),
            0,
            2,
            BOUNDARY_ERR_INPUT,
            "two distinct",
        ),
        (
            "one",
            one.as_ptr(),
            1,
            2,
            BOUNDARY_ERR_INPUT,
            "two distinct",
        ),
        (
            "duplicates",
            twins.as_ptr(),
            2,
            2,
            BOUNDARY_ERR_INPUT,
            "two distinct",
        ),
        (
            "nan",
            nan.as_ptr(),
            2,
            2,
            BOUNDARY_ERR_INPUT,
            "particle 1: coordinate 0",
        ),
        (
            "flat",
            flat.as_ptr(),
            3,
            3,
            BOUNDARY_ERR_INPUT,
            "a flat set is 2D",
        ),
        (
            "null",
            std::ptr::null(),
            4,
            2,
            BOUNDARY_ERR_NULL,
            "xyz is NULL",
        ),
        (
            "dim",
            square.as_ptr(),
            2,
            4,
            BOUNDARY_ERR_SIZE,
            "dim must be 2 or 3",
        ),
        (
            "overflow",
            square.as_ptr(),
            usize::MAX,
            3,
            BOUNDARY_ERR_SIZE,
            "too many",
        ),
    ];
    for (what, xyz, n, dim, expected, text) in cases {
        let mut out = -7.0;
        let code =
            unsafe { boundary_bulk_spacing(xyz, n, dim, &mut out, err.as_mut_ptr(), err.len()) };
        assert_eq!(code, expected, "bulk_spacing {what}: {}", message(&err));
        assert!(
            message(&err).contains(text),
            "bulk_spacing {what}: {}",
            message(&err)
        );
        assert_eq!(out, -7.0, "{what}");
        let (mut r, mut dp) = (-7.0, -7.0);
        let code = unsafe {
            boundary_auto_radius(xyz, n, dim, &mut r, &mut dp, err.as_mut_ptr(), err.len())
        };
        assert_eq!(code, expected, "auto_radius {what}: {}", message(&err));
        assert!(
            message(&err).contains(text),
            "auto_radius {what}: {}",
            message(&err)
        );
        assert_eq!((r, dp), (-7.0, -7.0), "{what}");
    }
    // A NULL output is refused, not written through.
    let code = unsafe {
        boundary_bulk_spacing(
            square.as_ptr(),
            4,
            2,
            std::ptr::null_mut(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(
        (code, message(&err).as_str()),
        (BOUNDARY_ERR_NULL, "out_spacing is NULL")
    );
    let code = unsafe {
        boundary_auto_radius(
            square.as_ptr(),
            4,
            2,
            std::ptr::null_mut(),
            std::ptr::null_mut(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(
        (code, message(&err).as_str()),
        (BOUNDARY_ERR_NULL, "out_r is NULL")
    );
}
