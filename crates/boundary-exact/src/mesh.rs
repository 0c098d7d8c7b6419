//! Solid meshes (crate docs, "Solid meshes"): the labels without the meshes, then a witness
//! search on the spheres whose ball meets a mesh surface.

use boundary_core::{
    DetectError, Detection, HalfSpace, Labels, ParticleSet, Point, RadiusGrid, SolidMesh,
};
use rayon::prelude::*;
use std::sync::Arc;

/// Points of the Fibonacci sphere sampled on each sphere that meets a mesh surface.
pub(crate) const SAMPLES: usize = 2048;

/// The best samples refined by a local search on the sphere.
const REFINED: usize = 8;

/// The smallest step of the local search, in radians (units of `r_i` on the sphere).
const FINEST_STEP: f64 = 1e-7;

/// Relative slack of every test of a witness: outside each neighbour ball by `1e-9·r_i` (in
/// squared distance, about `2e-9` relative), outside each half-space and each mesh by
/// `1e-9·r_i` plus their rounding.
pub(crate) const WITNESS_SLACK: f64 = 1e-9;

/// How a mesh meets one particle's ball.
enum Reach {
    /// Every mesh stays clear of the closed ball, and none holds it.
    Clear,
    /// A mesh holds the whole ball: interior.
    Held,
    /// Some mesh surface meets the ball (or comes within the slack of it).
    Meets,
}

/// Classifies the first `owned` particles of `set` with the meshes `meshes` (3D) and the
/// half-spaces `half_spaces` covering, given `base`, their detection without the meshes
/// (with the half-spaces). `radii` are the particles' radii.
pub(crate) fn apply_meshes(
    set: &ParticleSet<3>,
    owned: usize,
    radii: &[f64],
    meshes: &[Arc<SolidMesh>],
    half_spaces: &[HalfSpace],
    base: Detection,
) -> Result<Detection, DetectError> {
    let positions = set.positions();
    let base_margins = base.margin.clone().unwrap_or_else(|| vec![0.0; owned]);
    let reach = |i: usize| {
        let p = &positions[i];
        let ri = radii[i];
        let mut meets = false;
        for m in meshes {
            let (inside, d) = m.locate(p);
            let band = ri * (1.0 + WITNESS_SLACK) + m.rounding(p);
            if d > band {
                if inside {
                    return Reach::Held;
                }
            } else {
                meets = true;
            }
        }
        if meets {
            Reach::Meets
        } else {
            Reach::Clear
        }
    };
    let reaches: Vec<Reach> = (0..owned).into_par_iter().map(reach).collect();
    // The spheres to search: their ball meets a mesh and they are boundary without it.
    let search: Vec<usize> = (0..owned)
        .filter(|&i| matches!(reaches[i], Reach::Meets) && base.labels.is_boundary(i))
        .collect();
    let found: Vec<bool> = if search.is_empty() {
        Vec::new()
    } else {
        let grid = RadiusGrid::new(set, radii)?;
        let directions = fibonacci_sphere(SAMPLES);
        search
            .par_iter()
            .map_init(Vec::new, |near: &mut Vec<([f64; 3], f64)>, &i| {
                if boundary_core::stop::requested() {
                    return Default::default();
                }
                let p = positions[i];
                near.clear();
                grid.for_each_reaching(&p, radii[i], |j, d2| {
                    // d2 == 0: `i` itself or an exact duplicate, which does not cover.
                    if d2 > 0.0 {
                        let q = positions[j] - p;
                        near.push(([q[0], q[1], q[2]], radii[j]));
                    }
                });
                let sphere = Sphere {
                    centre: p,
                    radius: radii[i],
                    near,
                    half_spaces,
                    meshes,
                };
                sphere.witness(&directions).is_some()
            })
            .collect()
    };
    let mut boundary = Vec::with_capacity(owned);
    let mut margins = Vec::with_capacity(owned);
    let mut searched = search.iter().zip(found).peekable();
    for (i, reach) in reaches.iter().enumerate() {
        let label = match reach {
            Reach::Clear => base.labels.is_boundary(i),
            Reach::Held => false,
            Reach::Meets => match searched.peek() {
                Some(&(&k, witness)) if k == i => {
                    searched.next();
                    witness
                }
                _ => false,
            },
        };
        boundary.push(label);
        let m = base_margins.get(i).copied().unwrap_or(0.0);
        margins.push(if label { m } else { m.min(0.0) });
    }
    Ok(Detection {
        labels: Labels::new(boundary),
        margin: Some(margins),
    })
}

/// `n` nearly uniform unit vectors (the Fibonacci sphere), deterministic.
pub(crate) fn fibonacci_sphere(n: usize) -> Vec<[f64; 3]> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|k| {
            let z = 1.0 - (2.0 * k as f64 + 1.0) / n as f64;
            let s = (1.0 - z * z).max(0.0).sqrt();
            let phi = golden * k as f64;
            [s * phi.cos(), s * phi.sin(), z]
        })
        .collect()
}

/// One sphere `S_i` and what may cover it.
struct Sphere<'a> {
    centre: Point<3>,
    radius: f64,
    /// Neighbours reaching `S_i`: `(p_j − p_i, r_j)`.
    near: &'a [([f64; 3], f64)],
    half_spaces: &'a [HalfSpace],
    meshes: &'a [Arc<SolidMesh>],
}

