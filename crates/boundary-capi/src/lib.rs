//! C API of `boundary`: boundary particles of meshfree particle sets, for C and C++ solvers
//! that call it in situ, every time step.
//!
//! The header is `include/boundary.h` (generated from this file by cbindgen; the test
//! `tests/header.rs` fails when the committed header differs). Link `libboundary_capi.so` or
//! `libboundary_capi.a` (with `-lpthread -ldl -lm`).
//!
//! ```c
//! #include "boundary.h"
//! uint8_t labels[N];
//! char err[256];
//! if (boundary_detect(xyz, N, 3, 0.05, "ge", "depth=4", labels, err, sizeof err) != BOUNDARY_OK)
//!     fprintf(stderr, "boundary: %s\n", err);
//! ```
//!
//! For a simulation loop, create a `boundary_detector` once (method and parameters parsed
//! once) and call `boundary_detector_detect` every step; free it with
//! `boundary_detector_free`.
//!
//! A radius per particle (adaptive resolution): `boundary_detect_radii` and
//! `boundary_detector_detect_radii` take `radii` (`n` doubles, the factor `s_i` of each
//! particle, or NULL for the uniform case) and use `r_i = r * s_i`, so `r = 1` takes the radii
//! as they are. A radius that is not positive and finite (or leaves 1e-100..=1e100 once
//! scaled) is `BOUNDARY_ERR_INPUT` naming the particle; a method without per-particle support
//! returns `BOUNDARY_ERR_DETECT` saying so.
//!
//! The resolution `r` in a solver's terms: in SPH, `r` is the smoothing length `h`
//! (`boundary_detect_h` and `boundary_detector_detect_h` take `h`, and refuse a method whose
//! `h_over_r` would make the SPH sums use another one); from the particle spacing `dp`,
//! `boundary_radius_from_spacing` gives `r = BOUNDARY_RADIUS_PER_SPACING * dp`;
//! `boundary_bulk_spacing` measures `dp` in the bulk of a set and `boundary_auto_radius` the
//! `r` of `boundary detect --radius auto`.
//!
//! A simulation's domain (see the library's `boundary::domain`) belongs to the handle, set
//! once since it usually does not move: `boundary_detector_set_walls` (covering-only wall
//! particles), `boundary_detector_add_solid` (a closed solid half-space, `"y<0"`),
//! `boundary_detector_add_periodic` (`"x:0:1"`), `boundary_detector_clear_domain`. Every
//! detection by that handle then honours it; `boundary_detector_detect_phases` also takes a
//! phase number per particle and writes the interface labels. A method that cannot honour a
//! solid returns `BOUNDARY_ERR_DETECT` saying so; a malformed or mismatched domain is
//! `BOUNDARY_ERR_DOMAIN`.
//!
//! # Contract
//! - `xyz` holds `n * dim` doubles, particle after particle (`x0 y0 [z0] x1 y1 ...`), `dim` 2
//!   or 3; it may be NULL only when `n == 0`. Labels are written to `out_labels[0..n]` (1
//!   boundary, 0 interior) only on success; nothing is written on error.
//! - Every function returns `BOUNDARY_OK` (0) or one of the `BOUNDARY_ERR_*` codes, and
//!   writes a NUL-terminated one-line message into `err` (truncated to `err_len - 1` bytes;
//!   `err` may be NULL). The messages are those of the `boundary` command.
//! - No panic crosses the boundary (each entry point catches unwinding; a caught panic is
//!   `BOUNDARY_ERR_INTERNAL`), and no allocation escapes: results go into the caller's
//!   buffers; the only object the library allocates for the caller is the handle, released
//!   by `boundary_detector_free`.
//! - Threads: detection runs on rayon's pool of all cores, on the pool set by
//!   `boundary_set_threads` (for `boundary_detect` and handles without their own), or on the
//!   handle's own (`boundary_detector_set_threads`). Labels do not depend on the thread count.
//!   A handle may be used from one thread at a time; different handles from different threads.
//!
//! This crate only translates: the detectors are the Rust library's (`boundary` facade).

// A C API reads raw pointers and exports unmangled symbols, which is `unsafe_code`; the
// workspace forbids it everywhere else. Each unsafe block here is one operation with its
// SAFETY argument (enforced by clippy's `undocumented_unsafe_blocks` and
// `multiple_unsafe_ops_per_block`, see Cargo.toml).
#![allow(unsafe_code)]

