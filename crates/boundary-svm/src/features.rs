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
//! | 6 | **ours**: sampled cover margin | `max_k min_j (\|d_j − n_k\|² − 1)` over the sample points `x_i + r n_k` of `S_i` and the points of a local ascent from the best of them (below), clamped to `[−0.25, 1]`; `1` with no distinct neighbour |
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
//! the 6 axes and the 8 cube diagonals (normalised). Where the best of these points is
//! covered but less deeply than the floor `−0.25`, a **local ascent** ([`ASCENT_STEPS`]
//! steps) moves it along the sphere away from its nearest neighbour (by 0.5 rad, halved
//! after each step that does not raise the value) and keeps the highest value met. Fixed
//! samples miss the small uncovered caps that neighbours at `r` of 2–3 spacings leave
//! (thin sheets of splash frames): there most uncertified particles were boundary, and the
//! model had to tell them from interior ones whose samples were as shallowly covered. The
//! ascent certifies most of them and makes the margin of the rest a closer bound of the true
//! one; deeply covered particles do not start it, so it costs little in the bulk (its effect
//! on the splash frames: `docs/METHODS.md`, section "`svm`"). A margin above
//! [`CERTIFICATE_TOLERANCE`] proves that `p` is uncovered: the particle is boundary by the
//! definition, which the detector uses as a certificate (see the crate documentation); a
//! margin near 0 says that the sphere is nearly uncovered there, which the SVM uses as a
//! feature.
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
use boundary_core::{CoreError, NeighbourGrid, Neighbourhood, ParticleSet, Point, Radius};
use boundary_sph::SymmetricEigen; // the fallback of `extreme_eigen`

/// Number of features per particle.
pub const N_FEATURES: usize = 7;

/// Version of the feature definition; a model records the version it was trained on and is
/// refused by a detector that computes another.
pub const FEATURE_VERSION: u32 = 3;

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

/// [`feature_reach`] in units of `r` (the same number: a factor 2 scales exactly).
pub const REACH_OVER_R: f64 = 2.0 * (1.0 + 1e-9);

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
#[derive(Debug, Clone, Copy, Default, PartialEq)]
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

    /// Whether the particle sits at a near tie: not certified in dimension `dim`, and a
    /// sampled point of its sphere is within the rounding bound of being uncovered (cover
    /// margin above `−`[`CERTIFICATE_TOLERANCE`]). The detector leaves these to `exact`.
    pub fn near_tie(&self, dim: usize) -> bool {
        !self.certified_boundary(dim) && self.features[MARGIN_FEATURE] > -CERTIFICATE_TOLERANCE
    }
}

/// [`compute_features`] with the count of distinct neighbours.
pub fn particle_features<const D: usize>(
    set: &ParticleSet<D>,
    count: usize,
    r: Radius,
) -> Result<Vec<ParticleFeatures>, CoreError> {
    map_particle_features(set, count, r, |p| *p)
}

