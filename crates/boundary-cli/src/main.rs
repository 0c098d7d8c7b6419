//! `boundary`: boundary particles of meshfree particle files.
//!
//! ```text
//! boundary detect INPUT --radius R [--method NAME] [--set KEY=VALUE]... [--output FILE]
//!                 [--dim 2|3] [--format FMT] [--margin] [--threads N] [--json]
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
use boundary_io::{read_particles, write_particles, Column, Format, ReadOptions};
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
    /// Particle file: .csv (header x,y[,z]), .xyz/.txt, .ply, .vtk (legacy).
    input: PathBuf,
    /// Particle resolution r (positive, in the file's length unit).
    #[arg(long, short, value_parser = parse_radius, value_name = "R", allow_negative_numbers = true)]
    radius: f64,
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
    #[arg(long, requires = "output")]
    margin: bool,
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

fn parse_radius(text: &str) -> Result<f64, String> {
    let value: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("'{text}' is not a number"))?;
    Radius::new(value).map_err(|e| e.to_string())?;
    Ok(value)
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

/// The particle set of `args.input`.
fn read_input(args: &InputArgs) -> Result<AnyParticleSet, String> {
    let options = ReadOptions {
        dim: args.dim.map(usize::from),
        format: args.format,
    };
    read_particles(&args.input, &options).map_err(|e| e.to_string())
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
            "{}: unknown output format (use .csv, .xyz, .ply or .vtk)",
            path.display()
        )
    })
}

fn detect(args: DetectArgs) -> Result<(), String> {
    let detector = detector_with_params(&args.method.method, &args.method.params)
        .map_err(|e| e.to_string())?;
    let output_format = args.output.as_deref().map(output_format).transpose()?;
    let r = radius(args.input.radius)?;
    let set = read_input(&args.input)?;
    let pool = pool(args.input.threads)?;
    let (detection, seconds) = run_timed(&pool, detector.as_ref(), &set, r)?;
    if let (Some(path), Some(format)) = (&args.output, output_format) {
        let flags: Vec<i64> = detection
            .labels
            .as_slice()
            .iter()
            .map(|&b| i64::from(b))
            .collect();
        let mut columns = vec![("boundary", Column::Int(&flags))];
        if args.margin {
            match &detection.margin {
                Some(margin) => columns.push(("margin", Column::Float(margin))),
                None => {
                    return Err(format!(
                        "method '{}' reports no margin (drop --margin)",
                        detector.name()
                    ))
                }
            }
        }
        write_particles(path, Some(format), &set, &columns).map_err(|e| e.to_string())?;
    }
    let boundary = detection.labels.boundary_count();
    if args.input.json {
        let object = json!({
            "method": detector.name(),
            "params": detector.params().to_string(),
            "input": args.input.input.display().to_string(),
            "n": set.len(),
            "dim": set.dim(),
            "radius": args.input.radius,
            "boundary": boundary,
            "seconds": seconds,
            "threads": pool.current_num_threads(),
        });
        println!("{object}");
    } else {
        eprintln!(
            "{}: {} of {} particles boundary ({:.1}%), {}D, r = {}, {} in {:.3} s on {} thread{}{}",
            args.input.input.display(),
            boundary,
            set.len(),
            percent(boundary, set.len()),
            set.dim(),
            args.input.radius,
            method_label(detector.as_ref()),
            seconds,
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

fn percent(part: usize, whole: usize) -> f64 {
    if whole == 0 {
        0.0
    } else {
        100.0 * part as f64 / whole as f64
    }
}

/// `name` or `name (k=v, …)`.
fn method_label(detector: &dyn BoundaryDetector) -> String {
    let params = detector.params();
    if params.0.is_empty() {
        detector.name().to_owned()
    } else {
        format!("{} ({params})", detector.name())
    }
}

fn score(args: ScoreArgs) -> Result<(), String> {
    let detector = detector_with_params(&args.method.method, &args.method.params)
        .map_err(|e| e.to_string())?;
    let r = radius(args.input.radius)?;
    let set = read_input(&args.input)?;
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
            "radius": args.input.radius,
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
            args.input.radius
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
    let r = radius(args.input.radius)?;
    let set = read_input(&args.input)?;
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
            "radius": args.input.radius,
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
