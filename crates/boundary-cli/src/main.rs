//! `boundary`: boundary particles of meshfree particle files.
//!
//! ```text
//! boundary detect INPUT --radius R|auto [--method NAME] [--set KEY=VALUE]... [--output FILE]
//!                 [--dim 2|3] [--format FMT] [--margin] [--normals] [--threads N] [--json]
//! boundary detect 'frames/fluid_*.vtk' --radius R|auto --output-dir DIR [--output-format FMT]
//!                 [--summary FILE.csv] [...]
//! boundary detect INPUT --radius-attribute NAME [--radius-scale F] [...]
//!                 # a radius per particle: r_i = F·(attribute NAME of particle i)
//! boundary detect INPUT --radius R [--walls FILE]... [--wall-attribute NAME=V[,V...]]
//!                 [--solid 'y<0']... [--periodic x:MIN:MAX]... [--phase-attribute NAME] [...]
//!                 # a simulation's walls, solids, periodic axes and phases
//! boundary score INPUT --radius R --method NAME [--set KEY=VALUE]... [--truth FILE] [--json]
//!                 (score also takes --radius-attribute NAME [--radius-scale F])
//! boundary resample INPUT --radius R [--method NAME] [--set KEY=VALUE]... --output FILE
//!                   [--k K] [--alpha A] [--shift S] [--json]
//! boundary methods [--json]
//! ```
//!
//! Errors print one line `error: …` on stderr and exit with status 1 (2 for malformed
//! arguments); nothing else is printed on failure. A run over frames stopped by Ctrl-C or
//! SIGTERM keeps the frames done, says how to resume, and exits with 130 or 143. A closed
//! stdout (`boundary methods | head`) ends the command quietly with status 0.
//!
//! One module per subcommand (`detect`, `score`, `resample`, `methods`), what they share in
//! `common`, the error type in `error` ([`CliError`]), and stdout/stderr writes that never
//! panic in `output`.

mod common;
mod detect;
mod domain;
mod error;
mod interrupt;
mod methods;
mod output;
mod resample;
mod score;

use clap::{Parser, Subcommand};
use error::CliError;
use output::errln;
use std::process::ExitCode;

#[derive(Debug, Parser)]
#[command(
    name = "boundary",
    version,
    about = "Boundary particles of meshfree particle sets (free surface, bubbles, sheets, droplets)",
    long_about = "Finds the particles whose sphere of radius r is not covered by the balls of \
                  radius r of their neighbours (Sandim et al., JCP 2020), with every published \
                  method, and scores methods against the exact labels."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Label every particle of INPUT as boundary (1) or interior (0).
    // Boxed: the detect options are by far the largest variant (clippy::large_enum_variant).
    Detect(Box<detect::DetectArgs>),
    /// Compare a method with the truth: TP, TN, FP, FN, Rec, FPR, M.
    Score(score::ScoreArgs),
    /// Classify the boundary particles by feature (droplet, ligament, sheet, regular) and
    /// resample thin features (thesis Sec. 2.6); writes the new set with a `feature` column.
    Resample(resample::ResampleArgs),
    /// List the available methods with their parameters and defaults.
    Methods(methods::MethodsArgs),
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(err) if !err.use_stderr() => {
            // --help, --version.
            let _ = err.print();
            return ExitCode::SUCCESS;
        }
        Err(err) => {
            errln!("{}", one_line(&err.render().to_string()));
            return ExitCode::from(2);
        }
    };
    let result: Result<(), CliError> = match cli.command {
        Command::Detect(args) => detect::detect(*args),
        Command::Score(args) => score::score(args),
        Command::Resample(args) => resample::resample(args),
        Command::Methods(args) => methods::list_methods(args),
    };
    match result {
        // The reader of stdout went away (`| head`): it asked for no more.
        Ok(()) | Err(CliError::BrokenPipe) => ExitCode::SUCCESS,
        // Ctrl-C (130) or SIGTERM (143): the shell's convention for a run a signal ended.
        Err(error @ CliError::Interrupted { signal, .. }) => {
            errln!("{error}");
            ExitCode::from(u8::try_from(128 + signal).unwrap_or(1))
        }
        Err(error) => {
            errln!("error: {error}");
            ExitCode::FAILURE
        }
    }
}

/// Clap's multi-line error (message, details, usage, hint) as one line: the message and its
/// details, without the usage block.
fn one_line(rendered: &str) -> String {
    let mut parts = Vec::new();
    for line in rendered.lines() {
        let line = line.trim();
        if line.starts_with("Usage:") || line.starts_with("For more information") {
            break;
        }
        if !line.is_empty() {
            parts.push(line);
        }
    }
    let text = parts.join(" ");
    if text.starts_with("error:") {
        text
    } else {
        format!("error: {text}")
    }
}