use boundary::{
    auto_radius, bulk_spacing, detector_with_params, parse_param_list, radius_from_spacing,
    AnyParticleSet, BoundaryDetector, DetectError, Detection, Domain, Flatness, HalfSpace, Labels,
    ParticleSet, Periodic, Point, Radius,
};
use boundary::{Dim, SupportedDim};
use std::ffi::{c_char, c_int, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::{Arc, Mutex};

mod tracker;
pub use tracker::{
    boundary_tracker, boundary_tracker_add_periodic, boundary_tracker_add_solid,
    boundary_tracker_free, boundary_tracker_new, boundary_tracker_set_walls,
    boundary_tracker_update, boundary_tracker_update_domain, boundary_tracker_update_ids,
};

/// Success.
pub const BOUNDARY_OK: c_int = 0;
/// A required pointer argument is NULL.
pub const BOUNDARY_ERR_NULL: c_int = 1;
/// A size or layout is invalid: `dim` not 2 or 3, `n * dim` too large, a misaligned buffer.
pub const BOUNDARY_ERR_SIZE: c_int = 2;
/// The input is invalid: a non-finite coordinate or a bad per-particle radius (the message
/// names the particle), `r` not positive and finite, more than 2^32 - 1 particles, a flat 3D
/// set (every particle with the same z, or y, or x, or all at one place: every particle would
/// be boundary; the message names the coordinates to pass with `dim` 2).
pub const BOUNDARY_ERR_INPUT: c_int = 3;
/// No method of that name (the message lists the available ones).
pub const BOUNDARY_ERR_METHOD: c_int = 4;
/// A parameter is malformed (not `key=value`), unknown to the method, or out of range.
pub const BOUNDARY_ERR_PARAM: c_int = 5;
/// `method` or `params` is not valid UTF-8.
pub const BOUNDARY_ERR_UTF8: c_int = 6;
/// The method could not run on this input (the message says why), e.g. per-particle radii
/// given to a method that does not support them.
pub const BOUNDARY_ERR_DETECT: c_int = 7;
/// `out_margin` was given but the method reports no margin.
pub const BOUNDARY_ERR_NO_MARGIN: c_int = 8;
/// Worker threads could not be started.
pub const BOUNDARY_ERR_THREADS: c_int = 9;
/// A bug in the library was caught (a panic); please report the message.
pub const BOUNDARY_ERR_INTERNAL: c_int = 10;
/// The domain is invalid: a malformed solid or periodic text, walls of another dimension than
/// the particles, a particle outside a periodic range, a period shorter than the method's
/// reach, a solid on a periodic axis (the message names the option or the particle).
pub const BOUNDARY_ERR_DOMAIN: c_int = 11;

/// The factor `k` of `r = k * dp` for a particle spacing `dp` (`boundary_radius_from_spacing`,
/// the command line's `--spacing`): between the smoothing lengths SPH solvers use by default
/// (1.2 to 1.73 spacings); `boundary_auto_radius` applies it to the spacing it measures.
pub const BOUNDARY_RADIUS_PER_SPACING: f64 = 1.45;

// The header's value is the library's.
const _: () = assert!(BOUNDARY_RADIUS_PER_SPACING == boundary::RADIUS_PER_SPACING);

/// A detector created once (method and parameters parsed once) and used every time step.
/// Opaque: create with `boundary_detector_new`, release with `boundary_detector_free`.
#[allow(non_camel_case_types)] // the C type's name
#[derive(Debug)]
pub struct boundary_detector {
    detector: Box<dyn BoundaryDetector>,
    pool: Option<Arc<rayon::ThreadPool>>,
    /// Walls, solids and periodic axes (never phases: those come with each call).
    domain: Domain,
}

/// An error code with its message.
#[derive(Debug)]
struct Failure {
    code: c_int,
    message: String,
}

impl Failure {
    fn new(code: c_int, message: impl Into<String>) -> Self {
        Failure {
            code,
            message: message.into(),
        }
    }
}

/// The pool set by `boundary_set_threads`; `None`: rayon's global pool (all cores).
static DEFAULT_POOL: Mutex<Option<Arc<rayon::ThreadPool>>> = Mutex::new(None);

fn default_pool() -> Option<Arc<rayon::ThreadPool>> {
    // A poisoned lock only means a panic elsewhere while it was held; the value is intact.
    match DEFAULT_POOL.lock() {
        Ok(guard) => guard.clone(),
        Err(poisoned) => poisoned.into_inner().clone(),
    }
}

/// A pool of `threads` workers; 0: `None` (all cores).
fn make_pool(threads: usize) -> Result<Option<Arc<rayon::ThreadPool>>, Failure> {
    if threads == 0 {
        return Ok(None);
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map(|p| Some(Arc::new(p)))
        .map_err(|e| {
            Failure::new(
                BOUNDARY_ERR_THREADS,
                format!("cannot start worker threads: {e}"),
            )
        })
}

/// Writes `message` into `err[0..err_len]`, NUL-terminated, cut at a character boundary.
///
/// # Safety
/// `err` is NULL or valid for writes of `err_len` bytes.
unsafe fn write_message(err: *mut c_char, err_len: usize, message: &str) {
    if err.is_null() || err_len == 0 {
        return;
    }
    let mut len = message.len().min(err_len - 1);
    while !message.is_char_boundary(len) {
        len -= 1;
    }
    // SAFETY: the caller guarantees `err` is valid for `err_len` bytes; `len < err_len`.
    let out = unsafe { std::slice::from_raw_parts_mut(err.cast::<u8>(), err_len) };
    out[..len].copy_from_slice(&message.as_bytes()[..len]);
    out[len] = 0;
}

/// Runs `body`, catching any panic, and reports its outcome through `err`.
///
/// # Safety
/// `err` is NULL or valid for writes of `err_len` bytes.
unsafe fn guarded(
    err: *mut c_char,
    err_len: usize,
    body: impl FnOnce() -> Result<(), Failure>,
) -> c_int {
    let outcome = catch_unwind(AssertUnwindSafe(body)).unwrap_or_else(|payload| {
        let text = payload
            .downcast_ref::<&str>()
            .map(|s| (*s).to_owned())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown panic".to_owned());
        Err(Failure::new(
            BOUNDARY_ERR_INTERNAL,
            format!("internal error (please report it): {text}"),
        ))
    });
    let (code, message) = match outcome {
        Ok(()) => (BOUNDARY_OK, String::new()),
        Err(f) => (f.code, f.message),
    };
    // SAFETY: forwarded from the caller's contract.
    unsafe { write_message(err, err_len, &message) };
    code
}

/// A C string argument as UTF-8.
///
/// # Safety
/// `text` is NULL or points to a NUL-terminated string that lives for `'a`.
unsafe fn c_str<'a>(text: *const c_char, what: &str) -> Result<&'a str, Failure> {
    if text.is_null() {
        return Err(Failure::new(BOUNDARY_ERR_NULL, format!("{what} is NULL")));
    }
    // SAFETY: non-NULL and NUL-terminated by the caller's contract.
    let bytes = unsafe { CStr::from_ptr(text) };
    bytes
        .to_str()
        .map_err(|e| Failure::new(BOUNDARY_ERR_UTF8, format!("{what} is not UTF-8: {e}")))
}

/// The detector `method` with `params` (`"key=value,key=value"`, NULL or "" for none).
///
/// # Safety
/// `method` and `params` are NULL or NUL-terminated strings.
unsafe fn make_detector(
    method: *const c_char,
    params: *const c_char,
) -> Result<Box<dyn BoundaryDetector>, Failure> {
    // SAFETY: forwarded from the caller's contract.
    let method = unsafe { c_str(method, "method") }?;
    let params = if params.is_null() {
        Vec::new()
    } else {
        // SAFETY: non-NULL, forwarded from the caller's contract.
        let text = unsafe { c_str(params, "params") }?;
        parse_param_list(text)
            .map_err(|e| Failure::new(BOUNDARY_ERR_PARAM, format!("params: {e}")))?
    };
    detector_with_params(method, &params).map_err(|e| {
        let code = match e {
            boundary::RegistryError::UnknownMethod { .. } => BOUNDARY_ERR_METHOD,
            // A parameter error, or a kind of error added later: the parameters are at fault.
            _ => BOUNDARY_ERR_PARAM,
        };
        Failure::new(code, e.to_string())
    })
}

/// The particle set of `xyz[0..n*dim]`, validated (finite coordinates), with the radii
/// `radii[0..n]` when not NULL (validated: positive, finite, in range).
///
/// # Safety
/// `xyz` is NULL or valid for reads of `n * dim` doubles; `radii` NULL or valid for reads of
/// `n` doubles.
unsafe fn particle_set(
    xyz: *const f64,
    n: usize,
    dim: c_int,
    radii: *const f64,
) -> Result<AnyParticleSet, Failure> {
    let dim = match dim {
        2 => 2usize,
        3 => 3,
        other => {
            return Err(Failure::new(
                BOUNDARY_ERR_SIZE,
                format!("dim must be 2 or 3, got {other}"),
            ))
        }
    };
    let len = n
        .checked_mul(dim)
        .filter(|len| {
            len.checked_mul(size_of::<f64>())
                .is_some_and(|b| b <= isize::MAX as usize)
        })
        .ok_or_else(|| Failure::new(BOUNDARY_ERR_SIZE, format!("n = {n} particles is too many")))?;
    let coords: &[f64] = if n == 0 {
        &[]
    } else if xyz.is_null() {
        return Err(Failure::new(BOUNDARY_ERR_NULL, "xyz is NULL"));
    } else if xyz.align_offset(align_of::<f64>()) != 0 {
        return Err(Failure::new(
            BOUNDARY_ERR_SIZE,
            "xyz is not aligned for double",
        ));
    } else {
        // SAFETY: non-NULL, aligned, `len * 8 <= isize::MAX`, and valid for `len` doubles by
        // the caller's contract; only read while this call runs.
        unsafe { std::slice::from_raw_parts(xyz, len) }
    };
    fn build<const D: usize>(coords: &[f64]) -> Result<ParticleSet<D>, boundary::CoreError>
    where
        Dim<D>: SupportedDim,
    {
        ParticleSet::new(
            coords
                .chunks_exact(D)
                .map(Point::<D>::from_column_slice)
                .collect(),
        )
    }
    let set = if dim == 2 {
        build::<2>(coords).map(AnyParticleSet::from)
    } else {
        build::<3>(coords).map(AnyParticleSet::from)
    };
    let set = set.map_err(|e| Failure::new(BOUNDARY_ERR_INPUT, e.to_string()))?;
    if radii.is_null() {
        return Ok(set);
    }
    let values: Vec<f64> = if n == 0 {
        Vec::new()
    } else if radii.align_offset(align_of::<f64>()) != 0 {
        return Err(Failure::new(
            BOUNDARY_ERR_SIZE,
            "radii is not aligned for double",
        ));
    } else {
        // SAFETY: non-NULL, aligned, `n <= len` doubles fit in memory (checked above), valid
        // for `n` doubles by the caller's contract; copied while this call runs.
        unsafe { std::slice::from_raw_parts(radii, n) }.to_vec()
    };
    set.with_radii(values)
        .map_err(|e| Failure::new(BOUNDARY_ERR_INPUT, e.to_string()))
}

/// Refuses a flat 3D set (`BOUNDARY_ERR_INPUT`): with `dim` 3, every particle of it would be
/// boundary. Wall particles are not checked (a wall is often one plane of particles).
fn refuse_flat(set: &AnyParticleSet) -> Result<(), Failure> {
    let message = match set.flatness() {
        None => return Ok(()),
        Some(flatness @ Flatness::Plane { axis, .. }) => {
            let kept = match axis {
                2 => "x and y",
                1 => "x and z",
                _ => "y and z",
            };
            format!(
                "{flatness}: a flat set is 2D, and with dim = 3 every particle would be \
                 boundary; pass dim = 2 with the {kept} coordinates"
            )
        }
        Some(flatness) => {
            format!("{flatness}: the set has no extent, and every particle would be boundary")
        }
    };
    Err(Failure::new(BOUNDARY_ERR_INPUT, message))
}

/// With the smoothing length `h` as `r`, the SPH-sum methods (`marrone`, `muller`, `divr`,
/// `asymmetry`, `randles`) use `h` itself: a parameter `h_over_r` other than 1 (which would
/// make their smoothing length a multiple of `h`) is `BOUNDARY_ERR_PARAM`, as the command
/// line refuses it with `--smoothing-length`.
fn refuse_h_over_r(detector: &dyn BoundaryDetector, h: f64) -> Result<(), Failure> {
    for p in detector.describe().0 {
        let one = p.value.trim().parse::<f64>().is_ok_and(|v| v == 1.0);
        if p.name == "h_over_r" && !one {
            return Err(Failure::new(
                BOUNDARY_ERR_PARAM,
                format!(
                    "the smoothing length h = {h} is the SPH sums' h itself; h_over_r={v} would \
                     make it {v} x {h}: drop h_over_r, or pass r with it to boundary_detect",
                    v = p.value
                ),
            ));
        }
    }
    Ok(())
}

/// One double written to `out` (checked non-NULL and aligned) after every other check.
///
/// # Safety
/// `out` is NULL or valid for a write of one double.
unsafe fn out_double<'a>(out: *mut f64, what: &str) -> Result<&'a mut f64, Failure> {
    if out.is_null() {
        return Err(Failure::new(BOUNDARY_ERR_NULL, format!("{what} is NULL")));
    }
    if out.align_offset(align_of::<f64>()) != 0 {
        return Err(Failure::new(
            BOUNDARY_ERR_SIZE,
            format!("{what} is not aligned for double"),
        ));
    }
    // SAFETY: non-NULL, aligned, valid for one write by the caller's contract.
    Ok(unsafe { &mut *out })
}

/// A mutable output buffer of `n` elements; NULL is allowed only when `n == 0`.
///
/// # Safety
/// `out` is NULL or valid for writes of `n` elements, not aliased during the call.
unsafe fn out_slice<'a, T>(out: *mut T, n: usize, what: &str) -> Result<&'a mut [T], Failure> {
    if n == 0 {
        return Ok(&mut []);
    }
    if out.is_null() {
        return Err(Failure::new(BOUNDARY_ERR_NULL, format!("{what} is NULL")));
    }
    if out.align_offset(align_of::<T>()) != 0 {
        return Err(Failure::new(
            BOUNDARY_ERR_SIZE,
            format!("{what} is not aligned"),
        ));
    }
    // SAFETY: non-NULL, aligned, valid for `n` elements and unaliased by the caller's
    // contract (`n` elements fit in memory since the caller allocated them).
    Ok(unsafe { std::slice::from_raw_parts_mut(out, n) })
}

/// Runs `detector` on `set` in `domain` (with `phases` when given) in `pool` (rayon's global
/// pool when `None`): the free-surface detection and, with phases, the interface labels.
fn run(
    detector: &dyn BoundaryDetector,
    set: &AnyParticleSet,
    domain: &Domain,
    phases: Option<Vec<u32>>,
    r: f64,
    pool: Option<&rayon::ThreadPool>,
) -> Result<(Detection, Option<Labels>), Failure> {
    let r = Radius::new(r).map_err(|e| Failure::new(BOUNDARY_ERR_INPUT, e.to_string()))?;
    // Scaled radii out of range name the particle (an input error, like the unscaled ones).
    let resolved = |set: &AnyParticleSet| match set {
        AnyParticleSet::D2(s) => s.resolved_radii(r).map(drop),
        AnyParticleSet::D3(s) => s.resolved_radii(r).map(drop),
    };
    resolved(set).map_err(|e| Failure::new(BOUNDARY_ERR_INPUT, e.to_string()))?;
    if let Some(walls) = domain.walls() {
        resolved(walls).map_err(|e| Failure::new(BOUNDARY_ERR_INPUT, format!("walls: {e}")))?;
    }
    let detect = || -> Result<(Detection, Option<Labels>), DetectError> {
        let split = |d: boundary::DomainDetection| (d.detection, d.interface);
        match phases {
            None if domain.is_bare() => detector.detect(set, r).map(|d| (d, None)),
            None => detector.detect_in(set, domain, r).map(split),
            Some(phases) => detector
                .detect_in(set, &domain.clone().with_phases(phases), r)
                .map(split),
        }
    };
    match pool {
        Some(pool) => pool.install(detect),
        None => detect(),
    }
    .map_err(|e| {
        let code = match e {
            DetectError::Domain(_) => BOUNDARY_ERR_DOMAIN,
            _ => BOUNDARY_ERR_DETECT,
        };
        Failure::new(code, in_c_terms(&e))
    })
}

/// The library's names of the inputs a detection takes, with the function of this API that
/// gives each. The library names inputs in its own terms; the C API adds its function after
/// the first mention of each. Solid meshes have no function here.
const FUNCTIONS: &[(&str, &str)] = &[
    ("half-spaces", "boundary_detector_add_solid"),
    ("wall particles", "boundary_detector_set_walls"),
];

/// A detector's error message in the C API's spelling:
/// `solid half-spaces (boundary_detector_add_solid)`.
pub(crate) fn in_c_terms(error: &DetectError) -> String {
    let mut message = error.to_string();
    for (term, function) in FUNCTIONS {
        if let Some(at) = message.find(term) {
            message.insert_str(at + term.len(), &format!(" ({function})"));
        }
    }
    message
}

/// The phase numbers `phases[0..n]`, or `None` when `phases` is NULL.
///
/// # Safety
/// `phases` is NULL or valid for reads of `n` `uint32_t`, and `n` doubles fit in memory.
unsafe fn read_phases(phases: *const u32, n: usize) -> Result<Option<Vec<u32>>, Failure> {
    if phases.is_null() {
        return Ok(None);
    }
    if n == 0 {
        return Ok(Some(Vec::new()));
    }
    if phases.align_offset(align_of::<u32>()) != 0 {
        return Err(Failure::new(
            BOUNDARY_ERR_SIZE,
            "phases is not aligned for uint32_t",
        ));
    }
    // SAFETY: non-NULL, aligned, `n` values fit in memory (the caller checked `n` doubles do)
    // and are valid for reads by the caller's contract; copied while this call runs.
    Ok(Some(
        unsafe { std::slice::from_raw_parts(phases, n) }.to_vec(),
    ))
}

/// Where a detection goes and what it reads besides the particles.
struct Request<'a> {
    domain: &'a Domain,
    phases: *const u32,
    out_labels: *mut u8,
    out_interface: *mut u8,
    out_margin: *mut f64,
}

/// Detects and writes the labels (and the margin and the interface labels when asked);
/// nothing is written on error.
///
/// # Safety
/// As [`boundary_detector_detect_phases`]: `xyz` and `radii` as there, the pointers of
/// `request` as its `phases`, `out_labels`, `out_interface` and `out_margin`.
#[allow(clippy::too_many_arguments)]
unsafe fn detect_into(
    detector: &dyn BoundaryDetector,
    pool: Option<&rayon::ThreadPool>,
    xyz: *const f64,
    n: usize,
    dim: c_int,
    radii: *const f64,
    r: f64,
    request: &Request<'_>,
) -> Result<(), Failure> {
    // SAFETY: forwarded from the caller's contract.
    let set = unsafe { particle_set(xyz, n, dim, radii) }?;
    // SAFETY: forwarded from the caller's contract; `n` doubles fit (checked by particle_set).
    let phases = unsafe { read_phases(request.phases, n) }?;
    // SAFETY: forwarded from the caller's contract.
    let labels = unsafe { out_slice(request.out_labels, n, "out_labels") }?;
    let margin = if request.out_margin.is_null() {
        None
    } else {
        // SAFETY: non-NULL, forwarded from the caller's contract.
        Some(unsafe { out_slice(request.out_margin, n, "out_margin") }?)
    };
    let interface = match (&phases, request.out_interface.is_null()) {
        (None, true) => None,
        (None, false) => {
            return Err(Failure::new(
                BOUNDARY_ERR_NULL,
                "out_interface is given but phases is NULL (interfaces need phases)",
            ))
        }
        // SAFETY: forwarded from the caller's contract.
        (Some(_), _) => Some(unsafe { out_slice(request.out_interface, n, "out_interface") }?),
    };
    refuse_flat(&set)?;
    let (detection, found) = run(detector, &set, request.domain, phases, r, pool)?;
    // Every check before the first write.
    if margin.is_some() && detection.margin.is_none() {
        return Err(Failure::new(
            BOUNDARY_ERR_NO_MARGIN,
            format!(
                "method '{}' reports no margin (pass NULL as out_margin)",
                detector.name()
            ),
        ));
    }
    if interface.is_some() && found.is_none() {
        return Err(Failure::new(
            BOUNDARY_ERR_INTERNAL,
            "internal error (please report it): no interface labels with phases",
        ));
    }
    if let (Some(out), Some(values)) = (margin, &detection.margin) {
        out.copy_from_slice(values);
    }
    if let (Some(out), Some(found)) = (interface, &found) {
        for (out, &b) in out.iter_mut().zip(found.as_slice()) {
            *out = u8::from(b);
        }
    }
    for (out, &b) in labels.iter_mut().zip(detection.labels.as_slice()) {
        *out = u8::from(b);
    }
    Ok(())
}

/// The library's version, e.g. `"0.1.0"` (a static string; do not free it).
#[no_mangle]
pub extern "C" fn boundary_version() -> *const c_char {
    const VERSION: &CStr =
        match CStr::from_bytes_with_nul(concat!(env!("CARGO_PKG_VERSION"), "\0").as_bytes()) {
            Ok(v) => v,
            Err(_) => c"unknown",
        };
    VERSION.as_ptr()
}

/// Labels the `n` particles at `xyz` (`n * dim` doubles, `dim` 2 or 3) with resolution `r`
/// by `method` (`"exact"`, `"ge"`, ... as `boundary methods` lists them) with `params`
/// (`"key=value,key=value"` as `--set`, or NULL / `""`): `out_labels[i]` is 1 for a boundary
/// particle, 0 for an interior one. Returns `BOUNDARY_OK` or a `BOUNDARY_ERR_*` code with the
/// message in `err` (`err_len` bytes, may be NULL).
///
/// # Safety
/// `xyz` is valid for reads of `n * dim` doubles (may be NULL when `n == 0`); `out_labels`
/// valid for writes of `n` bytes; `method` and `params` NUL-terminated strings (or NULL);
/// `err` NULL or valid for writes of `err_len` bytes.
#[no_mangle]
#[allow(clippy::too_many_arguments)] // the C signature
pub unsafe extern "C" fn boundary_detect(
    xyz: *const f64,
    n: usize,
    dim: c_int,
    r: f64,
    method: *const c_char,
    params: *const c_char,
    out_labels: *mut u8,
    err: *mut c_char,
    err_len: usize,
) -> c_int {
    // SAFETY: this function's contract, with no radii (NULL: one radius for all).
    unsafe {
        boundary_detect_radii(
            xyz,
            n,
            dim,
            std::ptr::null(),
            r,
            method,
            params,
            out_labels,
            err,
            err_len,
        )
    }
}

/// `boundary_detect` with a radius per particle: `radii` holds `n` doubles, the factor `s_i`
/// of particle `i` (or is NULL: one radius `r` for all, as `boundary_detect`), and particle
/// `i` gets the radius `r_i = r * s_i` (`r = 1`: the radii as given). A radius that is not
/// positive and finite, or leaves 1e-100..=1e100 once scaled, is `BOUNDARY_ERR_INPUT` with a
/// message naming the particle (`particle 3: radius must be positive and finite, got -1`); a
/// method that does not support per-particle radii returns `BOUNDARY_ERR_DETECT`.
///
/// # Safety
/// As `boundary_detect`; `radii` NULL or valid for reads of `n` doubles.
#[no_mangle]
#[allow(clippy::too_many_arguments)] // the C signature
pub unsafe extern "C" fn boundary_detect_radii(
    xyz: *const f64,
    n: usize,
    dim: c_int,
    radii: *const f64,
    r: f64,
    method: *const c_char,
    params: *const c_char,
    out_labels: *mut u8,
    err: *mut c_char,
    err_len: usize,
) -> c_int {
    let body = || {
        // SAFETY: forwarded from this function's contract.
        let detector = unsafe { make_detector(method, params) }?;
        let pool = default_pool();
        let request = Request {
            domain: &Domain::new(),
            phases: std::ptr::null(),
            out_labels,
            out_interface: std::ptr::null_mut(),
            out_margin: std::ptr::null_mut(),
        };
        // SAFETY: forwarded from this function's contract.
        unsafe {
            detect_into(
                detector.as_ref(),
                pool.as_deref(),
                xyz,
                n,
                dim,
                radii,
                r,
                &request,
            )
        }
    };
    // SAFETY: forwarded from this function's contract.
    unsafe { guarded(err, err_len, body) }
}

/// The smoothing length `h` as the resolution, checked: positive and finite
/// (`BOUNDARY_ERR_INPUT`).
fn smoothing_length(h: f64) -> Result<f64, Failure> {
    Radius::new(h)
        .map(Radius::get)
        .map_err(|e| Failure::new(BOUNDARY_ERR_INPUT, format!("smoothing length h: {e}")))
}

/// `boundary_detect` with the smoothing length `h` of an SPH solver instead of `r`: `r = h`
/// (the definition's resolution is the smoothing length; the command line's
/// `--smoothing-length`), and the SPH-sum methods (`marrone`, `muller`, `divr`, `asymmetry`,
/// `randles`) use `h` itself as their smoothing length. The labels are those of
/// `boundary_detect` with `r = h`. `params` setting `h_over_r` other than 1 (which would make
/// the sums' smoothing length a multiple of `h`) is `BOUNDARY_ERR_PARAM`; `h` not positive and
/// finite is `BOUNDARY_ERR_INPUT`.
///
/// # Safety
/// As `boundary_detect`.
#[no_mangle]
#[allow(clippy::too_many_arguments)] // the C signature
pub unsafe extern "C" fn boundary_detect_h(
    xyz: *const f64,
    n: usize,
    dim: c_int,
    h: f64,
    method: *const c_char,
    params: *const c_char,
    out_labels: *mut u8,
    err: *mut c_char,
    err_len: usize,
) -> c_int {
    let body = || {
        let r = smoothing_length(h)?;
        // SAFETY: forwarded from this function's contract.
        let detector = unsafe { make_detector(method, params) }?;
        refuse_h_over_r(detector.as_ref(), h)?;
        let pool = default_pool();
        let request = Request {
            domain: &Domain::new(),
            phases: std::ptr::null(),
            out_labels,
            out_interface: std::ptr::null_mut(),
            out_margin: std::ptr::null_mut(),
        };
        // SAFETY: forwarded from this function's contract, with no radii.
        unsafe {
            detect_into(
                detector.as_ref(),
                pool.as_deref(),
                xyz,
                n,
                dim,
                std::ptr::null(),
                r,
                &request,
            )
        }
    };
    // SAFETY: forwarded from this function's contract.
    unsafe { guarded(err, err_len, body) }
}

/// Creates a detector for repeated use: `method` with `params` as in `boundary_detect`,
/// parsed once. Returns NULL on error, with the message in `err`. Release it with
/// `boundary_detector_free`.
///
/// # Safety
/// `method` and `params` are NUL-terminated strings (or NULL); `err` NULL or valid for writes
/// of `err_len` bytes.
#[no_mangle]
pub unsafe extern "C" fn boundary_detector_new(
    method: *const c_char,
    params: *const c_char,
    err: *mut c_char,
    err_len: usize,
) -> *mut boundary_detector {
    let mut handle = std::ptr::null_mut();
    let body = || {
        // SAFETY: forwarded from this function's contract.
        let detector = unsafe { make_detector(method, params) }?;
        handle = Box::into_raw(Box::new(boundary_detector {
            detector,
            pool: None,
            domain: Domain::new(),
        }));
        Ok(())
    };
    // SAFETY: forwarded from this function's contract.
    unsafe { guarded(err, err_len, body) };
    handle
}

/// Labels the `n` particles at `xyz` with the detector `handle` (as `boundary_detect`, in the
/// handle's domain when it has walls, solids or periodic axes); when `out_margin` is not NULL,
/// also writes the method's per-particle margin there (`n` doubles; positive leans boundary;
/// `BOUNDARY_ERR_NO_MARGIN` if the method has none).
///
/// # Safety
/// `handle` comes from `boundary_detector_new` and is not freed nor used by another thread
/// during the call; `xyz` is valid for reads of `n * dim` doubles (may be NULL when `n == 0`);
/// `out_labels` valid for writes of `n` bytes; `out_margin` NULL or valid for writes of `n`
/// doubles; `err` NULL or valid for writes of `err_len` bytes.
#[no_mangle]
#[allow(clippy::too_many_arguments)] // the C signature
pub unsafe extern "C" fn boundary_detector_detect(
    handle: *const boundary_detector,
    xyz: *const f64,
    n: usize,
    dim: c_int,
    r: f64,
    out_labels: *mut u8,
    out_margin: *mut f64,
    err: *mut c_char,
    err_len: usize,
) -> c_int {
    // SAFETY: this function's contract, with no radii (NULL: one radius for all).
    unsafe {
        boundary_detector_detect_radii(
            handle,
            xyz,
            n,
            dim,
            std::ptr::null(),
            r,
            out_labels,
            out_margin,
            err,
            err_len,
        )
    }
}

/// `boundary_detector_detect` with the smoothing length `h` instead of `r` (`r = h`, as
/// `boundary_detect_h`): the labels are those of `boundary_detector_detect` with `r = h`. A
/// handle whose method has `h_over_r` other than 1 is `BOUNDARY_ERR_PARAM` (the SPH sums would
/// not use `h`); `h` not positive and finite is `BOUNDARY_ERR_INPUT`. With per-particle radii
/// or phases, pass `r = h` to `boundary_detector_detect_radii` / `_phases` (a handle created
/// without `h_over_r` uses `h` itself).
///
/// # Safety
/// As `boundary_detector_detect`.
#[no_mangle]
#[allow(clippy::too_many_arguments)] // the C signature
pub unsafe extern "C" fn boundary_detector_detect_h(
    handle: *const boundary_detector,
    xyz: *const f64,
    n: usize,
    dim: c_int,
    h: f64,
    out_labels: *mut u8,
    out_margin: *mut f64,
    err: *mut c_char,
    err_len: usize,
) -> c_int {
    let body = || {
        // SAFETY: NULL or a live handle from `boundary_detector_new` (this function's contract).
        let handle = unsafe { handle.as_ref() }
            .ok_or_else(|| Failure::new(BOUNDARY_ERR_NULL, "handle is NULL"))?;
        let r = smoothing_length(h)?;
        refuse_h_over_r(handle.detector.as_ref(), h)?;
        let pool = handle.pool.clone().or_else(default_pool);
        let request = Request {
            domain: &handle.domain,
            phases: std::ptr::null(),
            out_labels,
            out_interface: std::ptr::null_mut(),
            out_margin,
        };
        // SAFETY: forwarded from this function's contract, with no radii.
        unsafe {
            detect_into(
                handle.detector.as_ref(),
                pool.as_deref(),
                xyz,
                n,
                dim,
                std::ptr::null(),
                r,
                &request,
            )
        }
    };
    // SAFETY: forwarded from this function's contract.
    unsafe { guarded(err, err_len, body) }
}

/// `boundary_detector_detect` with a radius per particle: `radii` (`n` doubles or NULL) as in
/// `boundary_detect_radii`, `r_i = r * s_i`.
///
/// # Safety
/// As `boundary_detector_detect`; `radii` NULL or valid for reads of `n` doubles.
#[no_mangle]
#[allow(clippy::too_many_arguments)] // the C signature
pub unsafe extern "C" fn boundary_detector_detect_radii(
    handle: *const boundary_detector,
    xyz: *const f64,
    n: usize,
    dim: c_int,
    radii: *const f64,
    r: f64,
    out_labels: *mut u8,
    out_margin: *mut f64,
    err: *mut c_char,
    err_len: usize,
) -> c_int {
    // SAFETY: this function's contract, with no phases (NULL) and so no interface labels.
    unsafe {
        boundary_detector_detect_phases(
            handle,
            xyz,
            n,
            dim,
            radii,
            r,
            std::ptr::null(),
            out_labels,
            std::ptr::null_mut(),
            out_margin,
            err,
            err_len,
        )
    }
}

/// `boundary_detector_detect_radii` with a phase number per particle: `phases` holds `n`
/// values (or is NULL: one phase, as `boundary_detector_detect_radii`). With phases,
/// `out_labels[i]` is 1 for a particle on the free surface (uncovered by the particles of
/// every phase, the walls and the solids) and `out_interface[i]` (`n` bytes, required with
/// phases) is 1 for a particle on an interface between phases: not on the free surface, but
/// uncovered once only its own phase, the walls and the solids may cover. Nothing is written
/// on error; `out_interface` without `phases` is `BOUNDARY_ERR_NULL`.
///
/// # Safety
/// As `boundary_detector_detect_radii`; `phases` NULL or valid for reads of `n` `uint32_t`;
/// `out_interface` NULL or valid for writes of `n` bytes.
#[no_mangle]
#[allow(clippy::too_many_arguments)] // the C signature
pub unsafe extern "C" fn boundary_detector_detect_phases(
    handle: *const boundary_detector,
    xyz: *const f64,
    n: usize,
    dim: c_int,
    radii: *const f64,
    r: f64,
    phases: *const u32,
    out_labels: *mut u8,
    out_interface: *mut u8,
    out_margin: *mut f64,
    err: *mut c_char,
    err_len: usize,
) -> c_int {
    let body = || {
        // SAFETY: NULL or a live handle from `boundary_detector_new` (this function's contract).
        let handle = unsafe { handle.as_ref() }
            .ok_or_else(|| Failure::new(BOUNDARY_ERR_NULL, "handle is NULL"))?;
        let pool = handle.pool.clone().or_else(default_pool);
        let request = Request {
            domain: &handle.domain,
            phases,
            out_labels,
            out_interface,
            out_margin,
        };
        // SAFETY: forwarded from this function's contract.
        unsafe {
            detect_into(
                handle.detector.as_ref(),
                pool.as_deref(),
                xyz,
                n,
                dim,
                radii,
                r,
                &request,
            )
        }
    };
    // SAFETY: forwarded from this function's contract.
    unsafe { guarded(err, err_len, body) }
}

/// Runs `change` on the domain of `handle`, reporting through `err`.
///
/// # Safety
/// `handle` is NULL or comes from `boundary_detector_new`, not freed nor used by another
/// thread during the call; `err` NULL or valid for writes of `err_len` bytes.
unsafe fn change_domain(
    handle: *mut boundary_detector,
    err: *mut c_char,
    err_len: usize,
    change: impl FnOnce(Domain) -> Result<Domain, Failure>,
) -> c_int {
    let body = || {
        // SAFETY: NULL or a live, unaliased handle (the caller's contract).
        let handle = unsafe { handle.as_mut() }
            .ok_or_else(|| Failure::new(BOUNDARY_ERR_NULL, "handle is NULL"))?;
        // On error the domain stays as it was.
        handle.domain = change(handle.domain.clone())?;
        Ok(())
    };
    // SAFETY: forwarded from the caller's contract.
    unsafe { guarded(err, err_len, body) }
}

/// The solids and periodic axes of `domain`, without its walls.
fn without_walls(domain: &Domain) -> Domain {
    let mut out = Domain::new();
    for &h in domain.solids().half_spaces() {
        out = out.with_solid(h);
    }
    for &p in domain.periodic() {
        out = out.with_periodic(p);
    }
    out
}

/// `domain` with the walls `xyz` (`m * dim` doubles, `radii` NULL or `m` factors) in place of
/// its own; `m == 0` removes them. The change of `*_set_walls`.
///
/// # Safety
/// As `boundary_detector_set_walls` for `xyz` and `radii`.
pub(crate) unsafe fn domain_with_walls(
    domain: &Domain,
    xyz: *const f64,
    m: usize,
    dim: c_int,
    radii: *const f64,
) -> Result<Domain, Failure> {
    if m == 0 {
        return Ok(without_walls(domain));
    }
    // SAFETY: forwarded from this function's contract.
    let walls = unsafe { particle_set(xyz, m, dim, radii) }.map_err(|f| Failure {
        code: f.code,
        message: format!("walls: {}", f.message),
    })?;
    Ok(domain.clone().with_walls(walls))
}

/// `domain` with the solid half-space `text` (`"y<0"`) added. The change of `*_add_solid`.
///
/// # Safety
/// `text` is NULL or a NUL-terminated string.
pub(crate) unsafe fn domain_with_solid(
    domain: Domain,
    text: *const c_char,
) -> Result<Domain, Failure> {
    // SAFETY: forwarded from this function's contract.
    let text = unsafe { c_str(text, "solid") }?;
    let solid =
        HalfSpace::parse(text).map_err(|e| Failure::new(BOUNDARY_ERR_DOMAIN, e.to_string()))?;
    Ok(domain.with_solid(solid))
}

/// `domain` with the periodic axis `text` (`"x:0:1.5"`) added. The change of
/// `*_add_periodic`.
///
/// # Safety
/// `text` is NULL or a NUL-terminated string.
pub(crate) unsafe fn domain_with_periodic(
    domain: Domain,
    text: *const c_char,
) -> Result<Domain, Failure> {
    // SAFETY: forwarded from this function's contract.
    let text = unsafe { c_str(text, "periodic") }?;
    let axis =
        Periodic::parse(text).map_err(|e| Failure::new(BOUNDARY_ERR_DOMAIN, e.to_string()))?;
    Ok(domain.with_periodic(axis))
}

/// Sets the walls of `handle`: `m` covering-only particles at `xyz` (`m * dim` doubles, `dim`
/// 2 or 3, that of the particles to come), which cover the particles every detection by this
/// handle labels but get no label themselves; set them once, as a solver's fixed boundary
/// particles. `radii` is NULL or holds `m` radius factors (`r_i = r * s_i`, as the particles'
/// own; walls without radii have the factor 1 beside particles with radii). Replaces walls set
/// before; `m == 0` removes them. A non-finite coordinate or a bad radius is
/// `BOUNDARY_ERR_INPUT` naming the wall particle, and leaves the walls unchanged.
///
/// # Safety
/// `handle` is NULL or comes from `boundary_detector_new`, not freed nor used by another
/// thread during the call; `xyz` valid for reads of `m * dim` doubles (may be NULL when
/// `m == 0`); `radii` NULL or valid for reads of `m` doubles; `err` NULL or valid for writes
/// of `err_len` bytes. The library copies the walls: the buffers may be freed afterwards.
#[no_mangle]
#[allow(clippy::too_many_arguments)] // the C signature
pub unsafe extern "C" fn boundary_detector_set_walls(
    handle: *mut boundary_detector,
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

/// Adds a closed solid half-space to the domain of `handle`: `text` is an axis `x|y|z`, `<`
/// or `>` and a number (`"y<0"`: the solid `{y <= 0}` below a floor; spaces allowed). The
/// solid covers what lies in it (a sphere wholly inside is interior). A malformed text is
/// `BOUNDARY_ERR_DOMAIN` quoting it; a method that cannot honour solids returns
/// `BOUNDARY_ERR_DETECT` at detection, saying so.
///
/// # Safety
/// `handle` is NULL or comes from `boundary_detector_new`, not freed nor used by another
/// thread during the call; `text` a NUL-terminated string (or NULL); `err` NULL or valid for
/// writes of `err_len` bytes.
#[no_mangle]
pub unsafe extern "C" fn boundary_detector_add_solid(
    handle: *mut boundary_detector,
    text: *const c_char,
    err: *mut c_char,
    err_len: usize,
) -> c_int {
    // SAFETY: forwarded from this function's contract.
    let change = |domain: Domain| unsafe { domain_with_solid(domain, text) };
    // SAFETY: forwarded from this function's contract.
    unsafe { change_domain(handle, err, err_len, change) }
}

/// Adds a periodic axis to the domain of `handle`: `text` is `AXIS:MIN:MAX` (`"x:0:1.5"`):
/// particles (and walls) leaving `MAX` re-enter at `MIN`, and their images cover. Every
/// particle must then lie in `[MIN, MAX]`, and the period must be at least the method's
/// reach (both checked at detection, `BOUNDARY_ERR_DOMAIN`). A malformed text is
/// `BOUNDARY_ERR_DOMAIN` quoting it.
///
/// # Safety
/// As `boundary_detector_add_solid`.
#[no_mangle]
pub unsafe extern "C" fn boundary_detector_add_periodic(
    handle: *mut boundary_detector,
    text: *const c_char,
    err: *mut c_char,
    err_len: usize,
) -> c_int {
    // SAFETY: forwarded from this function's contract.
    let change = |domain: Domain| unsafe { domain_with_periodic(domain, text) };
    // SAFETY: forwarded from this function's contract.
    unsafe { change_domain(handle, err, err_len, change) }
}

/// Removes the walls, solids and periodic axes of `handle`: its detections are those of the
/// bare particle cloud again.
///
/// # Safety
/// `handle` is NULL or comes from `boundary_detector_new`, not freed nor used by another
/// thread during the call; `err` NULL or valid for writes of `err_len` bytes.
#[no_mangle]
pub unsafe extern "C" fn boundary_detector_clear_domain(
    handle: *mut boundary_detector,
    err: *mut c_char,
    err_len: usize,
) -> c_int {
    // SAFETY: forwarded from this function's contract.
    unsafe { change_domain(handle, err, err_len, |_| Ok(Domain::new())) }
}

/// Sets the number of worker threads of `handle` (0: back to the default of
/// `boundary_set_threads`).
///
/// # Safety
/// `handle` is NULL or comes from `boundary_detector_new`, not freed nor used by another
/// thread during the call; `err` NULL or valid for writes of `err_len` bytes.
#[no_mangle]
pub unsafe extern "C" fn boundary_detector_set_threads(
    handle: *mut boundary_detector,
    threads: usize,
    err: *mut c_char,
    err_len: usize,
) -> c_int {
    let body = || {
        // SAFETY: NULL or a live, unaliased handle (this function's contract).
        let handle = unsafe { handle.as_mut() }
            .ok_or_else(|| Failure::new(BOUNDARY_ERR_NULL, "handle is NULL"))?;
        handle.pool = make_pool(threads)?;
        Ok(())
    };
    // SAFETY: forwarded from this function's contract.
    unsafe { guarded(err, err_len, body) }
}

/// Releases a detector from `boundary_detector_new`; NULL is ignored.
///
/// # Safety
/// `handle` is NULL or comes from `boundary_detector_new` and is not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn boundary_detector_free(handle: *mut boundary_detector) {
    if handle.is_null() {
        return;
    }
    // Dropping a detector does not panic; the guard keeps unwinding out of C all the same.
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: `handle` came from `Box::into_raw` in `boundary_detector_new` and is
        // released once (this function's contract).
        drop(unsafe { Box::from_raw(handle) });
    }));
}

