//! The generated training scenes: seeded, made at training time, spacing 1.
//!
//! None of them is a scene of `fixtures/scenes.toml` or of the shared data, nor made by the
//! generators behind them (no single-vortex, Enright, Zalesak or ball-with-bubble flow):
//! every scene the sweep reports stays held out. The families (each in 2D and 3D):
//!
//! - **blobs**: star-shaped bodies (radius modulated by a few random harmonics) with 0–3
//!   spherical bubbles, filled with a square/hexagonal (2D) or cubic/face-centred (3D)
//!   lattice, randomly rotated, jittered by 0–0.3 spacing or relaxed from random points;
//! - **stretched flows**: blobs advected (RK4) by a random divergence-free field, the curl
//!   of a few random Fourier modes, until they form tails, filaments and sheets;
//! - **thin features**: curved strips / sheets one to three particles thick, filaments,
//!   droplets of one to eight particles, next to a pool;
//! - **lattices**: perfect square, hexagonal, cubic and face-centred lattices at radii at,
//!   just below and just above their tie radii and at a range of others.
//!
//! Each scene is used at one or more radii `r` (in spacings): the real data sets have
//! `r`/spacing between about 0.8 and 6.

use boundary_core::Point;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use std::f64::consts::PI;

/// One generated scene: its name, particles and the radii it is labelled at.
pub struct Generated<const D: usize> {
    pub name: String,
    pub points: Vec<Point<D>>,
    pub radii: Vec<f64>,
}

/// Lattice kinds.
#[derive(Clone, Copy, Debug)]
enum Lattice {
    /// Square (2D) or cubic (3D), spacing 1.
    Cubic,
    /// Hexagonal (2D) or face-centred cubic (3D), nearest-neighbour spacing 1.
    Dense,
}

/// Lattice points in the cube `[-half, half]^D`, nearest spacing 1.
fn lattice<const D: usize>(kind: Lattice, half: f64) -> Vec<Point<D>> {
    let mut out = vec![];
    match kind {
        Lattice::Cubic => {
            let n = half.floor() as i64;
            let side = (2 * n + 1) as usize;
            for code in 0..side.pow(D as u32) {
                let mut c = code;
                out.push(Point::<D>::from_fn(|_, _| {
                    let v = (c % side) as i64 - n;
                    c /= side;
                    v as f64
                }));
            }
        }
        Lattice::Dense if D == 2 => {
            let dy = 3f64.sqrt() / 2.0;
            let rows = (half / dy).floor() as i64;
            let cols = half.floor() as i64 + 1;
            for row in -rows..=rows {
                let shift = if row.rem_euclid(2) == 1 { 0.5 } else { 0.0 };
                for col in -cols..=cols {
                    let x = col as f64 + shift;
                    if x.abs() <= half {
                        out.push(Point::<D>::from_fn(|k, _| {
                            if k == 0 {
                                x
                            } else {
                                row as f64 * dy
                            }
                        }));
                    }
                }
            }
        }
        Lattice::Dense => {
            // Face-centred cubic: cube side √2, four points per cell.
            let a = 2f64.sqrt();
            let n = (half / a).floor() as i64 + 1;
            let basis = [
                [0.0, 0.0, 0.0],
                [0.5, 0.5, 0.0],
                [0.5, 0.0, 0.5],
                [0.0, 0.5, 0.5],
            ];
            let side = (2 * n + 1) as usize;
            for code in 0..side.pow(D as u32) {
                let mut c = code;
                let cell: Vec<f64> = (0..D)
                    .map(|_| {
                        let v = (c % side) as i64 - n;
                        c /= side;
                        v as f64
                    })
                    .collect();
                for b in &basis {
                    let p = Point::<D>::from_fn(|k, _| (cell[k] + b[k]) * a);
                    if p.iter().all(|x| x.abs() <= half) {
                        out.push(p);
                    }
                }
            }
        }
    }
    out
}

/// A uniformly random rotation (2D: an angle; 3D: a random unit quaternion).
fn random_rotation<const D: usize>(rng: &mut StdRng) -> impl Fn(&Point<D>) -> Point<D> {
    let (a, b, c, d): (f64, f64, f64, f64) = loop {
        let q = (
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
        );
        let n2: f64 = q.0 * q.0 + q.1 * q.1 + q.2 * q.2 + q.3 * q.3;
        if n2 > 0.01 && n2 <= 1.0 {
            let n = n2.sqrt();
            break (q.0 / n, q.1 / n, q.2 / n, q.3 / n);
        }
    };
    let angle = rng.gen_range(0.0..2.0 * PI);
    let m3 = [
        [
            a * a + b * b - c * c - d * d,
            2.0 * (b * c - a * d),
            2.0 * (b * d + a * c),
        ],
        [
            2.0 * (b * c + a * d),
            a * a - b * b + c * c - d * d,
            2.0 * (c * d - a * b),
        ],
        [
            2.0 * (b * d - a * c),
            2.0 * (c * d + a * b),
            a * a - b * b - c * c + d * d,
        ],
    ];
    let m2 = [[angle.cos(), -angle.sin()], [angle.sin(), angle.cos()]];
    move |p: &Point<D>| {
        Point::<D>::from_fn(|row, _| {
            (0..D)
                .map(|k| if D == 2 { m2[row][k] } else { m3[row][k] } * p[k])
                .sum()
        })
    }
}

