//! Smoothing kernels with compact support `2h`, in 2D and 3D.
//!
//! Both kernels are radial, `W(x, h) = σ_D h^-D f(|x|/h)`, with `q = |x|/h` in `[0, 2]` and
//! `f(q) = 0` beyond. They are normalised so that `∫ W dV = 1` over `R^D` (tested by numeric
//! integration).
//!
//! | kernel | `f(q)` | `σ_2` | `σ_3` |
//! |---|---|---|---|
//! | Wendland C2 (Wendland 1995) | `(1 − q/2)^4 (2q + 1)` | `7/(4π)` | `21/(16π)` |
//! | cubic spline (Monaghan & Lattanzio 1985) | `1 − 3q²/2 + 3q³/4` on `[0,1)`, `(2 − q)³/4` on `[1,2)` | `10/(7π)` | `1/π` |

use boundary_core::Point;
use std::f64::consts::PI;
use std::fmt;
use std::str::FromStr;

/// Ratio of the support radius to the smoothing length, for both kernels.
pub const SUPPORT_FACTOR: f64 = 2.0;

/// A smoothing-kernel shape; see the module documentation for the formulas.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Kernel {
    /// Wendland's C2 function: positive, smooth, no pairing instability; the usual choice of
    /// modern weakly compressible SPH solvers.
    #[default]
    WendlandC2,
    /// Monaghan's cubic B-spline (M4).
    CubicSpline,
}

impl Kernel {
    /// Every kernel, in the order `name` lists them.
    pub const ALL: [Kernel; 2] = [Kernel::WendlandC2, Kernel::CubicSpline];

    /// The name used in parameters (`wendland`, `cubic`).
    pub fn name(self) -> &'static str {
        match self {
            Kernel::WendlandC2 => "wendland",
            Kernel::CubicSpline => "cubic",
        }
    }

    /// The support radius `2h`: `W` vanishes at and beyond it.
    pub fn support_radius(self, h: f64) -> f64 {
        SUPPORT_FACTOR * h
    }

    /// The dimensionless shape `f(q)` (zero for `q >= 2`).
    pub fn shape(self, q: f64) -> f64 {
        match self {
            Kernel::WendlandC2 => {
                if q >= 2.0 {
                    0.0
                } else {
                    let t = 1.0 - 0.5 * q;
                    let t2 = t * t;
                    t2 * t2 * (2.0 * q + 1.0)
                }
            }
            Kernel::CubicSpline => {
                if q >= 2.0 {
                    0.0
                } else if q >= 1.0 {
                    let t = 2.0 - q;
                    0.25 * t * t * t
                } else {
                    1.0 - 1.5 * q * q + 0.75 * q * q * q
                }
            }
        }
    }

    /// The derivative `f'(q)` (zero for `q >= 2`; `f'(0) = 0` for both kernels).
    pub fn shape_derivative(self, q: f64) -> f64 {
        match self {
            Kernel::WendlandC2 => {
                if q >= 2.0 {
                    0.0
                } else {
                    let t = 1.0 - 0.5 * q;
                    -5.0 * q * t * t * t
                }
            }
            Kernel::CubicSpline => {
                if q >= 2.0 {
                    0.0
                } else if q >= 1.0 {
                    let t = 2.0 - q;
                    -0.75 * t * t
                } else {
                    q * (2.25 * q - 3.0)
                }
            }
        }
    }

    /// The radial weight of the gradient, `−f'(q)/q >= 0`, finite at `q = 0` (both shapes have
    /// `f'(q) = O(q)`): `∇_i W_ij = σ_D h^-(D+2) · (−f'(q)/q) · (x_j − x_i)`. Zero for `q >= 2`.
    pub fn gradient_weight(self, q: f64) -> f64 {
        match self {
            Kernel::WendlandC2 => {
                if q >= 2.0 {
                    0.0
                } else {
                    let t = 1.0 - 0.5 * q;
                    5.0 * t * t * t
                }
            }
            Kernel::CubicSpline => {
                if q >= 2.0 {
                    0.0
                } else if q >= 1.0 {
                    let t = 2.0 - q;
                    0.75 * t * t / q
                } else {
                    3.0 - 2.25 * q
                }
            }
        }
    }

    /// The dimensionless normalisation `σ_D` (the kernel is `σ_D h^-D f(q)`).
    pub fn sigma<const D: usize>(self) -> f64 {
        const { assert!(D == 2 || D == 3, "SPH kernels are defined in 2D and 3D") };
        match (self, D) {
            (Kernel::WendlandC2, 2) => 7.0 / (4.0 * PI),
            (Kernel::WendlandC2, _) => 21.0 / (16.0 * PI),
            (Kernel::CubicSpline, 2) => 10.0 / (7.0 * PI),
            (Kernel::CubicSpline, _) => 1.0 / PI,
        }
    }
}

impl fmt::Display for Kernel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A kernel name that is not `wendland` or `cubic`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UnknownKernel(pub String);

