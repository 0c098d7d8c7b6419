//! Test helpers: small sets, the shared data folder, reading from bytes.
#![allow(dead_code)]
#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_core::{AnyParticleSet, ParticleSet};
use boundary_io::{read_particles_from, Format, IoError, ReadOptions};
use std::path::PathBuf;

/// A 2D set whose coordinates need full precision to round-trip.
pub fn set2() -> AnyParticleSet {
    ParticleSet::from_rows(&[
        [0.1, -2.5],
        [1e-7, 3.0e5],
        [1.0 / 3.0, 7.0],
        [-0.0, 1e300],
        [5e-324, -123456.789],
    ])
    .unwrap()
    .to_any()
}

/// A 3D set whose coordinates need full precision to round-trip.
pub fn set3() -> AnyParticleSet {
    ParticleSet::from_rows(&[
        [0.1, -2.5, 1.0],
        [1e6 + 0.01, 2.0, -0.0],
        [0.2, 0.7, 1e-12],
        [std::f64::consts::PI, -std::f64::consts::E, 2.0f64.sqrt()],
        [1e16 - 2.0, 1e16, -1e-5],
    ])
    .unwrap()
    .to_any()
}

/// Reads `bytes` as `format` under the name `name`.
pub fn read_bytes(
    bytes: &[u8],
    name: &str,
    format: Format,
    dim: Option<usize>,
) -> Result<AnyParticleSet, IoError> {
    read_particles_from(bytes, name, format, &ReadOptions { dim, format: None })
}

/// The shared data directory: `$BOUNDARY_DATA_DIR`, else `<workspace>/../shared/data`.
pub fn data_dir() -> PathBuf {
    if let Ok(dir) = std::env::var("BOUNDARY_DATA_DIR") {
        return PathBuf::from(dir);
    }
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data")
}

/// Bitwise equality of two sets (distinguishes -0.0 from 0.0).
pub fn same_bits(a: &AnyParticleSet, b: &AnyParticleSet) -> bool {
    a.dim() == b.dim()
        && a.len() == b.len()
        && (0..a.len()).all(|i| {
            a.coords(i)
                .iter()
                .zip(b.coords(i))
                .all(|(x, y)| x.to_bits() == y.to_bits())
        })
}
