//! Scenes with solid half-spaces and a brute-force check of a certified detector on them,
//! shared by the tests of the methods that honour solids (`ia`, `ge`).
//!
//! The check is independent of every detector: each sphere `S_i` is sampled densely, and a
//! sample that lies outside every closed solid and outside every other closed ball, both by a
//! relative margin of `1e-9`, proves particle `i` boundary. A certified detector must label
//! every such particle boundary. Samples cannot prove a particle interior, so the check also
//! counts the particles the detector calls boundary although no sample of theirs is uncovered
//! (at zero margin): an estimate of its false positives, not a proof.

use crate::certify::jittered_lattice;
use boundary_core::{AnyParticleSet, HalfSpace, Labels, ParticleSet, Radius, Solids};
use boundary_core::{Dim, SupportedDim};
use rand::{rngs::StdRng, Rng, SeedableRng};

/// A scene with solids: the first `owned` particles of `set` are classified, the others cover
/// only (ghosts).
#[derive(Debug, Clone)]
pub struct SolidCase {
    /// What the case is (for messages).
    pub name: String,
    /// The particles, owned first.
    pub set: AnyParticleSet,
    /// How many particles are classified.
    pub owned: usize,
    /// The solid half-spaces.
    pub solids: Solids,
    /// The resolution r.
    pub radius: f64,
}

impl SolidCase {
    /// The resolution as a [`Radius`].
    pub fn r(&self) -> Radius {
        Radius::new(self.radius).expect("the cases have positive radii")
    }
}

/// Relative margin (units of r) by which a sample must clear every solid and every ball to
/// prove its particle boundary.
const MARGIN: f64 = 1e-9;

fn solids(text: &[&str]) -> Solids {
    let mut s = Solids::new();
    for t in text {
        s.push(HalfSpace::parse(t).expect("valid half-space"));
    }
    s
}

/// An `n^D` lattice of spacing 1 without jitter.
fn lattice<const D: usize>(n: usize) -> Vec<[f64; D]> {
    jittered_lattice::<D>(n, 0.0, 0)
}

fn case<const D: usize>(
    name: String,
    rows: &[[f64; D]],
    radii: Option<Vec<f64>>,
    owned: usize,
    solids: Solids,
    radius: f64,
) -> SolidCase
where
    ParticleSet<D>: Into<AnyParticleSet>,
    Dim<D>: SupportedDim,
{
    let mut set = ParticleSet::from_rows(rows).expect("generated coordinates are finite");
    if let Some(radii) = radii {
        set = set.with_radii(radii).expect("positive radius factors");
    }
    SolidCase {
        name,
        set: set.into(),
        owned,
        solids,
        radius,
    }
}

/// Radius factors in `[0.8, 1.25]`, seeded.
fn factors(n: usize, seed: u64) -> Vec<f64> {
    let mut rng = StdRng::seed_from_u64(seed);
    (0..n).map(|_| rng.gen_range(0.8..=1.25)).collect()
}

