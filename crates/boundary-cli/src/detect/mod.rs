//! `boundary detect`: label the particles of one file, or of every frame a pattern matches.
//!
//! By concern: [`frame`] runs one frame (read once into a `boundary_io::Frame`, detected,
//! written), [`frames`] many frames (outputs, one radius, parallel runs), [`resume`] what a
//! stopped run already did, [`summary`] the per-frame CSV and the closing report.

mod frame;
mod frames;
mod resume;
mod summary;

use crate::common::{
    detector_for, output_format, parse_output_format, pool, read_options, InputArgs, MethodArgs,
};
use crate::domain::{DomainArgs, DomainSetup};
use crate::error::CliError;
use boundary_io::Format;
use clap::Args;
use frame::{check_normals, reads_attributes, FrameJob};
use serde_json::json;
use std::path::PathBuf;

#[derive(Debug, Args)]
pub(crate) struct DetectArgs {
    #[command(flatten)]
    input: InputArgs,
    #[command(flatten)]
    method: MethodArgs,
    #[command(flatten)]
    domain: DomainArgs,
    /// Write the particles with a `boundary` column (0/1) and the input's point attributes,
    /// format by extension: .csv, .xyz (.txt, .dat), .ply, .vtk (legacy), .vtu, .vtp, .bgeo,
    /// .bgeo.gz. A vector attribute is written as the columns `name:0`, `name:1`, … in CSV,
    /// XYZ and legacy VTK, as one array `name` in .vtu, .vtp and .bgeo, and as the properties
    /// `name_0`, `name_1`, … in PLY (whose property names are identifiers: `velocity_0`).
    #[arg(long, short)]
    output: Option<PathBuf>,
    /// Also write the method's per-particle margin (if it has one) as a `margin` column.
    #[arg(long)]
    margin: bool,
    /// Also write outward unit normals of the boundary particles as `normal:0`, `normal:1`
    /// [, `normal:2`] (one vector array `normal` in .vtu/.vtp/.bgeo, `normal_0`, `normal_1`
    /// [, `normal_2`] in .ply): the colour-field gradient with the Wendland C2 kernel at
    /// h = r; zero for interior particles.
    #[arg(long)]
    normals: bool,
    /// Widen the boundary to a narrow band: every particle within K·r of a boundary particle
    /// is labelled boundary too (K > 0; with --radius-attribute, r is --radius-scale). Any
    /// method; the margin column stays the method's.
    #[arg(long, value_name = "K", value_parser = parse_band)]
    band: Option<f64>,
    /// Process every frame INPUT (a file or glob pattern) matches, in natural order, writing
    /// one output per frame into DIR, named after its input.
    #[arg(long, value_name = "DIR", conflicts_with = "output")]
    output_dir: Option<PathBuf>,
    /// Format of the files written to --output-dir (default: each input's format; .vtu for
    /// an input only read, PySPH's .hdf5 and .npz).
    #[arg(long, value_parser = parse_output_format, value_name = "FMT", requires = "output_dir")]
    output_format: Option<Format>,
    /// With several frames: write one CSV line per frame (frame, input, output, n, dim, radius,
    /// boundary, seconds, error; with --radius-attribute also radius_min, radius_max before
    /// error; with walls, solids, periodic axes or phases also walls, interface before
    /// error) to this file.
    #[arg(long, value_name = "FILE.csv")]
    summary: Option<PathBuf>,
    /// With several frames: go on with a run that was stopped (Ctrl-C, a crash). The frames
    /// already done are skipped and their rows of --summary kept: a frame is done when its
    /// output in --output-dir exists and, with --summary, the summary holds its row. The
    /// result is that of a run never stopped.
    #[arg(long)]
    resume: bool,
    /// With several frames of the same particles (same count, same order): label them in
    /// order with the incremental tracker, which recomputes only the particles whose label
    /// may have changed since the previous frame; the labels are those of `exact`. A frame
    /// with another particle count starts over (every particle recomputed) unless
    /// --track-ids names the particles' ids. Needs --method exact (default parameters), a
    /// uniform --radius and no domain options; the summary gets a `recomputed` column.
    #[arg(long, conflicts_with_all = ["resume", "margin"])]
    track: bool,
    /// With --track: the point attribute that holds each particle's stable id (DualSPHysics'
    /// `Idp`, for example). The tracker then follows particles by id, so frames may gain and
    /// lose particles (inflow, outflow) and reorder them. Ids are whole numbers >= 0, unique
    /// within a frame.
    #[arg(long, value_name = "NAME", requires = "track")]
    track_ids: Option<String>,
}

/// `, band: K` for the human summaries (empty without `--band`).
pub(super) fn band_text(band: Option<f64>) -> String {
    band.map(|k| format!(", band: {k}")).unwrap_or_default()
}

/// `--band K`: a number, finite and `> 0`.
fn parse_band(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(k) if k.is_finite() && k > 0.0 => Ok(k),
        _ => Err(format!("'{text}' is not a number > 0")),
    }
}

/// Whether `text` holds a glob metacharacter.
fn is_pattern(text: &str) -> bool {
    text.contains(['*', '?', '['])
}

pub(crate) fn detect(args: DetectArgs) -> Result<(), CliError> {
    let detector = detector_for(&args.method.method, &args.method.params, &args.input)?;
    let pattern = args.input.input.to_string_lossy().into_owned();
    // A single file with --output-dir or --summary is a sequence of one frame.
    if args.output_dir.is_some() || args.summary.is_some() || is_pattern(&pattern) {
        return frames::detect_frames(&args, detector.as_ref());
    }
    if (args.margin || args.normals) && args.output.is_none() {
        return Err(CliError::Usage(
            "--margin and --normals need --output or --output-dir",
        ));
    }
    let radius_mode = args.input.radius_mode()?;
    check_normals(args.normals, &radius_mode)?;
    let output_format = args.output.as_deref().map(output_format).transpose()?;
    let setup = DomainSetup::new(&args.domain, &args.input, &radius_mode)?;
    let pool = pool(args.input.threads)?;
    let job = FrameJob {
        detector: detector.as_ref(),
        domain: setup.as_ref(),
        options: read_options(&args.input),
        array: args.input.array.as_deref(),
        margin: args.margin,
        normals: args.normals,
        band: args.band,
        pool: &pool,
        tracker: None,
        track_ids: None,
        reads_attributes: reads_attributes(&args, &radius_mode),
    };
    let output = args.output.as_deref().zip(output_format);
    let frame = job.read(&args.input.input, output.is_some())?;
    let outcome = job.run(frame, &radius_mode, output)?;
    summary::report_one(
        &args,
        detector.as_ref(),
        &outcome,
        setup.as_ref(),
        pool.current_num_threads(),
    )
}

/// The JSON record of the domain options (`null` for a bare cloud).
pub(super) fn domain_json(setup: Option<&DomainSetup>) -> serde_json::Value {
    match setup {
        None => serde_json::Value::Null,
        Some(d) => json!({
            "wall_attribute": d.wall_attribute(),
            "wall_arrays": d.wall_arrays(),
            "solids": d.solids(),
            "solid_meshes": d.solid_meshes(),
            "periodic": d.periodic(),
            "phases": d.has_phases(),
        }),
    }
}
