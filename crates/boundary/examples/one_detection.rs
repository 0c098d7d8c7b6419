//! One detection of one method on a small jittered ball, and nothing else: the unit of a
//! profile under callgrind, where the instruction count of a method is compared before and
//! after a change.
//!
//! ```text
//! cargo build --profile test -p boundary --example one_detection
//! valgrind --tool=callgrind target/test/examples/one_detection exact 4000
//! ```
//!
//! Arguments: the method (default `exact`) and the particle count (default 4000; a 3D
//! jittered cubic lattice of spacing 1 filling a ball, jitter 0.3, seed 7, at r = 1.2).

#![allow(clippy::print_stdout)] // an example prints its result

use boundary::{detector_by_name, AnyParticleSet, Radius};
use boundary_scenes::jittered_lattice_ball;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let method = args.next().unwrap_or_else(|| "exact".to_owned());
    let n: usize = match args.next() {
        Some(text) => text.parse()?,
        None => 4000,
    };
    let (set, _) = jittered_lattice_ball(n, 0.3, 7);
    let set = AnyParticleSet::from(set);
    let detector = detector_by_name(&method)?;
    let detection = detector.detect(&set, Radius::new(1.2)?)?;
    println!(
        "{detector}: {} of {} particles boundary",
        detection.labels.boundary_count(),
        set.len()
    );
    Ok(())
}
