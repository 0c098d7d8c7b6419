//! Timing of `exact` on the fixture scenes where the exact predicate does the work (the
//! perfect lattices at their tie radius, whose inner particles are genuine near ties):
//! `cargo run --release -p boundary-exact --example tie_lattice [REPS] [SCENE,...]`.
//! One thread; for each scene prints the time per detection, the number of particles the
//! exact predicate decided, and a checksum of the margins' bit patterns and of the labels (a
//! change that must not alter the output must leave both unchanged). Default: 5 repetitions
//! of `cubic_lattice_tie3d`, `square_lattice_tie2d` and `duplicates3d`; `REPS = 1` suits
//! callgrind.
#![allow(clippy::unwrap_used)] // a measuring tool: failing loudly is fine
use boundary_core::Radius;
use boundary_exact::ExactDetector;
use boundary_scenes::all_scenes;
use std::time::Instant;

fn main() {
    let reps: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(5);
    let names: Vec<String> = std::env::args()
        .nth(2)
        .map(|s| s.split(',').map(|t| t.trim().to_string()).collect())
        .unwrap_or_else(|| {
            [
                "cubic_lattice_tie3d",
                "square_lattice_tie2d",
                "duplicates3d",
            ]
            .map(String::from)
            .to_vec()
        });
    let scenes = all_scenes();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    for name in &names {
        let Some(scene) = scenes.iter().find(|s| &s.name == name) else {
            eprintln!("no fixture scene named {name}");
            continue;
        };
        let r = Radius::new(scene.radius).unwrap();
        let mut best = f64::INFINITY;
        let mut total = 0.0;
        let mut last = None;
        for _ in 0..reps.max(1) {
            let t = Instant::now();
            let out = pool.install(|| {
                ExactDetector::default()
                    .detect_counting_fallbacks(&scene.set, r)
                    .unwrap()
            });
            let s = t.elapsed().as_secs_f64();
            best = best.min(s);
            total += s;
            last = Some(out);
        }
        let (d, fallbacks) = last.unwrap();
        let checksum = d.margin.unwrap().iter().fold(0u64, |h, m| {
            (h ^ m.to_bits()).wrapping_mul(0x0100_0000_01b3)
        });
        println!(
            "{name}: n = {}, {} exact fallbacks, best {:.3} ms, mean {:.3} ms per detection \
             ({reps} reps), {} boundary, labels {:016x}, margins {checksum:016x}",
            scene.set.len(),
            fallbacks,
            best * 1e3,
            total / reps.max(1) as f64 * 1e3,
            d.labels.boundary_count(),
            d.labels.fingerprint(),
        );
    }
}
