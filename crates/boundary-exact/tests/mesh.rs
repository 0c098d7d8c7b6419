//! `exact` with solid meshes: a box mesh against the same box as half-spaces (the exact
//! path), and an icosphere obstacle against a dense-sampling oracle written here (its own
//! inside test: the icosphere is convex, so a point is inside iff it is behind every face).

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_core::{
    AnyParticleSet, BoundaryDetector, DetectError, Domain, HalfSpace, ParticleSet, Point, Radius,
    SolidMesh,
};
use boundary_exact::ExactDetector;
use std::sync::Arc;

/// A small deterministic generator.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A jittered `n³` block of spacing 1 starting at `offset` on every axis.
fn block(n: usize, offset: f64, jitter: f64, seed: u64) -> Vec<Point<3>> {
    let mut rng = Lcg(seed);
    (0..n * n * n)
        .map(|k| {
            let c = [k % n, (k / n) % n, k / (n * n)];
            Point::<3>::from_fn(|a, _| offset + c[a] as f64 + jitter * (rng.next() - 0.5))
        })
        .collect()
}

/// The box `[lo, hi]` as 12 outward triangles.
fn box_mesh(lo: [f64; 3], hi: [f64; 3]) -> SolidMesh {
    let v: Vec<[f64; 3]> = (0..8)
        .map(|k| {
            [
                if k & 1 == 0 { lo[0] } else { hi[0] },
                if k & 2 == 0 { lo[1] } else { hi[1] },
                if k & 4 == 0 { lo[2] } else { hi[2] },
            ]
        })
        .collect();
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let t = quads
        .iter()
        .flat_map(|f| [[f[0], f[1], f[2]], [f[0], f[2], f[3]]])
        .collect();
    SolidMesh::new(v, t).unwrap()
}

fn labels(set: &ParticleSet<3>, domain: &Domain, r: f64) -> Vec<bool> {
    ExactDetector::default()
        .detect_in(
            &AnyParticleSet::from(set.clone()),
            domain,
            Radius::new(r).unwrap(),
        )
        .unwrap()
        .detection
        .labels
        .into_vec()
}

fn half_spaces(domain: Domain, text: &[&str]) -> Domain {
    text.iter()
        .fold(domain, |d, h| d.with_solid(HalfSpace::parse(h).unwrap()))
}

/// The tank `[0, L]^3` (L = n − 1 + 0.5, the block 0.25 from every wall) with its floor
/// `z < 0` and its wall `x > L` given once as half-spaces and once as two box meshes that
/// agree with them wherever a sphere reaches. Near-ties excluded: particles whose label
/// with the half-spaces changes when those two planes move by `±1e-4·r`.
#[test]
fn box_meshes_give_the_labels_of_the_same_half_spaces() {
    let n = 7;
    let side = (n - 1) as f64 + 0.5;
    let mut checked_near = 0;
    let mut excluded = 0;
    let mut total = 0;
    for (seed, r, jitter) in [
        (1u64, 0.8, 0.3),
        (2, 1.0, 0.5),
        (3, 1.2, 0.6),
        (4, 0.7, 0.2),
    ] {
        let set = ParticleSet::new(block(n, 0.25, jitter, seed)).unwrap();
        let others = ["x<0", "y<0", "y>L", "z>L"].map(|h| h.replace('L', &side.to_string()));
        let others: Vec<&str> = others.iter().map(String::as_str).collect();
        let with = |floor: f64, wall: f64| {
            let d = half_spaces(Domain::new(), &others);
            let d = d
                .with_solid(HalfSpace::new(2, true, floor).unwrap())
                .with_solid(HalfSpace::new(0, false, wall).unwrap());
            labels(&set, &d, r)
        };
        let planes = with(0.0, side);
        let inner = with(-1e-4 * r, side + 1e-4 * r);
        let outer = with(1e-4 * r, side - 1e-4 * r);
        let big = side + 2.0;
        let floor = box_mesh([-2.0, -2.0, -2.0], [big, big, 0.0]);
        let wall = box_mesh([side, -2.0, -2.0], [big, big, big]);
        let meshed = half_spaces(Domain::new(), &others)
            .with_solid_mesh(Arc::new(floor))
            .with_solid_mesh(Arc::new(wall));
        let got = labels(&set, &meshed, r);
        for i in 0..set.len() {
            total += 1;
            if inner[i] != outer[i] {
                excluded += 1;
                continue;
            }
            let p = set.positions()[i];
            if p[2] <= r * 1.001 || p[0] >= side - r * 1.001 {
                checked_near += 1;
            }
            assert_eq!(
                got[i], planes[i],
                "seed {seed} r {r}: particle {i} at {p:?}: mesh {} half-spaces {}",
                got[i], planes[i]
            );
        }
    }
    assert!(
        checked_near > 300,
        "{checked_near} particles near the meshes"
    );
    assert!(excluded * 50 < total, "{excluded} near-ties of {total}");
}