/// `then(features)` for each of the first `count` particles of `set` at resolution `r`, in
/// input order, without keeping the features (a detector keeps its decision, 8 bytes, not
/// the 72 of [`ParticleFeatures`]). `then` runs in parallel, right after each particle's
/// features.
pub fn map_particle_features<const D: usize, T: Send + Sync + Default>(
    set: &ParticleSet<D>,
    count: usize,
    r: Radius,
    then: impl Fn(&ParticleFeatures) -> T + Sync + Send,
) -> Result<Vec<T>, CoreError> {
    // The certificate looks a little beyond 2r (more neighbours can only make it more
    // conservative), so that rounding in the distance cannot drop a ball that touches S_i.
    let reach = feature_reach(r);
    let r = r.get();
    // Cells of half the reach: a query visits about 5^D cells whose union hugs the ball
    // better than 3^D cells of the full reach (fewer distance tests, as `exact` does).
    let grid = NeighbourGrid::new(set, 0.5 * reach)?;
    let positions = set.positions();
    let directions = sample_directions::<D>();
    // One pass over the neighbourhoods, in the grid's cell order.
    Ok(grid.par_map_within(
        reach,
        count,
        Offsets::<D>::default,
        |buffer, i, neighbours| {
            then(&one_particle(
                &positions[i],
                neighbours,
                r,
                &directions,
                buffer,
            ))
        },
    ))
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

/// The Wendland C2 shape `f(q)` and `w(q) = −f'(q)/q`, for `q <= 2` (both 0 at `q = 2`).
fn wendland(q: f64) -> (f64, f64) {
    let t = 1.0 - 0.5 * q;
    let t3 = t * t * t;
    (t3 * t * (2.0 * q + 1.0), 5.0 * t3)
}

/// The distinct neighbours' offsets `d_j` (units of `r`), by coordinate, with `|d_j|²` and
/// whether `j` is within `2r`, in chunks padded with far points (`|d|² = 1e300`, outside)
/// that cover nothing and weigh nothing. The neighbour query only fills this; the sums of the
/// features then run over whole chunks, branch-free (they vectorise).
///
/// The offsets within [`NEAR`] are also kept, in the same order, in `near`: the cover search
/// scans those first (see [`Offsets::cover_value`]).
struct Offsets<const D: usize> {
    chunks: Vec<Chunk<D>>,
    len: usize,
    near: Vec<Chunk<D>>,
    near_len: usize,
}

impl<const D: usize> Default for Offsets<D> {
    fn default() -> Self {
        Offsets {
            chunks: vec![],
            len: 0,
            near: vec![],
            near_len: 0,
        }
    }
}

/// `|d|` (units of `r`) up to which an offset is also kept among the near ones. A neighbour
/// covers a point `n` of the unit sphere to depth `|d − n|² − 1 <= MARGIN_FLOOR` only if
/// `|d| <= 1 + √(1 + MARGIN_FLOOR) ≈ 1.87`; most points are covered that deep by a
/// neighbour within `1.1` (callgrind, features of the 10^5 jittered ball at r = 1.2
/// spacings, NEAR from 1.0 to 1.7: 1831, 1810, 1816, 1828, 1851 (1.5), 1874M instructions;
/// fewer near chunks to scan, fewer mispredicted exits from the scan).
const NEAR: f64 = 1.1;

/// Offsets per chunk of the cover search: branch-free inside a chunk (it vectorises), an
/// early exit between chunks.
const CHUNK: usize = 8;

/// Lanes of a chunk whose feature sums are taken together ([`Offsets::sums`]): one SSE2
/// register of `f64`.
const GROUP: usize = 2;

/// [`CHUNK`] offsets, by coordinate.
#[derive(Clone, Copy)]
struct Chunk<const D: usize> {
    coords: [[f64; CHUNK]; D],
    norms: [f64; CHUNK],
    /// 1 for a neighbour within `2r`, 0 for one only the certificate sees, and padding.
    inside: [f64; CHUNK],
}

impl<const D: usize> Chunk<D> {
    const FAR: Self = Chunk {
        coords: [[0.0; CHUNK]; D],
        norms: [1e300; CHUNK],
        inside: [0.0; CHUNK],
    };
}

/// The sums over the neighbours within `2r` (units of `r`): `Σ f(q)` (without `i`),
/// `Σ w(q) d`, `Σ w(q) q²`, `Σ d`, `Σ d dᵀ`, the count.
struct Sums<const D: usize> {
    density: f64,
    gradient: Point<D>,
    divergence: f64,
    first: Point<D>,
    second: SMatrix<f64, D, D>,
    count: usize,
}

impl<const D: usize> Offsets<D> {
    /// Empties the offsets; the chunks stay allocated (and are reset as they are reused).
    fn clear(&mut self) {
        self.len = 0;
        self.near_len = 0;
    }

    /// The chunks in use.
    fn chunks(&self) -> &[Chunk<D>] {
        &self.chunks[..self.len.div_ceil(CHUNK)]
    }

    /// The chunks of the near offsets in use.
    fn near_chunks(&self) -> &[Chunk<D>] {
        &self.near[..self.near_len.div_ceil(CHUNK)]
    }

    /// Appends one offset (`inside`: the neighbour is within `2r`).
    #[cfg(test)]
    fn push(&mut self, d: &Point<D>, inside: bool) {
        self.reserve(self.len + 1);
        self.write(d, inside);
        self.pad();
    }

    /// Makes room for `n` offsets in all (chunks of padding where there were none).
    fn reserve(&mut self, n: usize) {
        let need = n.div_ceil(CHUNK);
        for chunks in [&mut self.chunks, &mut self.near] {
            if chunks.len() < need {
                chunks.resize(need, Chunk::FAR);
            }
        }
    }

    /// Writes one offset after the others, to the near ones too, with no branch: it is
    /// written at the end of the near ones either way and kept (the count advances) only
    /// if `|d| <= NEAR`. Needs the room ([`Offsets::reserve`]); [`Offsets::pad`] after the
    /// last.
    #[inline(always)]
    fn write(&mut self, d: &Point<D>, inside: bool) {
        let norm = d.norm_squared();
        let inside = if inside { 1.0 } else { 0.0 };
        put(&mut self.chunks, self.len, d, norm, inside);
        self.len += 1;
        put(&mut self.near, self.near_len, d, norm, inside);
        self.near_len += (norm <= NEAR * NEAR) as usize;
    }

    /// Pads the last chunk in use of both lists: far norms and zero weights in the lanes
    /// past the offsets (stale coordinates there are finite: they cover and weigh nothing).
    fn pad(&mut self) {
        for (chunks, len) in [
            (&mut self.chunks, self.len),
            (&mut self.near, self.near_len),
        ] {
            if let Some(chunk) = chunks.get_mut(len / CHUNK) {
                for lane in len % CHUNK..CHUNK {
                    chunk.norms[lane] = Chunk::<D>::FAR.norms[lane];
                    chunk.inside[lane] = Chunk::<D>::FAR.inside[lane];
                }
            }
        }
    }

    /// The feature sums, lane by lane over whole chunks (padding and neighbours beyond `2r`
    /// weigh 0), then across lanes.
    ///
    /// Each lane keeps its own running sums over the chunks, in chunk order, and the lanes
    /// are added in order at the end. The lanes are taken [`GROUP`] at a time (one vector
    /// register), each group through every chunk with its 15 sums (3D) held in registers:
    /// chunk by chunk over all the lanes, 48 sums of 8 lanes did not fit and went through
    /// memory on every update (callgrind: a third of the features' arithmetic was loads and
    /// stores of the sums). The order of every addition is unchanged, so are the sums.
    fn sums(&self) -> Sums<D> {
        let mut density = [0.0; CHUNK];
        let mut divergence = [0.0; CHUNK];
        let mut count = [0.0; CHUNK];
        let mut gradient = [[0.0; CHUNK]; D];
        let mut first = [[0.0; CHUNK]; D];
        let mut second = [[[0.0; CHUNK]; D]; D];
        let chunks = self.chunks();
        for g in (0..CHUNK).step_by(GROUP) {
            let lanes = g..g + GROUP;
            let mut s_density = [0.0; GROUP];
            let mut s_divergence = [0.0; GROUP];
            let mut s_count = [0.0; GROUP];
            let mut s_gradient = [[0.0; GROUP]; D];
            let mut s_first = [[0.0; GROUP]; D];
            let mut s_second = [[[0.0; GROUP]; D]; D];
            for chunk in chunks {
                let m: [f64; GROUP] = std::array::from_fn(|l| chunk.inside[g + l]);
                let norms: [f64; GROUP] = std::array::from_fn(|l| chunk.norms[g + l]);
                let mut f = [0.0; GROUP];
                let mut w = [0.0; GROUP];
                for l in 0..GROUP {
                    // Zero weights from q = 2 on (f(2) = w(2) = 0) and for padding.
                    // (`if`, not `f64::min`: the norms are never NaN, and it vectorises.)
                    let q = norms[l].sqrt();
                    let (fl, wl) = wendland(if q < 2.0 { q } else { 2.0 });
                    f[l] = m[l] * fl;
                    w[l] = m[l] * wl;
                }
                for l in 0..GROUP {
                    s_density[l] += f[l];
                    s_divergence[l] += w[l] * norms[l];
                    s_count[l] += m[l];
                }
                let d: [[f64; GROUP]; D] =
                    std::array::from_fn(|a| std::array::from_fn(|l| chunk.coords[a][g + l]));
                for a in 0..D {
                    let mut md = [0.0; GROUP];
                    for l in 0..GROUP {
                        s_gradient[a][l] += w[l] * d[a][l];
                        md[l] = m[l] * d[a][l];
                        s_first[a][l] += md[l];
                    }
                    for b in a..D {
                        for l in 0..GROUP {
                            s_second[a][b][l] += md[l] * d[b][l];
                        }
                    }
                }
            }
            density[lanes.clone()].copy_from_slice(&s_density);
            divergence[lanes.clone()].copy_from_slice(&s_divergence);
            count[lanes.clone()].copy_from_slice(&s_count);
            for a in 0..D {
                gradient[a][lanes.clone()].copy_from_slice(&s_gradient[a]);
                first[a][lanes.clone()].copy_from_slice(&s_first[a]);
                for b in a..D {
                    second[a][b][lanes.clone()].copy_from_slice(&s_second[a][b]);
                }
            }
        }
        let total = |v: &[f64; CHUNK]| v.iter().sum::<f64>();
        Sums {
            density: total(&density),
            gradient: Point::<D>::from_fn(|a, _| total(&gradient[a])),
            divergence: total(&divergence),
            first: Point::<D>::from_fn(|a, _| total(&first[a])),
            second: SMatrix::<f64, D, D>::from_fn(|a, b| total(&second[a.min(b)][a.max(b)])),
            count: total(&count) as usize,
        }
    }

    /// `min_j (|d_j − n|² − 1)` over every offset (no early exit) and the offset `d_j` that
    /// attains it (the first such in push order), or `None` without offsets.
    fn nearest(&self, n: &Point<D>) -> Option<(f64, Point<D>)> {
        let mut lowest = f64::INFINITY;
        let mut at = None;
        for (c, chunk) in self.chunks().iter().enumerate() {
            for lane in 0..CHUNK {
                if c * CHUNK + lane >= self.len {
                    break;
                }
                let mut dot = 0.0;
                for k in 0..D {
                    dot += chunk.coords[k][lane] * n[k];
                }
                let v = chunk.norms[lane] - 2.0 * dot;
                if v < lowest {
                    lowest = v;
                    at = Some((c, lane));
                }
            }
        }
        at.map(|(c, lane)| {
            let chunk = &self.chunks[c];
            (lowest, Point::<D>::from_fn(|k, _| chunk.coords[k][lane]))
        })
    }

    /// `min_j (|d_j − n|² − 1)`, computed as `|d_j|² − 2 d_j·n` (`|n| = 1` up to rounding,
    /// which [`CERTIFICATE_TOLERANCE`] covers), stopping after the first chunk that brings it
    /// to `floor` or below (the caller only needs to know whether it beats `floor`).
    ///
    /// The near offsets are scanned first: where they bring the value to `floor` that value
    /// is returned; otherwise every offset is scanned. A value above `floor` is therefore
    /// always the minimum over every offset, the same as without the near scan (`min` is
    /// exact in floating point), so the features do not depend on it.
    fn cover_value(&self, n: &Point<D>, floor: f64) -> f64 {
        let near = min_over(self.near_chunks(), n, floor);
        if near <= floor {
            return near;
        }
        min_over(self.chunks(), n, floor)
    }
}

/// Writes offset number `index` into its lane of `chunks` (which has room for it).
#[inline(always)]
fn put<const D: usize>(
    chunks: &mut [Chunk<D>],
    index: usize,
    d: &Point<D>,
    norm: f64,
    inside: f64,
) {
    if let Some(chunk) = chunks.get_mut(index / CHUNK) {
        let lane = index % CHUNK;
        for k in 0..D {
            chunk.coords[k][lane] = d[k];
        }
        chunk.norms[lane] = norm;
        chunk.inside[lane] = inside;
    }
}

/// `min_j (|d_j|² − 2 d_j·n)` over `chunks` (padding gives about `1e300`), stopping after
/// the first chunk that brings it to `floor` or below.
///
/// The values of a chunk are computed lane by lane and then reduced pairwise (a running
/// `f64::min` across lanes kept the loop scalar and NaN-aware). The minimum does not depend
/// on the order: the values are never NaN and never `−0` (`|d|²` is `+0` or positive, and
/// `x − x = +0`).
fn min_over<const D: usize>(chunks: &[Chunk<D>], n: &Point<D>, floor: f64) -> f64 {
    let mut lowest = f64::INFINITY;
    for chunk in chunks {
        let mut dot = [0.0; CHUNK];
        for (coords, nk) in chunk.coords.iter().zip(n.iter()) {
            for (d, c) in dot.iter_mut().zip(coords) {
                *d += c * nk;
            }
        }
        let mut v = [0.0; CHUNK];
        for lane in 0..CHUNK {
            v[lane] = chunk.norms[lane] - 2.0 * dot[lane];
        }
        // `if b < a { b } else { a }`, not `f64::min`: the same value for numbers that are
        // not NaN, one `minpd`/`minsd` instead of a NaN-aware sequence.
        let mut width = CHUNK / 2;
        while width > 0 {
            for lane in 0..width {
                let (a, b) = (v[lane], v[lane + width]);
                v[lane] = if b < a { b } else { a };
            }
            width /= 2;
        }
        if v[0] < lowest {
            lowest = v[0];
        }
        if lowest <= floor {
            break;
        }
    }
    lowest
}

/// The smallest and largest eigenvalue of the symmetric `D × D` matrix `a` and a unit
/// eigenvector of the smallest (or the zero vector where it is not well defined: a multiple
/// smallest eigenvalue), in closed form for `D` = 2 and 3 (the trigonometric solution of
/// the characteristic cubic: absolute error a few `ε |a|`), by [`SymmetricEigen`] otherwise
/// and where the closed form's eigenvector would be ill-conditioned.
fn extreme_eigen<const D: usize>(a: &SMatrix<f64, D, D>) -> (f64, f64, Point<D>) {
    let jacobi = |a: &SMatrix<f64, D, D>| {
        let e = SymmetricEigen::new(a);
        (
            e.values[0],
            e.values[D - 1],
            e.vectors.column(0).into_owned(),
        )
    };
    match D {
        2 => {
            let (p, q, o) = (a[(0, 0)], a[(1, 1)], a[(0, 1)]);
            let mid = 0.5 * (p + q);
            let half = (0.25 * (p - q) * (p - q) + o * o).sqrt();
            let (low, high) = (mid - half, mid + half);
            // (A − low I) has rows (p − low, o) and (o, q − low); an eigenvector of `low` is
            // orthogonal to the longer one.
            let (r0, r1) = ([p - low, o], [o, q - low]);
            let row = if r0[0] * r0[0] + r0[1] * r0[1] >= r1[0] * r1[0] + r1[1] * r1[1] {
                r0
            } else {
                r1
            };
            let len = (row[0] * row[0] + row[1] * row[1]).sqrt();
            let v = if len > 1e-8 * (p.abs() + q.abs() + o.abs()) && len > 0.0 {
                Point::<D>::from_fn(|k, _| if k == 0 { -row[1] / len } else { row[0] / len })
            } else {
                Point::<D>::zeros()
            };
            (low, high, v)
        }
        3 => {
            let off = a[(0, 1)] * a[(0, 1)] + a[(0, 2)] * a[(0, 2)] + a[(1, 2)] * a[(1, 2)];
            let scale = a.norm();
            if scale == 0.0 || !scale.is_finite() || off <= 1e-24 * scale * scale {
                return jacobi(a);
            }
            let mean = (a[(0, 0)] + a[(1, 1)] + a[(2, 2)]) / 3.0;
            let spread = ((a[(0, 0)] - mean).powi(2)
                + (a[(1, 1)] - mean).powi(2)
                + (a[(2, 2)] - mean).powi(2)
                + 2.0 * off)
                / 6.0;
            let p = spread.sqrt();
            let b =
                |i: usize, j: usize| -> f64 { (a[(i, j)] - if i == j { mean } else { 0.0 }) / p };
            let det = b(0, 0) * (b(1, 1) * b(2, 2) - b(1, 2) * b(2, 1))
                - b(0, 1) * (b(1, 0) * b(2, 2) - b(1, 2) * b(2, 0))
                + b(0, 2) * (b(1, 0) * b(2, 1) - b(1, 1) * b(2, 0));
            let half_det: f64 = (0.5 * det).clamp(-1.0, 1.0);
            let phi = half_det.acos() / 3.0;
            let high = mean + 2.0 * p * phi.cos();
            let low = mean + 2.0 * p * (phi + 2.0 * std::f64::consts::FRAC_PI_3).cos();
            // An eigenvector of `low`: the longest cross product of two rows of A − low I.
            let m = a - SMatrix::<f64, D, D>::identity() * low;
            let row = |k: usize| -> [f64; 3] { [m[(k, 0)], m[(k, 1)], m[(k, 2)]] };
            let cross = |u: [f64; 3], v: [f64; 3]| -> [f64; 3] {
                [
                    u[1] * v[2] - u[2] * v[1],
                    u[2] * v[0] - u[0] * v[2],
                    u[0] * v[1] - u[1] * v[0],
                ]
            };
            let mut best = [0.0; 3];
            let mut best2 = 0.0;
            for (u, v) in [(0, 1), (0, 2), (1, 2)] {
                let c = cross(row(u), row(v));
                let c2 = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
                if c2 > best2 {
                    best = c;
                    best2 = c2;
                }
            }
            // Rank below 2 up to rounding: `low` is (nearly) a double eigenvalue, whose
            // eigenvector the closed form cannot resolve.
            let gap = high - low;
            if best2.is_nan() || best2 <= 1e-12 * gap.powi(4) {
                return jacobi(a);
            }
            let len = best2.sqrt();
            (low, high, Point::<D>::from_fn(|k, _| best[k] / len))
        }
        _ => jacobi(a),
    }
}

/// Steps of the cover margin's local ascent on the unit sphere (the margin starts from the
/// best sampled direction and moves away from its nearest neighbour at most this many times).
pub const ASCENT_STEPS: usize = 12;

/// The largest `min_j (|d_j − n|² − 1)` found by a local ascent on the unit sphere from
/// `start`: at each step the point moves away from its nearest neighbour (along the sphere,
/// by an angle that starts at 0.5 rad and halves after every step that does not improve;
/// from a neighbour straight along the point, toward the coordinate axis least aligned
/// with it),
/// for [`ASCENT_STEPS`] steps or until the point is uncovered beyond
/// [`CERTIFICATE_TOLERANCE`]. Every value is that of an actual (normalised) direction, so
/// the result is a lower bound of the true margin up to the rounding bound, as the sampled
/// values are.
fn ascend<const D: usize>(offsets: &Offsets<D>, start: Point<D>) -> f64 {
    let Some((mut value, mut nearest)) = offsets.nearest(&start) else {
        return f64::INFINITY;
    };
    let mut n = start;
    let mut step: f64 = 0.5;
    for _ in 0..ASCENT_STEPS {
        if value > CERTIFICATE_TOLERANCE {
            break;
        }
        // The tangent of the sphere at n pointing away from the nearest neighbour; where the
        // neighbour lies straight along n (a lattice's axis neighbour) every tangent is as
        // good, and the one toward the axis least aligned with n is taken.
        let mut away = n * nearest.dot(&n) - nearest;
        if away.norm().is_nan() || away.norm() <= 1e-12 {
            let k = (0..D)
                .min_by(|&a, &b| n[a].abs().total_cmp(&n[b].abs()))
                .unwrap_or(0);
            away = -n * n[k];
            away[k] += 1.0;
        }
        let len = away.norm();
        if len.is_nan() || len <= 1e-12 {
            break;
        }
        let (cos, sin) = (step.cos(), step.sin());
        let candidate = (n * cos + away * (sin / len)).normalize();
        match offsets.nearest(&candidate) {
            Some((v, d)) if v > value => {
                value = v;
                nearest = d;
                n = candidate;
            }
            _ => step *= 0.5,
        }
    }
    value
}

fn one_particle<const D: usize>(
    xi: &Point<D>,
    neighbours: &Neighbourhood<'_, D>,
    r: f64,
    directions: &[Point<D>],
    offsets: &mut Offsets<D>,
) -> ParticleFeatures {
    let inv_r = 1.0 / r;
    offsets.clear();
    let inside2 = 4.0 * r * r;
    // The query only gathers the offsets; the sums run over them afterwards. The particle
    // itself is among the neighbours at distance 0, with its duplicates: each duplicate is a
    // neighbour with density f(0) = 1 that covers nothing.
    let mut zeros = 0usize;
    offsets.reserve(neighbours.len());
    for (dist2, pj) in neighbours.distances_and_positions() {
        if dist2 == 0.0 {
            zeros += 1;
            continue;
        }
        offsets.write(&((pj - xi) * inv_r), dist2 <= inside2);
    }
    offsets.pad();
    let duplicates = zeros.saturating_sub(1);
    let sums = offsets.sums();
    let distinct = sums.count;
    let count = distinct + duplicates;
    // f(0) = 1 for the particle itself and for each duplicate.
    let density = 1.0 + duplicates as f64 + sums.density;
    let gradient = sums.gradient;
    // Moments of the neighbourhood relative to x_i (i itself contributes the zero vector),
    // so that the covariance does not lose digits far from the origin.
    let k = (count + 1) as f64;
    let mean = sums.first / k;
    let covariance = sums.second / k - mean * mean.transpose();
    let (low, high, low_vector) = extreme_eigen(&covariance);

    let margin = if offsets.len == 0 {
        1.0
    } else {
        // Below the floor the value is clamped anyway: a direction whose point is covered
        // that deep needs no further neighbours.
        let mut best = MARGIN_FLOOR;
        let mut best_direction = None;
        let mut try_direction = |n: Point<D>| {
            let v = offsets.cover_value(&n, best);
            if v > best {
                best = v;
                best_direction = Some(n);
            }
        };
        let g = gradient.norm();
        if g > 0.0 {
            try_direction(-gradient / g);
        }
        if low_vector.norm_squared() > 0.5 {
            try_direction(low_vector);
            try_direction(-low_vector);
        }
        for n in directions {
            try_direction(*n);
        }
        // The ascent: from the best sample point above the floor, not yet certified.
        if let Some(start) = best_direction {
            if best <= CERTIFICATE_TOLERANCE {
                best = best.max(ascend(offsets, start));
            }
        }
        best.clamp(MARGIN_FLOOR, 1.0)
    };
    ParticleFeatures {
        features: [
            density,
            gradient.norm(),
            sums.divergence / density,
            count as f64,
            // Rounding can make a zero eigenvalue slightly negative; the covariance is PSD.
            low.max(0.0),
            high.max(0.0),
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

    /// The closed-form extreme eigenpairs against the Jacobi solver of boundary-sph, on
    /// random symmetric matrices and the shapes the covariance takes (sheet: one small
    /// eigenvalue; filament: a double small one; isotropic; diagonal).
    #[test]
    fn extreme_eigen_matches_jacobi() {
        fn check<const D: usize>(a: &SMatrix<f64, D, D>) {
            let (low, high, v) = extreme_eigen(a);
            let e = SymmetricEigen::new(a);
            let scale = a.norm().max(1e-300);
            assert!((low - e.values[0]).abs() <= 1e-12 * scale, "{a}: {low}");
            assert!(
                (high - e.values[D - 1]).abs() <= 1e-12 * scale,
                "{a}: {high}"
            );
            // A unit eigenvector of `low`, or zero where the solver gives none.
            if v.norm_squared() > 0.5 {
                assert!((v.norm() - 1.0).abs() < 1e-12);
                let residual = (a * v - v * low).norm();
                assert!(residual <= 1e-9 * scale, "{a}: residual {residual}");
            }
        }
        let mut seed = 12345u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for _ in 0..2000 {
            let b = SMatrix::<f64, 3, 3>::from_fn(|_, _| next());
            check(&(b * b.transpose()));
            let c = SMatrix::<f64, 2, 2>::from_fn(|_, _| next());
            check(&(c * c.transpose()));
            // Sheet-like and filament-like: rank-deficient plus a little noise.
            let u = Point::<3>::from_fn(|_, _| next());
            let w = Point::<3>::from_fn(|_, _| next());
            let eps = 1e-6 * next().abs();
            check(
                &(u * u.transpose() + w * w.transpose() + SMatrix::<f64, 3, 3>::identity() * eps),
            );
            check(&(u * u.transpose() + SMatrix::<f64, 3, 3>::identity() * eps));
        }
        check(&SMatrix::<f64, 3, 3>::identity());
        check(&SMatrix::<f64, 3, 3>::from_diagonal(&Point::<3>::new(
            3.0, 1.0, 2.0,
        )));
        check(&SMatrix::<f64, 3, 3>::zeros());
        check(&SMatrix::<f64, 2, 2>::identity());
        check(&SMatrix::<f64, 2, 2>::zeros());
    }

    /// The ascent on a hand-computed configuration: one neighbour at `d = (1.2, 0)` (units
    /// of `r`), where `|d − n|² − 1 = 1.44 − 2.4 cos θ` at the angle `θ` of `n`. From
    /// `θ = 0.1`: step 1 (0.5 rad) improves (1.44 − 2.4 cos 0.6 = −0.541), step 2 (another
    /// 0.5 rad) reaches `1.44 − 2.4 cos 1.1 = 0.351 > 0`: uncovered, so the ascent stops
    /// there. From `θ = 0`, straight toward the neighbour, the tangent toward the y axis is
    /// taken: `θ` = 0.5, then 1, `1.44 − 2.4 cos 1 = 0.143`.
    #[test]
    fn ascent_steps_away_from_the_nearest_neighbour() {
        let mut offsets = Offsets::<2>::default();
        offsets.push(&Point::<2>::new(1.2, 0.0), true);
        let at = |t: f64| Point::<2>::new(t.cos(), t.sin());
        let (at_start, nearest) = offsets.nearest(&at(0.1)).unwrap();
        assert!(
            (at_start - (1.44 - 2.4 * 0.1f64.cos())).abs() < 1e-12,
            "{at_start}"
        );
        assert_eq!(nearest, Point::<2>::new(1.2, 0.0));
        for (start, end) in [(0.1f64, 1.1f64), (0.0, 1.0)] {
            let value = ascend(&offsets, at(start));
            let expected = 1.44 - 2.4 * end.cos();
            assert!((value - expected).abs() < 1e-12, "{value} vs {expected}");
        }
        // Without offsets nothing covers the sphere.
        assert_eq!(ascend(&Offsets::<2>::default(), at(0.0)), f64::INFINITY);
    }

    /// The near-first cover search answers as the plain scan does: above `floor` it is the
    /// minimum over every offset, at or below it so is the minimum (random offsets in the
    /// ball of radius 2, random unit directions, floors from −1 to 0.5).
    #[test]
    fn cover_value_above_the_floor_is_the_minimum_over_every_offset() {
        let mut seed = 11u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let (mut above, mut below) = (0, 0);
        for trial in 0..300 {
            let mut offsets = Offsets::<3>::default();
            let mut all = vec![];
            for _ in 0..(trial % 70 + 1) {
                let d = Point::<3>::new(4.0 * next(), 4.0 * next(), 4.0 * next());
                if d.norm() <= 2.0 {
                    offsets.push(&d, true);
                    all.push(d);
                }
            }
            if all.is_empty() {
                continue;
            }
            assert!(offsets.near_len <= offsets.len);
            let n = Point::<3>::new(next(), next(), next()).normalize();
            let floor = 1.5 * next() - 0.25;
            let full = all
                .iter()
                .map(|d| d.norm_squared() - 2.0 * d.dot(&n))
                .fold(f64::INFINITY, f64::min);
            let v = offsets.cover_value(&n, floor);
            if v > floor {
                above += 1;
                assert_eq!(v, full, "trial {trial}");
            } else {
                below += 1;
                assert!(full <= floor, "trial {trial}: {full} > {floor}");
            }
        }
        assert!(above > 20 && below > 20, "{above} above, {below} below");
    }

    /// The sampled points with the ascent give a lower bound of the true margin
    /// `max_{|n| = 1} min_j (|d_j − n|² − 1)` (estimated from above on 20,000 directions of
    /// the circle: between them the value moves by at most `4 · 2 · π/20000`), and find
    /// the uncovered points the fixed samples miss: on a jittered disc at `r` = 2.7
    /// spacings, every particle with a point uncovered by more than 0.05 is certified.
    #[test]
    fn margin_is_a_lower_bound_and_finds_clearly_uncovered_points() {
        let mut rows = vec![];
        let mut seed = 7u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for k in 0..400 {
            let (x, y) = ((k % 20) as f64, (k / 20) as f64);
            if (x - 9.5).powi(2) + (y - 9.5).powi(2) < 90.0 {
                rows.push([x + 0.5 * next(), y + 0.5 * next()]);
            }
        }
        let set = ParticleSet::from_rows(&rows).unwrap();
        let r = 2.7;
        let f = particle_features(&set, set.len(), Radius::new(r).unwrap()).unwrap();
        let p = set.positions();
        let dense = 20_000;
        let slack = 8.0 * std::f64::consts::PI / dense as f64;
        let mut clearly_uncovered = 0;
        for (i, pf) in f.iter().enumerate() {
            let offsets: Vec<Point<2>> = (0..p.len())
                .filter(|&j| j != i)
                .map(|j| (p[j] - p[i]) / r)
                .filter(|d| d.norm() <= 2.0)
                .collect();
            let truth = (0..dense)
                .map(|k| {
                    let t = 2.0 * std::f64::consts::PI * k as f64 / dense as f64;
                    let n = Point::<2>::new(t.cos(), t.sin());
                    offsets
                        .iter()
                        .map(|d| (d - n).norm_squared() - 1.0)
                        .fold(f64::INFINITY, f64::min)
                })
                .fold(f64::NEG_INFINITY, f64::max);
            let margin = pf.features[MARGIN_FEATURE];
            // The feature is clamped to [MARGIN_FLOOR, 1].
            let bound = truth.clamp(MARGIN_FLOOR, 1.0);
            assert!(margin <= bound + slack, "particle {i}: {margin} > {truth}");
            if truth > 0.05 {
                clearly_uncovered += 1;
                assert!(
                    pf.certified_boundary(2),
                    "particle {i}: {margin}, true {truth}"
                );
            }
        }
        assert!(clearly_uncovered > 20, "{clearly_uncovered}");
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
