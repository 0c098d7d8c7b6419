//! Scene generators: only what each scene needs (analytic velocity fields integrated with RK4,
//! lattices, jitter from a seeded generator); no fluid solver.

use boundary_core::{AnyParticleSet, Domain, HalfSpace, ParticleSet, Periodic, Point};
use boundary_core::{Dim, SupportedDim};
use rand::{rngs::StdRng, Rng, SeedableRng};
use std::f64::consts::PI;

/// A generated scene: particles, resolution and how they were made.
#[derive(Debug, Clone)]
pub struct Scene {
    /// Unique short name (also the file stem in `fixtures/`).
    pub name: String,
    /// The particles.
    pub set: AnyParticleSet,
    /// The resolution r.
    pub radius: f64,
    /// Generator name.
    pub generator: &'static str,
    /// Generator parameters, `key=value` separated by `, `.
    pub params: String,
    /// Walls, solids, periodic axes and phases around the particles (the bare cloud for most
    /// scenes): what every method classifies the scene in.
    pub domain: Domain,
}

/// Lattice points of spacing `h` (plus uniform jitter of `±jitter·h` per axis) in the box
/// `[lo, hi]` for which `inside` holds (tested on the unjittered point).
pub fn fill<const D: usize>(
    lo: [f64; D],
    hi: [f64; D],
    h: f64,
    jitter: f64,
    rng: &mut StdRng,
    inside: impl Fn(&Point<D>) -> bool,
) -> Vec<Point<D>> {
    let counts: Vec<usize> = (0..D)
        .map(|a| ((hi[a] - lo[a]) / h).floor() as usize + 1)
        .collect();
    let total: usize = counts.iter().product();
    let mut out = Vec::new();
    for k in 0..total {
        let mut p = Point::<D>::zeros();
        let mut rest = k;
        for a in 0..D {
            p[a] = lo[a] + (rest % counts[a]) as f64 * h;
            rest /= counts[a];
        }
        if inside(&p) {
            if jitter > 0.0 {
                for a in 0..D {
                    p[a] += rng.gen_range(-jitter..=jitter) * h;
                }
            }
            out.push(p);
        }
    }
    out
}

