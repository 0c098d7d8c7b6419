//! Feature label counts on the splash frames of `../shared/data` (exact boundary labels):
//! `cargo run --release -p boundary-resample --example splash_counts`.
#![allow(clippy::unwrap_used)] // a measuring tool: failing loudly is fine

use boundary_core::{BoundaryDetector, ParticleSet, Point, Radius};
use boundary_core::{Dim, SupportedDim};
use boundary_exact::ExactDetector;
use boundary_resample::{resample, ResampleConfig};
use std::path::PathBuf;

fn read<const D: usize>(path: &PathBuf) -> ParticleSet<D>
where
    Dim<D>: SupportedDim,
{
    let text = std::fs::read_to_string(path).unwrap();
    let pts = text
        .lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|f| f.trim().parse().unwrap()).collect();
            Point::<D>::from_fn(|k, _| v[k])
        })
        .collect();
    ParticleSet::new(pts).unwrap()
}

fn report<const D: usize>(name: &str, set: &ParticleSet<D>, r: f64)
where
    Dim<D>: SupportedDim,
{
    let radius = Radius::new(r).unwrap();
    let labels = ExactDetector::default()
        .detect(&set.to_any(), radius)
        .unwrap()
        .labels;
    let out = resample(set, radius, &labels, &ResampleConfig::default()).unwrap();
    let mut counts = [0usize; 4];
    let mut seen = vec![false; set.len()];
    for (&code, &src) in out.feature.iter().zip(&out.source) {
        if code >= 0 && !seen[src] {
            seen[src] = true;
            counts[code as usize] += 1;
        }
    }
    println!(
        "| {name} | {r} | {} | {} | {} | {} | {} | {} | {} |",
        set.len(),
        labels.boundary_count(),
        counts[0],
        counts[1],
        counts[2],
        counts[3],
        out.set.len()
    );
}

fn main() {
    let data = std::env::var("BOUNDARY_DATA_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|_| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data"));
    println!("| scene | r | n | boundary | droplet | ligament | sheet | regular | n after |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for (file, r) in [
        (
            "particles2d/sandim_vortex_spin_frame_050_1698.csv",
            0.022105,
        ),
        (
            "particles2d/sandim_vortex_spin_frame_100_1698.csv",
            0.022105,
        ),
    ] {
        report(file, &read::<2>(&data.join(file)), r);
    }
    for (file, r) in [
        ("particles3d/splashsurf_dam_break_frame_23_24389.csv", 0.05),
        (
            "particles3d/splashsurf_double_dam_break_frame_26_4732.csv",
            0.05,
        ),
        (
            "particles3d/pysplashsurf_ParticleData_Fluid_50_4732.csv",
            0.05,
        ),
        ("particles3d/splashsurf_bunny_frame_14_7706.csv", 0.05),
    ] {
        report(file, &read::<3>(&data.join(file)), r);
    }
}