/// Sets the number of worker threads used by `boundary_detect` and by handles without their
/// own (0: all cores, the initial setting). Returns `BOUNDARY_OK` or
/// `BOUNDARY_ERR_THREADS`.
///
/// # Safety
/// `err` is NULL or valid for writes of `err_len` bytes.
#[no_mangle]
pub unsafe extern "C" fn boundary_set_threads(
    threads: usize,
    err: *mut c_char,
    err_len: usize,
) -> c_int {
    let body = || {
        let pool = make_pool(threads)?;
        match DEFAULT_POOL.lock() {
            Ok(mut guard) => *guard = pool,
            Err(poisoned) => *poisoned.into_inner() = pool,
        }
        Ok(())
    };
    // SAFETY: forwarded from this function's contract.
    unsafe { guarded(err, err_len, body) }
}

/// The resolution for a particle spacing `dp` (the solver's initial spacing, `dp`, `dx`,
/// particle diameter): `*out_r = BOUNDARY_RADIUS_PER_SPACING * dp`, as the command line's
/// `--spacing`. `dp` not positive and finite, or an `r` outside 1e-100..=1e100, is
/// `BOUNDARY_ERR_INPUT`; `*out_r` is written only on success.
///
/// # Safety
/// `out_r` is NULL or valid for a write of one double; `err` NULL or valid for writes of
/// `err_len` bytes.
#[no_mangle]
pub unsafe extern "C" fn boundary_radius_from_spacing(
    spacing: f64,
    out_r: *mut f64,
    err: *mut c_char,
    err_len: usize,
) -> c_int {
    let body = || {
        // SAFETY: forwarded from this function's contract.
        let out = unsafe { out_double(out_r, "out_r") }?;
        let r = radius_from_spacing(spacing)
            .map_err(|e| Failure::new(BOUNDARY_ERR_INPUT, format!("spacing: {e}")))?;
        *out = r.get();
        Ok(())
    };
    // SAFETY: forwarded from this function's contract.
    unsafe { guarded(err, err_len, body) }
}

