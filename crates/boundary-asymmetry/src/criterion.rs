//! The asymmetry criterion itself, on the sums of one particle: no neighbour search here, so
//! it is tested on hand-computed sums.

use boundary_core::Point;

/// The sums of one particle `i` that the criterion reads, all in units of `h` (so the same
/// for a scene and its scaled copy).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AsymmetrySums<const D: usize> {
    /// `Σ_j w_ij (x_j − x_i)/h` over the particles within the support, `w_ij = σ_D f(q_ij)`.
    pub offset: Point<D>,
    /// `n_i = Σ_j w_ij`, `j = i` included: the number density in units of `h`.
    pub density: f64,
    /// The largest `n_j` over `i` and the particles within its support: the reference density.
    pub reference_density: f64,
    /// Whether some particle lies inside the open support at a positive distance (duplicates
    /// of `x_i`, and particles exactly `2h` away, whose weight is zero, do not count).
    pub has_neighbour: bool,
}

/// The quantities the thresholds apply to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AsymmetryValue {
    /// `|x̄_i − x_i| / h` with `x̄_i = Σ_j w_ij x_j / Σ_j w_ij`: the asymmetry value.
    pub asymmetry: f64,
    /// `n_i / max_j n_j`, in `(0, 1]`.
    pub relative_density: f64,
    /// No particle within the support at a positive distance.
    pub isolated: bool,
}

impl<const D: usize> AsymmetrySums<D> {
    /// The asymmetry value and relative density of these sums. The density includes the
    /// particle itself, so it is positive and the division is safe.
    pub fn value(&self) -> AsymmetryValue {
        AsymmetryValue {
            asymmetry: self.offset.norm() / self.density,
            relative_density: self.density / self.reference_density,
            isolated: !self.has_neighbour,
        }
    }
}

impl AsymmetryValue {
    /// The signed margin: `max(asymmetry − threshold, density_ratio − relative_density)`,
    /// positive iff the particle is boundary by one of the two tests; `1` for an isolated
    /// particle (boundary whatever the thresholds).
    pub fn margin(&self, threshold: f64, density_ratio: f64) -> f64 {
        if self.isolated {
            return 1.0;
        }
        (self.asymmetry - threshold).max(density_ratio - self.relative_density)
    }

    /// Boundary iff isolated, or `asymmetry > threshold`, or
    /// `relative_density < density_ratio` (both strict: a value on a threshold is interior).
    pub fn is_boundary(&self, threshold: f64, density_ratio: f64) -> bool {
        self.isolated || self.asymmetry > threshold || self.relative_density < density_ratio
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hand_computed_sums_give_the_stated_value_and_labels() {
        // Two neighbours at +1 and +2 (units of h) along x with weights 3 and 1, self weight
        // 4: offset = 3·1 + 1·2 = 5, density 8, asymmetry 5/8.
        let sums = AsymmetrySums::<2> {
            offset: Point::<2>::new(5.0, 0.0),
            density: 8.0,
            reference_density: 10.0,
            has_neighbour: true,
        };
        let v = sums.value();
        assert_eq!(v.asymmetry, 0.625);
        assert_eq!(v.relative_density, 0.8);
        assert!(v.is_boundary(0.6, 0.7));
        assert!(!v.is_boundary(0.625, 0.7), "on the threshold: interior");
        assert!(v.is_boundary(0.7, 0.81), "the density test alone");
        assert!(!v.is_boundary(0.7, 0.8), "on the density ratio: interior");
        assert!((v.margin(0.6, 0.7) - 0.025).abs() < 1e-15);
        assert!((v.margin(0.7, 0.9) - 0.1).abs() < 1e-15);
        assert!(v.margin(0.7, 0.7) < 0.0);
    }

    #[test]
    fn an_isolated_particle_is_boundary_with_a_positive_margin() {
        let sums = AsymmetrySums::<3> {
            offset: Point::<3>::zeros(),
            density: 2.0,
            reference_density: 2.0,
            has_neighbour: false,
        };
        let v = sums.value();
        assert_eq!((v.asymmetry, v.relative_density), (0.0, 1.0));
        assert!(v.is_boundary(100.0, 0.0));
        assert_eq!(v.margin(100.0, 0.0), 1.0);
    }
}