fn jitter<const D: usize>(points: &mut [Point<D>], amount: f64, rng: &mut StdRng) {
    if amount > 0.0 {
        for p in points.iter_mut() {
            for k in 0..D {
                p[k] += rng.gen_range(-amount..amount);
            }
        }
    }
}

/// Pushes apart pairs closer than spacing 1 (a few sweeps of pairwise repulsion, in index
/// order: deterministic): from random points, a blue-noise distribution like a relaxed SPH
/// fluid.
fn relax<const D: usize>(points: &mut [Point<D>], sweeps: usize) {
    for _ in 0..sweeps {
        // Cell list of side 1.
        let mut cells: std::collections::HashMap<[i64; D], Vec<usize>> =
            std::collections::HashMap::new();
        for (i, p) in points.iter().enumerate() {
            cells
                .entry(std::array::from_fn(|k| p[k].floor() as i64))
                .or_default()
                .push(i);
        }
        let mut shift = vec![Point::<D>::zeros(); points.len()];
        for (i, p) in points.iter().enumerate() {
            let c: [i64; D] = std::array::from_fn(|k| p[k].floor() as i64);
            for code in 0..3usize.pow(D as u32) {
                let mut rest = code;
                let key: [i64; D] = std::array::from_fn(|k| {
                    let o = (rest % 3) as i64 - 1;
                    rest /= 3;
                    c[k] + o
                });
                if let Some(list) = cells.get(&key) {
                    for &j in list {
                        if j == i {
                            continue;
                        }
                        let d = p - points[j];
                        let dist = d.norm();
                        if dist < 1.0 && dist > 0.0 {
                            shift[i] += d * (0.25 * (1.0 - dist) / dist);
                        }
                    }
                }
            }
        }
        for (p, s) in points.iter_mut().zip(&shift) {
            *p += s;
        }
    }
}

/// A star-shaped body of mean radius `radius` with bubbles, filled as chosen by `rng`.
fn blob<const D: usize>(radius: f64, rng: &mut StdRng) -> Vec<Point<D>> {
    // Radius modulation: a few random harmonics of the direction.
    let harmonics: Vec<(Point<D>, f64, f64)> = (0..4)
        .map(|_| {
            let dir = Point::<D>::from_fn(|_, _| rng.gen_range(-1.0..1.0));
            let k = rng.gen_range(1.0..4.0);
            let amp = rng.gen_range(0.0..0.12);
            (dir * k, amp, rng.gen_range(0.0..2.0 * PI))
        })
        .collect();
    let bubbles: Vec<(Point<D>, f64)> = (0..rng.gen_range(0..4))
        .map(|_| {
            let c = Point::<D>::from_fn(|_, _| rng.gen_range(-0.5..0.5) * radius);
            (c, rng.gen_range(1.2..0.35 * radius))
        })
        .collect();
    let inside = |p: &Point<D>| {
        let n = p.norm();
        if n == 0.0 {
            return true;
        }
        let u = p / n;
        let mut rad = radius;
        for (k, amp, phase) in &harmonics {
            rad += radius * amp * (k.dot(&u) + phase).sin();
        }
        n <= rad && bubbles.iter().all(|(c, b)| (p - c).norm() > *b)
    };
    let half = radius * 1.5;
    let mode = rng.gen_range(0..5);
    let mut points: Vec<Point<D>> = if mode == 4 {
        // Random points at the lattice's density, relaxed.
        let volume = (2.0 * half).powi(D as i32);
        let n = volume as usize;
        let mut pts: Vec<Point<D>> = (0..n)
            .map(|_| Point::<D>::from_fn(|_, _| rng.gen_range(-half..half)))
            .collect();
        relax(&mut pts, 12);
        pts
    } else {
        let kind = if mode % 2 == 0 {
            Lattice::Cubic
        } else {
            Lattice::Dense
        };
        let rotate = random_rotation::<D>(rng);
        let mut pts: Vec<Point<D>> = lattice::<D>(kind, half).iter().map(&rotate).collect();
        let amount = [0.0, 0.05, 0.15, 0.3][rng.gen_range(0..4)];
        jitter(&mut pts, amount, rng);
        pts
    };
    points.retain(inside);
    points
}

