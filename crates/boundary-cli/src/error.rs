//! The CLI's error type: every failure of a subcommand, with the message `main` prints after
//! `error: `. The messages are the CLI's interface (tests match them): keep them stable.

use std::path::PathBuf;
use thiserror::Error;

/// Why a subcommand failed.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum CliError {
    /// Reading or writing a particle file (the message names the file and the line or element).
    #[error(transparent)]
    Io(#[from] boundary_io::IoError),
    /// An unknown method or parameter, or a bad parameter value.
    #[error(transparent)]
    Registry(#[from] boundary::RegistryError),
    /// A detector failed on the input (its message with the options named as flags).
    #[error("{}", in_cli_terms(.0))]
    Detect(#[from] boundary::DetectError),
    /// Invalid core values (radius, label counts, grid limits).
    #[error(transparent)]
    Core(#[from] boundary::CoreError),
    /// Resampling could not run.
    #[error(transparent)]
    Resample(#[from] boundary_resample::ResampleError),
    /// The rayon pool could not be built.
    #[error("cannot start worker threads: {0}")]
    Threads(#[from] rayon::ThreadPoolBuildError),
    /// Options that do not go together, or a value they need is missing.
    #[error("{0}")]
    Usage(&'static str),
    /// A 3D input that is flat (every particle boundary in 3D) read without `--dim`.
    #[error("{}: {}", .path.display(), flat_advice(.flatness))]
    Flat {
        /// The input.
        path: PathBuf,
        /// How it is flat.
        flatness: boundary::Flatness,
    },
    /// `--smoothing-length` with a method parameter `h_over_r` other than 1.
    #[error(
        "--smoothing-length {h} gives the SPH sums h = {h} itself; --set h_over_r={value} would \
         make it {value} x {h}: drop h_over_r, or give --radius with it"
    )]
    SmoothingLengthRatio {
        /// The smoothing length given.
        h: f64,
        /// The `h_over_r` given.
        value: String,
    },
    /// `--radius auto` on a set with fewer than two distinct positions.
    #[error("{}: --radius auto needs at least two distinct particle positions", .0.display())]
    AutoRadiusTooFew(PathBuf),
    /// An option that reads a point attribute (`--radius-attribute`, `--wall-attribute`,
    /// `--phase-attribute`) names none of the input.
    #[error(
        "{}: no point attribute {name:?} for {option} (the file has: {available})",
        .path.display()
    )]
    AttributeMissing {
        /// The input.
        path: PathBuf,
        /// The name asked for.
        name: String,
        /// The option.
        option: &'static str,
        /// The attributes the file has (and those not read, with why).
        available: String,
    },
    /// An option that reads a point attribute names a vector attribute.
    #[error(
        "{}: point attribute {name:?} is a vector of {components} components, not {what} \
         ({option} needs one value per particle)",
        .path.display()
    )]
    AttributeVector {
        /// The input.
        path: PathBuf,
        /// The name asked for.
        name: String,
        /// Its number of components.
        components: usize,
        /// The option.
        option: &'static str,
        /// What the option needs (`a radius`).
        what: &'static str,
    },
    /// A per-particle radius that is not positive and finite, or out of range.
    #[error(
        "{}: radius attribute {attribute:?}: particle {index}{}: {problem}",
        .path.display(),
        .line.map(|l| format!(" (line {l})")).unwrap_or_default()
    )]
    RadiusValue {
        /// The input.
        path: PathBuf,
        /// The attribute.
        attribute: String,
        /// The particle, in file order.
        index: usize,
        /// Its line (CSV).
        line: Option<usize>,
        /// What is wrong with its radius.
        problem: String,
    },
    /// The tracker refused a frame (`--track`: its ids).
    #[error("{}: {}", .path.display(), in_cli_terms(.error))]
    Track {
        /// The frame.
        path: PathBuf,
        /// Why.
        #[source]
        error: boundary::DetectError,
    },
    /// A `--track-ids` value that is not a whole number >= 0.
    #[error(
        "{}: id attribute {attribute:?}: particle {index}{}: {problem}",
        .path.display(),
        .line.map(|l| format!(" (line {l})")).unwrap_or_default()
    )]
    IdValue {
        /// The input.
        path: PathBuf,
        /// The attribute.
        attribute: String,
        /// The particle, in file order.
        index: usize,
        /// Its line (CSV).
        line: Option<usize>,
        /// What is wrong with its id.
        problem: String,
    },
    /// A `--walls` file that cannot serve as walls (empty, or of another dimension than the
    /// other wall files).
    #[error("{}: --walls: {problem}", .path.display())]
    WallFile {
        /// The wall file.
        path: PathBuf,
        /// What is wrong with it.
        problem: String,
    },
    /// A `--solid-mesh` file that is no closed triangle mesh.
    #[error("{}: --solid-mesh: {problem}", .path.display())]
    SolidMesh {
        /// The mesh file.
        path: PathBuf,
        /// What is wrong with it.
        problem: String,
    },
    /// Walls of another dimension than the input.
    #[error(
        "{}: --walls: {wall_dim}D particles beside the {dim}D particles of {} (--dim 2 reads a \
         3D file with one constant axis as 2D)",
        .wall.display(), .input.display()
    )]
    WallDimension {
        /// The (first) wall file.
        wall: PathBuf,
        /// Its dimension.
        wall_dim: usize,
        /// The input.
        input: PathBuf,
        /// The input's dimension.
        dim: usize,
    },
    /// A `--phase-attribute` value that is not a phase number.
    #[error(
        "{}: --phase-attribute {attribute:?}: particle {index}{}: {value} is not a phase \
         number (an integer from 0 to 4294967295)",
        .path.display(),
        .line.map(|l| format!(" (line {l})")).unwrap_or_default()
    )]
    PhaseValue {
        /// The input.
        path: PathBuf,
        /// The attribute.
        attribute: String,
        /// The particle (input row, in file order).
        index: usize,
        /// Its line (CSV).
        line: Option<usize>,
        /// The value found.
        value: f64,
    },
    /// An output file whose extension names no format.
    #[error(
        "{}: unknown output format (use .csv, .xyz, .ply, .vtk, .vtu, .vtp, .bgeo or .bgeo.gz)",
        .0.display()
    )]
    UnknownOutputFormat(PathBuf),
    /// A frame whose format neither its extension nor an option names.
    #[error("{}: unknown format (name it with --format / --output-format)", .0.display())]
    UnknownFrameFormat(PathBuf),
    /// `--margin` with a method that has none.
    #[error("method '{0}' reports no margin (drop --margin)")]
    NoMargin(&'static str),
    /// A glob pattern that does not parse.
    #[error("invalid pattern {pattern:?}: {reason}")]
    Pattern {
        /// The pattern as given.
        pattern: String,
        /// The glob crate's message.
        reason: String,
    },
    /// A pattern that matches no file.
    #[error("no file matches {0:?}")]
    NoMatch(String),
    /// Two frames that would be written to the same output file.
    #[error("{} and {} would both be written to {}", .first.display(), .second.display(), .output.display())]
    OutputClash {
        /// The first frame.
        first: PathBuf,
        /// The second frame.
        second: PathBuf,
        /// Their common output.
        output: PathBuf,
    },
    /// A directory that cannot be created.
    #[error("cannot create {}: {source}", .path.display())]
    CreateDir {
        /// The directory.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// `--radius auto` over frames none of which could be read.
    #[error("--radius auto: no frame could be read to estimate r")]
    NoFrameForAutoRadius,
    /// Every frame of a sequence failed.
    #[error("all {0} frames failed")]
    AllFramesFailed(usize),
    /// A truth file whose label count differs from the particle count.
    #[error("{}: {found} truth labels for {n} particles", .path.display())]
    TruthCount {
        /// The truth file.
        path: PathBuf,
        /// Labels in it.
        found: usize,
        /// Particles in the input.
        n: usize,
    },
    /// A truth label that is not 0 or 1.
    #[error("{}: particle {index}: boundary must be 0 or 1, got {value}", .path.display())]
    TruthValue {
        /// The truth file.
        path: PathBuf,
        /// The particle.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// A run over frames stopped by SIGINT or SIGTERM: the frames done are kept. `main` prints
    /// this line as it is (no `error: `) and exits with 128 + the signal's number.
    #[error("interrupted: {done} of {total} frames done; rerun with --resume to finish")]
    Interrupted {
        /// The signal (2 for SIGINT, 15 for SIGTERM).
        signal: i32,
        /// Frames done (this run's and those kept from the previous run).
        done: usize,
        /// Frames in all.
        total: usize,
    },
    /// The handlers of SIGINT and SIGTERM could not be installed.
    #[error("cannot catch Ctrl-C (SIGINT, SIGTERM): {0}")]
    Signals(std::io::Error),
    /// `--resume` with a summary it cannot use.
    #[error("{}: --resume: {problem}", .path.display())]
    Resume {
        /// The summary file.
        path: PathBuf,
        /// Why it cannot be used.
        problem: String,
    },
    /// Standard output was closed by its reader (`boundary methods | head`): not a failure,
    /// `main` exits quietly.
    #[error("standard output closed")]
    BrokenPipe,
    /// Writing to standard output failed otherwise.
    #[error("cannot write to standard output: {0}")]
    Stdout(std::io::Error),
}

/// The library's names of the inputs a detection takes, with the flag that gives each on
/// the command line. The library's messages name inputs in its own terms (Python and C users
/// have no flags); the CLI adds its flag after the first mention of each.
const FLAGS: &[(&str, &str)] = &[
    ("half-spaces", "--solid"),
    ("solid meshes", "--solid-mesh"),
    ("wall particles", "--walls"),
];

/// A detector's error message in the CLI's spelling: each input of [`FLAGS`] named by the
/// library is followed by its flag, `solid half-spaces (--solid)`.
fn in_cli_terms(error: &boundary::DetectError) -> String {
    let mut message = error.to_string();
    for (term, flag) in FLAGS {
        if let Some(at) = message.find(term) {
            message.insert_str(at + term.len(), &format!(" ({flag})"));
        }
    }
    message
}

/// The message of [`CliError::Flat`]: what is flat and what to pass instead.
fn flat_advice(flatness: &boundary::Flatness) -> String {
    let fix = match flatness {
        boundary::Flatness::Plane { axis: 2, .. } => "pass --dim 2 to drop z".to_owned(),
        boundary::Flatness::Plane { axis, .. } => {
            let name = boundary::Flatness::axis_name(*axis);
            let kept = match axis {
                1 => "x and z",
                _ => "y and z",
            };
            format!("pass --dim 2 to drop {name} (it keeps {kept})")
        }
        boundary::Flatness::Point { .. } => {
            return format!(
                "{flatness}: the set has no extent, and every particle would be boundary \
                 (--dim 3 detects anyway)"
            )
        }
    };
    format!(
        "{flatness}: a flat set is 2D, and read as 3D every particle would be boundary; {fix} \
         (--dim 3 detects in 3D anyway)"
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use boundary::{detector_by_name, methods, Domain, Radius};

    /// Every refusal of a solid by a registered method, as the CLI prints it: each input the
    /// library names carries its flag, and the library's own text carries none.
    #[test]
    fn solid_refusals_name_the_flags() {
        let set = boundary::ParticleSet::<3>::from_rows(&[[0.0, 0.0, 0.5], [0.3, 0.0, 0.5]])
            .expect("two particles")
            .to_any();
        let floor = boundary::HalfSpace::parse("z<0").expect("a half-space");
        let domain = Domain::new().with_solid(floor);
        let r = Radius::new(0.2).expect("a radius");
        let mut refused = 0;
        for name in methods() {
            let detector = detector_by_name(name).expect("a registered method");
            let Err(error) = detector.detect_in(&set, &domain, r) else {
                continue;
            };
            let library = error.to_string();
            assert!(!library.contains("--"), "{name}: {library}");
            let cli = CliError::from(error).to_string();
            assert!(
                cli.contains("solid half-spaces (--solid):"),
                "{name}: {cli}"
            );
            assert!(cli.contains("wall particles (--walls)"), "{name}: {cli}");
            refused += 1;
        }
        assert!(refused >= 8, "{refused} methods refused half-spaces");
    }

    #[test]
    fn each_flag_follows_the_first_mention_of_its_input() {
        let error = boundary::DetectError::UnsupportedOption {
            method: "m",
            option: "solid meshes",
            reason: "give the solid as half-spaces or the walls as wall particles",
        };
        assert_eq!(
            in_cli_terms(&error),
            "method 'm' cannot honour solid meshes (--solid-mesh): give the solid as half-spaces \
             (--solid) or the walls as wall particles (--walls)"
        );
    }
}