/// The particle set of `xyz` for the spacing functions, refusing a flat 3D set.
///
/// # Safety
/// As [`particle_set`] without radii.
unsafe fn spacing_set(xyz: *const f64, n: usize, dim: c_int) -> Result<AnyParticleSet, Failure> {
    // SAFETY: forwarded from the caller's contract, with no radii.
    let set = unsafe { particle_set(xyz, n, dim, std::ptr::null()) }?;
    refuse_flat(&set)?;
    Ok(set)
}

/// Runs `job` on the pool of `boundary_set_threads` (rayon's global pool by default).
fn in_default_pool<T: Send>(job: impl FnOnce() -> T + Send) -> T {
    match default_pool() {
        Some(pool) => pool.install(job),
        None => job(),
    }
}

/// The particle spacing `dp` of the `n` particles at `xyz` (`n * dim` doubles) as a solver
/// defines it: the side of the volume (area in 2D) per particle in the bulk of the set,
/// `dp = (V / N)^(1/dim)`, which jitter, disorder and compression at constant volume do not
/// shrink (the library's `boundary::bulk_spacing`). Written to `*out_spacing` on success.
/// Fewer than two distinct positions, a non-finite coordinate or a flat 3D set is
/// `BOUNDARY_ERR_INPUT`.
///
/// # Safety
/// `xyz` is valid for reads of `n * dim` doubles (may be NULL when `n == 0`); `out_spacing`
/// NULL or valid for a write of one double; `err` NULL or valid for writes of `err_len` bytes.
#[no_mangle]
pub unsafe extern "C" fn boundary_bulk_spacing(
    xyz: *const f64,
    n: usize,
    dim: c_int,
    out_spacing: *mut f64,
    err: *mut c_char,
    err_len: usize,
) -> c_int {
    let body = || {
        // SAFETY: forwarded from this function's contract.
        let set = unsafe { spacing_set(xyz, n, dim) }?;
        // SAFETY: forwarded from this function's contract.
        let out = unsafe { out_double(out_spacing, "out_spacing") }?;
        let spacing = in_default_pool(|| bulk_spacing(&set))
            .map_err(|e| Failure::new(BOUNDARY_ERR_INPUT, e.to_string()))?
            .ok_or_else(|| {
                Failure::new(
                    BOUNDARY_ERR_INPUT,
                    "the particle spacing needs at least two distinct particle positions",
                )
            })?;
        *out = spacing;
        Ok(())
    };
    // SAFETY: forwarded from this function's contract.
    unsafe { guarded(err, err_len, body) }
}

