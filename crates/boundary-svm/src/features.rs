//! The per-particle feature vector: the thesis' six SPH features (Sec. 3.2.1), made
//! scale-free, and one of ours, all computed in one neighbour query per particle.
//!
//! Everything is computed in units of `r`: with `d_j = (x_j − x_i)/r`, `q_j = |d_j|` and the
//! Wendland C2 shape `f(q) = (1 − q/2)^4 (2q + 1)` (support `q < 2`, i.e. the influence radius
//! `2h` at `h = r`), the features of particle `i` are
//!
//! | index | feature (thesis Fig. 18) | definition here |
//! |---|---|---|
//! | 0 | density function (Parzen window) | `Σ_j f(q_j)` (`j = i` included): `ρ_i r^D / σ_D`, the number density in units of `r` |
//! | 1 | modulus of the density gradient | `\|Σ_{j≠i} w(q_j) d_j\|` with `w(q) = −f'(q)/q = 5 (1 − q/2)^3`: `\|∇ρ_i\| r^{D+1} / σ_D` |
//! | 2 | divergence | `Σ_j w(q_j) q_j² / Σ_j f(q_j)`: the SPH divergence of the position field, `∇·x`, with the particle's own volume `1/ρ_i` for every neighbour; `D` inside a uniform fluid |
//! | 3 | number of neighbours within the influence radius | count of `j ≠ i` with `\|x_j − x_i\| <= 2r` (duplicates included) |
//! | 4 | smallest eigenvalue of the neighbourhood covariance | `λ_min(C_i) / r²` |
//! | 5 | largest eigenvalue of the neighbourhood covariance | `λ_max(C_i) / r²` |
//! | 6 | **ours**: sampled cover margin | `max_k min_j (\|d_j − n_k\|² − 1)` over the sample points `x_i + r n_k` of `S_i` (below), clamped to `[−0.25, 1]`; `1` with no distinct neighbour |
//!
//! `C_i = (1/k) Σ (x_j − x̄)(x_j − x̄)ᵀ` over the `k` positions of the neighbourhood (`i` and
//! its neighbours within `2r`), `x̄` their mean.
//!
//! **The divergence term.** The thesis lists "the modulus of [the density's] gradient and
//! divergence" without saying of what field the divergence is taken; the divergence of a
//! scalar density is not defined. We use the SPH divergence of the position field, `∇·x`,
//! which is `D` for a full, uniform neighbourhood and drops where the neighbourhood is
//! one-sided (the free-surface indicator of Lee et al. 2008). Taking the particle's own
//! volume for its neighbours' (instead of each neighbour's summation volume, which needs a
//! second neighbour pass) keeps the features to one neighbour query per particle.
//!
//! **The sampled cover margin (ours, not in the thesis).** Point `p = x_i + r n` (`|n| = 1`) of
//! the sphere `S_i` is covered by the ball of neighbour `j` iff `|d_j − n|² <= 1`. The margin
//! is the largest, over a fixed set of sample directions `n_k`, of the smallest such value
//! over the distinct neighbours within `2r` (duplicates cover nothing). The directions are
//! the outward normal estimate `−Σ w d_j / |·|` (minus the density gradient), both
//! directions of the covariance's smallest eigenvector (the normal of a sheet, of a
//! filament's cross-section), and fixed directions: in 2D the 8 of `{−1, 0, 1}² \ 0`, in 3D
//! the 6 axes and the 8 cube diagonals (normalised). A margin above [`CERTIFICATE_TOLERANCE`] proves that `p` is uncovered:
//! the particle is boundary by the definition, which the detector uses as a certificate
//! (see the crate documentation); a margin near 0 says that the sphere is nearly uncovered
//! there, which the SVM uses as a feature.
//!
//! **Scale-freeness.** Scaling every position and `r` by the same factor leaves every feature
//! unchanged up to rounding (tested for factors `2^k`, relative tolerance `1e-12`), so a model
//! trained at one resolution applies at another with the same `r`/spacing ratio.
//!
//! **Degenerate input.** An isolated particle has density `f(0) = 1`, gradient 0, divergence
//! 0, no neighbours, a zero covariance and margin 1. Duplicates of `x_i` count as neighbours
//! and add to its density, but contribute no gradient, divergence or cover (their direction
//! is undefined).

use boundary_core::nalgebra::SMatrix;
use boundary_core::{CoreError, NeighbourGrid, ParticleSet, Point, Radius};
use boundary_sph::SymmetricEigen;
use rayon::prelude::*;

