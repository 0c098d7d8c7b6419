//! How the default thresholds are chosen, reproducibly, on scenes disjoint from the reported
//! ones: M = Rec·(1 − FPR) against `exact`, averaged over the tuning scenes of
//! `boundary_scenes::tuning` (seeds from 5000 in 2D, 6000 in 3D; none is in
//! `fixtures/scenes.toml`), for every threshold `k/40` and density ratio of [`RATIOS`]; the
//! defaults must be the best pair. `cargo test -p boundary-asymmetry --test threshold --
//! --nocapture` prints the table.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test
#![allow(clippy::print_stdout)] // the table is the evidence

use boundary_asymmetry::{
    AsymmetryDetector, AsymmetryValue, DEFAULT_DENSITY_RATIO, DEFAULT_THRESHOLD,
};
use boundary_core::{BoundaryDetector, Confusion, ParticleSet, Radius};
use boundary_exact::ExactDetector;
use boundary_scenes::tuning::{tuning_cases_2d, tuning_cases_3d};

const RATIOS: [f64; 6] = [0.0, 0.5, 0.6, 0.7, 0.8, 0.9];

fn thresholds() -> Vec<f64> {
    (1..=40).map(|k| k as f64 / 40.0).collect()
}

/// M for every (ratio, threshold) pair, ratio-major.
fn m_grid<const D: usize>(set: &ParticleSet<D>, r: f64) -> Vec<f64>
where
    boundary_core::Dim<D>: boundary_core::SupportedDim,
{
    let r = Radius::new(r).unwrap();
    let values: Vec<AsymmetryValue> = AsymmetryDetector::default().values(set, r).unwrap();
    let truth = ExactDetector::default()
        .detect(&set.to_any(), r)
        .unwrap()
        .labels;
    let mut out = Vec::new();
    for ratio in RATIOS {
        for t in thresholds() {
            let labels: Vec<bool> = values.iter().map(|v| v.is_boundary(t, ratio)).collect();
            out.push(
                Confusion::from_labels(&labels, truth.as_slice())
                    .unwrap()
                    .m(),
            );
        }
    }
    out
}

#[test]
fn the_default_thresholds_maximise_mean_m_on_the_tuning_scenes() {
    let mut rows: Vec<(String, Vec<f64>)> = Vec::new();
    for case in tuning_cases_2d(5000) {
        rows.push((case.name, m_grid(&case.set, case.r)));
    }
    for case in tuning_cases_3d(6000) {
        rows.push((case.name, m_grid(&case.set, case.r)));
    }
    let ts = thresholds();
    let cells = RATIOS.len() * ts.len();
    let mean: Vec<f64> = (0..cells)
        .map(|c| rows.iter().map(|(_, m)| m[c]).sum::<f64>() / rows.len() as f64)
        .collect();
    // The best pair; a tie goes to the first (smaller ratio, then smaller threshold).
    let best = (0..cells).fold(0, |b, c| if mean[c] > mean[b] { c } else { b });
    let (best_ratio, best_t) = (RATIOS[best / ts.len()], ts[best % ts.len()]);
    println!(
        "mean M by density ratio and threshold on {} tuning scenes (asymmetry, wendland, h = r):",
        rows.len()
    );
    for (k, ratio) in RATIOS.iter().enumerate() {
        let row = &mean[k * ts.len()..(k + 1) * ts.len()];
        let top = (0..ts.len()).fold(0, |b, t| if row[t] > row[b] { t } else { b });
        println!(
            "  density_ratio {ratio}: best threshold {} (mean M {:.4}); at 0.1 {:.4}, 0.2 {:.4}, 0.3 {:.4}, 0.5 {:.4}",
            ts[top], row[top], row[3], row[7], row[11], row[19]
        );
    }
    let default = RATIOS
        .iter()
        .position(|&x| x == DEFAULT_DENSITY_RATIO)
        .unwrap()
        * ts.len()
        + ts.iter().position(|&t| t == DEFAULT_THRESHOLD).unwrap();
    for (name, m) in &rows {
        let top = (0..cells).fold(0, |b, c| if m[c] > m[b] { c } else { b });
        println!(
            "  {name}: M {:.3} at the defaults, best {:.3} at ratio {} threshold {}",
            m[default],
            m[top],
            RATIOS[top / ts.len()],
            ts[top % ts.len()]
        );
    }
    println!(
        "best: density_ratio {best_ratio}, threshold {best_t} (mean M {:.4})",
        mean[best]
    );
    assert!(rows.iter().all(|(_, m)| m.iter().any(|&x| x > 0.0)));
    assert_eq!(
        (DEFAULT_DENSITY_RATIO, DEFAULT_THRESHOLD),
        (best_ratio, best_t),
        "the defaults are not the best pair on the tuning scenes"
    );
}