/// The resolution estimated from the particles, as `boundary detect --radius auto`:
/// `*out_r = BOUNDARY_RADIUS_PER_SPACING * dp` for the spacing `dp` of
/// `boundary_bulk_spacing`, also written to `*out_spacing` unless it is NULL. An estimate, the
/// fallback when the solver's smoothing length or spacing is not known. Errors as
/// `boundary_bulk_spacing`; nothing is written on error.
///
/// # Safety
/// As `boundary_bulk_spacing`; `out_r` NULL or valid for a write of one double,
/// `out_spacing` NULL or valid for a write of one double, not the same as `out_r`.
#[no_mangle]
pub unsafe extern "C" fn boundary_auto_radius(
    xyz: *const f64,
    n: usize,
    dim: c_int,
    out_r: *mut f64,
    out_spacing: *mut f64,
    err: *mut c_char,
    err_len: usize,
) -> c_int {
    let body = || {
        // SAFETY: forwarded from this function's contract.
        let set = unsafe { spacing_set(xyz, n, dim) }?;
        // SAFETY: forwarded from this function's contract.
        let out = unsafe { out_double(out_r, "out_r") }?;
        let spacing = if out_spacing.is_null() {
            None
        } else {
            // SAFETY: non-NULL, forwarded from this function's contract.
            Some(unsafe { out_double(out_spacing, "out_spacing") }?)
        };
        let auto = in_default_pool(|| auto_radius(&set))
            .map_err(|e| Failure::new(BOUNDARY_ERR_INPUT, e.to_string()))?
            .ok_or_else(|| {
                Failure::new(
                    BOUNDARY_ERR_INPUT,
                    "the estimated radius needs at least two distinct particle positions",
                )
            })?;
        *out = auto.radius.get();
        if let Some(spacing) = spacing {
            *spacing = auto.spacing;
        }
        Ok(())
    };
    // SAFETY: forwarded from this function's contract.
    unsafe { guarded(err, err_len, body) }
}

