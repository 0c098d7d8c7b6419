//! `boundary`: boundary particles of meshfree particle files.
//!
//! ```text
//! boundary detect INPUT --radius R|auto [--method NAME] [--set KEY=VALUE]... [--output FILE]
//!                 [--dim 2|3] [--format FMT] [--margin] [--normals] [--threads N] [--json]
//! boundary detect 'frames/fluid_*.vtk' --radius R|auto --output-dir DIR [--output-format FMT]
//!                 [--summary FILE.csv] [...]
//! boundary score INPUT --radius R --method NAME [--set KEY=VALUE]... [--truth FILE] [--json]
//! boundary resample INPUT --radius R [--method NAME] [--set KEY=VALUE]... --output FILE
//!                   [--k K] [--alpha A] [--shift S] [--json]
//! boundary methods [--json]
//! ```
//!
//! Errors print one line `error: …` on stderr and exit with status 1 (2 for malformed
//! arguments); nothing else is printed on failure.

use boundary::{
    detector_with_params, methods, parse_param, summary, AnyParticleSet, BoundaryDetector,
    Confusion, Detection, Radius,
};
use boundary_io::{read_particle_file, write_particles, Column, Format, ReadOptions};
use clap::{Args, Parser, Subcommand};
use serde_json::json;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

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
    Detect(DetectArgs),
    /// Compare a method with the truth: TP, TN, FP, FN, Rec, FPR, M.
    Score(ScoreArgs),
    /// Classify the boundary particles by feature (droplet, ligament, sheet, regular) and
    /// resample thin features (thesis Sec. 2.6); writes the new set with a `feature` column.
    Resample(ResampleArgs),
    /// List the available methods with their parameters and defaults.
    Methods(MethodsArgs),
}

#[derive(Debug, Args)]
struct InputArgs {
    /// Particle file: .csv (header x,y[,z]), .xyz/.txt, .ply, .vtk (legacy), .vtu, .vtp,
    /// .bgeo[.gz].
    /// `detect` also takes a glob pattern of frames ('frames/fluid_*.vtu', quoted).
    input: PathBuf,
    /// Particle resolution r (positive, in the file's length unit), or `auto`: the median
    /// nearest-neighbour spacing of the particles (an estimate; printed, with a warning).
    #[arg(long, short, value_parser = parse_radius, value_name = "R|auto", allow_negative_numbers = true)]
    radius: RadiusArg,
    /// Dimension of the scene; 2 on a file with x,y,z drops the constant axis.
    #[arg(long, value_parser = clap::value_parser!(u8).range(2..=3))]
    dim: Option<u8>,
    /// Input format, when the extension does not say it.
    #[arg(long, value_parser = parse_format, value_name = "FMT")]
    format: Option<Format>,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..))]
    threads: Option<u16>,
    /// Print one JSON object on stdout instead of the human summary.
    #[arg(long)]
    json: bool,
}

#[derive(Debug, Args)]
struct MethodArgs {
    /// Method name (see `boundary methods`).
    #[arg(long, short, default_value = "exact")]
    method: String,
    /// Method parameter, repeatable: `--set depth=4`.
    #[arg(long = "set", value_parser = parse_param, value_name = "KEY=VALUE")]
    params: Vec<(String, String)>,
}

#[derive(Debug, Args)]
struct DetectArgs {
    #[command(flatten)]
    input: InputArgs,
    #[command(flatten)]
    method: MethodArgs,
    /// Write the particles with a `boundary` column (0/1), format by extension
    /// (.csv, .xyz, .ply, .vtk).
    #[arg(long, short)]
    output: Option<PathBuf>,
    /// Also write the method's per-particle margin (if it has one) as a `margin` column.
    #[arg(long)]
    margin: bool,
    /// Also write outward unit normals of the boundary particles as `normal:0`, `normal:1`
    /// [, `normal:2`] (one vector array `normal` in .vtu/.vtp): the colour-field gradient with
    /// the Wendland C2 kernel at h = r; zero for interior particles.
    #[arg(long)]
    normals: bool,
    /// Process every frame INPUT (a file or glob pattern) matches, in natural order, writing
    /// one output per frame into DIR, named after its input.
    #[arg(long, value_name = "DIR", conflicts_with = "output")]
    output_dir: Option<PathBuf>,
    /// Format of the files written to --output-dir (default: each input's format).
    #[arg(long, value_parser = parse_format, value_name = "FMT", requires = "output_dir")]
    output_format: Option<Format>,
    /// With several frames: write one CSV line per frame (frame, input, output, n, dim, radius,
    /// boundary, seconds, error) to this file.
    #[arg(long, value_name = "FILE.csv")]
    summary: Option<PathBuf>,
}

