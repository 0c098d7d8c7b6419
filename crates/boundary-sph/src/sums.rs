//! Summation density, particle volumes and the per-particle kernel sums.

use crate::kernel::SphKernel;
use boundary_core::nalgebra::SMatrix;
use boundary_core::{CoreError, NeighbourGrid, ParticleSet, Point};
use rayon::prelude::*;

/// The number density `n_i = Σ_j W_ij` of every particle (`j` over all particles within the
/// support, `i` itself and its duplicates included), in input order. With a uniform mass `m`
/// the summation density is `ρ_i = m n_i`; `n_i >= W(0) > 0`. In physical units (a factor
/// `h^-D`: not finite for extreme `h`; [`SphContext`] works in units of `h`).
pub fn number_density<const D: usize>(
    positions: &[Point<D>],
    grid: &NeighbourGrid<D>,
    kernel: &SphKernel<D>,
) -> Vec<f64> {
    let scale = kernel.h().powi(-(D as i32));
    reduced_number_density(positions, grid, kernel)
        .into_iter()
        .map(|n| n * scale)
        .collect()
}

/// `n_i · h^D = Σ_j σ_D f(|x_j − x_i|/h)`: the number density in units of `h` (no power of
/// `h`, finite for every `h`). Distances are divided by `h` before their norm is taken.
fn reduced_number_density<const D: usize>(
    positions: &[Point<D>],
    grid: &NeighbourGrid<D>,
    kernel: &SphKernel<D>,
) -> Vec<f64> {
    let support = kernel.support();
    let inv_h = 1.0 / kernel.h();
    positions
        .par_iter()
        .map(|p| {
            let mut sum = 0.0;
            grid.for_each_within(p, support, |j, _| {
                let q = ((positions[j] - p) * inv_h).norm();
                sum += kernel.reduced_value(q);
            });
            sum
        })
        .collect()
}

/// The summation density `ρ_i = Σ_j m W_ij` with a uniform particle mass `m`.
pub fn summation_density<const D: usize>(
    positions: &[Point<D>],
    grid: &NeighbourGrid<D>,
    kernel: &SphKernel<D>,
    mass: f64,
) -> Vec<f64> {
    let mut rho = number_density(positions, grid, kernel);
    rho.iter_mut().for_each(|r| *r *= mass);
    rho
}

/// The sums over the neighbours `j` of one particle `i` that the SPH detectors use, with
/// `V_j = m/ρ_j` the summation-density volumes and `∇W_ij = ∇_i W(|x_i − x_j|)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalSums<const D: usize> {
    /// Shepard sum `Σ_j V_j W_ij` (`j = i` included): the SPH interpolant of the constant 1,
    /// Müller et al.'s colour field `c_i`; close to 1 inside the fluid.
    pub shepard: f64,
    /// `Σ_j V_j ∇W_ij`: the SPH gradient of the constant 1, the colour-field gradient `∇c_i`;
    /// close to 0 inside, pointing into the fluid near its surface. Physical units (1/length):
    /// `gradient_h / h`.
    pub gradient: Point<D>,
    /// `∇c_i · h`: the same gradient in units of `1/h`, dimensionless and computed without any
    /// power of `h`, so it is the same for a scene and its scaled copy (at every scale whose
    /// squared distances are finite). The detectors use this one.
    pub gradient_h: Point<D>,
    /// The renormalisation matrix `B_i = Σ_j V_j (x_j − x_i) ⊗ ∇W_ij` (Randles & Libersky
    /// 1996; Marrone et al. 2010 write its inverse `L_i`): symmetric, positive semi-definite,
    /// close to the identity inside the fluid.
    pub renormalisation: SMatrix<f64, D, D>,
    /// Number of other particles within the support (duplicates of `x_i` included).
    pub neighbours: usize,
}

/// Positions, the neighbour grid (cells of one support radius), the kernel and the particle
/// volumes of a set: everything the SPH kernel sums need, built once per detection.
///
/// Every sum is computed in units of `h` (distances divided by `h` first, the kernel without
/// its `h^-D`, volumes as `V/h^D`), so the dimensionless results (Shepard sum, `∇c·h`, the
/// renormalisation matrix) are the same for a scene and its scaled copy, for every `h` whose
/// squared support radius is a normal `f64` (about `1e-150 <= h <= 1e150`; the neighbour
/// grid compares squared distances).
#[derive(Debug)]
pub struct SphContext<'a, const D: usize> {
    positions: &'a [Point<D>],
    grid: NeighbourGrid<D>,
    kernel: SphKernel<D>,
    /// `V_i / h^D`.
    reduced_volumes: Vec<f64>,
    /// `V_i` (physical; may be 0 or infinite for extreme `h`).
    volumes: Vec<f64>,
}

