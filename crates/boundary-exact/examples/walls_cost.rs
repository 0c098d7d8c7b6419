//! What walls and solids cost: `cargo run --release -p boundary-exact --example walls_cost
//! [N] [THREADS]`. A jittered block of about `N` particles (spacing 1, jitter ±0.15,
//! r = 1.2) resting in an open tank, timed four ways on the same pool: the fluid alone, the
//! fluid with three layers of wall particles (`Domain::with_walls`), the union of fluid and
//! walls classified whole (what the walls must not exceed), and the tank as five solid
//! half-spaces. Then the shared DualSPHysics 3D dam break with its wall file at r = 0.03
//! (skipped with a note when the data folder is missing). Each variant runs twice,
//! alternating, and its faster run is reported.
#![allow(clippy::unwrap_used)] // a measuring tool: failing loudly is fine
use boundary_core::{AnyParticleSet, BoundaryDetector, Domain, ParticleSet, Radius};
use boundary_exact::ExactDetector;
use boundary_scenes::{block_in_tank, shared_set};
use std::time::Instant;

fn union(a: &ParticleSet<3>, b: &ParticleSet<3>) -> AnyParticleSet {
    let mut all = a.positions().to_vec();
    all.extend(b.positions());
    ParticleSet::new(all).unwrap().into()
}

/// Times each variant twice, alternating; prints the faster run and the boundary count.
fn compare(pool: &rayon::ThreadPool, variants: &[(&str, &(dyn Fn() -> usize + Sync))]) {
    let mut best = vec![f64::INFINITY; variants.len()];
    let mut counts = vec![0; variants.len()];
    for _ in 0..2 {
        for (k, (_, run)) in variants.iter().enumerate() {
            let t = Instant::now();
            counts[k] = pool.install(run);
            best[k] = best[k].min(t.elapsed().as_secs_f64());
        }
    }
    for (k, (name, _)) in variants.iter().enumerate() {
        println!(
            "  {name:<34} {:>8.3} s  {:>8} boundary (fluid)",
            best[k], counts[k]
        );
    }
}

/// Times `fluid` alone, with `walls` (`detect_in`), the union of both classified whole and,
/// when given, `fluid` in the solids of `tank`.
fn compare_walls(
    pool: &rayon::ThreadPool,
    fluid: &ParticleSet<3>,
    walls: &ParticleSet<3>,
    r: Radius,
    tank: Option<&Domain>,
) {
    let fluid_any = AnyParticleSet::from(fluid.clone());
    let all = union(fluid, walls);
    let in_domain = |domain: &Domain| {
        ExactDetector::default()
            .detect_in(&fluid_any, domain, r)
            .unwrap()
            .detection
            .labels
            .boundary_count()
    };
    let (bare, with_walls) = (
        Domain::new(),
        Domain::new().with_walls(walls.clone().into()),
    );
    let union_count = || {
        let labels = ExactDetector::default().detect(&all, r).unwrap().labels;
        labels.as_slice()[..fluid.len()]
            .iter()
            .filter(|&&b| b)
            .count()
    };
    let alone = || in_domain(&bare);
    let walled = || in_domain(&with_walls);
    let mut variants: Vec<(&str, &(dyn Fn() -> usize + Sync))> = vec![
        ("fluid alone", &alone),
        ("fluid with walls (detect_in)", &walled),
        ("union of fluid and walls (detect)", &union_count),
    ];
    let solid = tank.map(|t| move || in_domain(t));
    if let Some(solid) = &solid {
        variants.push(("fluid in five half-spaces", solid));
    }
    compare(pool, &variants);
}

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let threads: usize = std::env::args()
        .nth(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let (fluid, walls, tank) = block_in_tank(n, 7);
    println!(
        "block of {} particles in a tank of {} wall particles, r = 1.2, {threads} thread(s):",
        fluid.len(),
        walls.len()
    );
    compare_walls(
        &pool,
        &fluid,
        &walls,
        Radius::new(1.2).unwrap(),
        Some(&tank),
    );

    let data = (
        shared_set::<3>("walls/dualsphysics_dambreak3d_dp0.02_fluid.csv"),
        shared_set::<3>("walls/dualsphysics_dambreak3d_dp0.02_walls.csv"),
    );
    let (Ok(Some(fluid)), Ok(Some(walls))) = data else {
        println!("shared DualSPHysics dam break: data folder missing, skipped");
        return;
    };
    println!(
        "DualSPHysics 3D dam break: {} fluid, {} wall particles, r = 0.03:",
        fluid.len(),
        walls.len()
    );
    compare_walls(&pool, &fluid, &walls, Radius::new(0.03).unwrap(), None);
}