/// An icosphere: the icosahedron subdivided `levels` times, pushed onto the sphere.
fn icosphere(centre: [f64; 3], radius: f64, levels: usize) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let g = (1.0 + 5f64.sqrt()) / 2.0;
    let mut v: Vec<[f64; 3]> = vec![
        [-1.0, g, 0.0],
        [1.0, g, 0.0],
        [-1.0, -g, 0.0],
        [1.0, -g, 0.0],
        [0.0, -1.0, g],
        [0.0, 1.0, g],
        [0.0, -1.0, -g],
        [0.0, 1.0, -g],
        [g, 0.0, -1.0],
        [g, 0.0, 1.0],
        [-g, 0.0, -1.0],
        [-g, 0.0, 1.0],
    ];
    let mut t: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    let unit = |p: [f64; 3]| {
        let n = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        p.map(|c| c / n)
    };
    v = v.into_iter().map(unit).collect();
    for _ in 0..levels {
        let mut mid = std::collections::HashMap::new();
        let mut next = Vec::new();
        let mut midpoint = |a: u32, b: u32, v: &mut Vec<[f64; 3]>| {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (p, q) = (v[a as usize], v[b as usize]);
                v.push(unit([p[0] + q[0], p[1] + q[1], p[2] + q[2]]));
                (v.len() - 1) as u32
            })
        };
        for [a, b, c] in t {
            let ab = midpoint(a, b, &mut v);
            let bc = midpoint(b, c, &mut v);
            let ca = midpoint(c, a, &mut v);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        t = next;
    }
    let v = v
        .into_iter()
        .map(|p| [0, 1, 2].map(|k| centre[k] + radius * p[k]))
        .collect();
    (v, t)
}

/// The oracle's view of one point `x` of `S_i`: the smallest clearance from the other balls
/// and from the convex mesh (its largest face-plane distance: positive outside, a lower
/// bound of the distance there), in units of `r`.
fn oracle_score(
    x: [f64; 3],
    others: &[[f64; 3]],
    r: f64,
    planes: &[([f64; 3], f64)],
    best: f64,
) -> f64 {
    let mut s = f64::INFINITY;
    for q in others {
        let d = ((x[0] - q[0]).powi(2) + (x[1] - q[1]).powi(2) + (x[2] - q[2]).powi(2)).sqrt();
        s = s.min((d - r) / r);
        if s <= best {
            return s;
        }
    }
    let outside = planes
        .iter()
        .map(|(n, c)| n[0] * x[0] + n[1] * x[1] + n[2] * x[2] - c)
        .fold(f64::NEG_INFINITY, f64::max);
    s.min(outside / r)
}