#[derive(Debug, Args)]
struct ScoreArgs {
    #[command(flatten)]
    input: InputArgs,
    #[command(flatten)]
    method: MethodArgs,
    /// Truth labels: a CSV with a `boundary` column (0/1) in input order. Default: the exact
    /// method.
    #[arg(long)]
    truth: Option<PathBuf>,
}

#[derive(Debug, Args)]
struct ResampleArgs {
    #[command(flatten)]
    input: InputArgs,
    #[command(flatten)]
    method: MethodArgs,
    /// Output file (.csv, .xyz, .ply, .vtk): every particle of the resampled set with a
    /// `feature` column (-1 interior, 0 droplet, 1 ligament, 2 sheet, 3 regular boundary) and a
    /// `source` column (the input index it comes from); PLY and VTK also get `red`, `green`,
    /// `blue` in the colours of thesis Fig. 15.
    #[arg(long, short)]
    output: PathBuf,
    /// K of Eq. 2.5: fewer neighbours (the particle included) make a droplet.
    #[arg(long, default_value_t = 4)]
    k: usize,
    /// alpha of Eq. 2.5: eigenvalue ratio below which a direction is thin.
    #[arg(long, default_value_t = 0.2, allow_negative_numbers = true)]
    alpha: f64,
    /// Shift of the new and of the moved particles, in units of r.
    #[arg(long, default_value_t = 0.5, allow_negative_numbers = true)]
    shift: f64,
}

#[derive(Debug, Args)]
struct MethodsArgs {
    /// Print a JSON array instead of the text list.
    #[arg(long)]
    json: bool,
}