/// The scenes: lattice blocks (spacing 1, perfect and jittered) resting on a floor `y<c` with
/// `c` exactly at a particle layer, between layers, through the block (particles partly and
/// wholly inside the solid) and touching the lowest spheres; a tank of four half-spaces in 2D
/// and five in 3D (walls at particle layers and between them); per-particle radii; ghosts;
/// a lone particle deep in the solid; a scene offset by 1e6.
pub fn solid_cases() -> Vec<SolidCase> {
    let mut cases = Vec::new();
    let r2 = 1.2;
    let r3 = 1.2;
    let square = lattice::<2>(10);
    let jittered2 = jittered_lattice::<2>(10, 0.15, 21);
    for c in [0.0, 0.5, -0.5, 2.0, 3.5, -1.2, 1.0] {
        let floor = solids(&[&format!("y<{c}")]);
        for (kind, rows) in [("square", &square), ("jittered square", &jittered2)] {
            cases.push(case(
                format!("{kind} lattice on y<{c}"),
                rows,
                None,
                rows.len(),
                floor.clone(),
                r2,
            ));
        }
    }
    // Solid above: a lid.
    cases.push(case(
        "jittered square lattice under y>8.5".into(),
        &jittered2,
        None,
        jittered2.len(),
        solids(&["y>8.5"]),
        r2,
    ));
    for walls in [
        ["x<0", "x>9", "y<0", "y>12"],
        ["x<-0.4", "x>9.4", "y<-0.4", "y>12"],
    ] {
        cases.push(case(
            format!("jittered square lattice in the tank {walls:?}"),
            &jittered2,
            None,
            jittered2.len(),
            solids(&walls),
            r2,
        ));
    }
    cases.push(case(
        "jittered square lattice with radii on y<0.5".into(),
        &jittered2,
        Some(factors(jittered2.len(), 5)),
        jittered2.len(),
        solids(&["y<0.5"]),
        1.0,
    ));
    // Ghosts: the upper half covers only.
    cases.push(case(
        "jittered square lattice, lower half owned, on y<-0.3".into(),
        &jittered2,
        None,
        50,
        solids(&["y<-0.3"]),
        r2,
    ));
    let mut lone = jittered2.clone();
    lone.insert(0, [4.5, -5.0]);
    cases.push(case(
        "jittered square lattice and a lone particle deep in y<0".into(),
        &lone,
        None,
        lone.len(),
        solids(&["y<0"]),
        r2,
    ));
    let offset: Vec<[f64; 2]> = jittered2.iter().map(|p| [p[0] + 1e6, p[1] + 1e6]).collect();
    cases.push(case(
        "jittered square lattice offset by 1e6 on y<1e6+0.5".into(),
        &offset,
        None,
        offset.len(),
        solids(&["y<1000000.5"]),
        r2,
    ));

    let cubic = lattice::<3>(6);
    let jittered3 = jittered_lattice::<3>(6, 0.15, 31);
    for c in [0.0, 0.5, -0.5, 2.0] {
        let floor = solids(&[&format!("y<{c}")]);
        for (kind, rows) in [("cubic", &cubic), ("jittered cubic", &jittered3)] {
            cases.push(case(
                format!("{kind} lattice on y<{c}"),
                rows,
                None,
                rows.len(),
                floor.clone(),
                r3,
            ));
        }
    }
    for (kind, rows, walls) in [
        ("cubic", &cubic, ["x<0", "x>5", "y<0", "z<0", "z>5"]),
        (
            "jittered cubic",
            &jittered3,
            ["x<-0.4", "x>5.4", "y<-0.4", "z<-0.4", "z>5.4"],
        ),
        (
            "jittered cubic",
            &jittered3,
            ["x<0", "x>5", "y<0", "z<0", "z>5"],
        ),
    ] {
        cases.push(case(
            format!("{kind} lattice in the tank {walls:?}"),
            rows,
            None,
            rows.len(),
            solids(&walls),
            r3,
        ));
    }
    cases.push(case(
        "jittered cubic lattice with radii on y<0.5".into(),
        &jittered3,
        Some(factors(jittered3.len(), 7)),
        jittered3.len(),
        solids(&["y<0.5"]),
        1.0,
    ));
    cases
}

/// Per owned particle: `(surely, uncovered)`: `surely` if a sample of `S_i` clears every solid
/// and every other ball by the margin (proven boundary, up to the rounding of the samples,
/// far below the margin); `uncovered` if some sample is outside them at zero margin.
pub fn sampled_labels(case: &SolidCase) -> Vec<(bool, bool)> {
    match &case.set {
        AnyParticleSet::D2(s) => sampled::<2>(s, case),
        AnyParticleSet::D3(s) => sampled::<3>(s, case),
    }
}

/// Points of the unit sphere: 1440 angles in 2D, 6000 Fibonacci points in 3D.
fn directions<const D: usize>() -> Vec<[f64; D]> {
    if D == 2 {
        (0..1440)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / 1440.0;
                std::array::from_fn(|a| if a == 0 { t.cos() } else { t.sin() })
            })
            .collect()
    } else {
        let n = 6000;
        (0..n)
            .map(|k| {
                let z = 1.0 - 2.0 * (k as f64 + 0.5) / n as f64;
                let rho = (1.0 - z * z).sqrt();
                let phi = k as f64 * 2.399_963_229_728_653;
                std::array::from_fn(|a| match a {
                    0 => rho * phi.cos(),
                    1 => rho * phi.sin(),
                    _ => z,
                })
            })
            .collect()
    }
}

