//! Test helpers: locate `../shared/data` and read its CSVs with a few lines of parsing (the IO
//! crate is not a dependency of the method crates), plus small scene builders.
#![allow(dead_code)]
#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_core::{ParticleSet, Point};
use std::path::PathBuf;

/// The shared data directory: `$BOUNDARY_DATA_DIR`, else `<workspace>/../shared/data`.
pub fn data_dir() -> PathBuf {
    if let Ok(dir) = std::env::var("BOUNDARY_DATA_DIR") {
        return PathBuf::from(dir);
    }
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data")
}

/// Reads a CSV with a header line (`x,y` or `x,y,z`) and one particle per line.
pub fn read_csv<const D: usize>(rel: &str) -> ParticleSet<D> {
    let path = data_dir().join(rel);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        panic!(
            "cannot read {} ({e}); set BOUNDARY_DATA_DIR to the shared data folder",
            path.display()
        )
    });
    let mut lines = text.lines();
    let header = lines.next().unwrap_or_default();
    assert_eq!(header.split(',').count(), D, "{rel}: header '{header}'");
    let points = lines
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(k, l)| {
            let v: Vec<f64> = l
                .split(',')
                .map(|f| {
                    f.trim()
                        .parse()
                        .unwrap_or_else(|e| panic!("{rel}:{}: '{f}': {e}", k + 2))
                })
                .collect();
            assert_eq!(v.len(), D, "{rel}:{}: {} fields", k + 2, v.len());
            Point::<D>::from_fn(|c, _| v[c])
        })
        .collect();
    ParticleSet::new(points).unwrap()
}

/// The table of `../shared/data/README.md`: file, dimension, r, boundary count.
pub const SHARED_SCENES: &[(&str, usize, f64, usize)] = &[
    (
        "particles2d/dualsphysics_dambreak2d_dp0.02_fluid_4416.csv",
        2,
        0.0283,
        280,
    ),
    (
        "particles2d/sandim_vortex_spin_frame_001_1698.csv",
        2,
        0.022105,
        202,
    ),
    (
        "particles2d/sandim_vortex_spin_frame_050_1698.csv",
        2,
        0.022105,
        239,
    ),
    (
        "particles2d/sandim_vortex_spin_frame_100_1698.csv",
        2,
        0.022105,
        437,
    ),
    (
        "particles3d/dualsphysics_dambreak3d_dp0.02_fluid.csv",
        3,
        0.0346,
        2580,
    ),
    (
        "particles3d/pysph_sphysics_case5_dambreak_initial_fluid_15827.csv",
        3,
        0.0253,
        4931,
    ),
    (
        "particles3d/pysplashsurf_ParticleData_Fluid_50_4732.csv",
        3,
        0.05,
        4411,
    ),
    (
        "particles3d/pysplashsurf_ParticleData_Fluid_50_4732.csv",
        3,
        0.1,
        4117,
    ),
    (
        "particles3d/splashsurf_bunny_frame_14_7706.csv",
        3,
        0.05,
        2714,
    ),
    (
        "particles3d/splashsurf_bunny_frame_14_7706.csv",
        3,
        0.1,
        1811,
    ),
    (
        "particles3d/splashsurf_dam_break_frame_23_24389.csv",
        3,
        0.05,
        8256,
    ),
    (
        "particles3d/splashsurf_dam_break_frame_23_24389.csv",
        3,
        0.1,
        7301,
    ),
    (
        "particles3d/splashsurf_dam_break_frame_9_6859.csv",
        3,
        0.05,
        2407,
    ),
    (
        "particles3d/splashsurf_dam_break_frame_9_6859.csv",
        3,
        0.1,
        2089,
    ),
    (
        "particles3d/splashsurf_double_dam_break_frame_26_4732.csv",
        3,
        0.05,
        4623,
    ),
    (
        "particles3d/splashsurf_double_dam_break_frame_26_4732.csv",
        3,
        0.1,
        4155,
    ),
];

/// An `n × n` square lattice of spacing `a`, x fastest.
pub fn square_lattice(n: usize, a: f64) -> Vec<[f64; 2]> {
    (0..n * n)
        .map(|k| [(k % n) as f64 * a, (k / n) as f64 * a])
        .collect()
}

/// An `n × n × n` cubic lattice of spacing `a`, x fastest.
pub fn cubic_lattice(n: usize, a: f64) -> Vec<[f64; 3]> {
    (0..n * n * n)
        .map(|k| {
            [
                (k % n) as f64 * a,
                ((k / n) % n) as f64 * a,
                (k / (n * n)) as f64 * a,
            ]
        })
        .collect()
}
