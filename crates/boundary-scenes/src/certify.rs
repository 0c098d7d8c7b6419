//! What a certified detector (no false negative against the exact labels) is checked on, and
//! the check itself, shared by the tests of every certified method (`ia`, `ge`, …).

use crate::{all_scenes, cubic_lattice, square_lattice, SharedData, SHARED_SCENES};
use boundary_core::{AnyParticleSet, Labels, ParticleSet};
use boundary_core::{Dim, SupportedDim};
use rand::{rngs::StdRng, Rng, SeedableRng};

/// A named particle set with its resolution.
#[derive(Debug, Clone)]
pub struct Case {
    /// What the case is (for messages).
    pub name: String,
    /// The particles.
    pub set: AnyParticleSet,
    /// The resolution r.
    pub radius: f64,
}

impl Case {
    fn new<const D: usize>(name: impl Into<String>, rows: &[[f64; D]], radius: f64) -> Self
    where
        ParticleSet<D>: Into<AnyParticleSet>,
        Dim<D>: SupportedDim,
    {
        let set = ParticleSet::from_rows(rows).expect("generated coordinates are finite");
        Case {
            name: name.into(),
            set: set.into(),
            radius,
        }
    }
}

/// A jittered `n^D` lattice of spacing 1 (uniform jitter `±jitter` per axis), seeded.
pub fn jittered_lattice<const D: usize>(n: usize, jitter: f64, seed: u64) -> Vec<[f64; D]> {
    let mut rng = StdRng::seed_from_u64(seed);
    (0..n.pow(D as u32))
        .map(|k| {
            let mut p = [0.0; D];
            let mut rest = k;
            for c in p.iter_mut() {
                *c = (rest % n) as f64 + rng.gen_range(-jitter..=jitter);
                rest /= n;
            }
            p
        })
        .collect()
}

/// The hard cases: perfect lattices at and a few ulps around their tie radii (`a/√2` in 2D,
/// `a·√3/2` in 3D) and at ordinary radii, exact duplicates and near-duplicates (1e-12 apart),
/// a coincident pair, a scene offset by 1e6 with r = 0.012, a line in 2D and a plane in 3D
/// (everything boundary), single particles, two particles exactly 2r apart, and jittered
/// lattices.
pub fn hard_cases() -> Vec<Case> {
    let mut cases = Vec::new();
    let square = square_lattice(12, 1.0);
    let tie2 = std::f64::consts::FRAC_1_SQRT_2;
    for r in [tie2, ulps(tie2, -4), ulps(tie2, 4), 0.8, 1.0, 1.5] {
        cases.push(Case::new(format!("square lattice r={r:e}"), &square, r));
    }
    let cubic = cubic_lattice(7, 1.0);
    let tie3 = 3f64.sqrt() / 2.0;
    for r in [tie3, ulps(tie3, -4), ulps(tie3, 4), 1.0, 1.2] {
        cases.push(Case::new(format!("cubic lattice r={r:e}"), &cubic, r));
    }
    let small = cubic_lattice(5, 1.0);
    let doubled: Vec<[f64; 3]> = small.iter().chain(small.iter()).copied().collect();
    cases.push(Case::new("exact duplicates", &doubled, 1.2));
    let near: Vec<[f64; 3]> = small
        .iter()
        .chain(small.iter())
        .enumerate()
        .map(|(k, p)| {
            let shift = if k < small.len() { 0.0 } else { 1e-12 };
            [p[0] + shift, p[1], p[2]]
        })
        .collect();
    cases.push(Case::new("near duplicates 1e-12", &near, 1.2));
    cases.push(Case::new("coincident pair", &[[0.0, 0.0], [0.0, 0.0]], 1.0));
    let far: Vec<[f64; 3]> = jittered_lattice::<3>(8, 0.2, 4)
        .iter()
        .map(|p| [1e6 + 0.01 * p[0], -1e6 + 0.01 * p[1], 1e6 + 0.01 * p[2]])
        .collect();
    cases.push(Case::new("offset 1e6", &far, 0.012));
    let line: Vec<[f64; 2]> = (0..20).map(|k| [k as f64 * 0.5, 0.0]).collect();
    cases.push(Case::new("line", &line, 1.0));
    let plane: Vec<[f64; 3]> = square_lattice(6, 1.0)
        .iter()
        .map(|p| [p[0], p[1], 0.0])
        .collect();
    cases.push(Case::new("plane", &plane, 1.5));
    cases.push(Case::new("single 2D", &[[0.5, 0.5]], 1.0));
    cases.push(Case::new("single 3D", &[[0.5, 0.5, 0.5]], 1.0));
    cases.push(Case::new(
        "pair at 2r",
        &[[0.0, 0.0, 0.0], [2.0, 0.0, 0.0]],
        1.0,
    ));
    for seed in 0..2 {
        cases.push(Case::new(
            format!("jittered 2D seed {seed}"),
            &jittered_lattice::<2>(20, 0.3, seed),
            0.9,
        ));
        cases.push(Case::new(
            format!("jittered 3D seed {seed}"),
            &jittered_lattice::<3>(9, 0.3, seed),
            1.1,
        ));
    }
    cases
}