/// `--radius`: a value, or `auto` (estimated from the particles).
#[derive(Debug, Clone, Copy)]
enum RadiusArg {
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
fn resolve_radius(
    arg: RadiusArg,
    set: &AnyParticleSet,
    input: &Path,
) -> Result<(f64, bool), String> {
    match arg {
        RadiusArg::Value(v) => Ok((v, false)),
        RadiusArg::Auto => {
            let spacing = match set {
                AnyParticleSet::D2(s) => boundary::median_nearest_neighbour_distance(s),
                AnyParticleSet::D3(s) => boundary::median_nearest_neighbour_distance(s),
            }
            .map_err(|e| e.to_string())?
            .ok_or_else(|| {
                format!(
                    "{}: --radius auto needs at least two distinct particle positions",
                    input.display()
                )
            })?;
            Ok((AUTO_RADIUS_FACTOR * spacing, true))
        }
    }
}

/// The warning printed when the radius was estimated.
fn auto_warning(r: f64, input: &Path) -> String {
    format!(
        "warning: --radius auto: using r = {r} ({AUTO_RADIUS_FACTOR} x the median \
         nearest-neighbour spacing of {}); this is an estimate, pass --radius to set r",
        input.display()
    )
}

fn parse_format(text: &str) -> Result<Format, String> {
    text.parse()
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
            eprintln!("{}", one_line(&err.render().to_string()));
            return ExitCode::from(2);
        }
    };
    let result = match cli.command {
        Command::Detect(args) => detect(args),
        Command::Score(args) => score(args),
        Command::Resample(args) => resample(args),
        Command::Methods(args) => list_methods(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
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

fn read_options(args: &InputArgs) -> ReadOptions {
    ReadOptions {
        dim: args.dim.map(usize::from),
        format: args.format,
    }
}

/// The particle set of `args.input` and the radius to use on it (a warning printed when it was
/// estimated).
fn read_input(args: &InputArgs) -> Result<(AnyParticleSet, f64), String> {
    let set =
        boundary_io::read_particles(&args.input, &read_options(args)).map_err(|e| e.to_string())?;
    let (r, estimated) = resolve_radius(args.radius, &set, &args.input)?;
    if estimated {
        eprintln!("{}", auto_warning(r, &args.input));
    }
    Ok((set, r))
}

/// The rayon pool the detection runs in.
fn pool(threads: Option<u16>) -> Result<rayon::ThreadPool, String> {
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(n) = threads {
        builder = builder.num_threads(usize::from(n));
    }
    builder
        .build()
        .map_err(|e| format!("cannot start worker threads: {e}"))
}

/// Runs `detector` on `set` in `pool`; returns the detection and its wall time in seconds.
fn run_timed(
    pool: &rayon::ThreadPool,
    detector: &dyn BoundaryDetector,
    set: &AnyParticleSet,
    r: Radius,
) -> Result<(Detection, f64), String> {
    pool.install(|| {
        let start = Instant::now();
        let detection = detector.detect(set, r).map_err(|e| e.to_string())?;
        Ok((detection, start.elapsed().as_secs_f64()))
    })
}

fn radius(value: f64) -> Result<Radius, String> {
    Radius::new(value).map_err(|e| e.to_string())
}

/// The format of an output file, from its extension: checked before the work, not after it.
fn output_format(path: &Path) -> Result<Format, String> {
    Format::from_path(path).ok_or_else(|| {
        format!(
            "{}: unknown output format (use .csv, .xyz, .ply, .vtk, .vtu, .vtp, .bgeo or .bgeo.gz)",
            path.display()
        )
    })
}

/// What one frame gave.
#[derive(Debug)]
struct FrameOutcome {
    n: usize,
    dim: usize,
    radius: f64,
    estimated: bool,
    boundary: usize,
    seconds: f64,
    /// Attributes of the input not written back, with the reason.
    skipped: Vec<String>,
}

/// What every frame of a `detect` run shares.
struct FrameJob<'a> {
    detector: &'a dyn BoundaryDetector,
    options: ReadOptions,
    margin: bool,
    normals: bool,
    pool: &'a rayon::ThreadPool,
}

impl FrameJob<'_> {
    /// Reads `input`, detects, and writes `output` (when given) with `boundary`, the optional
    /// `margin` and normals, and every attribute of the input it keeps.
    fn run(
        &self,
        input: &Path,
        radius_arg: RadiusArg,
        output: Option<(&Path, Format)>,
    ) -> Result<FrameOutcome, String> {
        let with_attributes = output.is_some();
        let file = if with_attributes {
            read_particle_file(input, &self.options).map_err(|e| e.to_string())?
        } else {
            boundary_io::ParticleFile {
                set: boundary_io::read_particles(input, &self.options)
                    .map_err(|e| e.to_string())?,
                attributes: Vec::new(),
                skipped: Vec::new(),
            }
        };
        let set = &file.set;
        let (r_value, estimated) = resolve_radius(radius_arg, set, input)?;
        let r = radius(r_value)?;
        let (detection, seconds) = run_timed(self.pool, self.detector, set, r)?;
        if let Some((path, format)) = output {
            let flags: Vec<i64> = detection
                .labels
                .as_slice()
                .iter()
                .map(|&b| i64::from(b))
                .collect();
            let normals: Vec<Vec<f64>> = if self.normals {
                self.pool
                    .install(|| normal_components(set, r_value, detection.labels.as_slice()))?
            } else {
                Vec::new()
            };
            const NORMAL_NAMES: [&str; 3] = ["normal:0", "normal:1", "normal:2"];
            let mut columns = vec![("boundary", Column::Int(&flags))];
            if self.margin {
                match &detection.margin {
                    Some(margin) => columns.push(("margin", Column::Float(margin))),
                    None => {
                        return Err(format!(
                            "method '{}' reports no margin (drop --margin)",
                            self.detector.name()
                        ))
                    }
                }
            }
            for (name, values) in NORMAL_NAMES.iter().zip(&normals) {
                columns.push((name, Column::Float(values)));
            }
            // The input's own columns of these names are replaced, not repeated.
            let mut ours: Vec<&str> = vec!["boundary", "margin"];
            if self.normals {
                ours.extend(NORMAL_NAMES);
            }
            columns.extend(file.columns(&ours));
            write_particles(path, Some(format), set, &columns).map_err(|e| e.to_string())?;
        }
        Ok(FrameOutcome {
            n: set.len(),
            dim: set.dim(),
            radius: r_value,
            estimated,
            boundary: detection.labels.boundary_count(),
            seconds,
            skipped: file.skipped,
        })
    }
}