/// A jittered block around an icosphere obstacle (particles deep inside removed, a few left
/// just inside its surface). For every particle whose ball meets the sphere's surface, the
/// oracle samples `S_i` densely (a random-rotation-free latitude–longitude grid of about
/// 40,000 points, unrelated to exact's sample): a point clear of every ball and of the mesh
/// by `1e-3·r` proves boundary; every sample covered by `0.015·r` or more proves interior (a
/// point of `S_i` lies within about `0.012` rad of a sample, and the clearance, a distance over
/// `r`, changes by at most that much between them); others are not compared (counted).
#[test]
fn an_icosphere_obstacle_matches_a_dense_sampling_oracle() {
    let n = 8;
    let centre = [3.6, 3.4, 3.5];
    let radius = 2.1;
    let (v, t) = icosphere(centre, radius, 3);
    let planes: Vec<([f64; 3], f64)> = t
        .iter()
        .map(|tri| {
            let [a, b, c] = tri.map(|k| v[k as usize]);
            let e1 = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let e2 = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
            let nn = [
                e1[1] * e2[2] - e1[2] * e2[1],
                e1[2] * e2[0] - e1[0] * e2[2],
                e1[0] * e2[1] - e1[1] * e2[0],
            ];
            let len = (nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]).sqrt();
            let nn = nn.map(|c| c / len);
            (nn, nn[0] * a[0] + nn[1] * a[1] + nn[2] * a[2])
        })
        .collect();
    let mesh = Arc::new(SolidMesh::new(v, t).unwrap());
    assert!(!mesh.was_flipped());
    let mut compared = 0;
    let mut skipped = 0;
    let mut witness_boundary = 0;
    let mut interior_near = 0;
    for (seed, r, jitter) in [(11u64, 0.9, 0.4), (12, 1.2, 0.6)] {
        let points: Vec<Point<3>> = block(n, 0.0, jitter, seed)
            .into_iter()
            .filter(|p| {
                let d = ((p[0] - centre[0]).powi(2)
                    + (p[1] - centre[1]).powi(2)
                    + (p[2] - centre[2]).powi(2))
                .sqrt();
                d > radius - 0.35
            })
            .collect();
        let set = ParticleSet::new(points.clone()).unwrap();
        let domain = Domain::new().with_solid_mesh(mesh.clone());
        let got = labels(&set, &domain, r);
        let plain = labels(&set, &Domain::new(), r);
        let grid = 200;
        let dirs: Vec<[f64; 3]> = (0..grid)
            .flat_map(|a| {
                let theta = std::f64::consts::PI * (a as f64 + 0.5) / grid as f64;
                let m = ((2.0 * grid as f64 * theta.sin()).ceil() as usize).max(1);
                (0..m).map(move |b| {
                    let phi = 2.0 * std::f64::consts::PI * (b as f64 + 0.5) / m as f64;
                    [
                        theta.sin() * phi.cos(),
                        theta.sin() * phi.sin(),
                        theta.cos(),
                    ]
                })
            })
            .collect();
        for (i, p) in points.iter().enumerate() {
            let d = ((p[0] - centre[0]).powi(2)
                + (p[1] - centre[1]).powi(2)
                + (p[2] - centre[2]).powi(2))
            .sqrt();
            if (d - radius).abs() > r * 1.05 {
                continue;
            }
            let others: Vec<[f64; 3]> = points
                .iter()
                .filter(|q| *q != p && (*q - p).norm() <= 2.0 * r)
                .map(|q| [q[0], q[1], q[2]])
                .collect();
            let mut best = f64::NEG_INFINITY;
            for u in &dirs {
                let x = [0, 1, 2].map(|k| p[k] + r * u[k]);
                best = best.max(oracle_score(x, &others, r, &planes, best));
            }
            if best > 1e-3 {
                compared += 1;
                witness_boundary += 1;
                assert!(
                    got[i],
                    "seed {seed}: particle {i} at {p:?}: oracle clearance {best}"
                );
            } else if best < -0.015 {
                compared += 1;
                interior_near += usize::from(plain[i]);
                assert!(
                    !got[i],
                    "seed {seed}: particle {i} at {p:?}: oracle clearance {best}"
                );
            } else {
                skipped += 1;
            }
        }
    }
    assert!(
        witness_boundary > 20,
        "{witness_boundary} boundary by a witness"
    );
    assert!(
        interior_near > 20,
        "{interior_near} made interior by the mesh"
    );
    assert!(
        skipped * 5 < compared,
        "{skipped} skipped, {compared} compared"
    );
}

