//! Writes the jittered lattice ball of the timings in docs/MPI.md (spacing 1, jitter ±0.15,
//! seed 42; run at r = 1.2):
//! `cargo run --release -p boundary-mpi --example write_ball -- 1000000 ball.csv`

use std::path::Path;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(n), Some(path)) = (args.first().and_then(|n| n.parse().ok()), args.get(1)) else {
        eprintln!("usage: write_ball N FILE");
        return ExitCode::FAILURE;
    };
    let (ball, _) = boundary_scenes::jittered_lattice_ball(n, 0.15, 42);
    match boundary_io::write_particles(Path::new(path), None, &ball.to_any(), &[]) {
        Ok(()) => {
            eprintln!("{path}: {} particles", ball.len());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("write_ball: {e}");
            ExitCode::FAILURE
        }
    }
}