/// Outward unit normals of the boundary particles from the colour-field gradient (h = r), one
/// vector per axis; zero for interior particles and where the gradient vanishes.
fn normal_components(
    set: &AnyParticleSet,
    r: f64,
    boundary: &[bool],
) -> Result<Vec<Vec<f64>>, String> {
    fn split<const D: usize>(normals: Vec<boundary::Point<D>>, boundary: &[bool]) -> Vec<Vec<f64>> {
        (0..D)
            .map(|k| {
                normals
                    .iter()
                    .zip(boundary)
                    .map(|(n, &b)| if b { n[k] } else { 0.0 })
                    .collect()
            })
            .collect()
    }
    match set {
        AnyParticleSet::D2(s) => {
            boundary_sph::colour_field_normals(s, r).map(|n| split(n, boundary))
        }
        AnyParticleSet::D3(s) => {
            boundary_sph::colour_field_normals(s, r).map(|n| split(n, boundary))
        }
    }
    .map_err(|e| e.to_string())
}

/// Whether `text` holds a glob metacharacter.
fn is_pattern(text: &str) -> bool {
    text.contains(['*', '?', '['])
}

fn detect(args: DetectArgs) -> Result<(), String> {
    let detector = detector_with_params(&args.method.method, &args.method.params)
        .map_err(|e| e.to_string())?;
    let pattern = args.input.input.to_string_lossy().into_owned();
    // A single file with --output-dir or --summary is a sequence of one frame.
    if args.output_dir.is_some() || args.summary.is_some() || is_pattern(&pattern) {
        return detect_frames(&args, detector.as_ref());
    }
    if (args.margin || args.normals) && args.output.is_none() {
        return Err("--margin and --normals need --output or --output-dir".into());
    }
    let output_format = args.output.as_deref().map(output_format).transpose()?;
    let pool = pool(args.input.threads)?;
    let job = FrameJob {
        detector: detector.as_ref(),
        options: read_options(&args.input),
        margin: args.margin,
        normals: args.normals,
        pool: &pool,
    };
    let output = args.output.as_deref().zip(output_format);
    let outcome = job.run(&args.input.input, args.input.radius, output)?;
    if outcome.estimated {
        eprintln!("{}", auto_warning(outcome.radius, &args.input.input));
    }
    for skipped in &outcome.skipped {
        eprintln!(
            "warning: {}: not written back: {skipped}",
            args.input.input.display()
        );
    }
    if args.input.json {
        let object = json!({
            "method": detector.name(),
            "params": detector.params().to_string(),
            "input": args.input.input.display().to_string(),
            "n": outcome.n,
            "dim": outcome.dim,
            "radius": outcome.radius,
            "radius_estimated": outcome.estimated,
            "boundary": outcome.boundary,
            "seconds": outcome.seconds,
            "threads": pool.current_num_threads(),
        });
        println!("{object}");
    } else {
        eprintln!(
            "{}: {} of {} particles boundary ({:.1}%), {}D, r = {}, {} in {:.3} s on {} thread{}{}",
            args.input.input.display(),
            outcome.boundary,
            outcome.n,
            percent(outcome.boundary, outcome.n),
            outcome.dim,
            outcome.radius,
            method_label(detector.as_ref()),
            outcome.seconds,
            pool.current_num_threads(),
            if pool.current_num_threads() == 1 {
                ""
            } else {
                "s"
            },
            match &args.output {
                Some(p) => format!(", written to {}", p.display()),
                None => String::new(),
            }
        );
    }
    Ok(())
}

/// Compares file names so that `frame_2` comes before `frame_10`: runs of ASCII digits compare
/// by value (then by length, so `07` follows `7`), everything else byte by byte. Hand-written:
/// a dozen lines, where the natural-sort crates are unmaintained or pull in Unicode tables.
fn natural_cmp(a: &str, b: &str) -> std::cmp::Ordering {
    use std::cmp::Ordering;
    let (a, b) = (a.as_bytes(), b.as_bytes());
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        if a[i].is_ascii_digit() && b[j].is_ascii_digit() {
            let run =
                |s: &[u8], k: usize| k + s[k..].iter().take_while(|c| c.is_ascii_digit()).count();
            let (ei, ej) = (run(a, i), run(b, j));
            let trim = |s: &[u8]| {
                let z = s.iter().take_while(|&&c| c == b'0').count();
                s[z..].to_vec()
            };
            let (da, db) = (trim(&a[i..ei]), trim(&b[j..ej]));
            let order = da
                .len()
                .cmp(&db.len())
                .then_with(|| da.cmp(&db))
                .then_with(|| (ei - i).cmp(&(ej - j)));
            if order != Ordering::Equal {
                return order;
            }
            (i, j) = (ei, ej);
        } else {
            if a[i] != b[j] {
                return a[i].cmp(&b[j]);
            }
            i += 1;
            j += 1;
        }
    }
    (a.len() - i).cmp(&(b.len() - j))
}