impl fmt::Display for UnknownKernel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "unknown kernel '{}' (kernels: wendland, cubic)", self.0)
    }
}

impl std::error::Error for UnknownKernel {}

/// The text form of the `kernel` parameter: its name.
impl boundary_core::ParamValue for Kernel {
    fn from_text(text: &str) -> Result<Self, Option<String>> {
        text.parse().map_err(|e: UnknownKernel| Some(e.to_string()))
    }
    fn to_text(&self) -> String {
        self.name().to_owned()
    }
}

impl FromStr for Kernel {
    type Err = UnknownKernel;

    /// Accepts `wendland` (or `wendland_c2`, `wendland-c2`) and `cubic` (or `cubic_spline`,
    /// `cubic-spline`), case-insensitively.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().replace('-', "_").as_str() {
            "wendland" | "wendland_c2" => Ok(Kernel::WendlandC2),
            "cubic" | "cubic_spline" => Ok(Kernel::CubicSpline),
            _ => Err(UnknownKernel(s.to_owned())),
        }
    }
}

/// A kernel at a fixed smoothing length `h` in `D` dimensions, with its constants
/// precomputed: `W(r) = norm · f(r/h)`, `∇_i W_ij = norm/h · f'(q) · (x_i − x_j)/r`.
///
/// **Units.** [`value`](Self::value), [`derivative`](Self::derivative) and
/// [`gradient`](Self::gradient) are in physical units, with the factor `h^-D`: it overflows or
/// underflows for extreme `h` (`h^-3` is not finite below `h ≈ 1e-103`). The *reduced*
/// forms [`reduced_value`](Self::reduced_value) (`W·h^D`) and
/// [`reduced_gradient_weight`](Self::reduced_gradient_weight) take `q = r/h` and carry no
/// power of `h`; [`SphContext`](crate::SphContext) computes every sum with them, in units of
/// `h`, so its dimensionless results do not depend on the scale of the scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SphKernel<const D: usize> {
    kernel: Kernel,
    h: f64,
    inv_h: f64,
    /// `σ_D`.
    sigma: f64,
    /// `σ_D h^-D`.
    norm: f64,
}

impl<const D: usize> SphKernel<D> {
    /// The kernel `kernel` at smoothing length `h` (finite and positive; checked in debug
    /// builds, the callers hold a validated `Radius`).
    pub fn new(kernel: Kernel, h: f64) -> Self {
        debug_assert!(h.is_finite() && h > 0.0, "smoothing length {h}");
        SphKernel {
            kernel,
            h,
            inv_h: 1.0 / h,
            sigma: kernel.sigma::<D>(),
            norm: kernel.sigma::<D>() * h.powi(-(D as i32)),
        }
    }

    /// `W·h^D = σ_D f(q)` at `q = r/h`: the kernel in units of `h` (finite for every `h`).
    #[inline]
    pub fn reduced_value(&self, q: f64) -> f64 {
        self.sigma * self.kernel.shape(q)
    }

    /// `σ_D · (−f'(q)/q)` at `q = r/h`, so that `∇_i W_ij · h^(D+1) = w · (x_j − x_i)/h`: the
    /// gradient's radial weight in units of `h` (finite for every `h`, also at `q = 0`).
    #[inline]
    pub fn reduced_gradient_weight(&self, q: f64) -> f64 {
        self.sigma * self.kernel.gradient_weight(q)
    }

    /// The kernel shape.
    pub fn kernel(&self) -> Kernel {
        self.kernel
    }

    /// The smoothing length `h`.
    pub fn h(&self) -> f64 {
        self.h
    }

    /// The support radius `2h`.
    pub fn support(&self) -> f64 {
        SUPPORT_FACTOR * self.h
    }

    /// `W(r)` at distance `r >= 0`.
    #[inline]
    pub fn value(&self, r: f64) -> f64 {
        self.norm * self.kernel.shape(r * self.inv_h)
    }

    /// `dW/dr` at distance `r >= 0` (non-positive: both kernels decrease).
    #[inline]
    pub fn derivative(&self, r: f64) -> f64 {
        self.norm * self.inv_h * self.kernel.shape_derivative(r * self.inv_h)
    }