/// Number of features per particle.
pub const N_FEATURES: usize = 7;

/// Version of the feature definition; a model records the version it was trained on and is
/// refused by a detector that computes another.
pub const FEATURE_VERSION: u32 = 2;

/// The names of the features, in order.
pub const FEATURE_NAMES: [&str; N_FEATURES] = [
    "density",
    "density_gradient",
    "divergence",
    "neighbours",
    "covariance_min",
    "covariance_max",
    "cover_margin",
];

/// Index of the sampled cover margin in [`Features`].
pub const MARGIN_FEATURE: usize = 6;

/// A sampled cover margin above this (in units of `r²`) certifies an uncovered point of
/// `S_i`. The computed value `|d_j − n|² − 1` (with `|d_j| <= 2`) is within `1e-14` of the
/// exact value for the exactly normalised direction and the exact positions (each
/// coordinate difference is rounded once, relative error `2^-53`; the rest is a dozen
/// roundings of numbers below 9), so `1e-12` leaves a factor 100.
pub const CERTIFICATE_TOLERANCE: f64 = 1e-12;

/// The sampled cover margin is clamped below at this value (a sample point covered deeper
/// than this is as good as any other for the model, and the clamp lets the search stop
/// early).
pub const MARGIN_FLOOR: f64 = -0.25;

/// One particle's features (see the module documentation for their order).
pub type Features = [f64; N_FEATURES];

/// How far from a particle its features look: the influence radius `2r`, widened by a
/// relative `1e-9` for the certificate (see [`particle_features`]).
pub fn feature_reach(r: Radius) -> f64 {
    2.0 * r.get() * (1.0 + 1e-9)
}

/// The features of the first `count` particles of `set` at resolution `r` (all particles
/// take part as neighbours), in input order; `count` is clamped to the set's length.
///
/// Fails only where the neighbour grid does (a bounding box of more than `2^52` radii).
pub fn compute_features<const D: usize>(
    set: &ParticleSet<D>,
    count: usize,
    r: Radius,
) -> Result<Vec<Features>, CoreError> {
    Ok(particle_features(set, count, r)?
        .into_iter()
        .map(|p| p.features)
        .collect())
}

/// One particle's features and what the detector needs besides them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParticleFeatures {
    /// The features.
    pub features: Features,
    /// Neighbours within `2r` that are not duplicates of the particle.
    pub distinct: usize,
}

impl ParticleFeatures {
    /// Whether the particle is boundary by a proof, whatever the model says, in dimension
    /// `dim`: at most `dim` distinct neighbours within `2r`, or a sampled cover margin above
    /// [`CERTIFICATE_TOLERANCE`] (an uncovered point of its sphere). See the crate
    /// documentation.
    pub fn certified_boundary(&self, dim: usize) -> bool {
        self.distinct <= dim || self.features[MARGIN_FEATURE] > CERTIFICATE_TOLERANCE
    }
}

/// [`compute_features`] with the count of distinct neighbours.
pub fn particle_features<const D: usize>(
    set: &ParticleSet<D>,
    count: usize,
    r: Radius,
) -> Result<Vec<ParticleFeatures>, CoreError> {
    // The certificate looks a little beyond 2r (more neighbours can only make it more
    // conservative), so that rounding in the distance cannot drop a ball that touches S_i.
    let reach = feature_reach(r);
    let r = r.get();
    // Cells of half the reach: a query visits about 5^D cells whose union hugs the ball
    // better than 3^D cells of the full reach (fewer distance tests, as `exact` does).
    let grid = NeighbourGrid::new(set, 0.5 * reach)?;
    let positions = set.positions();
    let count = count.min(set.len());
    let directions = sample_directions::<D>();
    Ok((0..count)
        .into_par_iter()
        .map_init(Offsets::default, |buffer, i| {
            one_particle(&grid, positions, i, r, reach, &directions, buffer)
        })
        .collect())
}

/// The fixed sample directions, normalised: in 2D the 8 of `{−1, 0, 1}² \ 0`; in 3D the 6
/// axis directions and the 8 cube diagonals.
fn sample_directions<const D: usize>() -> Vec<Point<D>> {
    let mut out = vec![];
    let total = 3usize.pow(D as u32);
    for code in 0..total {
        let mut c = code;
        let v = Point::<D>::from_fn(|_, _| {
            let digit = (c % 3) as f64 - 1.0;
            c /= 3;
            digit
        });
        let zeros = v.iter().filter(|x| **x == 0.0).count();
        // 3D: axes (two zeros) and diagonals (no zero); 2D: all but the origin.
        let keep = if D == 3 {
            zeros == 2 || zeros == 0
        } else {
            zeros < D
        };
        if keep {
            out.push(v.normalize());
        }
    }
    out
}