/// Perfect lattices just around their tie radii, where the exact labels flip: a 7² square
/// lattice at `a/√2` and a 5³ cubic lattice at `a·√3/2`, each at `tie·(1 ± k·1e-10)`,
/// `k = 1..5`, and `±1..4` ulps around the float tie radius (41 cases, small enough for every
/// depth of a certified method).
pub fn near_tie_cases() -> Vec<Case> {
    let near = near_tie_radii;
    let mut cases = Vec::new();
    let square = square_lattice(7, 1.0);
    for r in near(std::f64::consts::FRAC_1_SQRT_2) {
        cases.push(Case::new(
            format!("near-tie square lattice r={r:e}"),
            &square,
            r,
        ));
    }
    let cubic = cubic_lattice(5, 1.0);
    for r in near(3f64.sqrt() / 2.0) {
        cases.push(Case::new(
            format!("near-tie cubic lattice r={r:e}"),
            &cubic,
            r,
        ));
    }
    cases
}

/// The radii around a tie radius `tie`: `tie` itself, `tie·(1 ± k·1e-10)` for `k = 1..5`, and
/// `±1..4` ulps (19 radii), where the exact labels of a lattice flip.
pub fn near_tie_radii(tie: f64) -> Vec<f64> {
    let mut radii = vec![tie];
    for k in 1..=5 {
        radii.push(tie * (1.0 + k as f64 * 1e-10));
        radii.push(tie * (1.0 - k as f64 * 1e-10));
    }
    for k in 1..=4 {
        radii.push(ulps(tie, k));
        radii.push(ulps(tie, -k));
    }
    radii
}

/// `x` moved by `k` units in the last place.
pub fn ulps(x: f64, k: i64) -> f64 {
    let mut y = x;
    for _ in 0..k.unsigned_abs() {
        y = if k > 0 { y.next_up() } else { y.next_down() };
    }
    y
}

/// Every case a certified method must pass: the generated fixture scenes, the shared scenes
/// and the volumetric samples of the shared meshes (read through `data`, so a missing data
/// folder is an error unless `data` allows it), the hard cases and the near-tie lattices
/// ([`near_tie_cases`]). Also returns the files that were skipped (only when `data` allows
/// missing data).
pub fn certification_cases(data: &SharedData) -> Result<(Vec<Case>, Vec<String>), String> {
    let mut cases: Vec<Case> = all_scenes()
        .into_iter()
        .map(|s| Case {
            name: format!("fixture {}", s.name),
            set: s.set,
            radius: s.radius,
        })
        .collect();
    let mut skipped = Vec::new();
    for &(_, dim, file, r, _, _, _) in SHARED_SCENES {
        let set = if dim == 2 {
            data.set::<2>(file)?.map(AnyParticleSet::from)
        } else {
            data.set::<3>(file)?.map(AnyParticleSet::from)
        };
        match set {
            Some(set) => cases.push(Case {
                name: file.to_owned(),
                set,
                radius: r,
            }),
            None => skipped.push(file.to_owned()),
        }
    }
    for &(name, file, radius, params) in crate::mesh::MESH_SCENES {
        match data.mesh(file, params)? {
            Some(set) => cases.push(Case {
                name: name.to_owned(),
                set: set.into(),
                radius,
            }),
            None => skipped.push(file.to_owned()),
        }
    }
    cases.extend(hard_cases());
    cases.extend(near_tie_cases());
    Ok((cases, skipped))
}