/// The frames `pattern` matches (files only), in natural order of their paths.
fn frames(pattern: &str) -> Result<Vec<PathBuf>, String> {
    let paths = glob::glob(pattern).map_err(|e| format!("invalid pattern {pattern:?}: {e}"))?;
    let mut files: Vec<PathBuf> = paths
        .filter_map(Result::ok)
        .filter(|p| p.is_file())
        .collect();
    if files.is_empty() {
        return Err(format!("no file matches {pattern:?}"));
    }
    files.sort_by(|a, b| natural_cmp(&a.to_string_lossy(), &b.to_string_lossy()));
    Ok(files)
}

/// `detect` over a sequence of frames: one output per frame in `--output-dir`, a line (or CSV
/// row) per frame; a frame that fails is reported and skipped.
fn detect_frames(args: &DetectArgs, detector: &dyn BoundaryDetector) -> Result<(), String> {
    if args.output.is_some() {
        return Err("several frames need --output-dir, not --output".into());
    }
    if (args.margin || args.normals) && args.output_dir.is_none() {
        return Err("--margin and --normals need --output or --output-dir".into());
    }
    let pattern = args.input.input.to_string_lossy().into_owned();
    let paths = frames(&pattern)?;
    let options = read_options(&args.input);
    // Output path and format of each frame (an error for the frames that have none).
    let mut outputs: Vec<Result<Option<(PathBuf, Format)>, String>> = Vec::new();
    if let Some(dir) = &args.output_dir {
        std::fs::create_dir_all(dir)
            .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
        let mut taken = std::collections::HashMap::new();
        for path in &paths {
            let format = args
                .output_format
                .or(args.input.format)
                .or_else(|| Format::from_path(path));
            // `fluid_1.bgeo.gz` is named `fluid_1`, like `fluid_1.vtk`.
            let stem = path.file_stem().unwrap_or_default().to_string_lossy();
            let stem = match Format::from_path(path) {
                Some(Format::Bgeo) => Path::new(stem.as_ref())
                    .file_stem()
                    .map_or(stem.to_string(), |s| s.to_string_lossy().into_owned()),
                _ => stem.to_string(),
            };
            outputs.push(match format {
                None => Err(format!(
                    "{}: unknown format (name it with --format / --output-format)",
                    path.display()
                )),
                Some(f) => {
                    let out = dir.join(format!("{stem}.{}", f.name()));
                    if let Some(other) = taken.insert(out.clone(), path.clone()) {
                        return Err(format!(
                            "{} and {} would both be written to {}",
                            other.display(),
                            path.display(),
                            out.display()
                        ));
                    }
                    Ok(Some((out, f)))
                }
            });
        }
    } else {
        outputs.resize_with(paths.len(), || Ok(None));
    }
    // `--radius auto`: estimated once, on the first frame that reads, and used for all, so that
    // the counts of the frames are comparable.
    let radius_arg = match args.input.radius {
        RadiusArg::Value(v) => RadiusArg::Value(v),
        RadiusArg::Auto => {
            let mut estimate = None;
            for path in &paths {
                if let Ok(set) = boundary_io::read_particles(path, &options) {
                    if let Ok((r, _)) = resolve_radius(RadiusArg::Auto, &set, path) {
                        eprintln!("{} (used for every frame)", auto_warning(r, path));
                        estimate = Some(r);
                        break;
                    }
                }
            }
            RadiusArg::Value(estimate.ok_or("--radius auto: no frame could be read to estimate r")?)
        }
    };
    let pool = pool(args.input.threads)?;
    let job = FrameJob {
        detector,
        options,
        margin: args.margin,
        normals: args.normals,
        pool: &pool,
    };
    let bar = if args.input.json {
        indicatif::ProgressBar::hidden()
    } else {
        indicatif::ProgressBar::new(paths.len() as u64)
    };
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{bar:40} {pos}/{len} frames, {elapsed} (eta {eta})",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let total = paths.len();
    let results: Vec<Result<FrameOutcome, String>> = pool.install(|| {
        use rayon::prelude::*;
        paths
            .par_iter()
            .zip(&outputs)
            .enumerate()
            .map(|(k, (path, output))| {
                let result = match output {
                    Ok(out) => job.run(
                        path,
                        radius_arg,
                        out.as_ref().map(|(p, f)| (p.as_path(), *f)),
                    ),
                    Err(e) => Err(e.clone()),
                };
                if !args.input.json {
                    let line = match &result {
                        Ok(o) => format!(
                            "frame {}/{total} {}: {} of {} particles boundary ({:.1}%), {:.3} s",
                            k + 1,
                            path.display(),
                            o.boundary,
                            o.n,
                            percent(o.boundary, o.n),
                            o.seconds
                        ),
                        Err(e) => format!("frame {}/{total}: skipped: {e}", k + 1),
                    };
                    bar.suspend(|| eprintln!("{line}"));
                }
                bar.inc(1);
                result
            })
            .collect()
    });
    bar.finish_and_clear();
    let failed = results.iter().filter(|r| r.is_err()).count();
    if let Some(summary) = &args.summary {
        write_summary(summary, &paths, &outputs, &results)?;
    }
    if args.input.json {
        let frames: Vec<_> = paths
            .iter()
            .zip(&outputs)
            .zip(&results)
            .map(|((path, out), result)| {
                let output = out
                    .as_ref()
                    .ok()
                    .and_then(|o| o.as_ref())
                    .map(|(p, _)| p.display().to_string());
                match result {
                    Ok(o) => json!({
                        "input": path.display().to_string(), "output": output, "n": o.n,
                        "dim": o.dim, "radius": o.radius, "boundary": o.boundary,
                        "seconds": o.seconds,
                    }),
                    Err(e) => json!({
                        "input": path.display().to_string(), "output": output, "error": e,
                    }),
                }
            })
            .collect();
        let object = json!({
            "method": detector.name(),
            "params": detector.params().to_string(),
            "input": pattern,
            "radius": match radius_arg { RadiusArg::Value(v) => v, RadiusArg::Auto => f64::NAN },
            "radius_estimated": matches!(args.input.radius, RadiusArg::Auto),
            "frames": frames,
            "failed": failed,
            "threads": pool.current_num_threads(),
        });
        println!("{object}");
    } else {
        eprintln!(
            "{} of {total} frames done with {}{}",
            total - failed,
            method_label(detector),
            match &args.output_dir {
                Some(dir) => format!(", written to {}", dir.display()),
                None => String::new(),
            }
        );
    }
    if failed == total {
        return Err(format!("all {total} frames failed"));
    }
    if failed > 0 {
        eprintln!("warning: {failed} of {total} frames failed and were skipped");
    }
    Ok(())
}

