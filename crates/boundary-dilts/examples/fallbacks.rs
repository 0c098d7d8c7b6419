//! How often the exact fallback runs: `cargo run --release -p boundary-dilts --example
//! fallbacks [N]`. For every scene of `fixtures/scenes.toml` (those present), the number of
//! particles that `exact` and `dilts` leave to the exact predicate, then the same for `exact`
//! on the jittered lattice ball of N particles (default 1M, r = 1.2a) with its time.
#![allow(clippy::unwrap_used)] // a measuring tool
use boundary_core::Radius;
use boundary_dilts::DiltsDetector;
use boundary_exact::ExactDetector;
use boundary_scenes::{Manifest, Origin};
use std::time::Instant;

fn main() {
    let fixtures = boundary_scenes::fixtures_dir();
    let data = boundary_scenes::data_dir();
    let manifest = Manifest::load(&fixtures.join("scenes.toml")).unwrap();
    println!("scene, particles, exact fallbacks, dilts fallbacks");
    for entry in &manifest.scene {
        if entry.origin != Origin::Fixture && !entry.path(&fixtures, &data).is_file() {
            continue;
        }
        let Ok(set) = entry.load(&fixtures, &data) else {
            continue;
        };
        let r = Radius::new(entry.radius).unwrap();
        let (_, fe) = ExactDetector::default()
            .detect_counting_fallbacks(&set, r)
            .unwrap();
        let (_, fd) = DiltsDetector::default()
            .detect_counting_fallbacks(&set, r)
            .unwrap();
        println!("{}, {}, {fe}, {fd}", entry.name, set.len());
    }
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let (ball, _) = boundary_scenes::jittered_lattice_ball(n, 0.15, 7);
    let set = ball.into();
    let t = Instant::now();
    let (d, fe) = ExactDetector::default()
        .detect_counting_fallbacks(&set, Radius::new(1.2).unwrap())
        .unwrap();
    println!(
        "jittered ball {n}: exact fallbacks {fe}, {} boundary, {:.2} s",
        d.labels.boundary_count(),
        t.elapsed().as_secs_f64()
    );
}