/// Confusion counts and rates of predicted labels against the truth, boundary the positive
/// class: the keys of `boundary score --json` and of Python's `confusion`. A rate whose
/// denominator is zero is 0.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct boundary_confusion {
    /// Boundary in both.
    pub tp: u64,
    /// Interior in both.
    pub tn: u64,
    /// Predicted boundary, truly interior.
    pub fp: u64,
    /// Predicted interior, truly boundary.
    pub r#fn: u64,
    /// `tp / (tp + fn)`.
    pub recall: f64,
    /// `fp / (fp + tn)`.
    pub fpr: f64,
    /// `recall * (1 - fpr)` (J. Comput. Phys. 2020, Sec. 4).
    pub m: f64,
    /// `tp / (tp + fp)`.
    pub precision: f64,
    /// The harmonic mean of precision and recall.
    pub f1: f64,
}

/// Scores `n` predicted labels against `n` truth labels (1 boundary, 0 interior, as
/// `boundary_detect` writes them) into `*out`. Returns `BOUNDARY_OK`, `BOUNDARY_ERR_NULL`, or
/// `BOUNDARY_ERR_INPUT` for a label other than 0 or 1 (the message names the array and the
/// particle); `*out` is written only on success.
///
/// # Safety
/// `predicted` and `truth` are valid for reads of `n` bytes (may be NULL when `n == 0`);
/// `out` is valid for a write of one `boundary_confusion`; `err` is NULL or valid for writes
/// of `err_len` bytes.
#[no_mangle]
pub unsafe extern "C" fn boundary_confusion_from_labels(
    predicted: *const u8,
    truth: *const u8,
    n: usize,
    out: *mut boundary_confusion,
    err: *mut c_char,
    err_len: usize,
) -> c_int {
    let body = || {
        let labels = |values: *const u8, what: &str| -> Result<Vec<bool>, Failure> {
            if n == 0 {
                return Ok(Vec::new());
            }
            if values.is_null() {
                return Err(Failure::new(BOUNDARY_ERR_NULL, format!("{what} is NULL")));
            }
            // SAFETY: non-NULL and valid for reads of `n` bytes by this function's contract;
            // bytes need no alignment; only read while this call runs.
            let bytes = unsafe { std::slice::from_raw_parts(values, n) };
            bytes
                .iter()
                .enumerate()
                .map(|(i, &b)| match b {
                    0 => Ok(false),
                    1 => Ok(true),
                    other => Err(Failure::new(
                        BOUNDARY_ERR_INPUT,
                        format!("{what}: particle {i}: a label must be 0 or 1, got {other}"),
                    )),
                })
                .collect()
        };
        // SAFETY: NULL or valid for one write (this function's contract).
        let out = unsafe { out.as_mut() }
            .ok_or_else(|| Failure::new(BOUNDARY_ERR_NULL, "out is NULL"))?;
        let predicted = labels(predicted, "predicted")?;
        let truth = labels(truth, "truth")?;
        let c = boundary::Confusion::from_labels(&predicted, &truth)
            .map_err(|e| Failure::new(BOUNDARY_ERR_INPUT, e.to_string()))?;
        *out = boundary_confusion {
            tp: c.tp,
            tn: c.tn,
            fp: c.fp,
            r#fn: c.fn_,
            recall: c.recall(),
            fpr: c.fpr(),
            m: c.m(),
            precision: c.precision(),
            f1: c.f1(),
        };
        Ok(())
    };
    // SAFETY: forwarded from this function's contract.
    unsafe { guarded(err, err_len, body) }
}