    /// `∇_i W(|x_i − x_j|)` for `xij = x_i − x_j`: `dW/dr · xij / r`, and the zero vector for
    /// coincident particles (`r = 0`, where the radial kernel is flat).
    #[inline]
    pub fn gradient(&self, xij: &Point<D>) -> Point<D> {
        let r = xij.norm();
        if r > 0.0 {
            xij * (self.derivative(r) / r)
        } else {
            Point::<D>::zeros()
        }
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test
mod tests {
    use super::*;

    /// `∫_0^2 f(q) q^(D−1) dq · |S^(D−1)|` by composite Simpson on `n` intervals per unit of q
    /// (the cubic spline has a kink at q = 1, a node of the rule).
    fn radial_integral<const D: usize>(k: Kernel, n: usize) -> f64 {
        let m = 2 * n;
        let step = 2.0 / m as f64;
        let g = |q: f64| k.shape(q) * q.powi(D as i32 - 1);
        let mut sum = g(0.0) + g(2.0);
        for i in 1..m {
            let w = if i % 2 == 1 { 4.0 } else { 2.0 };
            sum += w * g(i as f64 * step);
        }
        let sphere = if D == 2 { 2.0 * PI } else { 4.0 * PI };
        sum * step / 3.0 * sphere
    }

    #[test]
    fn kernels_integrate_to_one() {
        for k in Kernel::ALL {
            let i2 = k.sigma::<2>() * radial_integral::<2>(k, 2000);
            let i3 = k.sigma::<3>() * radial_integral::<3>(k, 2000);
            assert!((i2 - 1.0).abs() < 1e-10, "{k} 2D: {i2}");
            assert!((i3 - 1.0).abs() < 1e-10, "{k} 3D: {i3}");
        }
    }

    #[test]
    fn derivative_matches_finite_differences_and_support_is_2h() {
        for k in Kernel::ALL {
            let w = SphKernel::<3>::new(k, 0.7);
            for i in 1..280 {
                let r = i as f64 * 0.005;
                let e = 1e-6;
                let fd = (w.value(r + e) - w.value(r - e)) / (2.0 * e);
                assert!(
                    (fd - w.derivative(r)).abs() < 1e-6 * (1.0 + fd.abs()),
                    "{k} r={r}: {fd} vs {}",
                    w.derivative(r)
                );
                assert!(w.derivative(r) <= 0.0);
            }
            assert_eq!(w.value(1.4), 0.0);
            assert_eq!(w.value(2.0), 0.0);
            assert!(w.value(1.399) > 0.0);
            assert_eq!(w.support(), 1.4);
            assert_eq!(k.shape_derivative(0.0), 0.0);
            // Continuity of the cubic spline's pieces at q = 1.
            assert!((k.shape(1.0 - 1e-12) - k.shape(1.0)).abs() < 1e-10);
        }
    }

    #[test]
    fn gradient_is_radial_and_matches_finite_differences() {
        let w = SphKernel::<2>::new(Kernel::WendlandC2, 1.0);
        let x = Point::<2>::new(0.3, -0.8);
        let g = w.gradient(&x);
        let e = 1e-6;
        for a in 0..2 {
            let mut xp = x;
            let mut xm = x;
            xp[a] += e;
            xm[a] -= e;
            let fd = (w.value(xp.norm()) - w.value(xm.norm())) / (2.0 * e);
            assert!((fd - g[a]).abs() < 1e-8, "axis {a}: {fd} vs {}", g[a]);
        }
        assert_eq!(w.gradient(&Point::<2>::zeros()), Point::<2>::zeros());
    }

    #[test]
    fn reduced_forms_match_the_physical_kernel_and_carry_no_power_of_h() {
        for k in Kernel::ALL {
            for h in [0.5, 1.0, 3.0] {
                let w = SphKernel::<3>::new(k, h);
                for i in 0..=40 {
                    let r = i as f64 * 0.05 * h;
                    let q = r / h;
                    let value = w.reduced_value(q) * h.powi(-3);
                    assert!(
                        (value - w.value(r)).abs() <= 1e-14 * w.value(0.0),
                        "{k} {r}"
                    );
                    if r > 0.0 {
                        // −W'(r)/r = h^-(D+2) · reduced weight.
                        let weight = w.reduced_gradient_weight(q) * h.powi(-5);
                        let expected = -w.derivative(r) / r;
                        assert!(
                            (weight - expected).abs() <= 1e-12 * (1.0 + expected.abs()),
                            "{k} h={h} r={r}: {weight} vs {expected}"
                        );
                    }
                }
            }
            // The weight at q = 0 is the limit of −f'(q)/q.
            let q = 1e-7;
            assert!((k.gradient_weight(0.0) + k.shape_derivative(q) / q).abs() < 1e-5);
            assert_eq!(k.gradient_weight(2.0), 0.0);
            // No power of h: the same numbers at h = 1e-200 and 1e200.
            let tiny = SphKernel::<3>::new(k, 1e-200);
            let huge = SphKernel::<3>::new(k, 1e200);
            assert_eq!(tiny.reduced_value(0.7), huge.reduced_value(0.7));
            assert_eq!(
                tiny.reduced_gradient_weight(0.7),
                huge.reduced_gradient_weight(0.7)
            );
            assert!(tiny.reduced_value(0.7) > 0.0 && tiny.reduced_value(0.7).is_finite());
        }
    }

    #[test]
    fn names_round_trip() {
        for k in Kernel::ALL {
            assert_eq!(k.name().parse::<Kernel>(), Ok(k));
        }
        assert_eq!("Wendland-C2".parse::<Kernel>(), Ok(Kernel::WendlandC2));
        let err = "gauss".parse::<Kernel>().unwrap_err();
        assert!(err.to_string().contains("gauss"));
    }
}
