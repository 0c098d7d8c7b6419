//! What the subcommands share: the input and method arguments, `--radius`, reading the
//! input, the worker pool, timing a detection.

use crate::error::CliError;
use crate::output::errln;
use boundary::{parse_param, AnyParticleSet, BoundaryDetector, Detection, Radius};
use boundary_io::{Format, ReadOptions};
use clap::Args;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Debug, Args)]
pub(crate) struct InputArgs {
    /// Particle file: .csv (header x,y[,z]), .xyz/.txt, .ply, .vtk (legacy), .vtu, .vtp,
    /// .bgeo[.gz].
    /// `detect` also takes a glob pattern of frames ('frames/fluid_*.vtu', quoted).
    pub(crate) input: PathBuf,
    /// Particle resolution r (positive, in the file's length unit), or `auto`: the median
    /// nearest-neighbour spacing of the particles (an estimate; printed, with a warning).
    #[arg(long, short, value_parser = parse_radius, value_name = "R|auto", allow_negative_numbers = true)]
    pub(crate) radius: RadiusArg,
    /// Dimension of the scene; 2 on a file with x,y,z drops the constant axis.
    #[arg(long, value_parser = clap::value_parser!(u8).range(2..=3))]
    pub(crate) dim: Option<u8>,
    /// Input format, when the extension does not say it.
    #[arg(long, value_parser = parse_format, value_name = "FMT")]
    pub(crate) format: Option<Format>,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..))]
    pub(crate) threads: Option<u16>,
    /// Print one JSON object on stdout instead of the human summary.
    #[arg(long)]
    pub(crate) json: bool,
}

#[derive(Debug, Args)]
pub(crate) struct MethodArgs {
    /// Method name (see `boundary methods`).
    #[arg(long, short, default_value = "exact")]
    pub(crate) method: String,
    /// Method parameter, repeatable: `--set depth=4`.
    #[arg(long = "set", value_parser = parse_param, value_name = "KEY=VALUE")]
    pub(crate) params: Vec<(String, String)>,
}

/// `--radius`: a value, or `auto` (estimated from the particles).
#[derive(Debug, Clone, Copy)]
pub(crate) enum RadiusArg {
    Value(f64),
    Auto,
}

/// `--radius auto` is this multiple of the median nearest-neighbour spacing. On a lattice of
/// spacing s the sphere of an interior particle is covered for r >= s/√2 (square) or
/// r >= s·√3/2 (cubic), and boundary particles stay boundary for any r; one spacing covers
/// both lattices with a margin for jitter.
const AUTO_RADIUS_FACTOR: f64 = 1.0;

fn parse_radius(text: &str) -> Result<RadiusArg, String> {
    if text.trim().eq_ignore_ascii_case("auto") {
        return Ok(RadiusArg::Auto);
    }
    let value: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("'{text}' is not a number or 'auto'"))?;
    Radius::new(value).map_err(|e| e.to_string())?;
    Ok(RadiusArg::Value(value))
}

/// The radius to use on `set`, and whether it was estimated.
pub(crate) fn resolve_radius(
    arg: RadiusArg,
    set: &AnyParticleSet,
    input: &Path,
) -> Result<(f64, bool), CliError> {
    match arg {
        RadiusArg::Value(v) => Ok((v, false)),
        RadiusArg::Auto => {
            let spacing = match set {
                AnyParticleSet::D2(s) => boundary::median_nearest_neighbour_distance(s),
                AnyParticleSet::D3(s) => boundary::median_nearest_neighbour_distance(s),
            }?
            .ok_or_else(|| CliError::AutoRadiusTooFew(input.to_path_buf()))?;
            Ok((AUTO_RADIUS_FACTOR * spacing, true))
        }
    }
}

/// The warning printed when the radius was estimated.
pub(crate) fn auto_warning(r: f64, input: &Path) -> String {
    format!(
        "warning: --radius auto: using r = {r} ({AUTO_RADIUS_FACTOR} x the median \
         nearest-neighbour spacing of {}); this is an estimate, pass --radius to set r",
        input.display()
    )
}

pub(crate) fn parse_format(text: &str) -> Result<Format, String> {
    text.parse()
}

pub(crate) fn read_options(args: &InputArgs) -> ReadOptions {
    ReadOptions {
        dim: args.dim.map(usize::from),
        format: args.format,
    }
}

/// The particle set of `args.input` and the radius to use on it (a warning printed when it was
/// estimated).
pub(crate) fn read_input(args: &InputArgs) -> Result<(AnyParticleSet, f64), CliError> {
    let set = boundary_io::read_particles(&args.input, &read_options(args))?;
    let (r, estimated) = resolve_radius(args.radius, &set, &args.input)?;
    if estimated {
        errln!("{}", auto_warning(r, &args.input));
    }
    Ok((set, r))
}

/// The rayon pool the detection runs in.
pub(crate) fn pool(threads: Option<u16>) -> Result<rayon::ThreadPool, CliError> {
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(n) = threads {
        builder = builder.num_threads(usize::from(n));
    }
    Ok(builder.build()?)
}

/// Runs `detector` on `set` in `pool`; returns the detection and its wall time in seconds.
pub(crate) fn run_timed(
    pool: &rayon::ThreadPool,
    detector: &dyn BoundaryDetector,
    set: &AnyParticleSet,
    r: Radius,
) -> Result<(Detection, f64), CliError> {
    pool.install(|| {
        let start = Instant::now();
        let detection = detector.detect(set, r)?;
        Ok((detection, start.elapsed().as_secs_f64()))
    })
}

pub(crate) fn radius(value: f64) -> Result<Radius, CliError> {
    Ok(Radius::new(value)?)
}

/// The format of an output file, from its extension: checked before the work, not after it.
pub(crate) fn output_format(path: &Path) -> Result<Format, CliError> {
    Format::from_path(path).ok_or_else(|| CliError::UnknownOutputFormat(path.to_path_buf()))
}

pub(crate) fn percent(part: usize, whole: usize) -> f64 {
    if whole == 0 {
        0.0
    } else {
        100.0 * part as f64 / whole as f64
    }
}

/// `name` or `name (k=v, …)`.
pub(crate) fn method_label(detector: &dyn BoundaryDetector) -> String {
    detector.to_string()
}