/// Checks the labels of a certified method at increasing depths (`by_depth[k]` at depth
/// `k + 1`) against the exact labels `truth`: no false negative at any depth, and a particle
/// labelled interior at one depth stays interior at every deeper one. Returns the false
/// positives per depth, or a message naming the first offending depth and particles.
pub fn check_depths(truth: &Labels, by_depth: &[Labels]) -> Result<Vec<usize>, String> {
    let mut fps = Vec::with_capacity(by_depth.len());
    for (k, labels) in by_depth.iter().enumerate() {
        let depth = k + 1;
        if labels.len() != truth.len() {
            return Err(format!(
                "depth {depth}: {} labels for {} particles",
                labels.len(),
                truth.len()
            ));
        }
        let missed: Vec<usize> = (0..truth.len())
            .filter(|&i| truth.is_boundary(i) && !labels.is_boundary(i))
            .collect();
        if !missed.is_empty() {
            return Err(format!(
                "depth {depth}: {} false negatives, particles {:?}",
                missed.len(),
                &missed[..missed.len().min(10)]
            ));
        }
        if k > 0 {
            let lost: Vec<usize> = (0..truth.len())
                .filter(|&i| !by_depth[k - 1].is_boundary(i) && labels.is_boundary(i))
                .collect();
            if !lost.is_empty() {
                return Err(format!(
                    "depth {depth}: interior at depth {} but boundary now: {:?}",
                    depth - 1,
                    &lost[..lost.len().min(10)]
                ));
            }
        }
        fps.push(labels.boundary_count() - truth.boundary_count());
    }
    Ok(fps)
}

/// Checks a certified method on every [`certification_cases`] case with [`check_depths`]:
/// `truth(case)` gives the exact labels, `at_depth(case, d)` the method's labels at depth `d`
/// (`1..=max_depth`). The shared data is read with [`SharedData::from_env`]: a missing data
/// folder is a failure unless `BOUNDARY_ALLOW_MISSING_DATA=1`. Returns a line per case
/// (`name r=…: FP by depth […]`, and the shared scenes that were skipped), or the failing
/// cases with their messages.
pub fn certify_every_case(
    truth: impl Fn(&Case) -> Labels,
    at_depth: impl Fn(&Case, u32) -> Labels,
    max_depth: u32,
) -> Result<Vec<String>, Vec<String>> {
    let (cases, skipped) = certification_cases(&SharedData::from_env()).map_err(|e| vec![e])?;
    let mut report = Vec::new();
    if !skipped.is_empty() {
        report.push(format!(
            "shared scenes skipped ({}=1): {skipped:?}",
            crate::ALLOW_MISSING_DATA_VAR
        ));
    }
    let mut failures = Vec::new();
    for case in &cases {
        let by_depth: Vec<Labels> = (1..=max_depth).map(|d| at_depth(case, d)).collect();
        match check_depths(&truth(case), &by_depth) {
            Ok(fps) => report.push(format!(
                "{} r={}: FP by depth {fps:?}",
                case.name, case.radius
            )),
            Err(e) => failures.push(format!("{} r={}: {e}", case.name, case.radius)),
        }
    }
    if failures.is_empty() {
        Ok(report)
    } else {
        Err(failures)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn check_depths_finds_false_negatives_and_lost_interiors() {
        let truth = Labels::new(vec![true, false, false]);
        let good = [
            Labels::new(vec![true, true, true]),
            Labels::new(vec![true, false, true]),
        ];
        assert_eq!(check_depths(&truth, &good), Ok(vec![2, 1]));
        let missed = [Labels::new(vec![false, false, false])];
        assert!(check_depths(&truth, &missed)
            .unwrap_err()
            .contains("false negatives"));
        let lost = [
            Labels::new(vec![true, false, true]),
            Labels::new(vec![true, true, false]),
        ];
        assert!(check_depths(&truth, &lost).unwrap_err().contains("depth 2"));
    }

    #[test]
    fn certification_cases_fail_on_a_missing_data_folder_unless_allowed() {
        let dir = std::env::temp_dir().join("boundary-certify-no-such-data-folder");
        let err = certification_cases(&SharedData::new(&dir, false)).unwrap_err();
        assert!(
            err.contains("boundary-certify-no-such-data-folder"),
            "{err}"
        );
        let (cases, skipped) = certification_cases(&SharedData::new(&dir, true)).unwrap();
        assert_eq!(
            skipped.len(),
            SHARED_SCENES.len() + crate::mesh::MESH_SCENES.len()
        );
        assert_eq!(
            cases.len(),
            all_scenes().len() + hard_cases().len() + near_tie_cases().len()
        );
    }

    #[test]
    fn hard_cases_hold_the_tie_radii_and_their_neighbours() {
        let cases = hard_cases();
        let tie = std::f64::consts::FRAC_1_SQRT_2;
        assert!(cases.iter().any(|c| c.radius == tie));
        assert!(cases
            .iter()
            .any(|c| c.radius < tie && c.radius > tie - 1e-15));
        assert!(cases
            .iter()
            .any(|c| c.radius > tie && c.radius < tie + 1e-15));
    }
}