/// Quotes a CSV field when it needs it.
fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_owned()
    }
}

/// One CSV row per frame: the boundary count per frame, for plotting.
fn write_summary(
    path: &Path,
    inputs: &[PathBuf],
    outputs: &[Result<Option<(PathBuf, Format)>, String>],
    results: &[Result<FrameOutcome, String>],
) -> Result<(), String> {
    use std::fmt::Write as _;
    let mut text = String::from("frame,input,output,n,dim,radius,boundary,seconds,error\n");
    for (k, ((input, output), result)) in inputs.iter().zip(outputs).zip(results).enumerate() {
        let output = match output {
            Ok(Some((p, _))) => p.display().to_string(),
            _ => String::new(),
        };
        let input = csv_field(&input.display().to_string());
        let output = csv_field(&output);
        let _ = match result {
            Ok(o) => writeln!(
                text,
                "{k},{input},{output},{},{},{},{},{:.6},",
                o.n, o.dim, o.radius, o.boundary, o.seconds
            ),
            Err(e) => writeln!(text, "{k},{input},{output},,,,,,{}", csv_field(e)),
        };
    }
    std::fs::write(path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

fn percent(part: usize, whole: usize) -> f64 {
    if whole == 0 {
        0.0
    } else {
        100.0 * part as f64 / whole as f64
    }
}

/// `name` or `name (k=v, …)`.
fn method_label(detector: &dyn BoundaryDetector) -> String {
    detector.to_string()
}

fn score(args: ScoreArgs) -> Result<(), String> {
    let detector = detector_with_params(&args.method.method, &args.method.params)
        .map_err(|e| e.to_string())?;
    let (set, r_value) = read_input(&args.input)?;
    let r = radius(r_value)?;
    let pool = pool(args.input.threads)?;
    let (detection, seconds) = run_timed(&pool, detector.as_ref(), &set, r)?;
    let (truth, truth_name, truth_seconds) = match &args.truth {
        Some(path) => (
            read_truth(path, set.len())?,
            path.display().to_string(),
            None,
        ),
        None => {
            let exact =
                detector_with_params::<&str, &str>("exact", &[]).map_err(|e| e.to_string())?;
            let (truth, t) = run_timed(&pool, exact.as_ref(), &set, r)?;
            (truth.labels.into_vec(), "exact".to_owned(), Some(t))
        }
    };
    let c =
        Confusion::from_labels(detection.labels.as_slice(), &truth).map_err(|e| e.to_string())?;
    if args.input.json {
        let object = json!({
            "method": detector.name(),
            "params": detector.params().to_string(),
            "truth": truth_name,
            "input": args.input.input.display().to_string(),
            "n": set.len(),
            "dim": set.dim(),
            "radius": r_value,
            "tp": c.tp, "tn": c.tn, "fp": c.fp, "fn": c.fn_,
            "recall": c.recall(), "fpr": c.fpr(), "m": c.m(),
            "precision": c.precision(), "f1": c.f1(),
            "seconds": seconds,
            "truth_seconds": truth_seconds,
            "threads": pool.current_num_threads(),
        });
        println!("{object}");
    } else {
        println!(
            "{} vs {truth_name} on {} ({} particles, {}D, r = {})",
            method_label(detector.as_ref()),
            args.input.input.display(),
            set.len(),
            set.dim(),
            r_value
        );
        println!("TP  {}\nTN  {}\nFP  {}\nFN  {}", c.tp, c.tn, c.fp, c.fn_);
        println!(
            "Rec {:.6}\nFPR {:.6}\nM   {:.6}",
            c.recall(),
            c.fpr(),
            c.m()
        );
        match truth_seconds {
            Some(t) => println!("time {seconds:.3} s (exact {t:.3} s)"),
            None => println!("time {seconds:.3} s"),
        }
    }
    Ok(())
}

/// Truth labels from the `boundary` column of a CSV, checked against the particle count.
fn read_truth(path: &Path, n: usize) -> Result<Vec<bool>, String> {
    let values = boundary_io::read_csv_column(path, "boundary").map_err(|e| e.to_string())?;
    if values.len() != n {
        return Err(format!(
            "{}: {} truth labels for {n} particles",
            path.display(),
            values.len()
        ));
    }
    values
        .iter()
        .enumerate()
        .map(|(i, &v)| match v {
            0.0 => Ok(false),
            1.0 => Ok(true),
            _ => Err(format!(
                "{}: particle {i}: boundary must be 0 or 1, got {v}",
                path.display()
            )),
        })
        .collect()
}

/// Colour of a feature code (thesis Fig. 15): regular boundary blue, droplet cyan, ligament
/// yellow, sheet magenta; interior grey.
fn feature_colour(code: i8) -> [u8; 3] {
    match code {
        0 => [0, 255, 255],
        1 => [255, 255, 0],
        2 => [255, 0, 255],
        3 => [0, 0, 255],
        _ => [160, 160, 160],
    }
}

fn resample(args: ResampleArgs) -> Result<(), String> {
    use boundary_resample::{ResampleConfig, Resampled};
    let detector = detector_with_params(&args.method.method, &args.method.params)
        .map_err(|e| e.to_string())?;
    let format = output_format(&args.output)?;
    let config = ResampleConfig {
        k: args.k,
        alpha: args.alpha,
        shift: args.shift,
        ..ResampleConfig::default()
    };
    let (set, r_value) = read_input(&args.input)?;
    let r = radius(r_value)?;
    let pool = pool(args.input.threads)?;
    let (detection, seconds) = run_timed(&pool, detector.as_ref(), &set, r)?;
    let labels = &detection.labels;
    let (out, feature, source): (AnyParticleSet, Vec<i8>, Vec<usize>) = pool
        .install(|| match &set {
            AnyParticleSet::D2(s) => boundary_resample::resample(s, r, labels, &config)
                .map(|o: Resampled<2>| (o.set.into(), o.feature, o.source)),
            AnyParticleSet::D3(s) => boundary_resample::resample(s, r, labels, &config)
                .map(|o: Resampled<3>| (o.set.into(), o.feature, o.source)),
        })
        .map_err(|e| e.to_string())?;
    // Per input particle, its feature code (a feature particle's replacements share it).
    let mut input_feature = vec![boundary_resample::INTERIOR_CODE; set.len()];
    for (&f, &i) in feature.iter().zip(&source) {
        input_feature[i] = f;
    }
    let counts: Vec<usize> = (-1..=3i8)
        .map(|code| input_feature.iter().filter(|&&f| f == code).count())
        .collect();
    let codes: Vec<i64> = feature.iter().map(|&f| i64::from(f)).collect();
    let sources: Vec<i64> = source
        .iter()
        .map(|&i| i64::try_from(i).unwrap_or(i64::MAX))
        .collect();
    let mut columns = vec![
        ("feature", Column::Int(&codes)),
        ("source", Column::Int(&sources)),
    ];
    let colours: Vec<[u8; 3]> = feature.iter().map(|&f| feature_colour(f)).collect();
    let channel = |k: usize| -> Vec<u8> { colours.iter().map(|c| c[k]).collect() };
    let (red, green, blue) = (channel(0), channel(1), channel(2));
    if matches!(format, Format::Ply | Format::Vtk) {
        columns.push(("red", Column::Byte(&red)));
        columns.push(("green", Column::Byte(&green)));
        columns.push(("blue", Column::Byte(&blue)));
    }
    write_particles(&args.output, Some(format), &out, &columns).map_err(|e| e.to_string())?;
    if args.input.json {
        let object = json!({
            "method": detector.name(),
            "params": detector.params().to_string(),
            "input": args.input.input.display().to_string(),
            "output": args.output.display().to_string(),
            "n": set.len(),
            "n_out": out.len(),
            "dim": set.dim(),
            "radius": r_value,
            "boundary": labels.boundary_count(),
            "interior": counts[0],
            "droplet": counts[1],
            "ligament": counts[2],
            "sheet": counts[3],
            "regular": counts[4],
            "seconds": seconds,
        });
        println!("{object}");
    } else {
        eprintln!(
            "{}: {} boundary particles ({}) of {}: {} droplet, {} ligament, {} sheet, {} regular; \
             {} particles written to {}",
            args.input.input.display(),
            labels.boundary_count(),
            method_label(detector.as_ref()),
            set.len(),
            counts[1],
            counts[2],
            counts[3],
            counts[4],
            out.len(),
            args.output.display()
        );
    }
    Ok(())
}

fn list_methods(args: MethodsArgs) -> Result<(), String> {
    let mut entries = Vec::new();
    for name in methods() {
        let detector = detector_with_params::<&str, &str>(name, &[]).map_err(|e| e.to_string())?;
        entries.push((name, detector));
    }
    if args.json {
        let list: Vec<_> = entries
            .iter()
            .map(|(name, d)| {
                json!({
                    "name": name,
                    "summary": summary(name),
                    "certified": d.certified(),
                    "params": d.params().0.iter().map(|p| json!({
                        "name": p.name, "default": p.default, "description": p.description,
                    })).collect::<Vec<_>>(),
                })
            })
            .collect();
        println!("{}", serde_json::Value::Array(list));
        return Ok(());
    }
    for (name, d) in &entries {
        let tag = if d.certified() { " [certified]" } else { "" };
        println!("{name}{tag}: {}", summary(name).unwrap_or(""));
        let params = d.params();
        if params.0.is_empty() {
            println!("    (no parameters)");
        }
        for p in &params.0 {
            println!("    --set {}={}  {}", p.name, p.default, p.description);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::natural_cmp;
    use std::cmp::Ordering::{Equal, Greater, Less};

    #[test]
    fn natural_order_compares_digit_runs_by_value() {
        assert_eq!(natural_cmp("fluid_2.vtk", "fluid_10.vtk"), Less);
        assert_eq!(natural_cmp("fluid_10.vtk", "fluid_9.vtk"), Greater);
        assert_eq!(natural_cmp("f_007", "f_7"), Greater);
        assert_eq!(natural_cmp("f_7", "f_7"), Equal);
        assert_eq!(natural_cmp("a1b2", "a1b10"), Less);
        assert_eq!(natural_cmp("run2/f_1", "run10/f_0"), Less);
        assert_eq!(natural_cmp("f", "f_1"), Less);
        assert_eq!(natural_cmp("b", "a99"), Greater);
    }
}