/// A random divergence-free velocity field: the curl of a few Fourier modes of a vector
/// potential (2D: a stream function), wavelengths 12–40 spacings, speed about 1.
fn random_flow<const D: usize>(rng: &mut StdRng) -> impl Fn(&Point<D>) -> Point<D> {
    let modes: Vec<(Point<D>, Point<D>, f64, f64)> = (0..4)
        .map(|_| {
            let dir = loop {
                let v = Point::<D>::from_fn(|_, _| rng.gen_range(-1.0..1.0));
                if v.norm() > 0.2 && v.norm() <= 1.0 {
                    break v.normalize();
                }
            };
            let k = dir * (2.0 * PI / rng.gen_range(12.0..40.0));
            let a = Point::<D>::from_fn(|_, _| rng.gen_range(-1.0..1.0));
            (k, a, rng.gen_range(0.0..2.0 * PI), rng.gen_range(0.5..1.5))
        })
        .collect();
    move |p: &Point<D>| {
        let mut v = Point::<D>::zeros();
        for (k, a, phase, amp) in &modes {
            let c = amp * (k.dot(p) + phase).cos() / k.norm();
            if D == 2 {
                // ψ = amp sin(k·x + φ)/|k|: u = (∂ψ/∂y, −∂ψ/∂x).
                v[0] += c * k[1];
                v[1] -= c * k[0];
            } else {
                // curl(a sin(k·x + φ)) = cos(k·x + φ) k × a.
                v[0] += c * (k[1] * a[2] - k[2] * a[1]);
                v[1] += c * (k[2] * a[0] - k[0] * a[2]);
                v[2] += c * (k[0] * a[1] - k[1] * a[0]);
            }
        }
        v
    }
}

