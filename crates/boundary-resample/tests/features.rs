//! Synthetic droplets, ligaments and sheets give the expected labels and particle counts.
#![allow(clippy::unwrap_used)] // test code

use boundary_core::{BoundaryDetector, Labels, ParticleSet, Radius};
use boundary_exact::ExactDetector;
use boundary_resample::{classify, resample, Feature, ResampleConfig, INTERIOR_CODE};

fn cfg() -> ResampleConfig {
    ResampleConfig::default()
}

fn features<const D: usize>(set: &ParticleSet<D>, r: f64, labels: &Labels) -> Vec<Option<Feature>>
where
    boundary_core::Dim<D>: boundary_core::SupportedDim,
{
    classify(set, Radius::new(r).unwrap(), labels, &cfg())
        .unwrap()
        .into_iter()
        .map(|c| c.feature)
        .collect()
}

#[test]
fn droplets_become_2d_particles_along_the_axes() {
    // Two droplets: an isolated particle and a pair, far apart (|N_i| = 1 and 2 < K = 4).
    let set = ParticleSet::<3>::from_rows(&[[0.0; 3], [10.0, 0.0, 0.0], [10.1, 0.0, 0.0]]).unwrap();
    let all = Labels::new(vec![true; 3]);
    assert_eq!(features(&set, 0.1, &all), vec![Some(Feature::Droplet); 3]);
    let out = resample(&set, Radius::new(0.1).unwrap(), &all, &cfg()).unwrap();
    assert_eq!(out.set.len(), 18);
    assert_eq!(out.source[..6], [0; 6]);
    // The six new particles of the isolated droplet sit at ±0.5 r on each axis.
    for p in &out.set.positions()[..6] {
        assert!((p.norm() - 0.05).abs() < 1e-15);
        assert_eq!(p.iter().filter(|c| c.abs() > 0.0).count(), 1);
    }
    let set2 = ParticleSet::<2>::from_rows(&[[0.0, 0.0]]).unwrap();
    let out2 = resample(
        &set2,
        Radius::new(1.0).unwrap(),
        &Labels::new(vec![true]),
        &cfg(),
    )
    .unwrap();
    assert_eq!(out2.set.len(), 4);
}

#[test]
fn straight_ligament_in_3d() {
    // 20 particles on a line, spacing 0.5 r: σ_1 = σ_2 = 0 <= α σ_3.
    let r = 0.1;
    let rows: Vec<[f64; 3]> = (0..20).map(|k| [k as f64 * 0.05, 0.0, 0.0]).collect();
    let set = ParticleSet::from_rows(&rows).unwrap();
    let labels = ExactDetector::default()
        .detect_3d(&set, Radius::new(r).unwrap())
        .unwrap()
        .labels;
    assert_eq!(labels.boundary_count(), 20);
    let f = features(&set, r, &labels);
    assert!(f.iter().all(|x| *x == Some(Feature::Ligament)), "{f:?}");
    let out = resample(&set, Radius::new(r).unwrap(), &labels, &cfg()).unwrap();
    assert_eq!(out.set.len(), 80);
    // New particles leave the line by 0.5 r, perpendicular to it.
    for p in out.set.positions() {
        assert!(((p.y * p.y + p.z * p.z).sqrt() - 0.05).abs() < 1e-12);
    }
}

#[test]
fn flat_sheet_in_3d() {
    // One layer of a square lattice (spacing 0.6 r): σ_1 = 0, σ_2 ~ σ_3.
    let r = 1.0;
    let rows: Vec<[f64; 3]> = (0..100)
        .map(|k| [(k % 10) as f64 * 0.6, (k / 10) as f64 * 0.6, 0.0])
        .collect();
    let set = ParticleSet::from_rows(&rows).unwrap();
    let labels = ExactDetector::default()
        .detect_3d(&set, Radius::new(r).unwrap())
        .unwrap()
        .labels;
    assert_eq!(labels.boundary_count(), 100);
    let f = features(&set, r, &labels);
    assert!(f.iter().all(|x| *x == Some(Feature::Sheet)), "{f:?}");
    let out = resample(&set, Radius::new(r).unwrap(), &labels, &cfg()).unwrap();
    assert_eq!(out.set.len(), 200);
    for p in out.set.positions() {
        assert!((p.z.abs() - 0.5).abs() < 1e-12); // along the sheet's normal
    }
}

#[test]
fn filament_in_2d_is_a_ligament() {
    let rows: Vec<[f64; 2]> = (0..15)
        .map(|k| [k as f64 * 0.5, 0.25 * k as f64 * 0.5])
        .collect();
    let set = ParticleSet::from_rows(&rows).unwrap();
    let all = Labels::new(vec![true; 15]);
    let f = features(&set, 1.0, &all);
    assert!(f.iter().all(|x| *x == Some(Feature::Ligament)), "{f:?}");
    assert_eq!(
        resample(&set, Radius::new(1.0).unwrap(), &all, &cfg())
            .unwrap()
            .set
            .len(),
        30
    );
}

#[test]
fn regular_ball_keeps_its_count_and_moves_the_surface_outwards() {
    // A lattice ball of radius 5 (spacing 1) at r = 1 (> a√3/2): boundary particles are regular,
    // interior ones untouched; the shifted ones move 0.5 r away from the centre.
    let mut rows = Vec::new();
    for x in -5i32..=5 {
        for y in -5i32..=5 {
            for z in -5i32..=5 {
                if x * x + y * y + z * z <= 25 {
                    rows.push([x as f64, y as f64, z as f64]);
                }
            }
        }
    }
    let set = ParticleSet::from_rows(&rows).unwrap();
    let r = Radius::new(1.0).unwrap();
    let labels = ExactDetector::default().detect_3d(&set, r).unwrap().labels;
    assert!(labels.boundary_count() < set.len() / 2);
    let out = resample(&set, r, &labels, &cfg()).unwrap();
    assert_eq!(out.set.len(), set.len());
    let mut moved_out = 0;
    for (k, (p, q)) in set.positions().iter().zip(out.set.positions()).enumerate() {
        if labels.is_boundary(k) {
            assert_eq!(out.feature[k], Feature::Regular.code());
            assert!(((q - p).norm() - 0.5).abs() < 1e-12 || q == p);
            moved_out += usize::from(q.norm() > p.norm());
        } else {
            assert_eq!(out.feature[k], INTERIOR_CODE);
            assert_eq!(p, q);
        }
    }
    assert_eq!(moved_out, labels.boundary_count());
}

#[test]
fn bad_input_is_an_error() {
    let set = ParticleSet::<2>::from_rows(&[[0.0, 0.0]]).unwrap();
    let r = Radius::new(1.0).unwrap();
    assert!(resample(&set, r, &Labels::new(vec![]), &cfg()).is_err());
    let bad = ResampleConfig {
        alpha: f64::NAN,
        ..cfg()
    };
    assert!(resample(&set, r, &Labels::new(vec![true]), &bad).is_err());
}