fn sampled<const D: usize>(set: &ParticleSet<D>, case: &SolidCase) -> Vec<(bool, bool)> {
    let r = case.radius;
    let radius = |i: usize| set.radii().map_or(r, |s| r * s[i]);
    let x = set.positions();
    let dirs = directions::<D>();
    (0..case.owned)
        .map(|i| {
            let ri = radius(i);
            let others: Vec<([f64; D], f64)> = (0..set.len())
                .filter(|&j| {
                    let d2 = (x[j] - x[i]).norm_squared();
                    d2 > 0.0 && d2.sqrt() <= ri + radius(j) + 1e-9 * r
                })
                .map(|j| (std::array::from_fn(|a| x[j][a]), radius(j)))
                .collect();
            let (mut surely, mut uncovered) = (false, false);
            for u in &dirs {
                let y: [f64; D] = std::array::from_fn(|a| x[i][a] + ri * u[a]);
                // Clearance: the smallest signed distance (positive outside) to a solid or a
                // sphere of a ball.
                let mut clear = f64::INFINITY;
                for h in case.solids.half_spaces() {
                    clear = clear.min(h.fluid_depth(&y));
                }
                for (q, rj) in &others {
                    let d: f64 = (0..D).map(|a| (y[a] - q[a]).powi(2)).sum::<f64>().sqrt();
                    clear = clear.min(d - rj);
                }
                uncovered |= clear > 0.0;
                if clear > MARGIN * r {
                    surely = true;
                    break;
                }
            }
            (surely, uncovered)
        })
        .collect()
}

/// Whether the closed ball of owned particle `i` lies in some solid by a relative margin:
/// its sphere is covered by the solid alone, so it must be interior.
pub fn deep_in_solid(case: &SolidCase, i: usize) -> bool {
    let (x, s): (Vec<f64>, f64) = match &case.set {
        AnyParticleSet::D2(set) => (
            set.positions()[i].iter().copied().collect(),
            set.radii().map_or(1.0, |s| s[i]),
        ),
        AnyParticleSet::D3(set) => (
            set.positions()[i].iter().copied().collect(),
            set.radii().map_or(1.0, |s| s[i]),
        ),
    };
    case.solids
        .half_spaces()
        .iter()
        .any(|h| -h.fluid_depth(&x) > case.radius * s * (1.0 + 1e-6))
}

/// Checks a certified method with solids on every [`solid_cases`] case: `detect(case,
/// solids)` classifies the case's owned particles with the given solids (the case's own, or
/// none). Fails on a particle proven boundary by the samples but labelled interior, a particle
/// wholly in a solid labelled boundary, or a particle interior without solids but boundary
/// with them (adding solids only covers more). Returns a line per case with its counts, or
/// the failures.
pub fn certify_with_solids(
    detect: impl Fn(&SolidCase, &Solids) -> Labels,
) -> Result<Vec<String>, Vec<String>> {
    let mut report = Vec::new();
    let mut failures = Vec::new();
    for case in solid_cases() {
        let labels = detect(&case, &case.solids);
        let bare = detect(&case, &Solids::new());
        let name = format!("{} r={}", case.name, case.radius);
        if labels.len() != case.owned || bare.len() != case.owned {
            failures.push(format!(
                "{name}: {} and {} labels for {} owned particles",
                labels.len(),
                bare.len(),
                case.owned
            ));
            continue;
        }
        let sampled = sampled_labels(&case);
        let pick = |f: &dyn Fn(usize) -> bool| -> Vec<usize> {
            (0..case.owned).filter(|&i| f(i)).collect()
        };
        let missed = pick(&|i| sampled[i].0 && !labels.is_boundary(i));
        let deep = pick(&|i| deep_in_solid(&case, i));
        let deep_boundary: Vec<usize> = deep
            .iter()
            .copied()
            .filter(|&i| labels.is_boundary(i))
            .collect();
        let lost = pick(&|i| labels.is_boundary(i) && !bare.is_boundary(i));
        for (what, list) in [
            ("proven boundary by a sample but labelled interior", &missed),
            ("wholly in a solid but labelled boundary", &deep_boundary),
            ("interior without solids but boundary with them", &lost),
        ] {
            if !list.is_empty() {
                failures.push(format!(
                    "{name}: {} particles {what}: {:?}",
                    list.len(),
                    &list[..list.len().min(10)]
                ));
            }
        }
        let surely = pick(&|i| sampled[i].0).len();
        let likely_fp = pick(&|i| labels.is_boundary(i) && !sampled[i].1).len();
        report.push(format!(
            "{name}: {} owned, {} wholly in a solid, {surely} proven boundary, {} labelled \
             boundary ({} without solids), {likely_fp} with no uncovered sample",
            case.owned,
            deep.len(),
            labels.boundary_count(),
            bare.boundary_count()
        ));
    }
    if failures.is_empty() {
        Ok(report)
    } else {
        Err(failures)
    }
}