/// The Wendland C2 shape `f(q)` and `w(q) = −f'(q)/q`, for `q < 2`.
fn wendland(q: f64) -> (f64, f64) {
    let t = 1.0 - 0.5 * q;
    let t3 = t * t * t;
    (t3 * t * (2.0 * q + 1.0), 5.0 * t3)
}

/// The distinct neighbours' offsets `d_j` (units of `r`), by coordinate, with `|d_j|²`, padded
/// to whole chunks with far points (`|d|² = 1e300`) that cover nothing.
#[derive(Default)]
struct Offsets {
    coords: Vec<[f64; CHUNK]>,
    norms: Vec<[f64; CHUNK]>,
    len: usize,
}

/// Offsets per chunk of the cover search: branch-free inside a chunk (it vectorises), an
/// early exit between chunks.
const CHUNK: usize = 8;

impl Offsets {
    fn clear(&mut self) {
        self.coords.clear();
        self.norms.clear();
        self.len = 0;
    }

    fn push<const D: usize>(&mut self, d: &Point<D>) {
        let (chunk, lane) = (self.len / CHUNK, self.len % CHUNK);
        if lane == 0 {
            self.coords.extend(std::iter::repeat_n([0.0; CHUNK], D));
            self.norms.push([1e300; CHUNK]);
        }
        for k in 0..D {
            self.coords[chunk * D + k][lane] = d[k];
        }
        self.norms[chunk][lane] = d.norm_squared();
        self.len += 1;
    }

    /// `min_j (|d_j − n|² − 1)`, computed as `|d_j|² − 2 d_j·n` (`|n| = 1` up to rounding,
    /// which [`CERTIFICATE_TOLERANCE`] covers), stopping after the first chunk that brings it
    /// to `floor` or below (the caller only needs to know whether it beats `floor`).
    fn cover_value<const D: usize>(&self, n: &Point<D>, floor: f64) -> f64 {
        let mut lowest = f64::INFINITY;
        for (c, norms) in self.norms.iter().enumerate() {
            let coords = &self.coords[c * D..(c + 1) * D];
            let mut chunk_min = f64::INFINITY;
            for lane in 0..CHUNK {
                let mut dot = 0.0;
                for k in 0..D {
                    dot += coords[k][lane] * n[k];
                }
                chunk_min = chunk_min.min(norms[lane] - 2.0 * dot);
            }
            lowest = lowest.min(chunk_min);
            if lowest <= floor {
                break;
            }
        }
        lowest
    }
}