impl<'a, const D: usize> SphContext<'a, D> {
    /// Builds the grid and the volumes `V_i = m/ρ_i = 1/n_i` (the uniform mass cancels, so
    /// only positions are needed). Fails only where the grid does (a bounding box of more
    /// than `2^52` support radii along an axis).
    pub fn new(set: &'a ParticleSet<D>, kernel: SphKernel<D>) -> Result<Self, CoreError> {
        let positions = set.positions();
        let grid = NeighbourGrid::new(set, kernel.support())?;
        let reduced_volumes: Vec<f64> = reduced_number_density(positions, &grid, &kernel)
            .into_iter()
            .map(|n| 1.0 / n)
            .collect();
        let h_d = kernel.h().powi(D as i32);
        let volumes = reduced_volumes.iter().map(|v| v * h_d).collect();
        Ok(SphContext {
            positions,
            grid,
            kernel,
            reduced_volumes,
            volumes,
        })
    }

    /// The positions, in input order.
    pub fn positions(&self) -> &'a [Point<D>] {
        self.positions
    }

    /// The neighbour grid (cells of one support radius).
    pub fn grid(&self) -> &NeighbourGrid<D> {
        &self.grid
    }

    /// The kernel.
    pub fn kernel(&self) -> &SphKernel<D> {
        &self.kernel
    }

    /// The volumes `V_i = m/ρ_i`, in input order (physical units: not finite for extreme
    /// `h`; see [`Self::reduced_volumes`]).
    pub fn volumes(&self) -> &[f64] {
        &self.volumes
    }

    /// The volumes in units of `h`, `V_i / h^D = 1 / Σ_j σ_D f(q_ij)`, in input order: finite
    /// and positive for every `h`.
    pub fn reduced_volumes(&self) -> &[f64] {
        &self.reduced_volumes
    }

    /// Calls `f(j, x_j − x_i, |x_j − x_i|)` for every particle `j != i` within the support of
    /// particle `i` (duplicates of `x_i` come with distance 0), in an unspecified but
    /// deterministic order.
    pub fn for_each_neighbour<F: FnMut(usize, Point<D>, f64)>(&self, i: usize, mut f: F) {
        let p = self.positions[i];
        self.grid
            .for_each_within(&p, self.kernel.support(), |j, d2| {
                if j != i {
                    f(j, self.positions[j] - p, d2.sqrt());
                }
            });
    }

    /// The kernel sums of particle `i`; see [`LocalSums`]. Computed in units of `h`:
    /// `V_j ∇W_ij · h = (V_j/h^D) · σ_D (−f'(q)/q) · (x_j − x_i)/h`.
    pub fn local_sums(&self, i: usize) -> LocalSums<D> {
        let kernel = &self.kernel;
        let inv_h = 1.0 / kernel.h();
        let p = self.positions[i];
        let mut sums = LocalSums {
            shepard: self.reduced_volumes[i] * kernel.reduced_value(0.0),
            gradient: Point::<D>::zeros(),
            gradient_h: Point::<D>::zeros(),
            renormalisation: SMatrix::<f64, D, D>::zeros(),
            neighbours: 0,
        };
        self.grid.for_each_within(&p, kernel.support(), |j, _| {
            if j == i {
                return;
            }
            let v = self.reduced_volumes[j];
            // x_j − x_i in units of h.
            let xji = (self.positions[j] - p) * inv_h;
            let q = xji.norm();
            sums.neighbours += 1;
            sums.shepard += v * kernel.reduced_value(q);
            if q > 0.0 {
                // ∇_i W_ij = W'(r) (x_i − x_j)/r = w (x_j − x_i) with w = −W'(r)/r >= 0.
                let g = xji * (v * kernel.reduced_gradient_weight(q));
                sums.gradient_h += g;
                sums.renormalisation += xji * g.transpose();
            }
        });
        sums.gradient = sums.gradient_h * inv_h;
        sums
    }
}

impl<const D: usize> SphContext<'_, D> {
    /// The divergence of position `∇·r_i = Σ_{j≠i} V_j (x_j − x_i)·∇_i W_ij` of particle `i`
    /// (dimensionless; the trace of [`LocalSums::renormalisation`], about `D` inside a full
    /// neighbourhood) and the number of other particles within the support (duplicates of
    /// `x_i` included; they add nothing to the sum). One neighbour pass without the matrix:
    /// `Σ_j (V_j/h^D) · σ_D (−f'(q)/q) · q²` with `q = |x_j − x_i|/h`.
    pub fn divergence_of_position(&self, i: usize) -> (f64, usize) {
        let kernel = &self.kernel;
        let inv_h = 1.0 / kernel.h();
        let p = self.positions[i];
        let mut sum = 0.0;
        let mut neighbours = 0;
        self.grid.for_each_within(&p, kernel.support(), |j, _| {
            if j != i {
                let q2 = ((self.positions[j] - p) * inv_h).norm_squared();
                sum += self.reduced_volumes[j] * kernel.reduced_gradient_weight(q2.sqrt()) * q2;
                neighbours += 1;
            }
        });
        (sum, neighbours)
    }
}

