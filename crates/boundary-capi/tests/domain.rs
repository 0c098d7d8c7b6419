//! A simulation's domain through the C API: walls, solid half-spaces and periodic axes set once
//! on a `boundary_detector` handle, phases with each call. The walls give the labels of the
//! union's fluid part, a periodic axis those of explicit images, a solid covers what lies in
//! it, phases give interfaces; every bad domain is an error code with the library's message.

// Calling the C API means passing raw pointers (see src/lib.rs for why the crate allows it).
#![allow(unsafe_code)]
#![allow(
    clippy::undocumented_unsafe_blocks,
    clippy::multiple_unsafe_ops_per_block
)]

use boundary_capi::*;
use std::ffi::{c_char, CStr, CString};

fn message(err: &[c_char]) -> String {
    unsafe { CStr::from_ptr(err.as_ptr()) }
        .to_string_lossy()
        .into_owned()
}

/// An owned handle, freed on drop.
struct Handle(*mut boundary_detector);

impl Handle {
    fn new(method: &str) -> Self {
        let method = CString::new(method).expect("no NUL");
        let mut err = [0 as c_char; 512];
        let handle = unsafe {
            boundary_detector_new(
                method.as_ptr(),
                std::ptr::null(),
                err.as_mut_ptr(),
                err.len(),
            )
        };
        assert!(!handle.is_null(), "{}", message(&err));
        Handle(handle)
    }

    /// `boundary_detector_set_walls` (flat coordinates, `dim` each); (code, message).
    fn set_walls(&self, xyz: &[f64], dim: usize, radii: Option<&[f64]>) -> (i32, String) {
        let mut err = [0 as c_char; 512];
        let code = unsafe {
            boundary_detector_set_walls(
                self.0,
                xyz.as_ptr(),
                xyz.len() / dim,
                dim as i32,
                radii.map_or(std::ptr::null(), <[f64]>::as_ptr),
                err.as_mut_ptr(),
                err.len(),
            )
        };
        (code, message(&err))
    }

    /// `boundary_detector_add_solid` or `_add_periodic`; (code, message).
    fn add(&self, periodic: bool, text: &str) -> (i32, String) {
        let text = CString::new(text).expect("no NUL");
        let mut err = [0 as c_char; 512];
        let add = if periodic {
            boundary_detector_add_periodic
        } else {
            boundary_detector_add_solid
        };
        let code = unsafe { add(self.0, text.as_ptr(), err.as_mut_ptr(), err.len()) };
        (code, message(&err))
    }

    fn clear(&self) {
        let mut err = [0 as c_char; 512];
        let code = unsafe { boundary_detector_clear_domain(self.0, err.as_mut_ptr(), err.len()) };
        assert_eq!(code, BOUNDARY_OK, "{}", message(&err));
    }