fn one_particle<const D: usize>(
    grid: &NeighbourGrid<D>,
    positions: &[Point<D>],
    i: usize,
    r: f64,
    reach: f64,
    directions: &[Point<D>],
    offsets: &mut Offsets,
) -> ParticleFeatures {
    let xi = positions[i];
    let inv_r = 1.0 / r;
    offsets.clear();
    let mut density = 1.0; // f(0): the particle itself
    let mut gradient = Point::<D>::zeros();
    let mut divergence = 0.0;
    let mut count = 0usize;
    let mut distinct = 0usize;
    // Moments of the neighbourhood relative to x_i (i itself contributes the zero vector),
    // so that the covariance does not lose digits far from the origin.
    let mut first = Point::<D>::zeros();
    let mut second = SMatrix::<f64, D, D>::zeros();
    let inside2 = 4.0 * r * r;
    grid.for_each_within(&xi, reach, |j, dist2| {
        if j == i {
            return;
        }
        if dist2 == 0.0 {
            // A duplicate: a neighbour with density f(0) = 1 that covers nothing.
            count += 1;
            density += 1.0;
            return;
        }
        let d = (positions[j] - xi) * inv_r;
        offsets.push(&d);
        if dist2 > inside2 {
            return; // only for the certificate
        }
        count += 1;
        distinct += 1;
        first += d;
        second += d * d.transpose();
        let q = dist2.sqrt() * inv_r;
        if q < 2.0 {
            let (f, w) = wendland(q);
            density += f;
            gradient += d * w;
            divergence += w * q * q;
        }
    });
    let k = (count + 1) as f64;
    let mean = first / k;
    let covariance = second / k - mean * mean.transpose();
    let eigen = SymmetricEigen::new(&covariance);

    let margin = if offsets.len == 0 {
        1.0
    } else {
        // Below the floor the value is clamped anyway: a direction whose point is covered
        // that deep needs no further neighbours.
        let mut best = MARGIN_FLOOR;
        let mut try_direction = |n: Point<D>| {
            let v = offsets.cover_value(&n, best);
            if v > best {
                best = v;
            }
        };
        let g = gradient.norm();
        if g > 0.0 {
            try_direction(-gradient / g);
        }
        let e: Point<D> = eigen.vectors.column(0).into_owned();
        if e.norm_squared() > 0.5 {
            try_direction(e);
            try_direction(-e);
        }
        for n in directions {
            try_direction(*n);
        }
        best.clamp(MARGIN_FLOOR, 1.0)
    };
    ParticleFeatures {
        features: [
            density,
            gradient.norm(),
            divergence / density,
            count as f64,
            // Rounding can make a zero eigenvalue slightly negative; the covariance is PSD.
            eigen.values[0].max(0.0),
            eigen.values[D - 1].max(0.0),
            margin,
        ],
        distinct,
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test
mod tests {
    use super::*;

    fn lattice(n: usize) -> ParticleSet<2> {
        let rows: Vec<[f64; 2]> = (0..n * n)
            .map(|k| [(k % n) as f64, (k / n) as f64])
            .collect();
        ParticleSet::from_rows(&rows).unwrap()
    }

    #[test]
    fn interior_lattice_particle_has_full_divergence_and_isotropic_covariance() {
        let set = lattice(15);
        let f = compute_features(&set, set.len(), Radius::new(1.5).unwrap()).unwrap();
        let centre = f[7 * 15 + 7];
        // Symmetric neighbourhood: no gradient, equal eigenvalues, ∇·x close to D = 2.
        assert!(centre[1].abs() < 1e-12, "{centre:?}");
        assert!((centre[4] - centre[5]).abs() < 1e-12, "{centre:?}");
        assert!((centre[2] - 2.0).abs() < 0.2, "{centre:?}");
        // Neighbours within 2r = 3 on the unit lattice: 28 others.
        assert_eq!(centre[3], 28.0);
        // Covered everywhere: the margin is negative.
        assert!(centre[MARGIN_FEATURE] < -0.1, "{centre:?}");
        let corner = f[0];
        assert!(
            corner[1] > 0.5 && corner[2] < 1.5 && corner[3] < 12.0,
            "{corner:?}"
        );
        // The corner's outward direction is uncovered: a positive margin.
        assert!(corner[MARGIN_FEATURE] > 0.1, "{corner:?}");
    }

    /// The margin against a brute-force check: a positive margin means some point of S_i
    /// is uncovered (checked on the sampled point itself with exact-rational-free reasoning:
    /// the point found by the feature is tested against every other particle directly).
    #[test]
    fn positive_margin_only_where_a_sampled_point_is_uncovered() {
        let set = lattice(9);
        for (r, expect_all_boundary) in [
            (std::f64::consts::FRAC_1_SQRT_2 * (1.0 - 1e-6), true),
            (std::f64::consts::FRAC_1_SQRT_2, false),
            (0.9, false),
        ] {
            let f = compute_features(&set, set.len(), Radius::new(r).unwrap()).unwrap();
            let interior = f[4 * 9 + 4][MARGIN_FEATURE];
            if expect_all_boundary {
                // Below the tie the diagonal points of every sphere are uncovered.
                assert!(interior > CERTIFICATE_TOLERANCE, "r={r}: {interior}");
            } else {
                // At the tie (r rounds above it) and above, the interior is covered.
                assert!(interior <= CERTIFICATE_TOLERANCE, "r={r}: {interior}");
            }
        }
    }

    #[test]
    fn isolated_particle_and_duplicates() {
        let set = ParticleSet::from_rows(&[[0.0, 0.0], [0.0, 0.0], [50.0, 50.0]]).unwrap();
        let r = Radius::new(1.0).unwrap();
        let f = compute_features(&set, 3, r).unwrap();
        assert_eq!(f[2], [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]);
        assert_eq!(f[0], [2.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0]);
        assert_eq!(compute_features(&set, 1, r).unwrap().len(), 1);
    }
}