fn advect<const D: usize>(
    points: &mut [Point<D>],
    time: f64,
    flow: impl Fn(&Point<D>) -> Point<D>,
) {
    let dt = 0.5;
    let steps = (time / dt).ceil() as usize;
    for p in points.iter_mut() {
        let mut x = *p;
        for _ in 0..steps {
            let k1 = flow(&x);
            let k2 = flow(&(x + k1 * (0.5 * dt)));
            let k3 = flow(&(x + k2 * (0.5 * dt)));
            let k4 = flow(&(x + k3 * dt));
            x += (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (dt / 6.0);
        }
        *p = x;
    }
}

/// Curved strips (2D) / sheets (3D) one to three layers thick, filaments, droplets and a
/// pool below them.
fn thin_features<const D: usize>(rng: &mut StdRng) -> Vec<Point<D>> {
    let mut out: Vec<Point<D>> = vec![];
    let spacing_jitter = [0.0, 0.05, 0.15][rng.gen_range(0..3)];
    // A pool: the lower slab.
    let pool_half = if D == 2 { 22.0 } else { 9.0 };
    let depth = rng.gen_range(3.0..6.0);
    for p in lattice::<D>(Lattice::Cubic, pool_half) {
        if p[D - 1] <= -pool_half + depth {
            out.push(p);
        }
    }
    // A sheet / strip of 1–3 layers, bent, above the pool.
    let layers = rng.gen_range(1..=3);
    let bend = rng.gen_range(0.0..0.08);
    let tilt = rng.gen_range(-0.3..0.3);
    let length = if D == 2 { 36 } else { 14 };
    for layer in 0..layers {
        for code in 0..length * if D == 3 { length } else { 1 } {
            let u = (code % length) as f64 - length as f64 / 2.0;
            let w = (code / length) as f64 - length as f64 / 2.0;
            let height = 2.0 + layer as f64 + bend * u * u + tilt * u;
            out.push(Point::<D>::from_fn(|k, _| match (D, k) {
                (_, 0) => u,
                (3, 1) => w,
                _ => height,
            }));
        }
    }
    // Filaments (3D) or a second, one-particle strip (2D), above the sheet.
    let filaments = rng.gen_range(1..4);
    for f in 0..filaments {
        let along = rng.gen_range(0..D - 1);
        let base = Point::<D>::from_fn(|k, _| {
            if k == D - 1 {
                -pool_half + depth + 3.0 + 3.0 * f as f64
            } else {
                rng.gen_range(-3.0..3.0)
            }
        });
        let thick = if D == 3 { rng.gen_range(1..3) } else { 1 };
        let wobble = rng.gen_range(0.0..0.3);
        for s in 0..rng.gen_range(8..20) {
            for t in 0..thick {
                let mut p = base;
                p[along] += s as f64;
                p[D - 1] += 10.0 + wobble * (s as f64 * 0.7).sin() * 3.0 + t as f64 * 0.9;
                if D == 3 {
                    let across = if along == 0 { 1 } else { 0 };
                    p[across] += t as f64 * 0.9;
                }
                out.push(p);
            }
        }
    }
    // Droplets of 1–8 particles.
    for _ in 0..rng.gen_range(4..12) {
        let centre = Point::<D>::from_fn(|k, _| {
            if k == D - 1 {
                rng.gen_range(-pool_half + depth + 4.0..pool_half)
            } else {
                rng.gen_range(-pool_half..pool_half)
            }
        });
        let size = rng.gen_range(1..=8);
        let mut members = vec![centre];
        while members.len() < size {
            let from = members[rng.gen_range(0..members.len())];
            let dir = Point::<D>::from_fn(|_, _| rng.gen_range(-1.0..1.0));
            if dir.norm() > 0.1 {
                members.push(from + dir.normalize() * rng.gen_range(0.8..1.2));
            }
        }
        out.extend(members);
    }
    jitter(&mut out, spacing_jitter, rng);
    out
}

/// Tie radii of the lattices (spacing 1): the radius at which the deepest uncovered point of
/// an interior sphere is reached exactly.
fn tie_radius<const D: usize>(kind: Lattice) -> f64 {
    match (kind, D) {
        (Lattice::Cubic, 2) => 0.5f64.sqrt(),
        (Lattice::Cubic, _) => 0.75f64.sqrt(),
        (Lattice::Dense, 2) => 1.0 / 3f64.sqrt(),
        // FCC: the octahedral hole is at distance √2/2 from its six neighbours.
        (Lattice::Dense, _) => 0.5f64.sqrt(),
    }
}

/// Every generated scene of dimension `D`, seeded by `seed`.
pub fn scenes<const D: usize>(seed: u64) -> Vec<Generated<D>> {
    let mut rng = StdRng::seed_from_u64(seed);
    let radii: &[f64] = if D == 2 {
        &[0.8, 1.0, 1.2, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0]
    } else {
        &[0.8, 1.0, 1.2, 1.5, 1.8, 2.2, 2.8]
    };
    let pick = |rng: &mut StdRng, k: usize| -> Vec<f64> {
        let mut out: Vec<f64> = vec![];
        while out.len() < k {
            let r = radii[rng.gen_range(0..radii.len())];
            if !out.contains(&r) {
                out.push(r);
            }
        }
        out
    };
    let size = |rng: &mut StdRng| {
        if D == 2 {
            rng.gen_range(8.0..18.0)
        } else {
            rng.gen_range(4.5..8.0)
        }
    };
    let mut out = vec![];
    let blobs = if D == 2 { 10 } else { 8 };
    for k in 0..blobs {
        let r0 = size(&mut rng);
        let points = blob::<D>(r0, &mut rng);
        out.push(Generated {
            name: format!("blob{D}d_{k}"),
            points,
            radii: pick(&mut rng, 2),
        });
    }
    let stretched = if D == 2 { 14 } else { 12 };
    for k in 0..stretched {
        let r0 = size(&mut rng);
        let mut points = blob::<D>(r0, &mut rng);
        let flow = random_flow::<D>(&mut rng);
        let time = [8.0, 16.0, 32.0][k % 3];
        advect(&mut points, time, flow);
        out.push(Generated {
            name: format!("stretched{D}d_{k}_t{time}"),
            points,
            radii: pick(&mut rng, 2),
        });
    }
    let thin = 8;
    for k in 0..thin {
        let points = thin_features::<D>(&mut rng);
        out.push(Generated {
            name: format!("thin{D}d_{k}"),
            points,
            radii: pick(&mut rng, 2),
        });
    }
    for (kind, label) in [(Lattice::Cubic, "cubic"), (Lattice::Dense, "dense")] {
        let tie = tie_radius::<D>(kind);
        let half = if D == 2 { 7.0 } else { 4.0 };
        let points = lattice::<D>(kind, half);
        let mut lattice_radii = vec![
            0.55,
            tie * (1.0 - 1e-6),
            tie,
            tie * (1.0 + 1e-6),
            0.9,
            1.0,
            1.3,
            1.7,
            2.0,
        ];
        if D == 2 {
            lattice_radii.push(3.0);
        }
        out.push(Generated {
            name: format!("lattice{D}d_{label}"),
            points,
            radii: lattice_radii,
        });
    }
    out
}