    /// `boundary_detector_detect_phases` (no radii, no margin); (code, labels, interface,
    /// message), the outputs 7 where nothing was written.
    fn detect(
        &self,
        xyz: &[f64],
        dim: usize,
        r: f64,
        phases: Option<&[u32]>,
    ) -> (i32, Vec<u8>, Vec<u8>, String) {
        let n = xyz.len() / dim;
        let mut labels = vec![7u8; n];
        let mut interface = vec![7u8; n];
        let mut err = [0 as c_char; 1024];
        let code = unsafe {
            boundary_detector_detect_phases(
                self.0,
                xyz.as_ptr(),
                n,
                dim as i32,
                std::ptr::null(),
                r,
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
        (code, labels, interface, message(&err))
    }

    /// Labels through `boundary_detector_detect` (the call a solver makes every step),
    /// asserting success.
    fn labels(&self, xyz: &[f64], dim: usize, r: f64) -> Vec<u8> {
        let n = xyz.len() / dim;
        let mut labels = vec![7u8; n];
        let mut err = [0 as c_char; 512];
        let code = unsafe {
            boundary_detector_detect(
                self.0,
                xyz.as_ptr(),
                n,
                dim as i32,
                r,
                labels.as_mut_ptr(),
                std::ptr::null_mut(),
                err.as_mut_ptr(),
                err.len(),
            )
        };
        assert_eq!(code, BOUNDARY_OK, "{}", message(&err));
        labels
    }
}

impl Drop for Handle {
    fn drop(&mut self) {
        unsafe { boundary_detector_free(self.0) };
    }
}

/// A deterministic jitter in [-0.1, 0.1) (no ties between lattice neighbours).
fn jitter(k: usize) -> f64 {
    let h = (k as u64 + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 40;
    (h as f64 / (1u64 << 24) as f64 - 0.5) * 0.2
}

/// A `w` x `h` jittered square lattice of spacing 1 with its first column at x = 0.5, flat.
fn lattice(w: usize, h: usize) -> Vec<f64> {
    (0..w * h)
        .flat_map(|k| {
            let (i, j) = (k % w, k / w);
            [i as f64 + 0.5 + jitter(2 * k), j as f64 + jitter(2 * k + 1)]
        })
        .collect()
}

#[test]
fn walls_give_the_labels_of_the_unions_fluid_part() {
    // The highest three rows of a 10 x 10 block are walls (a lid), the other seven the fluid.
    let all = lattice(10, 10);
    let (fluid, walls) = all.split_at(2 * 70);
    for method in ["exact", "dilts", "ge"] {
        let handle = Handle::new(method);
        let union = handle.labels(&all, 2, 0.9);
        let (code, err) = handle.set_walls(walls, 2, None);
        assert_eq!(code, BOUNDARY_OK, "{err}");
        // Set once, used every step.
        for _ in 0..2 {
            assert_eq!(handle.labels(fluid, 2, 0.9), union[..70], "{method}");
        }
        // The fluid's top row is covered by the walls; without them it is boundary.
        handle.clear();
        let bare = handle.labels(fluid, 2, 0.9);
        assert!(bare[60..].iter().all(|&b| b == 1), "{method}: {bare:?}");
        assert!(union[60..70].contains(&0), "{method}");
        // m = 0 removes the walls again.
        handle.set_walls(walls, 2, None);
        assert_eq!(handle.set_walls(&[], 2, None).0, BOUNDARY_OK);
        assert_eq!(handle.labels(fluid, 2, 0.9), bare, "{method}");
    }
}

#[test]
fn a_solid_covers_what_lies_in_it_and_a_method_without_solids_says_so() {
    // A lone particle resting on the floor y < 0 (its upper half uncovered: boundary); one
    // whose sphere lies inside the solid (interior); one whose sphere just touches the floor
    // (boundary).
    let xyz = [0.0, 0.5, 10.0, -2.0, 20.0, 1.0];
    let handle = Handle::new("exact");
    let block = lattice(6, 4);
    let bare = handle.labels(&block, 2, 0.9);
    assert_eq!(handle.labels(&xyz, 2, 1.0), [1, 1, 1]);
    let (code, err) = handle.add(false, "y < 0");
    assert_eq!(code, BOUNDARY_OK, "{err}");
    assert_eq!(handle.labels(&xyz, 2, 1.0), [1, 0, 1]);
    // A block resting on the floor: its bottom row is covered by it. More solid never makes a
    // particle boundary: a second floor higher up.
    let floor = handle.labels(&block, 2, 0.9);
    assert!(floor.iter().sum::<u8>() < bare.iter().sum::<u8>());
    handle.add(false, "y<0.5");
    let higher = handle.labels(&block, 2, 0.9);
    for labels in [&floor, &higher] {
        assert!(bare.iter().zip(labels).all(|(a, b)| b <= a));
    }
    assert!(floor.iter().zip(&higher).all(|(a, b)| b <= a));

    let muller = Handle::new("muller");
    muller.add(false, "y<0");
    let (code, labels, _, err) = muller.detect(&xyz, 2, 1.0, None);
    assert_eq!(code, BOUNDARY_ERR_DETECT);
    assert!(err.contains("method 'muller' cannot honour solid"), "{err}");
    assert_eq!(labels, [7, 7, 7], "nothing written on error");
    // The message names the functions of this API that give the inputs, not the CLI's flags.
    assert!(
        err.contains("solid half-spaces (boundary_detector_add_solid)"),
        "{err}"
    );
    assert!(
        err.contains("wall particles (boundary_detector_set_walls)"),
        "{err}"
    );
    assert!(!err.contains("--"), "{err}");
}

#[test]
fn a_periodic_axis_gives_the_labels_of_explicit_images() {
    // An 8 x 5 strip in x in [0, 8]: its images shifted by +-8 as walls (in the library's
    // order of images).
    let strip = lattice(8, 5);
    let images: Vec<f64> = [8.0, -8.0]
        .iter()
        .flat_map(|shift| {
            strip
                .chunks_exact(2)
                .flat_map(move |p| [p[0] + shift, p[1]])
        })
        .collect();
    for method in ["exact", "ia"] {
        let periodic = Handle::new(method);
        let bare = periodic.labels(&strip, 2, 0.9);
        let (code, err) = periodic.add(true, "x:0:8");
        assert_eq!(code, BOUNDARY_OK, "{err}");
        let explicit = Handle::new(method);
        explicit.set_walls(&images, 2, None);
        let labels = periodic.labels(&strip, 2, 0.9);
        assert_eq!(labels, explicit.labels(&strip, 2, 0.9), "{method}");
        // The ends of the strip are covered through the period.
        assert!(
            labels.iter().sum::<u8>() < bare.iter().sum::<u8>(),
            "{method}"
        );
    }
}

#[test]
fn phases_give_interface_labels_beside_the_free_surface() {
    // Left half phase 0, right half phase 1: the interface is where they meet.
    let block = lattice(10, 8);
    let phases: Vec<u32> = (0..80).map(|k| u32::from(k % 10 >= 5)).collect();
    let handle = Handle::new("exact");
    let (code, labels, interface, err) = handle.detect(&block, 2, 0.9, Some(&phases));
    assert_eq!(code, BOUNDARY_OK, "{err}");
    assert_eq!(
        labels,
        handle.labels(&block, 2, 0.9),
        "free surface as without phases"
    );
    assert!(interface.iter().all(|&b| b <= 1));
    assert!(interface.contains(&1));
    for k in 0..80 {
        if interface[k] == 1 {
            assert_eq!(labels[k], 0, "particle {k}: interface, not free surface");
            assert!(
                (4..=5).contains(&(k % 10)),
                "particle {k}: by the contact line"
            );
        }
    }
    // One phase: no interface.
    let (_, _, none, _) = handle.detect(&block, 2, 0.9, Some(&[3; 80]));
    assert!(none.iter().all(|&b| b == 0));
    // Phases need out_interface, and out_interface needs phases.
    let mut out = vec![7u8; 80];
    let mut err = [0 as c_char; 512];
    let code = unsafe {
        boundary_detector_detect_phases(
            handle.0,
            block.as_ptr(),
            80,
            2,
            std::ptr::null(),
            0.9,
            phases.as_ptr(),
            out.as_mut_ptr(),
            std::ptr::null_mut(),
            std::ptr::null_mut(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(code, BOUNDARY_ERR_NULL);
    assert_eq!(message(&err), "out_interface is NULL");
    let mut interface = vec![7u8; 80];
    let code = unsafe {
        boundary_detector_detect_phases(
            handle.0,
            block.as_ptr(),
            80,
            2,
            std::ptr::null(),
            0.9,
            std::ptr::null(),
            out.as_mut_ptr(),
            interface.as_mut_ptr(),
            std::ptr::null_mut(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(code, BOUNDARY_ERR_NULL);
    assert!(
        message(&err).contains("phases is NULL"),
        "{}",
        message(&err)
    );
    assert!(out.iter().chain(&interface).all(|&b| b == 7));
}

#[test]
fn bad_domains_give_their_code_and_the_library_message() {
    let handle = Handle::new("exact");
    let (code, err) = handle.add(false, "y<<0");
    assert_eq!(code, BOUNDARY_ERR_DOMAIN);
    assert!(err.starts_with("solid 'y<<0':"), "{err}");
    let (code, err) = handle.add(true, "x:1:0");
    assert_eq!(code, BOUNDARY_ERR_DOMAIN);
    assert!(err.starts_with("periodic 'x:1:0':"), "{err}");
    let mut err = [0 as c_char; 64];
    let code = unsafe {
        boundary_detector_add_solid(handle.0, std::ptr::null(), err.as_mut_ptr(), err.len())
    };
    assert_eq!(
        (code, message(&err).as_str()),
        (BOUNDARY_ERR_NULL, "solid is NULL")
    );
    let code = unsafe {
        boundary_detector_add_solid(
            std::ptr::null_mut(),
            c"y<0".as_ptr(),
            err.as_mut_ptr(),
            err.len(),
        )
    };
    assert_eq!(code, BOUNDARY_ERR_NULL);
    let code =
        unsafe { boundary_detector_clear_domain(std::ptr::null_mut(), std::ptr::null_mut(), 0) };
    assert_eq!(code, BOUNDARY_ERR_NULL);

    // Walls: a non-finite coordinate names the wall particle and leaves the walls as they were.
    let (code, err) = handle.set_walls(&[0.0, 0.0, f64::NAN, 1.0], 2, None);
    assert_eq!(code, BOUNDARY_ERR_INPUT);
    assert!(err.starts_with("walls: particle 1"), "{err}");
    let (code, err) = handle.set_walls(&[0.0, 0.0], 2, Some(&[-1.0]));
    assert_eq!(code, BOUNDARY_ERR_INPUT);
    assert!(err.starts_with("walls: particle 0: radius"), "{err}");
    let (code, err) = handle.set_walls(&[0.0; 4], 4, None);
    assert_eq!(code, BOUNDARY_ERR_SIZE, "{err}");
    let xyz3 = [0.0, 0.0, 0.0, 5.0, 1.0, 2.0];
    assert_eq!(handle.labels(&xyz3, 3, 1.0), [1, 1], "no walls set so far");
    // Walls of another dimension than the particles: at detection.
    handle.set_walls(&[0.0, -1.0], 2, None);
    let (code, labels, _, err) = handle.detect(&xyz3, 3, 1.0, None);
    assert_eq!(code, BOUNDARY_ERR_DOMAIN);
    assert_eq!(err, "the walls are 2D and the particles 3D");
    assert_eq!(labels, [7, 7]);
    handle.clear();

    // A particle outside the periodic range, a period shorter than the reach, a solid on a
    // periodic axis.
    handle.add(true, "x:0:1");
    let (code, _, _, err) = handle.detect(&[0.5, 0.0, 1.5, 0.0], 2, 0.2, None);
    assert_eq!(code, BOUNDARY_ERR_DOMAIN);
    assert!(err.starts_with("particle 1: x = 1.5 lies outside"), "{err}");
    let (code, _, _, err) = handle.detect(&[0.5, 0.0], 2, 1.0, None);
    assert_eq!(code, BOUNDARY_ERR_DOMAIN);
    assert!(err.contains("shorter than the reach"), "{err}");
    handle.add(false, "x<0");
    let (code, _, _, err) = handle.detect(&[0.5, 0.0], 2, 0.2, None);
    assert_eq!(code, BOUNDARY_ERR_DOMAIN);
    assert!(err.contains("periodic"), "{err}");
    // Cleared: the bare cloud again.
    handle.clear();
    assert_eq!(handle.labels(&[0.5, 0.0, 1.5, 0.0], 2, 1.0), [1, 1]);
}