/// Classic fourth-order Runge–Kutta for `dp/dt = v(p, t)` from `t0` to `t1` in `steps` steps.
pub fn rk4<const D: usize>(
    p: Point<D>,
    t0: f64,
    t1: f64,
    steps: usize,
    v: impl Fn(&Point<D>, f64) -> Point<D>,
) -> Point<D> {
    let dt = (t1 - t0) / steps as f64;
    let mut p = p;
    let mut t = t0;
    for _ in 0..steps {
        let k1 = v(&p, t);
        let k2 = v(&(p + k1 * (0.5 * dt)), t + 0.5 * dt);
        let k3 = v(&(p + k2 * (0.5 * dt)), t + 0.5 * dt);
        let k4 = v(&(p + k3 * dt), t + dt);
        p += (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (dt / 6.0);
        t += dt;
    }
    p
}

/// The single-vortex field of Bell, Colella & Glaz (1989) with period `T`: stream function
/// `ψ = sin²(πx) sin²(πy) cos(πt/T)/π`, `u = ∂ψ/∂y`, `v = −∂ψ/∂x`.
pub fn single_vortex(p: &Point<2>, t: f64, period: f64) -> Point<2> {
    let (x, y) = (p[0], p[1]);
    let c = (PI * t / period).cos();
    Point::<2>::new(
        (PI * x).sin().powi(2) * (2.0 * PI * y).sin() * c,
        -(PI * y).sin().powi(2) * (2.0 * PI * x).sin() * c,
    )
}

/// The deformation field of Enright et al. (2002) with period `T`.
pub fn enright(p: &Point<3>, t: f64, period: f64) -> Point<3> {
    let (x, y, z) = (p[0], p[1], p[2]);
    let c = (PI * t / period).cos();
    let s2 = |a: f64| (PI * a).sin().powi(2);
    let s = |a: f64| (2.0 * PI * a).sin();
    Point::<3>::new(
        2.0 * s2(x) * s(y) * s(z) * c,
        -s(x) * s2(y) * s(z) * c,
        -s(x) * s(y) * s2(z) * c,
    )
}

fn set<const D: usize>(points: Vec<Point<D>>) -> AnyParticleSet
where
    Dim<D>: SupportedDim,
{
    ParticleSet::new(points)
        .expect("generated coordinates are finite")
        .to_any()
}

/// A set of `coarse` particles (radius factor 2) and `fine` ones (factor 1).
fn graded<const D: usize>(coarse: Vec<Point<D>>, fine: Vec<Point<D>>) -> AnyParticleSet
where
    Dim<D>: SupportedDim,
{
    let radii = [vec![2.0; coarse.len()], vec![1.0; fine.len()]].concat();
    ParticleSet::new([coarse, fine].concat())
        .and_then(|s| s.with_radii(radii))
        .expect("generated coordinates and radii are valid")
        .to_any()
}

fn rows<const D: usize>(rows: &[[f64; D]]) -> Vec<Point<D>> {
    rows.iter().map(|r| Point::<D>::from(*r)).collect()
}

/// Spacing of the 2D analytic-flow scenes and their resolution factor `r = 1.5 h`.
const H2: f64 = 0.005;
/// Spacing of the 3D analytic-flow scenes.
const H3: f64 = 0.0125;
/// `r / h` of the generated fluid scenes.
const R_OVER_H: f64 = 1.5;

/// The disk of radius 0.15 at (0.5, 0.75), filled at spacing `H2` with 5% jitter.
fn vortex_disk(rng: &mut StdRng) -> Vec<Point<2>> {
    let c = Point::<2>::new(0.5, 0.75);
    fill([0.35, 0.6], [0.65, 0.9], H2, 0.05, rng, |p| {
        (p - c).norm() <= 0.15
    })
}

/// Every generated scene, deterministically (fixed seeds).
pub fn all_scenes() -> Vec<Scene> {
    let mut scenes = Vec::new();
    // --- 2D single vortex (T = 8) at several times.
    let period = 8.0;
    let disk = vortex_disk(&mut StdRng::seed_from_u64(1));
    for t in [0.0, 1.0, 2.0, 4.0, 8.0] {
        let steps = (t / 0.005) as usize;
        let points = disk
            .iter()
            .map(|&p| rk4(p, 0.0, t, steps.max(1), |q, s| single_vortex(q, s, period)))
            .collect();
        scenes.push(Scene {
            domain: Domain::new(),
            name: format!("vortex2d_t{t}"),
            set: set(points),
            radius: R_OVER_H * H2,
            generator: "single_vortex",
            params: format!("T={period}, t={t}, h={H2}, jitter=0.05h, rk4_dt=0.005, seed=1"),
        });
    }
    // --- Zalesak slotted disk, initial and rotated by 45° about (0.5, 0.5).
    let mut rng = StdRng::seed_from_u64(2);
    let c = Point::<2>::new(0.5, 0.75);
    let zalesak = fill([0.35, 0.6], [0.65, 0.9], H2, 0.05, &mut rng, |p| {
        let in_disk = (p - c).norm() <= 0.15;
        let in_slot = (p[0] - 0.5).abs() <= 0.025 && p[1] <= 0.85;
        in_disk && !in_slot
    });
    for degrees in [0.0f64, 45.0] {
        let (s, co) = degrees.to_radians().sin_cos();
        let points = zalesak
            .iter()
            .map(|p| {
                let (x, y) = (p[0] - 0.5, p[1] - 0.5);
                Point::<2>::new(0.5 + co * x - s * y, 0.5 + s * x + co * y)
            })
            .collect();
        scenes.push(Scene {
            domain: Domain::new(),
            name: format!("zalesak2d_rot{degrees}"),
            set: set(points),
            radius: R_OVER_H * H2,
            generator: "zalesak",
            params: format!(
                "R=0.15, slot=0.05x0.25, rotation={degrees}deg, h={H2}, jitter=0.05h, seed=2"
            ),
        });
    }
    // --- 3D Enright deformation (T = 3) at t = 0, 0.75, 1.5.
    let period = 3.0;
    let c3 = Point::<3>::new(0.35, 0.35, 0.35);
    let ball = fill(
        [0.2, 0.2, 0.2],
        [0.5, 0.5, 0.5],
        H3,
        0.05,
        &mut StdRng::seed_from_u64(3),
        |p| (p - c3).norm() <= 0.15,
    );
    for t in [0.0, 0.75, 1.5] {
        let steps = (t / 0.005) as usize;
        let points = ball
            .iter()
            .map(|&p| rk4(p, 0.0, t, steps.max(1), |q, s| enright(q, s, period)))
            .collect();
        scenes.push(Scene {
            domain: Domain::new(),
            name: format!("enright3d_t{t}"),
            set: set(points),
            radius: R_OVER_H * H3,
            generator: "enright",
            params: format!("T={period}, t={t}, h={H3}, jitter=0.05h, rk4_dt=0.005, seed=3"),
        });
    }
    // --- A ball with an inner bubble.
    let mut rng = StdRng::seed_from_u64(4);
    let bubble = Point::<3>::new(0.2, 0.0, 0.0);
    let points = fill([-1.0; 3], [1.0; 3], 0.1, 0.1, &mut rng, |p| {
        p.norm() <= 1.0 && (p - bubble).norm() >= 0.45
    });
    scenes.push(Scene {
        domain: Domain::new(),
        name: "ball_bubble3d".into(),
        set: set(points),
        radius: 0.15,
        generator: "ball_with_bubble",
        params: "R=1, bubble R=0.45 at (0.2,0,0), h=0.1, jitter=0.1h, seed=4".into(),
    });
    // --- A single-layer sheet, a ligament and isolated droplets (3D).
    let mut rng = StdRng::seed_from_u64(5);
    let mut sheet: Vec<Point<3>> = fill([0.0; 2], [2.9, 2.9], 0.1, 0.1, &mut rng, |_| true)
        .into_iter()
        .map(|p| Point::<3>::new(p[0], p[1], 0.02 * (3.0 * p[0]).sin()))
        .collect();
    let thin = sheet.len();
    // Ligament: a line of 40 particles along x above the sheet.
    sheet.extend((0..40).map(|k| Point::<3>::new(k as f64 * 0.08, 1.5, 1.0)));
    // Droplets: a single particle, a pair, a tetrahedron, and a small jittered ball.
    sheet.push(Point::<3>::new(4.0, 4.0, 4.0));
    sheet.extend(rows(&[[5.0, 4.0, 4.0], [5.1, 4.0, 4.0]]));
    let e = 0.1;
    sheet.extend(rows(&[
        [6.0, 4.0, 4.0],
        [6.0 + e, 4.0, 4.0],
        [6.0 + e / 2.0, 4.0 + e * 0.866, 4.0],
        [6.0 + e / 2.0, 4.0 + e * 0.289, 4.0 + e * 0.816],
    ]));
    let c = Point::<3>::new(7.0, 4.0, 4.0);
    sheet.extend(fill(
        [6.7, 3.7, 3.7],
        [7.3, 3.7 + 0.6, 4.3],
        0.1,
        0.1,
        &mut rng,
        |p| (p - c).norm() <= 0.25,
    ));
    scenes.push(Scene {
        domain: Domain::new(),
        name: "sheet_ligament_droplets3d".into(),
        set: set(sheet),
        radius: 0.15,
        generator: "sheet_ligament_droplets",
        params: format!(
            "sheet 30x30 h=0.1 jitter=0.1h ({thin} particles), ligament 40 at 0.08, droplets \
             1+2+4+ball R=0.25, seed=5"
        ),
    });
    // --- Hard cases.
    let square = rows(&crate::square_lattice(16, 1.0));
    scenes.push(Scene {
        domain: Domain::new(),
        name: "square_lattice_tie2d".into(),
        set: set(square),
        radius: std::f64::consts::FRAC_1_SQRT_2,
        generator: "lattice",
        params: "16x16, a=1, r=a/sqrt(2) (exact ties)".into(),
    });
    let cubic = rows(&crate::cubic_lattice(10, 1.0));
    scenes.push(Scene {
        domain: Domain::new(),
        name: "cubic_lattice_tie3d".into(),
        set: set(cubic),
        radius: 3f64.sqrt() / 2.0,
        generator: "lattice",
        params: "10x10x10, a=1, r=a*sqrt(3)/2 (exact ties)".into(),
    });
    let one = rows(&crate::cubic_lattice(6, 1.0));
    let six = one.iter().chain(one.iter()).copied().collect();
    scenes.push(Scene {
        domain: Domain::new(),
        name: "duplicates3d".into(),
        set: set(six),
        radius: 1.2,
        generator: "lattice",
        params: "6x6x6, a=1, every particle twice, r=1.2".into(),
    });
    let mut rng = StdRng::seed_from_u64(6);
    let offset = Point::<3>::new(1e6, -1e6, 1e6);
    let far = fill([-0.08; 3], [0.08; 3], 0.01, 0.1, &mut rng, |p| {
        p.norm() <= 0.08
    })
    .into_iter()
    .map(|p| p + offset)
    .collect();
    scenes.push(Scene {
        domain: Domain::new(),
        name: "far_offset3d".into(),
        set: set(far),
        radius: 0.012,
        generator: "ball_offset",
        params: "ball R=0.08, h=0.01, jitter=0.1h, translated by (1e6,-1e6,1e6), seed=6".into(),
    });
    // --- Graded resolution (per-particle radii): coarse particles (spacing 2h, radius factor
    // 2) under a refined zone (spacing h, factor 1) at the free surface, plus a fine droplet.
    let mut rng = StdRng::seed_from_u64(7);
    let coarse = fill([0.0, 0.0], [0.3, 0.145], 2.0 * H2, 0.05, &mut rng, |_| true);
    let fine = fill([0.0, 0.15], [0.3, 0.25], H2, 0.05, &mut rng, |_| true);
    let drop_c = Point::<2>::new(0.15, 0.3);
    let drop = fill([0.12, 0.27], [0.18, 0.33], H2, 0.05, &mut rng, |p| {
        (p - drop_c).norm() <= 0.02
    });
    scenes.push(Scene {
        domain: Domain::new(),
        name: "graded_column2d".into(),
        set: graded(coarse, [fine, drop].concat()),
        radius: R_OVER_H * H2,
        generator: "graded",
        params: format!(
            "h={H2}: spacing 2h, radius factor 2 for y<0.15; spacing h, factor 1 up to y=0.25; \
             droplet R=0.02 at (0.15,0.3); jitter=0.05h, seed=7"
        ),
    });
    let mut rng = StdRng::seed_from_u64(8);
    let coarse = fill([0.0; 3], [0.2, 0.2, 0.09], 2.0 * H3, 0.05, &mut rng, |_| {
        true
    });
    let fine = fill(
        [0.0, 0.0, 0.1],
        [0.2, 0.2, 0.15],
        H3,
        0.05,
        &mut rng,
        |_| true,
    );
    let drop_c = Point::<3>::new(0.1, 0.1, 0.21);
    let drop = fill(
        [0.06, 0.06, 0.17],
        [0.14, 0.14, 0.25],
        H3,
        0.05,
        &mut rng,
        |p| (p - drop_c).norm() <= 0.035,
    );
    scenes.push(Scene {
        domain: Domain::new(),
        name: "graded_pool3d".into(),
        set: graded(coarse, [fine, drop].concat()),
        radius: R_OVER_H * H3,
        generator: "graded",
        params: format!(
            "h={H3}: spacing 2h, radius factor 2 for z<0.1; spacing h, factor 1 up to z=0.15; \
             droplet R=0.035 at (0.1,0.1,0.21); jitter=0.05h, seed=8"
        ),
    });
    scenes.push(Scene {
        domain: Domain::new(),
        name: "tiny2d".into(),
        set: set(rows(&[[0.0, 0.0], [1.0, 0.0], [0.5, 0.8]])),
        radius: 1.0,
        generator: "explicit",
        params: "3 particles".into(),
    });
    scenes.push(Scene {
        domain: Domain::new(),
        name: "tiny3d".into(),
        set: set(rows(&[[0.0, 0.0, 0.0], [1.5, 0.0, 0.0]])),
        radius: 1.0,
        generator: "explicit",
        params: "2 particles 1.5r apart".into(),
    });
    scenes.extend(domain_scenes());
    scenes
}

/// The centres `(k + 1/2)·h` of the integer cells `k` with `lo <= k < hi` per axis for which
/// `keep(k)` holds, x fastest, each moved by up to `±jitter·h` per axis (not at all, and no
/// draw, when `jitter` is 0). Integer cells keep fluid, walls and solid faces on one lattice
/// without a rounded count.
fn cell_centres<const D: usize>(
    lo: [i64; D],
    hi: [i64; D],
    h: f64,
    jitter: f64,
    rng: &mut StdRng,
    keep: impl Fn([i64; D]) -> bool,
) -> Vec<Point<D>> {
    let counts: [i64; D] = std::array::from_fn(|a| (hi[a] - lo[a]).max(0));
    let total: i64 = counts.iter().product();
    let mut out = Vec::new();
    for k in 0..total {
        let mut rest = k;
        let cell: [i64; D] = std::array::from_fn(|a| {
            let c = lo[a] + rest % counts[a];
            rest /= counts[a];
            c
        });
        if !keep(cell) {
            continue;
        }
        let mut p = Point::<D>::from_fn(|a, _| (cell[a] as f64 + 0.5) * h);
        if jitter > 0.0 {
            for a in 0..D {
                p[a] += rng.gen_range(-jitter..=jitter) * h;
            }
        }
        out.push(p);
    }
    out
}

/// Whether `cell` lies in the box `[lo, hi)` of cells.
fn in_box<const D: usize>(cell: [i64; D], lo: [i64; D], hi: [i64; D]) -> bool {
    (0..D).all(|a| cell[a] >= lo[a] && cell[a] < hi[a])
}

/// The wall particles of an open-topped tank of `inner` cells (`[0, inner)` per axis, the
/// last axis vertical): `layers` unjittered layers of cells around the floor and the sides,
/// up to the tank's rim.
fn tank_walls<const D: usize>(inner: [i64; D], layers: i64, h: f64) -> AnyParticleSet
where
    Dim<D>: SupportedDim,
{
    let lo: [i64; D] = [-layers; D];
    let hi: [i64; D] = std::array::from_fn(|a| {
        if a == D - 1 {
            inner[a]
        } else {
            inner[a] + layers
        }
    });
    let mut unused = StdRng::seed_from_u64(0);
    set(cell_centres(lo, hi, h, 0.0, &mut unused, |c| {
        !in_box(c, [0; D], inner)
    }))
}

/// A jittered block of about `n` particles (spacing 1, jitter ±0.15, `s × s × 2s` cells, z up)
/// resting in an open-topped tank of three layers of unjittered wall particles, up to the
/// block's top, seeded: the scale tier's measure of what walls cost. Returns the fluid, the
/// walls and the tank's inner faces as solid half-spaces (on the cell faces: `x<-0.5`,
/// `x>s-0.5`, `y<-0.5`, `y>s-0.5`, `z<-0.5`).
pub fn block_in_tank(n: usize, seed: u64) -> (ParticleSet<3>, ParticleSet<3>, Domain) {
    let side = ((n as f64 / 2.0).cbrt().round() as i64).max(1);
    let inner = [side, side, 2 * side];
    let mut rng = StdRng::seed_from_u64(seed);
    let fluid = cell_centres([0; 3], inner, 1.0, 0.15, &mut rng, |_| true);
    // Cell centres sit at half-integers: shift the whole scene by −0.5 so that the fluid's
    // lattice is the integer one and the inner faces are at −0.5 and s − 0.5.
    let shift = |p: &Point<3>| Point::<3>::from_fn(|a, _| p[a] - 0.5);
    let fluid = ParticleSet::new(fluid.iter().map(shift).collect())
        .expect("generated coordinates are finite");
    let walls = match tank_walls(inner, 3, 1.0) {
        AnyParticleSet::D3(w) => ParticleSet::new(w.positions().iter().map(shift).collect())
            .expect("generated coordinates are finite"),
        AnyParticleSet::D2(_) => unreachable!("a 3D tank"),
    };
    let edge = side as f64 - 0.5;
    let faces = [
        HalfSpace::new(0, true, -0.5),
        HalfSpace::new(0, false, edge),
        HalfSpace::new(1, true, -0.5),
        HalfSpace::new(1, false, edge),
        HalfSpace::new(2, true, -0.5),
    ];
    let solids = faces
        .into_iter()
        .map(|h| h.expect("finite faces"))
        .fold(Domain::new(), Domain::with_solid);
    (fluid, walls, solids)
}

/// Spacing of the 2D domain scenes.
const H_DOMAIN2: f64 = 0.01;
/// Spacing of the 3D domain scenes.
const H_DOMAIN3: f64 = 0.02;

/// The scenes with a domain (see [`boundary_core::domain`]): fluid in a tank of wall particles
/// or of solid half-spaces, a periodic channel, a two-phase pool. Fluid on a lattice of cells
/// of spacing `h` jittered by ±0.05h, walls unjittered on the same lattice, the tank's inner
/// faces on cell faces (half a spacing from the outermost fluid layer), `r = 1.5h`.
fn domain_scenes() -> Vec<Scene> {
    let mut scenes = Vec::new();
    let h = H_DOMAIN2;
    // --- 2D dam break: a 40 x 60 column in the corner of a 100 x 70 tank, 3 wall layers.
    let mut rng = StdRng::seed_from_u64(9);
    let fluid = cell_centres([0, 0], [40, 60], h, 0.05, &mut rng, |_| true);
    scenes.push(Scene {
        name: "tank_dambreak2d_walls".into(),
        set: set(fluid),
        radius: R_OVER_H * h,
        generator: "tank_dambreak",
        params: format!(
            "h={h}: water column 40x60 cells at the left of a tank of 100x70 cells (inner \
             faces x=0, x=1, y=0), 3 layers of wall particles; jitter=0.05h (fluid), seed=9"
        ),
        domain: Domain::new().with_walls(tank_walls([100, 70], 3, h)),
    });
    // --- 3D dam break: a 10 x 15 x 18 column across the width of a 20 x 15 x 20 tank (z up).
    let h = H_DOMAIN3;
    let column = || {
        let mut rng = StdRng::seed_from_u64(10);
        set(cell_centres(
            [0, 0, 0],
            [10, 15, 18],
            h,
            0.05,
            &mut rng,
            |_| true,
        ))
    };
    scenes.push(Scene {
        name: "tank_dambreak3d_walls".into(),
        set: column(),
        radius: R_OVER_H * h,
        generator: "tank_dambreak",
        params: format!(
            "h={h}: water column 10x15x18 cells across the width of a tank of 20x15x20 cells \
             (z up), 2 layers of wall particles; jitter=0.05h (fluid), seed=10"
        ),
        domain: Domain::new().with_walls(tank_walls([20, 15, 20], 2, h)),
    });
    let solid = |text: &str| HalfSpace::parse(text).expect("a valid half-space");
    let (x1, y1) = (20.0 * h, 15.0 * h);
    scenes.push(Scene {
        name: "tank_dambreak3d_solids".into(),
        set: column(),
        radius: R_OVER_H * h,
        generator: "tank_dambreak",
        params: format!(
            "h={h}: the column of tank_dambreak3d_walls in the same tank given as 5 solid \
             half-spaces at its inner faces; jitter=0.05h, seed=10"
        ),
        domain: Domain::new()
            .with_solid(solid("x<0"))
            .with_solid(solid(&format!("x>{x1}")))
            .with_solid(solid("y<0"))
            .with_solid(solid(&format!("y>{y1}")))
            .with_solid(solid("z<0")),
    });
    // --- 2D periodic channel: 100 cells of period 1 in x, a wave on the free surface, a
    // floor of 3 wall layers.
    let h = H_DOMAIN2;
    let columns = 100;
    let period = columns as f64 * h;
    let surface = |x: f64| 0.2 + 0.03 * (2.0 * PI * x / period).sin();
    let mut rng = StdRng::seed_from_u64(11);
    let fluid = cell_centres([0, 0], [columns, 30], h, 0.05, &mut rng, |c| {
        (c[1] as f64 + 0.5) * h <= surface((c[0] as f64 + 0.5) * h)
    });
    let mut unused = StdRng::seed_from_u64(0);
    let floor = cell_centres([0, -3], [columns, 0], h, 0.0, &mut unused, |_| true);
    scenes.push(Scene {
        name: "channel2d_periodic".into(),
        set: set(fluid),
        radius: R_OVER_H * h,
        generator: "periodic_channel",
        params: format!(
            "h={h}: periodic in x over [0, {period}] ({columns} cells), free surface \
             y = 0.2 + 0.03 sin(2 pi x), 3 layers of floor walls; jitter=0.05h (fluid), seed=11"
        ),
        domain: Domain::new()
            .with_walls(set(floor))
            .with_periodic(Periodic::new(0, 0.0, period).expect("a valid period")),
    });
    // --- 2D two-phase pool: a heavy layer (phase 0) under a light one (phase 1), a heavy
    // droplet inside the light layer, in a tank of 60 x 45 cells with 3 wall layers.
    let mut rng = StdRng::seed_from_u64(12);
    let drop_c = [0.3, 0.3];
    let drop_r = 0.05;
    let in_drop = |c: [i64; 2]| {
        let (x, y) = ((c[0] as f64 + 0.5) * h, (c[1] as f64 + 0.5) * h);
        (x - drop_c[0]).hypot(y - drop_c[1]) <= drop_r
    };
    let cells: Vec<[i64; 2]> = (0..60 * 40).map(|k| [k % 60, k / 60]).collect();
    let phases: Vec<u32> = cells
        .iter()
        .map(|&c| u32::from(c[1] >= 20 && !in_drop(c)))
        .collect();
    let fluid = cell_centres([0, 0], [60, 40], h, 0.05, &mut rng, |_| true);
    scenes.push(Scene {
        name: "pool_droplet2d_phases".into(),
        set: set(fluid),
        radius: R_OVER_H * h,
        generator: "two_phase_pool",
        params: format!(
            "h={h}: 60x40 cells, phase 0 below y=0.2, phase 1 above, a phase-0 droplet \
             R={drop_r} at ({}, {}), in a tank of 60x45 cells with 3 layers of wall \
             particles; jitter=0.05h, seed=12",
            drop_c[0], drop_c[1]
        ),
        domain: Domain::new()
            .with_walls(tank_walls([60, 45], 3, h))
            .with_phases(phases),
    });
    scenes
}

/// A 3D jittered cubic lattice (spacing 1, jitter `±jitter` per axis) filling the ball with
/// about `n` particles, for benchmarks; also returns the ball's radius.
pub fn jittered_lattice_ball(n: usize, jitter: f64, seed: u64) -> (ParticleSet<3>, f64) {
    let radius = (3.0 * n as f64 / (4.0 * PI)).cbrt();
    let mut rng = StdRng::seed_from_u64(seed);
    let points = fill([-radius; 3], [radius; 3], 1.0, jitter, &mut rng, |p| {
        p.norm() <= radius
    });
    (
        ParticleSet::new(points).expect("generated coordinates are finite"),
        radius,
    )
}

/// A 2D jittered square lattice (spacing 1, unjittered points within `radius` of the origin,
/// jitter `±jitter` per axis), seeded: the disc counterpart of [`jittered_lattice_ball`].
pub fn jittered_lattice_disc(radius: f64, jitter: f64, seed: u64) -> ParticleSet<2> {
    let mut rng = StdRng::seed_from_u64(seed);
    let side = radius.floor();
    let points = fill([-side; 2], [side; 2], 1.0, jitter, &mut rng, |p| {
        p.norm() <= radius
    });
    ParticleSet::new(points).expect("generated coordinates are finite")
}

/// A time sequence for incremental detection: the jittered sphere of [`enright_sphere`]
/// (about `n` particles, spacing `h`) at `t = 0.5`, then `steps` more frames advected by
/// [`enright`] (T = 3), each step's `dt` chosen so that the fastest particle moves
/// `displacement·h` (to first order: `dt = displacement·h / max |v|`, then 4 RK4 substeps).
/// Returns the `steps + 1` frames and `h`; the scenes use `r = 1.5h`.
pub fn enright_sequence(n: usize, displacement: f64, steps: usize) -> (Vec<ParticleSet<3>>, f64) {
    use rayon::prelude::*;
    let period = 3.0;
    let (first, h) = enright_sphere(n, 0.5, 0.01);
    let mut t = 0.5;
    let mut points = first.into_positions();
    let mut frames = vec![ParticleSet::new(points.clone()).expect("finite")];
    for _ in 0..steps {
        let vmax = points
            .par_iter()
            .map(|p| enright(p, t, period).norm())
            .reduce(|| 0.0, f64::max);
        let dt = if vmax > 0.0 {
            displacement * h / vmax
        } else {
            0.0
        };
        points = points
            .into_par_iter()
            .map(|p| rk4(p, t, t + dt, 4, |q, s| enright(q, s, period)))
            .collect();
        t += dt;
        frames.push(ParticleSet::new(points.clone()).expect("finite"));
    }
    (frames, h)
}

/// The scale-tier analogue of the JCP Enright test (JCP Fig. 14, Table 3): the sphere of radius
/// 0.15 at (0.35, 0.35, 0.35) of the `enright3d_*` scenes, filled with about `n` particles (the
/// spacing `h` chosen from the sphere's volume, jitter ±0.05h, seed 3) and advected by
/// [`enright`] (T = 3) to time `t` with RK4 steps of `dt` (in parallel). Returns the set and `h`;
/// the scenes use `r = 1.5h`, as the fixtures do.
pub fn enright_sphere(n: usize, t: f64, dt: f64) -> (ParticleSet<3>, f64) {
    use rayon::prelude::*;
    let (radius, period) = (0.15, 3.0);
    let c = Point::<3>::new(0.35, 0.35, 0.35);
    let volume = 4.0 / 3.0 * PI * radius * radius * radius;
    let h = (volume / n.max(1) as f64).cbrt();
    let start = fill(
        std::array::from_fn(|a| c[a] - radius),
        std::array::from_fn(|a| c[a] + radius),
        h,
        0.05,
        &mut StdRng::seed_from_u64(3),
        |p| (p - c).norm() <= radius,
    );
    let steps = ((t / dt).ceil() as usize).max(1);
    let points = start
        .into_par_iter()
        .map(|p| rk4(p, 0.0, t, steps, |q, s| enright(q, s, period)))
        .collect();
    (
        ParticleSet::new(points).expect("generated coordinates are finite"),
        h,
    )
}
