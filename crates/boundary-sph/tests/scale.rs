//! The kernel sums are computed in units of `h`: a jittered lattice and its copies scaled by
//! `s` (with `h` scaled alike) give the same dimensionless sums (volumes in units of `h^D`,
//! Shepard sum, `∇c·h`, the renormalisation matrix) for every `s` from 1e-150 to 1e150, and
//! the physical volumes and gradient (what the `svm` features read) scale as `s^D` and `1/s`
//! wherever they are finite (1e-9 to 1e9 here).

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_core::{Dim, SupportedDim};
use boundary_core::{ParticleSet, Point};
use boundary_sph::{Kernel, SphContext, SphKernel};
use rand::{rngs::StdRng, Rng, SeedableRng};

fn jittered<const D: usize>(n: usize, seed: u64) -> ParticleSet<D>
where
    Dim<D>: SupportedDim,
{
    let mut rng = StdRng::seed_from_u64(seed);
    let points = (0..n.pow(D as u32))
        .map(|k| {
            let mut rest = k;
            Point::<D>::from_fn(|_, _| {
                let c = (rest % n) as f64 + rng.gen_range(-0.2..0.2);
                rest /= n;
                c
            })
        })
        .collect();
    ParticleSet::new(points).unwrap()
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * (1.0 + a.abs().max(b.abs()))
}

fn check<const D: usize>(set: &ParticleSet<D>, h: f64)
where
    Dim<D>: SupportedDim,
{
    for kernel in Kernel::ALL {
        let base = SphContext::new(set, SphKernel::<D>::new(kernel, h)).unwrap();
        for s in [1e-150, 1e-9, 1e-3, 0.37, 1e3, 1e9, 1e150] {
            let scaled = ParticleSet::new(set.positions().iter().map(|p| p * s).collect()).unwrap();
            let ctx = SphContext::new(&scaled, SphKernel::<D>::new(kernel, h * s)).unwrap();
            let physical = (1e-9..=1e9).contains(&s);
            for i in 0..set.len() {
                let (a, b) = (ctx.local_sums(i), base.local_sums(i));
                let what = format!("{D}D {kernel} s={s} particle {i}");
                assert!(
                    close(ctx.reduced_volumes()[i], base.reduced_volumes()[i]),
                    "{what}"
                );
                assert!(close(a.shepard, b.shepard), "{what}: shepard");
                assert_eq!(a.neighbours, b.neighbours, "{what}");
                for k in 0..D {
                    assert!(close(a.gradient_h[k], b.gradient_h[k]), "{what}: ∇c·h");
                    for l in 0..D {
                        let (x, y) = (a.renormalisation[(k, l)], b.renormalisation[(k, l)]);
                        assert!(close(x, y), "{what}: B");
                    }
                }
                if physical {
                    let v = ctx.volumes()[i] / s.powi(D as i32);
                    assert!(close(v, base.volumes()[i]), "{what}: V");
                    for k in 0..D {
                        assert!(close(a.gradient[k] * s, b.gradient[k]), "{what}: ∇c");
                    }
                }
            }
        }
    }
}

#[test]
fn kernel_sums_are_the_same_for_the_scene_scaled_from_1e_minus_150_to_1e150() {
    check(&jittered::<2>(12, 1), 1.3);
    check(&jittered::<3>(6, 2), 1.2);
}