impl Sphere<'_> {
    /// The smallest clearance of the point in direction `u` (unit) from every neighbour ball
    /// and half-space, minus the witness slack, in units of `r_i`: a witness needs it `> 0`.
    fn particle_score(&self, u: &[f64; 3]) -> f64 {
        let ri = self.radius;
        let y = u.map(|c| c * ri);
        let mut score = f64::INFINITY;
        for (q, rj) in self.near {
            let d2 = (y[0] - q[0]).powi(2) + (y[1] - q[1]).powi(2) + (y[2] - q[2]).powi(2);
            // Squared clearance against the ball grown by the slack.
            let grown = rj + WITNESS_SLACK * ri;
            let s = (d2 - grown * grown) / (ri * (rj + ri));
            score = score.min(s);
        }
        let p = self.centre.as_slice();
        for h in self.half_spaces {
            let a = h.axis();
            let step = if h.solid_below() { y[a] } else { -y[a] };
            let rounding = 4.0 * f64::EPSILON * (p[a].abs() + h.value().abs() + ri);
            let depth = h.fluid_depth(p) + step - rounding - WITNESS_SLACK * ri;
            score = score.min(depth / ri);
        }
        score
    }

    /// The signed clearance from every mesh (positive outside), minus the tolerance, in units
    /// of `r_i`.
    fn mesh_score(&self, u: &[f64; 3]) -> f64 {
        let ri = self.radius;
        let x = Point::<3>::new(
            self.centre[0] + ri * u[0],
            self.centre[1] + ri * u[1],
            self.centre[2] + ri * u[2],
        );
        let mut score = f64::INFINITY;
        for m in self.meshes {
            let (inside, d) = m.locate(&x);
            let signed = if inside { -d } else { d };
            let tol = WITNESS_SLACK * ri + m.rounding(&x);
            score = score.min((signed - tol) / ri);
        }
        score
    }

    /// A point of `S_i` (its direction) outside every ball, half-space and mesh with the
    /// slack: the dense sample first, then a local search from its best points.
    fn witness(&self, directions: &[[f64; 3]]) -> Option<[f64; 3]> {
        // The best samples by the full score; the mesh is queried only where the particles'
        // score could still enter the list (the full score is at most that).
        let mut best: Vec<(f64, [f64; 3])> = Vec::with_capacity(REFINED + 1);
        for u in directions {
            let ps = self.particle_score(u);
            if best.len() == REFINED && ps <= best[REFINED - 1].0 {
                continue;
            }
            let score = ps.min(self.mesh_score(u));
            if score > 0.0 {
                return Some(*u);
            }
            let at = best.partition_point(|b| b.0 >= score);
            best.insert(at, (score, *u));
            best.truncate(REFINED);
        }
        let step = (4.0 * std::f64::consts::PI / directions.len() as f64).sqrt();
        best.into_iter()
            .find_map(|(score, u)| self.ascend(u, score, step))
    }

    fn score(&self, u: &[f64; 3]) -> f64 {
        self.particle_score(u).min(self.mesh_score(u))
    }

    /// A compass search on the sphere from `u`: eight moves in the tangent plane, the step
    /// halved when none improves, down to [`FINEST_STEP`]; a point with a positive score is
    /// a witness.
    fn ascend(&self, mut u: [f64; 3], mut score: f64, mut step: f64) -> Option<[f64; 3]> {
        let mut moves = 0;
        while step >= FINEST_STEP && moves < 400 {
            moves += 1;
            let (t1, t2) = tangents(&u);
            let mut improved = None;
            for k in 0..8 {
                let angle = std::f64::consts::FRAC_PI_4 * k as f64;
                let (c, s) = (angle.cos(), angle.sin());
                let v = normalise([
                    u[0] + step * (c * t1[0] + s * t2[0]),
                    u[1] + step * (c * t1[1] + s * t2[1]),
                    u[2] + step * (c * t1[2] + s * t2[2]),
                ]);
                let sv = self.score(&v);
                if sv > 0.0 {
                    return Some(v);
                }
                if sv > improved.map_or(score, |(b, _)| b) {
                    improved = Some((sv, v));
                }
            }
            match improved {
                Some((sv, v)) => {
                    score = sv;
                    u = v;
                }
                None => step *= 0.5,
            }
        }
        None
    }
}

fn normalise(v: [f64; 3]) -> [f64; 3] {
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    v.map(|c| c / n)
}

/// Two unit vectors orthogonal to the unit `u` and to each other.
fn tangents(u: &[f64; 3]) -> ([f64; 3], [f64; 3]) {
    let a = if u[0].abs() < 0.6 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let t1 = normalise([
        u[1] * a[2] - u[2] * a[1],
        u[2] * a[0] - u[0] * a[2],
        u[0] * a[1] - u[1] * a[0],
    ]);
    let t2 = [
        u[1] * t1[2] - u[2] * t1[1],
        u[2] * t1[0] - u[0] * t1[2],
        u[0] * t1[1] - u[1] * t1[0],
    ];
    (t1, t2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fibonacci_sphere_is_unit_and_spread() {
        let d = fibonacci_sphere(512);
        for u in &d {
            let n = (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt();
            assert!((n - 1.0).abs() < 1e-14);
        }
        // Every direction of a coarse check set has a sample within 0.15 rad.
        for v in fibonacci_sphere(97) {
            let close = d
                .iter()
                .map(|u| u[0] * v[0] + u[1] * v[1] + u[2] * v[2])
                .fold(f64::MIN, f64::max);
            assert!(close > 0.15f64.cos(), "{v:?}");
        }
    }

    #[test]
    fn tangents_are_orthonormal() {
        for u in fibonacci_sphere(50) {
            let (a, b) = tangents(&u);
            let dot = |x: [f64; 3], y: [f64; 3]| x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
            assert!(dot(a, u).abs() < 1e-14 && dot(b, u).abs() < 1e-14 && dot(a, b).abs() < 1e-14);
            assert!((dot(a, a) - 1.0).abs() < 1e-14 && (dot(b, b) - 1.0).abs() < 1e-14);
        }
    }
}