/// Outward unit normals from the colour-field gradient (Müller et al., SCA 2003, Sec. 5):
/// `n_i = −∇c_i / |∇c_i|` with `∇c_i = Σ_j V_j ∇W_ij`, the gradient of unity of
/// [`LocalSums`] (it points into the fluid, so its negation points out), Wendland C2 at `h`.
///
/// Tolerance: where `|∇c_i| · h < 1e-9` (inside a symmetric neighbourhood, or an isolated
/// particle) the direction is undefined and the zero vector is returned. Exact duplicates
/// contribute nothing (their `∇W` is zero at distance 0).
///
/// ```
/// use boundary_core::ParticleSet;
/// use boundary_sph::colour_field_normals;
///
/// // A 5 x 5 lattice: the middle of the left edge points to −x, the centre has no normal.
/// let rows: Vec<[f64; 2]> = (0..25).map(|k| [(k % 5) as f64, (k / 5) as f64]).collect();
/// let set = ParticleSet::from_rows(&rows).unwrap();
/// let n = colour_field_normals(&set, 1.0).unwrap();
/// assert!((n[10].x + 1.0).abs() < 1e-12 && n[10].y.abs() < 1e-12);
/// assert_eq!(n[12].norm(), 0.0);
/// ```
pub fn colour_field_normals<const D: usize>(
    set: &ParticleSet<D>,
    h: f64,
) -> Result<Vec<Point<D>>, CoreError> {
    use crate::kernel::Kernel;
    let ctx = SphContext::new(set, SphKernel::new(Kernel::WendlandC2, h))?;
    Ok((0..set.len())
        .into_par_iter()
        .map(|i| {
            let g = ctx.local_sums(i).gradient_h;
            let norm = g.norm();
            if norm < 1e-9 {
                Point::<D>::zeros()
            } else {
                -g / norm
            }
        })
        .collect())
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test
mod tests {
    use super::*;
    use crate::kernel::Kernel;

    #[test]
    fn the_divergence_of_position_is_the_trace_of_the_renormalisation_matrix() {
        let rows: Vec<[f64; 3]> = (0..216)
            .map(|k| {
                let j = (k * 7919 % 1000) as f64 * 1e-4;
                [
                    (k % 6) as f64 + j,
                    (k / 6 % 6) as f64 - j,
                    (k / 36) as f64 + 0.5 * j,
                ]
            })
            .collect();
        let set = ParticleSet::from_rows(&rows).unwrap();
        for kernel in Kernel::ALL {
            let ctx = SphContext::new(&set, SphKernel::new(kernel, 1.3)).unwrap();
            for i in 0..set.len() {
                let sums = ctx.local_sums(i);
                let (divr, n) = ctx.divergence_of_position(i);
                assert_eq!(n, sums.neighbours);
                assert!((divr - sums.renormalisation.trace()).abs() < 1e-12, "{i}");
            }
        }
    }

    #[test]
    fn isolated_particles_and_duplicates_get_the_stated_volumes_and_sums() {
        let set =
            ParticleSet::from_rows(&[[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [9.0, 9.0, 9.0]]).unwrap();
        let kernel = SphKernel::<3>::new(Kernel::WendlandC2, 1.0);
        let ctx = SphContext::new(&set, kernel).unwrap();
        let w0 = kernel.value(0.0);
        assert!((ctx.volumes()[0] - 0.5 / w0).abs() < 1e-15);
        assert!((ctx.volumes()[2] - 1.0 / w0).abs() < 1e-15);
        let far = ctx.local_sums(2);
        assert_eq!(far.neighbours, 0);
        assert!((far.shepard - 1.0).abs() < 1e-15);
        assert_eq!(far.gradient, Point::<3>::zeros());
        let dup = ctx.local_sums(0);
        assert_eq!(dup.neighbours, 1);
        assert_eq!(dup.renormalisation, SMatrix::<f64, 3, 3>::zeros());
        assert!((dup.shepard - 1.0).abs() < 1e-15);
        let rho = summation_density(ctx.positions(), ctx.grid(), &kernel, 2.0);
        assert_eq!(ctx.divergence_of_position(2), (0.0, 0));
        assert_eq!(ctx.divergence_of_position(0), (0.0, 1));
        assert!((rho[0] - 4.0 * w0).abs() < 1e-12);
    }
}