#[test]
fn meshes_are_refused_where_they_cannot_apply() {
    let mesh = Arc::new(box_mesh([0.0; 3], [1.0; 3]));
    let domain = Domain::new().with_solid_mesh(mesh.clone());
    let r = Radius::new(0.5).unwrap();
    let flat = AnyParticleSet::from(ParticleSet::<2>::from_rows(&[[0.0, 0.0]]).unwrap());
    let e = ExactDetector::default()
        .detect_in(&flat, &domain, r)
        .unwrap_err();
    assert!(e.to_string().contains("3D set"), "{e}");
    // A periodic axis whose ends the mesh comes within the reach of.
    let set = AnyParticleSet::from(ParticleSet::<3>::from_rows(&[[2.0, 0.5, 0.5]]).unwrap());
    let periodic = domain
        .clone()
        .with_periodic(boundary_core::Periodic::new(0, -0.5, 3.0).unwrap());
    let e = ExactDetector::default()
        .detect_in(&set, &periodic, r)
        .unwrap_err();
    assert!(
        e.to_string().contains("not repeated across a period"),
        "{e}"
    );
    // A method that does not honour meshes refuses them by name, through the trait.
    #[derive(Debug)]
    struct PlanesOnly;
    impl boundary_core::Method for PlanesOnly {
        const NAME: &'static str = "planes-only";
        fn describe(&self) -> boundary_core::Params {
            boundary_core::Params::default()
        }
        fn capabilities(&self) -> boundary_core::Capabilities {
            boundary_core::Capabilities {
                half_spaces: boundary_core::Support::Honoured,
                meshes: boundary_core::Support::Refused("why"),
                ..boundary_core::Capabilities::DEFAULT
            }
        }
        fn classify<const D: usize>(
            &self,
            job: boundary_core::Job<'_, D>,
        ) -> Result<boundary_core::Detection, DetectError>
        where
            boundary_core::Dim<D>: boundary_core::SupportedDim,
        {
            job.run_on(&ExactDetector::default())
        }
    }
    let e = PlanesOnly.detect_in(&set, &domain, r).unwrap_err();
    assert!(
        matches!(
            e,
            DetectError::UnsupportedOption {
                option: "solid meshes",
                ..
            }
        ),
        "{e}"
    );
    // The face names the option, with the method's reason, when called directly too.
    let e = PlanesOnly
        .detect_owned_in(&set, 1, domain.solids(), r)
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "method 'planes-only' cannot honour solid meshes: why"
    );
}

/// Per-particle radii keep working: a set whose radius factors are all 1 gets the uniform
/// labels, and a particle held wholly inside a mesh is interior whatever its radius.
#[test]
fn per_particle_radii_work_with_meshes() {
    let pts = block(5, 0.0, 0.3, 7);
    let set = ParticleSet::new(pts.clone()).unwrap();
    let ones = set.clone().with_radii(vec![1.0; pts.len()]).unwrap();
    let mesh = Arc::new(box_mesh([-3.0, -3.0, -3.0], [6.0, 6.0, 1.5]));
    let domain = Domain::new().with_solid_mesh(mesh);
    let uniform = labels(&set, &domain, 0.9);
    let with_radii = labels(&ones, &domain, 0.9);
    assert_eq!(uniform, with_radii);
    let plain = labels(&set, &Domain::new(), 0.9);
    // The mesh only adds cover, and particles deep inside it are interior.
    for (i, p) in pts.iter().enumerate() {
        assert!(plain[i] || !uniform[i], "particle {i}");
        if p[2] < 1.5 - 0.95 {
            assert!(!uniform[i], "particle {i} at {p:?} is held by the mesh");
        }
    }
    assert!(uniform.iter().filter(|&&b| b).count() < plain.iter().filter(|&&b| b).count());
    // Graded radii: still running, the held particles interior.
    let graded = set
        .with_radii((0..pts.len()).map(|i| 1.0 + 0.5 * (i % 3) as f64).collect())
        .unwrap();
    let g = labels(&graded, &domain, 0.6);
    for (i, p) in pts.iter().enumerate() {
        let ri = 0.6 * (1.0 + 0.5 * (i % 3) as f64);
        if p[2] < 1.5 - ri * 1.01 {
            assert!(!g[i], "particle {i}");
        }
    }
}
