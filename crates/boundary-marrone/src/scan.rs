//! The scan region of Marrone et al. (2010), second step: the "umbrella" in front of a
//! candidate particle, along its outward normal.
//!
//! With `T = x_i + h n` and `d = |x_j − x_i|`, a neighbour `x_j` lies in the region when
//! - `d >= 2h cos θ` and `|x_j − T| < h` (the ball of radius `h` around `T`, far part), or
//! - `d < 2h cos θ` and the angle between `x_j − x_i` and `n` is below `θ` (the cone, near part).
//!
//! The paper's `θ = π/4` puts the switch at `√2 h`, where the cone's surface meets the sphere
//! `|x − T| = h` (a chord at angle `θ` from the diameter through `x_i` has length `2h cos θ`):
//! the region is the cone capped by the far part of the ball. Marrone et al. state the 3D
//! near part as this cone and the 2D one as `|n·(x_j − T)| + |τ·(x_j − T)| < h` (a square of
//! half-diagonal `h` centred at `T`, `τ ⊥ n`); inside the disc `d < √2 h` the two coincide
//! (for `s = n·(x_j − x_i) > h` and `|τ·(x_j − x_i)| < s`, Cauchy–Schwarz gives
//! `|τ·…| + s <= √2 d < 2h`), so one generic test serves both dimensions (checked against the
//! square form in the tests below).

use boundary_core::Point;

/// The scan region of one particle.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ScanRegion<const D: usize> {
    normal: Point<D>,
    h: f64,
    cos_theta: f64,
    /// `(2h cos θ)²`.
    switch2: f64,
}

impl<const D: usize> ScanRegion<D> {
    /// The region of a particle with unit outward normal `normal`, smoothing length `h` and
    /// cone half-angle `theta` (radians, in `(0, π/2)`).
    pub(crate) fn new(normal: Point<D>, h: f64, theta: f64) -> Self {
        let switch = 2.0 * h * theta.cos();
        ScanRegion {
            normal,
            h,
            cos_theta: theta.cos(),
            switch2: switch * switch,
        }
    }

    /// Whether the neighbour at `xji = x_j − x_i`, at distance `d = |xji| > 0`, lies in the
    /// region. Both parts are open, as in the paper (strict inequalities): a neighbour exactly
    /// on the cone's surface or the ball's sphere does not shield the particle.
    #[inline]
    pub(crate) fn contains(&self, xji: &Point<D>, d: f64) -> bool {
        if d * d >= self.switch2 {
            (xji - self.normal * self.h).norm_squared() < self.h * self.h
        } else {
            self.normal.dot(xji) > d * self.cos_theta
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{rngs::StdRng, Rng, SeedableRng};
    use std::f64::consts::FRAC_PI_4;

    /// The paper's 2D near part, literally: `|n·(x_j − T)| + |τ·(x_j − T)| < h`.
    fn square_form(n: &Point<2>, h: f64, xji: &Point<2>) -> bool {
        let d = xji.norm();
        let tau = Point::<2>::new(-n[1], n[0]);
        let xjt = xji - n * h;
        if d >= 2f64.sqrt() * h {
            xjt.norm() < h
        } else {
            n.dot(&xjt).abs() + tau.dot(&xjt).abs() < h
        }
    }

    #[test]
    fn the_2d_cone_is_the_papers_square() {
        let mut rng = StdRng::seed_from_u64(3);
        let mut inside = 0;
        for _ in 0..200_000 {
            let angle: f64 = rng.gen_range(0.0..std::f64::consts::TAU);
            let n = Point::<2>::new(angle.cos(), angle.sin());
            let h = rng.gen_range(0.1..3.0);
            let xji = Point::<2>::new(rng.gen_range(-2.0..2.0), rng.gen_range(-2.0..2.0)) * h;
            let d = xji.norm();
            let region = ScanRegion::new(n, h, FRAC_PI_4);
            let ours = region.contains(&xji, d);
            // Skip points within rounding of either boundary.
            let near_edge = ((d - 2f64.sqrt() * h).abs() < 1e-9 * h)
                || ((n.dot(&xji) - d * FRAC_PI_4.cos()).abs() < 1e-9 * h)
                || (((xji - n * h).norm() - h).abs() < 1e-9 * h);
            if !near_edge {
                assert_eq!(ours, square_form(&n, h, &xji), "n={n} h={h} x={xji}");
                inside += usize::from(ours);
            }
        }
        assert!(
            inside > 10_000,
            "the test must exercise the region ({inside})"
        );
    }

    #[test]
    fn the_3d_region_is_the_open_cone_near_and_the_open_ball_far() {
        let n = Point::<3>::new(0.0, 0.0, 1.0);
        let r = ScanRegion::new(n, 1.0, FRAC_PI_4);
        let at = |x: f64, y: f64, z: f64| {
            let p = Point::<3>::new(x, y, z);
            r.contains(&p, p.norm())
        };
        assert!(at(0.0, 0.0, 0.5)); // on the axis, near
        assert!(at(0.0, 0.0, 1.9)); // on the axis, far
        assert!(!at(0.0, 0.0, 2.0)); // the far pole, on the sphere: open region
        assert!(at(0.5, 0.0, 0.6)); // inside the cone (angle < 45°)
        assert!(!at(0.6, 0.0, 0.5)); // outside the cone, near
        assert!(at(0.9, 0.0, 1.3)); // far part: |x − T| < 1
        assert!(!at(0.0, 0.9, 0.2)); // beside the particle
        assert!(!at(0.0, 0.0, -0.5)); // behind
    }
}
