//! Cooperative cancellation (`boundary::stop`) on every registered detector: under a stopped
//! token a detection returns `DetectError::Interrupted` (never partial labels), on the bare
//! cloud and in a domain; under a token not stopped it gives the labels of the global pool.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary::stop::StopToken;
use boundary::{detector_by_name, methods, AnyParticleSet, DetectError, Domain, Radius};
use boundary_scenes::{jittered_lattice_ball, jittered_lattice_disc};

fn scenes() -> Vec<(AnyParticleSet, Radius)> {
    let (ball, _) = jittered_lattice_ball(2_000, 0.1, 3);
    let disc = jittered_lattice_disc(15.0, 0.1, 4);
    vec![
        (ball.into(), Radius::new(1.0).unwrap()),
        (disc.into(), Radius::new(1.0).unwrap()),
    ]
}

#[test]
fn a_stopped_token_interrupts_every_method() {
    let token = StopToken::new();
    let pool = token.pool_builder().num_threads(2).build().unwrap();
    token.stop();
    for (set, r) in scenes() {
        for name in methods() {
            let detector = detector_by_name(name).unwrap();
            let outcome = pool.install(|| detector.detect(&set, r));
            assert_eq!(
                outcome.err(),
                Some(DetectError::Interrupted),
                "{name} on a {}D set",
                set.dim()
            );
            // The domain path too (the set itself as walls: the extended set goes through
            // `detect_owned_in`).
            let domain = Domain::new().with_walls(set.clone());
            let outcome = pool.install(|| detector.detect_in(&set, &domain, r));
            assert_eq!(
                outcome.err(),
                Some(DetectError::Interrupted),
                "{name} in a domain"
            );
        }
    }
    // The error says what happened.
    assert!(DetectError::Interrupted.to_string().contains("interrupted"));
}

#[test]
fn a_token_not_stopped_changes_nothing() {
    let token = StopToken::new();
    let pool = token.pool_builder().num_threads(2).build().unwrap();
    for (set, r) in scenes() {
        for name in methods() {
            let detector = detector_by_name(name).unwrap();
            let under_token = pool.install(|| detector.detect(&set, r)).unwrap();
            let plain = detector.detect(&set, r).unwrap();
            assert_eq!(under_token.labels, plain.labels, "{name}");
        }
    }
    assert!(!token.is_stopped());
}
