//! The fixed cost of a tracker update in a solver's time loop: a 2D dam break the size of
//! PySPH's `dam_break_2d` (a 1 x 2 water column of spacing `dx = 0.015` at the left of a
//! 4 x 4 tank, 4 layers of wall particles, `r = h = 1.3 dx`), the water collapsing by a smooth
//! flow (`u = c x`, `v = -c y`) whose fastest particle moves `0.016 dx` a step, as PySPH's
//! does. The walls are fixed: set once, never moved.
//!
//! `cargo run --release -p boundary-exact --example tracker_dambreak [STEPS] [THREADS]`
//! (defaults 200 steps, 1 thread) prints the mean update time after the first, the mean share
//! of particles recomputed, and checks the last step against a full detection. Under
//! `valgrind --tool=callgrind` its instruction count per update is
//! `(total(STEPS) - total(0)) / STEPS`.
#![allow(clippy::unwrap_used)] // a measuring tool: failing loudly is fine
use boundary_core::{Domain, ParticleSet, Point, Radius};
use boundary_exact::{ExactDetector, Tracker};
use rand::{Rng, SeedableRng};
use std::time::Instant;

fn main() {
    let steps: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(200);
    let threads: usize = std::env::args()
        .nth(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    let dx = 0.015;
    let mut rng = rand::rngs::StdRng::seed_from_u64(44);
    let mut fluid: Vec<Point<2>> = Vec::new();
    let (nx, ny) = ((1.0 / dx) as usize, (2.0 / dx) as usize);
    for j in 0..ny {
        for i in 0..nx {
            let jitter = |rng: &mut rand::rngs::StdRng| rng.gen_range(-0.05..0.05) * dx;
            fluid.push(Point::<2>::new(
                (i as f64 + 0.5) * dx + jitter(&mut rng),
                (j as f64 + 0.5) * dx + jitter(&mut rng),
            ));
        }
    }
    let mut walls: Vec<Point<2>> = Vec::new();
    let side = (4.0 / dx) as usize;
    for layer in 0..4 {
        let off = (layer as f64 + 0.5) * dx;
        for k in 0..side {
            let t = (k as f64 + 0.5) * dx;
            walls.push(Point::<2>::new(t, -off));
            walls.push(Point::<2>::new(-off, t));
            walls.push(Point::<2>::new(4.0 + off, t));
        }
        for c in 0..=layer {
            let c = (c as f64 + 0.5) * dx;
            walls.push(Point::<2>::new(-c, -off));
            walls.push(Point::<2>::new(4.0 + c, -off));
        }
    }
    let r = Radius::new(1.3 * dx).unwrap();
    let walls = ParticleSet::new(walls).unwrap().to_any();
    let domain = Domain::new().with_walls(walls);
    let mut tracker = Tracker::new(r, Some(threads), domain.clone()).unwrap();
    // The fastest particle (at y = 2) moves 0.016 dx a step.
    let c = 0.016 * dx / 2.0;
    let set = ParticleSet::new(fluid.clone()).unwrap().to_any();
    tracker.update(&set).unwrap();
    let (mut seconds, mut recomputed) = (0.0, 0usize);
    for _ in 0..steps {
        for p in &mut fluid {
            *p = Point::<2>::new(p[0] * (1.0 + c), p[1] * (1.0 - c));
        }
        let set = ParticleSet::new(fluid.clone()).unwrap().to_any();
        let start = Instant::now();
        tracker.update(&set).unwrap();
        seconds += start.elapsed().as_secs_f64();
        recomputed += tracker.recomputed();
    }
    let set = ParticleSet::new(fluid.clone()).unwrap().to_any();
    let full = boundary_core::detect_in(&ExactDetector::default(), &set, &domain, r)
        .unwrap()
        .detection
        .labels;
    assert_eq!(
        tracker.labels(),
        &full,
        "the tracker's labels differ from detect's"
    );
    let steps_f = steps.max(1) as f64;
    println!(
        "{} fluid + {} wall particles, r = {}, {threads} thread(s), {steps} steps: update {:.3} ms \
         (mean after the first), recomputed {:.2} % of the fluid; {} boundary at the end \
         (= a full detection)",
        fluid.len(),
        domain.walls().map_or(0, |w| w.len()),
        r.get(),
        1e3 * seconds / steps_f,
        100.0 * recomputed as f64 / (steps_f * fluid.len() as f64),
        full.boundary_count(),
    );
}
