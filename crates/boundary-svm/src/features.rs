//! The per-particle feature vector of the thesis (Sec. 3.2.1), made scale-free.
//!
//! All sums run over the neighbours within the influence radius, the support `2h` of the
//! Wendland C2 kernel at `h = r` (`boundary-sph`). With `V_j = 1/Σ_k W_jk` the
//! summation-density volumes (uniform mass; it cancels), the six features of particle `i` are
//!
//! | index | feature (thesis Fig. 18) | definition here | why it is scale-free |
//! |---|---|---|---|
//! | 0 | density function (Parzen window) | `ρ_i r^D`, `ρ_i = Σ_j W_ij` (`j = i` included) | `W` scales as `h^-D` |
//! | 1 | modulus of the density gradient | `\|Σ_{j≠i} ∇W_ij\| r^{D+1}` (the SPH gradient `Σ_j m_j ∇W_ij` with unit mass) | `∇W` scales as `h^-(D+1)` |
//! | 2 | divergence | `∇·x = Σ_j V_j (x_j − x_i)·∇W_ij` (the trace of the renormalisation matrix) | dimensionless; `D` inside the fluid |
//! | 3 | number of neighbours within the influence radius | count of `j ≠ i` with `\|x_j − x_i\| <= 2r` | a count |
//! | 4 | smallest eigenvalue of the neighbourhood covariance | `λ_min(C_i) / r²` | `C` scales as `r²` |
//! | 5 | largest eigenvalue of the neighbourhood covariance | `λ_max(C_i) / r²` | as above |
//!
//! `C_i = (1/k) Σ (x_j − x̄)(x_j − x̄)ᵀ` over the `k` positions of the neighbourhood (`i` and
//! its neighbours within `2r`), `x̄` their mean.
//!
//! **The divergence term.** The thesis lists "the modulus of [the density's] gradient and
//! divergence" without saying of what field the divergence is taken; the divergence of a
//! scalar density is not defined. We use the SPH divergence of the position field, `∇·x`,
//! which is exactly `D` for a full, uniform neighbourhood and drops where the neighbourhood
//! is one-sided: the quantity the thesis' "divergence" most plausibly refers to (it is also
//! the classic free-surface indicator of Lee et al. 2008).
//!
//! **Scale-freeness.** Scaling every position and `r` by the same factor leaves every feature
//! unchanged up to rounding (tested for factors `2^k`, relative tolerance `1e-12`), so a model
//! trained at one resolution applies at another with the same `r`/spacing ratio.
//!
//! **Degenerate input.** An isolated particle has `ρ r^D = W(0) r^D`, gradient 0, divergence 0,
//! no neighbours and a zero covariance. Duplicates of `x_i` count as neighbours and add to its
//! density, but contribute no gradient or divergence (their direction is undefined).

use boundary_core::nalgebra::SMatrix;
use boundary_core::{CoreError, ParticleSet, Point, Radius};
use boundary_sph::{Kernel, SphContext, SphKernel, SymmetricEigen, SUPPORT_FACTOR};
use rayon::prelude::*;

/// Number of features per particle.
pub const N_FEATURES: usize = 6;

/// Version of the feature definition; a model records the version it was trained on and is
/// refused by a detector that computes another.
pub const FEATURE_VERSION: u32 = 1;

/// The names of the features, in order.
pub const FEATURE_NAMES: [&str; N_FEATURES] = [
    "density",
    "density_gradient",
    "divergence",
    "neighbours",
    "covariance_min",
    "covariance_max",
];

/// One particle's features (see the module documentation for their order).
pub type Features = [f64; N_FEATURES];

/// How far from a particle its features look: the volumes of its neighbours within `2r`
/// come from their own neighbours within `2r`.
pub fn feature_reach(r: Radius) -> f64 {
    2.0 * SUPPORT_FACTOR * r.get()
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
    Ok(features_and_distinct_neighbours(set, count, r)?
        .into_iter()
        .map(|(f, _)| f)
        .collect())
}

/// [`compute_features`], each with the number of neighbours within `2r` that are not
/// duplicates of the particle (the ones that can cover part of its sphere).
pub(crate) fn features_and_distinct_neighbours<const D: usize>(
    set: &ParticleSet<D>,
    count: usize,
    r: Radius,
) -> Result<Vec<(Features, usize)>, CoreError> {
    let r = r.get();
    let ctx = SphContext::new(set, SphKernel::<D>::new(Kernel::WendlandC2, r))?;
    let count = count.min(set.len());
    Ok((0..count)
        .into_par_iter()
        .map(|i| particle_features(&ctx, i, r))
        .collect())
}

fn particle_features<const D: usize>(
    ctx: &SphContext<'_, D>,
    i: usize,
    r: f64,
) -> (Features, usize) {
    let kernel = ctx.kernel();
    let volumes = ctx.volumes();
    let mut gradient = Point::<D>::zeros();
    let mut divergence = 0.0;
    let mut count = 0usize;
    let mut distinct = 0usize;
    // Moments of the neighbourhood relative to x_i (i itself contributes the zero vector),
    // so that the covariance does not lose digits far from the origin.
    let mut first = Point::<D>::zeros();
    let mut second = SMatrix::<f64, D, D>::zeros();
    ctx.for_each_neighbour(i, |j, xji, dist| {
        count += 1;
        first += xji;
        second += xji * xji.transpose();
        if dist > 0.0 {
            distinct += 1;
            // ∇_i W_ij = w (x_j − x_i) with w = −W'(r)/r >= 0 (boundary-sph convention).
            let w = -kernel.derivative(dist) / dist;
            gradient += xji * w;
            divergence += volumes[j] * w * xji.norm_squared();
        }
    });
    let k = (count + 1) as f64;
    let mean = first / k;
    let covariance = second / k - mean * mean.transpose();
    let eigen = SymmetricEigen::new(&covariance);
    let r2 = r * r;
    let rd = r.powi(D as i32);
    let features = [
        rd / volumes[i],
        gradient.norm() * rd * r,
        divergence,
        count as f64,
        // Rounding can make a zero eigenvalue slightly negative; the covariance is PSD.
        eigen.values[0].max(0.0) / r2,
        eigen.values[D - 1].max(0.0) / r2,
    ];
    (features, distinct)
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
        assert!((centre[2] - 2.0).abs() < 0.1, "{centre:?}");
        // Neighbours within 2r = 3 on the unit lattice: 28 others.
        assert_eq!(centre[3], 28.0);
        let corner = f[0];
        assert!(
            corner[1] > 0.5 && corner[2] < 1.5 && corner[3] < 12.0,
            "{corner:?}"
        );
    }

    #[test]
    fn isolated_particle_and_duplicates() {
        let set = ParticleSet::from_rows(&[[0.0, 0.0], [0.0, 0.0], [50.0, 50.0]]).unwrap();
        let r = Radius::new(1.0).unwrap();
        let f = compute_features(&set, 3, r).unwrap();
        let w0 = SphKernel::<2>::new(Kernel::WendlandC2, 1.0).value(0.0);
        assert_eq!(f[2], [w0, 0.0, 0.0, 0.0, 0.0, 0.0]);
        assert_eq!(f[0][1..], [0.0, 0.0, 1.0, 0.0, 0.0]);
        assert!((f[0][0] - 2.0 * w0).abs() < 1e-15);
        assert_eq!(compute_features(&set, 1, r).unwrap().len(), 1);
    }
}
