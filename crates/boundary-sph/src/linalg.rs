//! Eigen-decomposition of the small symmetric matrices of SPH (the renormalisation matrix is
//! `D × D`, `D` = 2 or 3), written once for every `D` with cyclic Jacobi rotations.
//!
//! Jacobi is chosen over closed forms because it is one routine for both dimensions, it is
//! accurate to a few ulps of the matrix norm even for (near-)repeated eigenvalues, where the
//! trigonometric 3 × 3 formula loses digits, and it costs next to nothing at this size (one
//! rotation in 2D, three to four sweeps of three rotations in 3D).

use boundary_core::nalgebra::{SMatrix, SVector};

/// Eigenvalues (ascending) and orthonormal eigenvectors (the columns, in the same order) of
/// a symmetric matrix.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SymmetricEigen<const D: usize> {
    /// Eigenvalues, smallest first.
    pub values: SVector<f64, D>,
    /// Column `k` is the unit eigenvector of `values[k]`.
    pub vectors: SMatrix<f64, D, D>,
}

impl<const D: usize> SymmetricEigen<D> {
    /// Decomposes `m`, which is read as symmetric: only `(m + mᵀ)/2` is used. Entries must be
    /// finite (a NaN entry gives NaN eigenvalues, never a panic).
    pub fn new(m: &SMatrix<f64, D, D>) -> Self {
        let mut a = (m + m.transpose()) * 0.5;
        let mut v = SMatrix::<f64, D, D>::identity();
        let scale = a.norm_squared();
        // Converged when the off-diagonal mass is below (1e-15 · |A|)²: rounding level.
        let tolerance = scale * 1e-30;
        for _sweep in 0..64 {
            let mut off = 0.0;
            for p in 0..D {
                for q in p + 1..D {
                    off += a[(p, q)] * a[(p, q)];
                }
            }
            // Done, or a NaN entry (no rotation can help): stop.
            if off <= tolerance || off.is_nan() {
                break;
            }
            for p in 0..D {
                for q in p + 1..D {
                    let apq = a[(p, q)];
                    if apq == 0.0 {
                        continue;
                    }
                    // The rotation J (J_pp = J_qq = c, J_pq = s, J_qp = −s) zeroing a_pq in
                    // JᵀAJ; t = tan of the angle, the smaller root for stability.
                    let theta = (a[(q, q)] - a[(p, p)]) / (2.0 * apq);
                    let t = if theta.abs() > 1e150 {
                        0.5 / theta
                    } else {
                        theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt())
                    };
                    let c = 1.0 / (t * t + 1.0).sqrt();
                    let s = t * c;
                    for k in 0..D {
                        let (akp, akq) = (a[(k, p)], a[(k, q)]);
                        a[(k, p)] = c * akp - s * akq;
                        a[(k, q)] = s * akp + c * akq;
                    }
                    for k in 0..D {
                        let (apk, aqk) = (a[(p, k)], a[(q, k)]);
                        a[(p, k)] = c * apk - s * aqk;
                        a[(q, k)] = s * apk + c * aqk;
                    }
                    for k in 0..D {
                        let (vkp, vkq) = (v[(k, p)], v[(k, q)]);
                        v[(k, p)] = c * vkp - s * vkq;
                        v[(k, q)] = s * vkp + c * vkq;
                    }
                }
            }
        }
        // Sort ascending (D <= 3: insertion sort on the indices).
        let mut order: [usize; D] = std::array::from_fn(|k| k);
        order.sort_by(|&x, &y| a[(x, x)].total_cmp(&a[(y, y)]));
        SymmetricEigen {
            values: SVector::<f64, D>::from_fn(|k, _| a[(order[k], order[k])]),
            vectors: SMatrix::<f64, D, D>::from_fn(|row, k| v[(row, order[k])]),
        }
    }

    /// A floor of [`Self::new`]`(m).min_value()` without the decomposition: Gershgorin's
    /// lower bound of the smallest eigenvalue of `(m + mᵀ)/2`, `min_k (a_kk − Σ_{j≠k} |a_kj|)`,
    /// lowered by [`Self::FLOOR_ALLOWANCE`] times the Frobenius norm of `(m + mᵀ)/2` for the
    /// rounding of the bound and of the Jacobi rotations (a few `1e-16` of the norm). Tight
    /// where `m` is close to diagonal, as the renormalisation matrix is inside a fluid: a
    /// test `floor > μ` then decides `min_value() > μ` without the rotations. NaN for a NaN
    /// entry (any comparison with it is false).
    pub fn min_value_floor(m: &SMatrix<f64, D, D>) -> f64 {
        let a = (m + m.transpose()) * 0.5;
        let mut floor = f64::INFINITY;
        for k in 0..D {
            let mut radius = 0.0;
            for j in 0..D {
                if j != k {
                    radius += a[(k, j)].abs();
                }
            }
            floor = floor.min(a[(k, k)] - radius);
        }
        let norm = a.norm();
        if norm.is_nan() {
            return f64::NAN;
        }
        floor - Self::FLOOR_ALLOWANCE * norm
    }

    /// The rounding allowance of [`Self::min_value_floor`], relative to the matrix's norm.
    pub const FLOOR_ALLOWANCE: f64 = 1e-12;

    /// The smallest eigenvalue.
    pub fn min_value(&self) -> f64 {
        self.values[0]
    }

    /// `M⁻¹ b = Σ_k (v_k · b / λ_k) v_k`; components along eigenvalues that are zero give
    /// non-finite results, so callers check `min_value` first.
    pub fn solve(&self, b: &SVector<f64, D>) -> SVector<f64, D> {
        let mut x = SVector::<f64, D>::zeros();
        for k in 0..D {
            let vk = self.vectors.column(k);
            x += vk * (vk.dot(b) / self.values[k]);
        }
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{rngs::StdRng, Rng, SeedableRng};

    fn check<const D: usize>(m: &SMatrix<f64, D, D>) {
        let e = SymmetricEigen::new(m);
        let scale = m.norm().max(1e-300);
        let rebuilt =
            e.vectors * SMatrix::<f64, D, D>::from_diagonal(&e.values) * e.vectors.transpose();
        assert!((rebuilt - m).norm() <= 1e-13 * scale, "{m} vs {rebuilt}");
        let orth = e.vectors.transpose() * e.vectors - SMatrix::<f64, D, D>::identity();
        assert!(orth.norm() < 1e-13);
        for k in 1..D {
            assert!(e.values[k - 1] <= e.values[k]);
        }
    }

    #[test]
    fn random_symmetric_matrices_are_rebuilt() {
        let mut rng = StdRng::seed_from_u64(1);
        for _ in 0..500 {
            let a = SMatrix::<f64, 3, 3>::from_fn(|_, _| rng.gen_range(-2.0..2.0));
            check(&(a + a.transpose()));
            let b = SMatrix::<f64, 2, 2>::from_fn(|_, _| rng.gen_range(-2.0..2.0));
            check(&(b + b.transpose()));
            // Positive semi-definite, rank one (a renormalisation matrix with one neighbour).
            let d = SVector::<f64, 3>::from_fn(|_, _| rng.gen_range(-1.0..1.0));
            check(&(d * d.transpose()));
        }
    }

    #[test]
    fn known_spectra_and_solves_are_recovered() {
        let m = SMatrix::<f64, 2, 2>::new(2.0, 1.0, 1.0, 2.0);
        let e = SymmetricEigen::new(&m);
        assert!((e.values[0] - 1.0).abs() < 1e-15 && (e.values[1] - 3.0).abs() < 1e-15);
        // Repeated eigenvalue and the identity: nothing to rotate.
        let e = SymmetricEigen::new(&SMatrix::<f64, 3, 3>::identity());
        assert_eq!(e.values, SVector::<f64, 3>::from_element(1.0));
        let z = SymmetricEigen::new(&SMatrix::<f64, 3, 3>::zeros());
        assert_eq!(z.min_value(), 0.0);
        // A solve through the decomposition.
        let m = SMatrix::<f64, 3, 3>::new(4.0, 1.0, 0.5, 1.0, 3.0, 0.2, 0.5, 0.2, 2.0);
        let b = SVector::<f64, 3>::new(1.0, -2.0, 0.5);
        let x = SymmetricEigen::new(&m).solve(&b);
        assert!((m * x - b).norm() < 1e-14);
    }

    /// The floor is never above the decomposition's smallest eigenvalue: random symmetric
    /// and positive semi-definite matrices, matrices near the identity (the renormalisation
    /// matrix inside a fluid), diagonal ones (where Gershgorin's bound is the eigenvalue
    /// itself), and rotations of a spectrum whose smallest value sits `1e-15..1e-6` from a
    /// threshold; where the floor clears the threshold, the eigenvalue does too.
    #[test]
    fn the_floor_is_below_the_smallest_eigenvalue() {
        fn check<const D: usize>(m: &SMatrix<f64, D, D>) -> (f64, f64) {
            let floor = SymmetricEigen::min_value_floor(m);
            let lambda = SymmetricEigen::new(m).min_value();
            assert!(floor <= lambda, "{m}: floor {floor} > λ {lambda}");
            (floor, lambda)
        }
        let mut rng = StdRng::seed_from_u64(9);
        let mut cleared = 0;
        for _ in 0..20_000 {
            let a = SMatrix::<f64, 3, 3>::from_fn(|_, _| rng.gen_range(-1.0..1.0));
            check(&(a + a.transpose()));
            check(&(a * a.transpose()));
            let b = SMatrix::<f64, 2, 2>::from_fn(|_, _| rng.gen_range(-1.0..1.0));
            check(&(b * b.transpose()));
            let eps: f64 = 10f64.powf(rng.gen_range(-6.0..-1.0));
            let near = SMatrix::<f64, 3, 3>::identity() + (a + a.transpose()) * eps;
            let (floor, _) = check(&near);
            cleared += usize::from(floor > 0.75);
            let d = SVector::<f64, 3>::from_fn(|_, _| rng.gen_range(0.0..2.0));
            let (floor, lambda) = check(&SMatrix::<f64, 3, 3>::from_diagonal(&d));
            assert!(lambda - floor <= 1e-11, "diagonal: the bound is tight");
            // A spectrum just above or below 0.75, turned by a random rotation.
            let gap = 10f64.powf(rng.gen_range(-15.0..-6.0)) * [-1.0, 1.0][rng.gen_range(0..2)];
            let spectrum = SVector::<f64, 3>::new(0.75 + gap, 1.0, rng.gen_range(1.0..1.2));
            let axis = SVector::<f64, 3>::from_fn(|_, _| rng.gen_range(-1.0..1.0));
            let turn = boundary_core::nalgebra::Rotation3::new(axis * rng.gen_range(0.0..1e-3));
            let q = turn.matrix();
            let m = q * SMatrix::<f64, 3, 3>::from_diagonal(&spectrum) * q.transpose();
            let (floor, lambda) = check(&m);
            if floor > 0.75 {
                assert!(lambda > 0.75);
            }
        }
        assert!(
            cleared > 10_000,
            "the floor decides most near-identity matrices: {cleared}"
        );
    }

    #[test]
    fn nan_entries_do_not_panic() {
        let m = SMatrix::<f64, 3, 3>::from_element(f64::NAN);
        let e = SymmetricEigen::new(&m);
        assert!(e.min_value().is_nan());
        assert!(SymmetricEigen::min_value_floor(&m).is_nan());
    }
}
