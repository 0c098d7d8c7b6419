//! `boundary detect`: label the particles of one file, or of every frame a pattern matches.

use crate::common::{
    attach_radii, detector_for, method_label, output_format, parse_format, percent,
    point_attribute, pool, radius, radius_note, read_options, refuse_flat, resolve_radius,
    run_timed, run_timed_in, InputArgs, MethodArgs, RadiiUsed, RadiusArg, RadiusMode,
    ResolvedRadius,
};
use crate::domain::{DomainArgs, DomainSetup};
use crate::error::CliError;
use crate::interrupt::Interrupt;
use crate::output::{errln, outln};
use boundary::{AnyParticleSet, BoundaryDetector, Detection, Domain, Tracker};
use boundary_io::{
    read_particle_file, write_particles, AttributeValues, Column, Format, ParticleFile,
    PositionColumns, ReadOptions,
};
use clap::Args;
use serde_json::json;
use std::path::{Path, PathBuf};

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
    /// Format of the files written to --output-dir (default: each input's format).
    #[arg(long, value_parser = parse_format, value_name = "FMT", requires = "output_dir")]
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

/// A frame's output: `Some((path, format))`, `None` (no output), or the input whose format
/// is unknown.
type Output = Result<Option<(PathBuf, Format)>, PathBuf>;

/// What became of one frame of a run.
#[derive(Debug)]
enum FrameResult {
    /// Detected (and written) by this run.
    Done(FrameOutcome),
    /// Done by the run that `--resume` goes on with: its output and summary row are kept.
    Kept,
    /// Failed, and skipped.
    Failed(CliError),
    /// Not started: the run was stopped first (a signal, or a summary that cannot be written).
    NotRun,
}

/// What one frame gave.
#[derive(Debug)]
struct FrameOutcome {
    n: usize,
    dim: usize,
    /// The input's coordinates the positions were read from ("2D from x, y").
    columns: PositionColumns,
    radius: f64,
    /// The uniform radius as resolved (`None` with `--radius-attribute`).
    resolved: Option<ResolvedRadius>,
    /// The per-particle radii used (`--radius-attribute`); `radius` is then their scale.
    radii: Option<RadiiUsed>,
    boundary: usize,
    /// The wall particles used (`--walls` or `--wall-attribute` given).
    walls: Option<usize>,
    /// The particles on an interface between phases (`--phase-attribute`).
    interface: Option<usize>,
    /// The wall rows of the input (`--wall-attribute`).
    wall_rows: Option<usize>,
    seconds: f64,
    /// With `--track`: the particles the tracker recomputed for this frame.
    recomputed: Option<usize>,
    /// Attributes of the input not written back, with the reason.
    skipped: Vec<String>,
}

impl FrameOutcome {
    /// `, 7846 wall particles, 12 interface` for the human summaries (empty for a bare cloud).
    fn domain_facts(&self) -> String {
        let mut text = String::new();
        if let Some(walls) = self.walls {
            text += &format!(
                ", {walls} wall particle{}",
                if walls == 1 { "" } else { "s" }
            );
        }
        if let Some(interface) = self.interface {
            text += &format!(
                ", {interface} interface particle{}",
                if interface == 1 { "" } else { "s" }
            );
        }
        text
    }
}

/// What every frame of a `detect` run shares.
struct FrameJob<'a> {
    detector: &'a dyn BoundaryDetector,
    /// Walls, solids, periodic axes, phases; `None` for the bare cloud.
    domain: Option<&'a DomainSetup>,
    options: ReadOptions,
    margin: bool,
    normals: bool,
    /// `--band K`.
    band: Option<f64>,
    pool: &'a rayon::ThreadPool,
    /// With `--track`: the tracker, created at the first frame (frames run in order).
    tracker: Option<&'a std::sync::Mutex<Option<Tracker>>>,
    /// `--track-ids`: the attribute of the particles' ids.
    track_ids: Option<&'a str>,
}

impl FrameJob<'_> {
    /// Reads `input`, detects, and writes `output` (when given) with `boundary`, the optional
    /// `margin` and normals, and every attribute of the input it keeps.
    fn run(
        &self,
        input: &Path,
        radius_mode: &RadiusMode,
        output: Option<(&Path, Format)>,
    ) -> Result<FrameOutcome, CliError> {
        let per_particle = matches!(radius_mode, RadiusMode::PerParticle { .. });
        let with_attributes = output.is_some()
            || per_particle
            || self.track_ids.is_some()
            || self.domain.is_some_and(DomainSetup::needs_attributes);
        let file = if with_attributes {
            read_particle_file(input, &self.options)?
        } else {
            boundary_io::read_positions(input, &self.options)?
        };
        refuse_flat(&file.set, input, &self.options)?;
        let (file, r_value, resolved, radii) = match radius_mode {
            RadiusMode::Uniform(arg) => {
                let resolved = resolve_radius(*arg, &file.set, input)?;
                (file, resolved.r, Some(resolved), None)
            }
            RadiusMode::PerParticle { attribute, scale } => {
                let (file, used) = attach_radii(file, attribute, *scale, input, &self.options)?;
                (file, *scale, None, Some(used))
            }
        };
        let r = radius(r_value)?;
        if let Some(setup) = self.domain {
            let outcome = FrameOutcome {
                n: 0,
                dim: file.set.dim(),
                columns: file.position_columns.clone(),
                radius: r_value,
                resolved,
                radii,
                boundary: 0,
                walls: None,
                interface: None,
                wall_rows: None,
                seconds: 0.0,
                recomputed: None,
                skipped: Vec::new(),
            };
            return self.run_in(setup, file, input, outcome, output);
        }
        let set = &file.set;
        let (mut detection, seconds, recomputed) = match self.tracker {
            None => {
                let (detection, seconds) = run_timed(self.pool, self.detector, set, r)?;
                (detection, seconds, None)
            }
            Some(tracker) => {
                let mut guard = tracker
                    .lock()
                    .map_err(|_| CliError::Usage("the tracker was lost to a failed frame"))?;
                let tracker = match guard.as_mut() {
                    Some(t) => t,
                    None => guard.insert(Tracker::new(r, None, Domain::new())?),
                };
                let ids = match self.track_ids {
                    Some(name) => Some(particle_ids(&file, name, input, &self.options)?),
                    None => None,
                };
                let (labels, seconds) = self.pool.install(|| {
                    let start = std::time::Instant::now();
                    let labels = match &ids {
                        Some(ids) => tracker.update_with_ids(set, ids).cloned(),
                        None => tracker.update(set).cloned(),
                    };
                    (labels, start.elapsed().as_secs_f64())
                });
                let detection = Detection {
                    labels: labels.map_err(|error| CliError::Track {
                        path: input.to_path_buf(),
                        error,
                    })?,
                    margin: None,
                };
                (detection, seconds, Some(tracker.recomputed()))
            }
        };
        self.widen(&mut detection, set, r_value)?;
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
            let margin = match (&detection.margin, self.margin) {
                (_, false) => None,
                (Some(m), true) => Some(m.as_slice()),
                (None, true) => return Err(CliError::NoMargin(self.detector.name())),
            };
            self.write(path, format, &file, &flags, margin, &normals, Vec::new())?;
        }
        Ok(FrameOutcome {
            n: set.len(),
            dim: set.dim(),
            columns: file.position_columns,
            radius: r_value,
            resolved,
            radii,
            boundary: detection.labels.boundary_count(),
            walls: None,
            interface: None,
            wall_rows: None,
            seconds,
            recomputed,
            skipped: file.skipped,
        })
    }

    /// [`FrameJob::run`] in the domain of `setup`: the classified particles are those of
    /// `file` less its wall rows; every row is written back. `outcome` holds what `run`
    /// resolved (dimension, radius); the counts are filled here.
    fn run_in(
        &self,
        setup: &DomainSetup,
        file: boundary_io::ParticleFile,
        input: &Path,
        mut outcome: FrameOutcome,
        output: Option<(&Path, Format)>,
    ) -> Result<FrameOutcome, CliError> {
        let frame = setup.frame(&file, input, &self.options)?;
        let fluid = frame.fluid(&file.set);
        let r = radius(outcome.radius)?;
        let (mut found, seconds) = run_timed_in(self.pool, self.detector, fluid, &frame.domain, r)?;
        self.widen(&mut found.detection, fluid, outcome.radius)?;
        let detection = &found.detection;
        if let Some((path, format)) = output {
            let rows = file.set.len();
            let labels: Vec<i64> = detection
                .labels
                .as_slice()
                .iter()
                .map(|&b| i64::from(b))
                .collect();
            let flags = frame.scatter(rows, &labels, 0);
            let margin = match (&detection.margin, self.margin) {
                (_, false) => None,
                (Some(m), true) => Some(frame.scatter(rows, m, f64::NAN)),
                (None, true) => return Err(CliError::NoMargin(self.detector.name())),
            };
            let normals: Vec<Vec<f64>> = if self.normals {
                self.pool
                    .install(|| {
                        normal_components(fluid, outcome.radius, detection.labels.as_slice())
                    })?
                    .iter()
                    .map(|axis| frame.scatter(rows, axis, 0.0))
                    .collect()
            } else {
                Vec::new()
            };
            let walls: Option<Vec<i64>> = frame
                .wall_rows
                .as_ref()
                .map(|mask| mask.iter().map(|&w| i64::from(w)).collect());
            let interface: Option<Vec<i64>> = found.interface.as_ref().map(|labels| {
                let flags: Vec<i64> = labels.as_slice().iter().map(|&b| i64::from(b)).collect();
                frame.scatter(rows, &flags, 0)
            });
            let mut extra: Vec<(&str, Column)> = Vec::new();
            if let Some(w) = &walls {
                extra.push(("wall", Column::Int(w)));
            }
            if let Some(i) = &interface {
                extra.push(("interface", Column::Int(i)));
            }
            self.write(
                path,
                format,
                &file,
                &flags,
                margin.as_deref(),
                &normals,
                extra,
            )?;
        }
        outcome.n = fluid.len();
        outcome.boundary = detection.labels.boundary_count();
        outcome.walls = setup.has_walls().then_some(frame.walls);
        outcome.interface = found.interface.as_ref().map(|l| l.boundary_count());
        outcome.wall_rows = frame
            .wall_rows
            .as_ref()
            .map(|mask| mask.iter().filter(|&&w| w).count());
        outcome.seconds = seconds;
        outcome.skipped = file.skipped;
        Ok(outcome)
    }

    /// `--band K`: the labels widened to every particle within `K·r` of a boundary one
    /// (`Labels::widen`), on the rayon pool of the run.
    fn widen(
        &self,
        detection: &mut boundary::Detection,
        set: &AnyParticleSet,
        r: f64,
    ) -> Result<(), CliError> {
        if let Some(k) = self.band {
            detection.labels = self
                .pool
                .install(|| detection.labels.widen_any(set, k * r))?;
        }
        Ok(())
    }

    /// Writes every row of `file` with the `boundary` flags, the optional margin and normals,
    /// the `extra` columns, and the input's other attributes.
    #[allow(clippy::too_many_arguments)]
    fn write(
        &self,
        path: &Path,
        format: Format,
        file: &boundary_io::ParticleFile,
        flags: &[i64],
        margin: Option<&[f64]>,
        normals: &[Vec<f64>],
        extra: Vec<(&str, Column)>,
    ) -> Result<(), CliError> {
        let mut columns = vec![("boundary", Column::Int(flags))];
        if let Some(margin) = margin {
            columns.push(("margin", Column::Float(margin)));
        }
        for (name, values) in NORMAL_NAMES.iter().zip(normals) {
            columns.push((name, Column::Float(values)));
        }
        // The input's own columns of these names are replaced, not repeated.
        let mut ours: Vec<&str> = vec!["boundary", "margin"];
        if self.normals {
            ours.extend(NORMAL_NAMES);
        }
        ours.extend(extra.iter().map(|(name, _)| *name));
        columns.extend(extra);
        columns.extend(file.columns(&ours));
        write_particles(path, Some(format), &file.set, &columns)?;
        Ok(())
    }
}

/// The normal columns' names, by axis.
const NORMAL_NAMES: [&str; 3] = ["normal:0", "normal:1", "normal:2"];

/// Outward unit normals of the boundary particles from the colour-field gradient (h = r), one
/// vector per axis; zero for interior particles and where the gradient vanishes.
fn normal_components(
    set: &AnyParticleSet,
    r: f64,
    boundary: &[bool],
) -> Result<Vec<Vec<f64>>, CliError> {
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
    .map_err(CliError::from)
}

/// `, band: K` for the human summaries (empty without `--band`).
fn band_text(band: Option<f64>) -> String {
    band.map(|k| format!(", band: {k}")).unwrap_or_default()
}

/// `--band K`: a number, finite and `> 0`.
fn parse_band(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(k) if k.is_finite() && k > 0.0 => Ok(k),
        _ => Err(format!("'{text}' is not a number > 0")),
    }
}

/// `--track` labels as `exact` does, at one radius, on a bare cloud.
fn check_track(
    detector: &dyn BoundaryDetector,
    mode: &RadiusMode,
    domain: bool,
) -> Result<(), CliError> {
    if detector.name() != "exact" || detector.params().0.iter().any(|p| p.value != p.default) {
        return Err(CliError::Usage(
            "--track gives the labels of exact at its default parameters: use --method exact \
             without --set",
        ));
    }
    if !matches!(mode, RadiusMode::Uniform(_)) {
        return Err(CliError::Usage(
            "--track needs a uniform --radius (not --radius-attribute)",
        ));
    }
    if domain {
        return Err(CliError::Usage(
            "--track takes no walls, solids, periodic axes or phases; run without --track",
        ));
    }
    Ok(())
}

/// The stable ids of `--track-ids` (whole numbers >= 0), or an error naming the particle.
fn particle_ids(
    file: &ParticleFile,
    name: &str,
    input: &Path,
    options: &ReadOptions,
) -> Result<Vec<u64>, CliError> {
    let attribute = point_attribute(file, name, input, "--track-ids", "an id")?;
    let bad = |index: usize, problem: String| CliError::IdValue {
        path: input.to_path_buf(),
        attribute: attribute.name.clone(),
        index,
        // Looked up only on the error path (CSV only).
        line: boundary_io::particle_line(input, options, index)
            .ok()
            .flatten(),
        problem,
    };
    // Below 2^53 every whole number is exact in f64.
    const EXACT: f64 = 9_007_199_254_740_992.0;
    match &attribute.values {
        AttributeValues::Int(v) => v
            .iter()
            .enumerate()
            .map(|(k, &i)| u64::try_from(i).map_err(|_| bad(k, format!("{i} is negative"))))
            .collect(),
        AttributeValues::Float(v) => v
            .iter()
            .enumerate()
            .map(|(k, &x)| {
                if (0.0..EXACT).contains(&x) && x.fract() == 0.0 {
                    Ok(x as u64)
                } else {
                    Err(bad(k, format!("{x} is not a whole number >= 0 below 2^53")))
                }
            })
            .collect(),
    }
}

/// `--normals` smooth over one length h = r: not defined with a radius per particle.
fn check_normals(normals: bool, mode: &RadiusMode) -> Result<(), CliError> {
    if normals && matches!(mode, RadiusMode::PerParticle { .. }) {
        return Err(CliError::Usage(
            "--normals needs a uniform --radius (the colour field's smoothing length h = r); \
             it does not take --radius-attribute",
        ));
    }
    Ok(())
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
        return detect_frames(&args, detector.as_ref());
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
        margin: args.margin,
        normals: args.normals,
        band: args.band,
        pool: &pool,
        tracker: None,
        track_ids: None,
    };
    let output = args.output.as_deref().zip(output_format);
    let outcome = job.run(&args.input.input, &radius_mode, output)?;
    if let Some(note) = outcome
        .resolved
        .as_ref()
        .and_then(|resolved| radius_note(resolved, &args.input.input))
    {
        errln!("{note}");
    }
    if let (Some(0), Some(selector)) = (outcome.wall_rows, setup.as_ref()) {
        errln!(
            "warning: {}: no row has --wall-attribute {}",
            args.input.input.display(),
            selector.wall_attribute().unwrap_or_default()
        );
    }
    for skipped in &outcome.skipped {
        errln!(
            "warning: {}: not written back: {skipped}",
            args.input.input.display()
        );
    }
    if args.input.json {
        let resolved = outcome.resolved.as_ref();
        let object = json!({
            "method": detector.name(),
            "params": detector.params().to_string(),
            "input": args.input.input.display().to_string(),
            "n": outcome.n,
            "dim": outcome.dim,
            "radius": outcome.radius,
            "radius_from": resolved.map_or("radius_attribute", |r| r.arg.source()),
            "spacing": resolved.and_then(|r| r.spacing),
            "radius_estimated": resolved.is_some_and(ResolvedRadius::estimated),
            "radius_warning": resolved.and_then(|r| r.concern).map(|c| c.to_string()),
            "radii": RadiiUsed::json(outcome.radii.as_ref()),
            "boundary": outcome.boundary,
            "seconds": outcome.seconds,
            "threads": pool.current_num_threads(),
            "domain": domain_json(setup.as_ref()),
            "walls": outcome.walls,
            "interface": outcome.interface,
            "position_columns": outcome.columns.names,
            "dropped_column": outcome.columns.dropped,
            "band": args.band,
        });
        outln!("{object}")?;
    } else {
        errln!(
            "{}: {} of {} particles boundary ({:.1}%), {}D from {}{}, {}{}, {} in {:.3} s on {} \
             thread{}{}",
            args.input.input.display(),
            outcome.boundary,
            outcome.n,
            percent(outcome.boundary, outcome.n),
            outcome.dim,
            outcome.columns,
            outcome.domain_facts(),
            match &outcome.radii {
                Some(radii) => radii.describe(),
                None => format!("r = {}", outcome.radius),
            },
            band_text(args.band),
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

/// Whether `path` is a temporary file of an atomic write (`.frame_1.csv.tmp-<pid>-<n>`), left
/// by a run that was killed: never a frame.
fn is_temp_file(path: &Path) -> bool {
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    temp_destination(&name).is_some()
}

/// The destination's name of a temporary file of an atomic write (`frame_1.csv` for
/// `.frame_1.csv.tmp-<pid>-<n>`), or `None` for any other name.
fn temp_destination(name: &str) -> Option<&str> {
    let rest = name.strip_prefix('.')?;
    let destination = &rest[..rest.rfind(boundary_io::TEMP_MARKER)?];
    (!destination.is_empty() && boundary_io::is_temp_name_for(name, destination))
        .then_some(destination)
}

/// The frames `pattern` matches (files only), in natural order of their paths.
fn frames(pattern: &str) -> Result<Vec<PathBuf>, CliError> {
    let paths = glob::glob(pattern).map_err(|e| CliError::Pattern {
        pattern: pattern.to_owned(),
        reason: e.to_string(),
    })?;
    let mut files: Vec<PathBuf> = paths
        .filter_map(Result::ok)
        .filter(|p| p.is_file() && !is_temp_file(p))
        .collect();
    if files.is_empty() {
        return Err(CliError::NoMatch(pattern.to_owned()));
    }
    files.sort_by(|a, b| natural_cmp(&a.to_string_lossy(), &b.to_string_lossy()));
    Ok(files)
}

/// `detect` over a sequence of frames: one output per frame in `--output-dir`, a line (or CSV
/// row) per frame; a frame that fails is reported and skipped.
fn detect_frames(args: &DetectArgs, detector: &dyn BoundaryDetector) -> Result<(), CliError> {
    if args.output.is_some() {
        return Err(CliError::Usage(
            "several frames need --output-dir, not --output",
        ));
    }
    if (args.margin || args.normals) && args.output_dir.is_none() {
        return Err(CliError::Usage(
            "--margin and --normals need --output or --output-dir",
        ));
    }
    let radius_mode = args.input.radius_mode()?;
    check_normals(args.normals, &radius_mode)?;
    let pattern = args.input.input.to_string_lossy().into_owned();
    let paths = frames(&pattern)?;
    let options = read_options(&args.input);
    // Output path and format of each frame (`Err(frame)` for the frames whose format is
    // unknown).
    let mut outputs: Vec<Output> = Vec::new();
    if let Some(dir) = &args.output_dir {
        std::fs::create_dir_all(dir).map_err(|source| CliError::CreateDir {
            path: dir.clone(),
            source,
        })?;
        let mut taken = std::collections::HashMap::new();
        for path in &paths {
            // A format that is only read (PySPH's) is written as .vtu.
            let format = args
                .output_format
                .or(args.input.format)
                .or_else(|| Format::from_path(path))
                .map(|f| if f.can_write() { f } else { Format::Vtu });
            // `fluid_1.bgeo.gz` is named `fluid_1`, like `fluid_1.vtk`.
            let stem = path.file_stem().unwrap_or_default().to_string_lossy();
            let stem = match Format::from_path(path) {
                Some(Format::Bgeo) => Path::new(stem.as_ref())
                    .file_stem()
                    .map_or(stem.to_string(), |s| s.to_string_lossy().into_owned()),
                _ => stem.to_string(),
            };
            outputs.push(match format {
                None => Err(path.clone()),
                Some(f) => {
                    let out = dir.join(format!("{stem}.{}", f.name()));
                    if let Some(other) = taken.insert(out.clone(), path.clone()) {
                        return Err(CliError::OutputClash {
                            first: other,
                            second: path.clone(),
                            output: out,
                        });
                    }
                    Ok(Some((out, f)))
                }
            });
        }
    } else {
        outputs.resize_with(paths.len(), || Ok(None));
    }
    // The spacing `auto` measured, for the JSON summary.
    let mut auto_spacing = None;
    // `--radius auto`: estimated once, on the first frame that reads, and used for all, so that
    // the counts of the frames are comparable.
    let radius_mode = match radius_mode {
        RadiusMode::Uniform(RadiusArg::Auto) => {
            let mut estimate = None;
            for path in &paths {
                if let Ok(set) = boundary_io::read_particles(path, &options) {
                    if let Ok(resolved) = resolve_radius(RadiusArg::Auto, &set, path) {
                        if let Some(note) = radius_note(&resolved, path) {
                            errln!("{note} (used for every frame)");
                        }
                        estimate = Some(resolved.r);
                        auto_spacing = resolved.spacing;
                        break;
                    }
                }
            }
            RadiusMode::Uniform(RadiusArg::Value(
                estimate.ok_or(CliError::NoFrameForAutoRadius)?,
            ))
        }
        other => other,
    };
    let setup = DomainSetup::new(&args.domain, &args.input, &radius_mode)?;
    if args.track {
        check_track(detector, &radius_mode, setup.is_some())?;
    }
    let pool = pool(args.input.threads)?;
    let tracker = std::sync::Mutex::new(None);
    let job = FrameJob {
        detector,
        domain: setup.as_ref(),
        options,
        margin: args.margin,
        normals: args.normals,
        band: args.band,
        pool: &pool,
        tracker: args.track.then_some(&tracker),
        track_ids: args.track_ids.as_deref(),
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
    let per_particle = matches!(radius_mode, RadiusMode::PerParticle { .. });
    let header = summary_header(per_particle, setup.is_some(), args.track);
    // `--resume`: the frames done before, each with its summary row (when there is a summary).
    let kept: Vec<Option<Option<String>>> = if args.resume {
        resumable(args, &paths, &outputs, &header)?
    } else {
        vec![None; total]
    };
    let summary = args.summary.as_ref().map(|path| {
        std::sync::Mutex::new(Summary {
            path: path.clone(),
            header: header.clone(),
            rows: kept.iter().map(|row| row.clone().flatten()).collect(),
        })
    });
    // Set when the summary cannot be written: no frame starts after that, as its row could
    // not be kept.
    let summary_error: std::sync::Mutex<Option<CliError>> = std::sync::Mutex::new(None);
    let interrupt = Interrupt::install()?;
    let process = |(k, (path, output)): (usize, (&PathBuf, &Output))| {
        if kept[k].is_some() {
            if !args.input.json {
                bar.suspend(|| {
                    errln!(
                        "frame {}/{total} {}: done before, kept",
                        k + 1,
                        path.display()
                    );
                });
            }
            bar.inc(1);
            return FrameResult::Kept;
        }
        let stopped = summary_error.lock().map_or(true, |e| e.is_some());
        if stopped || interrupt.received().is_some() {
            return FrameResult::NotRun;
        }
        let result = match output {
            Ok(out) => job.run(
                path,
                &radius_mode,
                out.as_ref().map(|(p, f)| (p.as_path(), *f)),
            ),
            Err(frame) => Err(CliError::UnknownFrameFormat(frame.clone())),
        };
        // The frame's row is on the disk before its line is printed.
        if let Some(summary) = &summary {
            let row = summary_row(
                path,
                output,
                &result,
                (per_particle, setup.is_some(), args.track),
            );
            let saved = match summary.lock() {
                Ok(mut summary) => {
                    summary.rows[k] = Some(row);
                    summary.save()
                }
                Err(_) => Ok(()),
            };
            if let (Err(e), Ok(mut first)) = (saved, summary_error.lock()) {
                first.get_or_insert(e);
            }
        }
        if !args.input.json {
            let line = match &result {
                Ok(o) => format!(
                    "frame {}/{total} {}: {} of {} particles boundary ({:.1}%), {}D from {}{}, \
                     {:.3} s{}",
                    k + 1,
                    path.display(),
                    o.boundary,
                    o.n,
                    percent(o.boundary, o.n),
                    o.dim,
                    o.columns,
                    o.domain_facts(),
                    o.seconds,
                    match o.resolved.as_ref().and_then(|r| r.concern) {
                        Some(concern) => format!("; warning: {concern}"),
                        None => String::new(),
                    }
                ),
                Err(e) => format!("frame {}/{total}: skipped: {e}", k + 1),
            };
            bar.suspend(|| errln!("{line}"));
        }
        bar.inc(1);
        match result {
            Ok(o) => FrameResult::Done(o),
            Err(e) => FrameResult::Failed(e),
        }
    };
    let results: Vec<FrameResult> = if args.track {
        // The tracker follows the frames in order, one after another.
        paths
            .iter()
            .zip(&outputs)
            .enumerate()
            .map(process)
            .collect()
    } else {
        pool.install(|| {
            use rayon::prelude::*;
            paths
                .par_iter()
                .zip(&outputs)
                .enumerate()
                .map(process)
                .collect()
        })
    };
    bar.finish_and_clear();
    let done = results
        .iter()
        .filter(|r| matches!(r, FrameResult::Done(_) | FrameResult::Kept))
        .count();
    let kept_count = results
        .iter()
        .filter(|r| matches!(r, FrameResult::Kept))
        .count();
    let failed = results
        .iter()
        .filter(|r| matches!(r, FrameResult::Failed(_)))
        .count();
    if let Some(e) = summary_error.into_inner().ok().flatten() {
        errln!("{done} of {total} frames done; rerun with --resume to finish");
        return Err(e);
    }
    if let Some(summary) = summary {
        // In frame order, every row there is (all of them unless the run was stopped).
        summary
            .into_inner()
            .map_err(|_| CliError::Usage("the summary was lost to a failed worker"))?
            .save()?;
    }
    if let Some(signal) = interrupt.received() {
        return Err(CliError::Interrupted {
            signal,
            done,
            total,
        });
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
                    FrameResult::Done(o) => json!({
                        "input": path.display().to_string(), "output": output, "n": o.n,
                        "dim": o.dim, "radius": o.radius,
                        "spacing": o.resolved.as_ref().and_then(|r| r.spacing),
                        "radius_warning": o
                            .resolved
                            .as_ref()
                            .and_then(|r| r.concern)
                            .map(|c| c.to_string()),
                        "radii": RadiiUsed::json(o.radii.as_ref()), "boundary": o.boundary,
                        "seconds": o.seconds, "walls": o.walls, "interface": o.interface,
                        "position_columns": o.columns.names,
                        "dropped_column": o.columns.dropped,
                    }),
                    FrameResult::Kept => json!({
                        "input": path.display().to_string(), "output": output, "kept": true,
                    }),
                    FrameResult::Failed(e) => json!({
                        "input": path.display().to_string(), "output": output,
                        "error": e.to_string(),
                    }),
                    FrameResult::NotRun => json!({
                        "input": path.display().to_string(), "output": output,
                        "error": "not run",
                    }),
                }
            })
            .collect();
        let object = json!({
            "method": detector.name(),
            "params": detector.params().to_string(),
            "input": pattern,
            "radius": match &radius_mode {
                RadiusMode::Uniform(arg) => arg.fixed().unwrap_or(f64::NAN),
                RadiusMode::PerParticle { scale, .. } => *scale,
            },
            "radius_from": match (&args.input.radius_mode()?, &radius_mode) {
                (RadiusMode::Uniform(arg), _) => arg.source(),
                (RadiusMode::PerParticle { .. }, _) => "radius_attribute",
            },
            "spacing": auto_spacing,
            "radius_estimated": matches!(args.input.radius, Some(RadiusArg::Auto)),
            "radius_attribute": match &radius_mode {
                RadiusMode::PerParticle { attribute, .. } => Some(attribute.as_str()),
                RadiusMode::Uniform(_) => None,
            },
            "domain": domain_json(setup.as_ref()),
            "band": args.band,
            "frames": frames,
            "failed": failed,
            "kept": kept_count,
            "threads": pool.current_num_threads(),
        });
        outln!("{object}")?;
    } else {
        errln!(
            "{done} of {total} frames done with {}{}{}{}",
            method_label(detector),
            band_text(args.band),
            match &args.output_dir {
                Some(dir) => format!(", written to {}", dir.display()),
                None => String::new(),
            },
            if kept_count > 0 {
                format!(" ({kept_count} kept from the run resumed)")
            } else {
                String::new()
            }
        );
    }
    if failed == total {
        return Err(CliError::AllFramesFailed(total));
    }
    if failed > 0 {
        errln!("warning: {failed} of {total} frames failed and were skipped");
    }
    Ok(())
}

/// `--resume`: for each frame, `Some(row)` when the run resumed did it (`row` its summary row
/// after the frame number, `None` without `--summary`), `None` when it is still to do. A frame
/// is done when its output exists (written atomically, so complete) and, with `--summary`, the
/// summary holds a row of it without an error. Removes the temporary files a killed run left
/// beside the outputs and the summary.
fn resumable(
    args: &DetectArgs,
    paths: &[PathBuf],
    outputs: &[Result<Option<(PathBuf, Format)>, PathBuf>],
    header: &str,
) -> Result<Vec<Option<Option<String>>>, CliError> {
    if args.output_dir.is_none() && args.summary.is_none() {
        return Err(CliError::Usage(
            "--resume needs --output-dir or --summary (where the done frames are found)",
        ));
    }
    let output_of = |k: usize| match &outputs[k] {
        Ok(Some((p, _))) => Some(p.as_path()),
        _ => None,
    };
    remove_stale_temporaries(
        (0..paths.len())
            .filter_map(output_of)
            .chain(args.summary.as_deref()),
    );
    let previous = match &args.summary {
        Some(path) => Some(previous_rows(path, header)?),
        None => None,
    };
    let mut kept = Vec::with_capacity(paths.len());
    for (k, input) in paths.iter().enumerate() {
        let output = output_of(k);
        let output_text = output.map(|p| p.display().to_string()).unwrap_or_default();
        // An output that is the input itself says nothing about the frame being done.
        let output_done = match output {
            None => args.output_dir.is_none(),
            Some(out) => {
                std::fs::metadata(out).is_ok_and(|m| m.is_file()) && !same_file(out, input)
                    || previous.is_some() && same_file(out, input)
            }
        };
        let row = match &previous {
            None => Some(None),
            Some(rows) => rows
                .get(&input.display().to_string())
                .filter(|(output, _)| *output == output_text)
                .map(|(_, row)| Some(row.clone())),
        };
        kept.push(row.filter(|_| output_done));
    }
    Ok(kept)
}

/// Whether `a` and `b` name the same existing file.
fn same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}

/// Removes, beside each of `files`, the temporary files of its atomic writes (left by a run
/// that was killed); what cannot be removed stays, as it is never taken for an output.
fn remove_stale_temporaries<'a>(files: impl Iterator<Item = &'a Path>) {
    let mut by_dir: std::collections::HashMap<PathBuf, Vec<String>> =
        std::collections::HashMap::new();
    for file in files {
        let dir = match file.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
            _ => PathBuf::from("."),
        };
        if let Some(name) = file.file_name() {
            by_dir
                .entry(dir)
                .or_default()
                .push(name.to_string_lossy().into_owned());
        }
    }
    for (dir, names) in by_dir {
        let names: std::collections::HashSet<String> = names.into_iter().collect();
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        for entry in entries.flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            if temp_destination(&name).is_some_and(|d| names.contains(d)) {
                let _ = std::fs::remove_file(entry.path());
            }
        }
    }
}

/// The rows of the summary a stopped run wrote, by input: its output and the row after the
/// frame number. Rows with an error are left out (their frames are done again). No summary
/// yet: no rows.
fn previous_rows(
    path: &Path,
    header: &str,
) -> Result<std::collections::HashMap<String, (String, String)>, CliError> {
    let text = match std::fs::read_to_string(path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Default::default()),
        Err(e) => {
            return Err(CliError::Resume {
                path: path.to_path_buf(),
                problem: format!("cannot read it: {e}"),
            })
        }
    };
    let mut lines = text.lines();
    if lines.next().is_some_and(|first| first != header) {
        return Err(CliError::Resume {
            path: path.to_path_buf(),
            problem: format!(
                "its columns are not those this run writes ({header}): resume with the options \
                 of the run that wrote it, or remove it to start over"
            ),
        });
    }
    let columns = header.split(',').count();
    let mut rows = std::collections::HashMap::new();
    for line in lines {
        let Some(fields) = split_csv_line(line).filter(|f| f.len() == columns) else {
            continue;
        };
        // Column 3 is `n`, empty on a row with an error.
        if fields[3].is_empty() {
            continue;
        }
        if let Some((_, row)) = line.split_once(',') {
            rows.insert(fields[1].clone(), (fields[2].clone(), row.to_owned()));
        }
    }
    Ok(rows)
}

/// The fields of one CSV line as [`csv_field`] writes them; `None` when the quotes do not
/// close.
fn split_csv_line(line: &str) -> Option<Vec<String>> {
    let mut fields = Vec::new();
    let mut field = String::new();
    let mut chars = line.chars().peekable();
    let mut quoted = false;
    while let Some(c) = chars.next() {
        match (quoted, c) {
            (false, ',') => fields.push(std::mem::take(&mut field)),
            (false, '"') if field.is_empty() => quoted = true,
            (true, '"') if chars.peek() == Some(&'"') => {
                chars.next();
                field.push('"');
            }
            (true, '"') => quoted = false,
            (_, c) => field.push(c),
        }
    }
    if quoted {
        return None;
    }
    fields.push(field);
    Some(fields)
}

/// The JSON record of the domain options (`null` for a bare cloud).
fn domain_json(setup: Option<&DomainSetup>) -> serde_json::Value {
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

/// Quotes a CSV field when it needs it.
fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_owned()
    }
}

/// The `--summary` file of a run: its header, and each frame's row once the frame is done.
struct Summary {
    path: PathBuf,
    header: String,
    /// Per frame, its row after the frame number.
    rows: Vec<Option<String>>,
}

impl Summary {
    /// Writes the header and the rows there are, in frame order, atomically.
    fn save(&self) -> Result<(), CliError> {
        boundary_io::write_atomic(&self.path, |out| {
            writeln!(out, "{}", self.header)?;
            for (k, row) in self.rows.iter().enumerate() {
                if let Some(row) = row {
                    writeln!(out, "{k},{row}")?;
                }
            }
            Ok(())
        })?;
        Ok(())
    }
}

/// The summary's header (without its newline).
fn summary_header(per_particle: bool, domain: bool, track: bool) -> String {
    let mut text = String::from("frame,input,output,n,dim,radius,boundary,seconds,");
    if per_particle {
        text += "radius_min,radius_max,";
    }
    if domain {
        text += "walls,interface,";
    }
    if track {
        text += "recomputed,";
    }
    text += "error";
    text
}

/// One frame's summary row after its frame number (without a newline): the boundary count
/// per frame, for plotting.
fn summary_row(
    input: &Path,
    output: &Result<Option<(PathBuf, Format)>, PathBuf>,
    result: &Result<FrameOutcome, CliError>,
    (per_particle, domain, track): (bool, bool, bool),
) -> String {
    let output = match output {
        Ok(Some((p, _))) => p.display().to_string(),
        _ => String::new(),
    };
    let input = csv_field(&input.display().to_string());
    let output = csv_field(&output);
    match result {
        Ok(o) => {
            let radii = match (&o.radii, per_particle) {
                (Some(r), true) => format!("{},{},", r.min, r.max),
                _ => String::new(),
            };
            let facts = if domain {
                let count = |c: Option<usize>| c.map(|c| c.to_string()).unwrap_or_default();
                format!("{},{},", count(o.walls), count(o.interface))
            } else {
                String::new()
            };
            let recomputed = match (o.recomputed, track) {
                (Some(c), true) => format!("{c},"),
                (None, true) => ",".to_owned(),
                _ => String::new(),
            };
            format!(
                "{input},{output},{},{},{},{},{:.6},{radii}{facts}{recomputed}",
                o.n, o.dim, o.radius, o.boundary, o.seconds
            )
        }
        Err(e) => format!(
            "{input},{output},,,,,,{}{}{}{}",
            if per_particle { ",," } else { "" },
            if domain { ",," } else { "" },
            if track { "," } else { "" },
            csv_field(&e.to_string())
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::{natural_cmp, split_csv_line, temp_destination};

    #[test]
    fn temporary_files_are_told_from_frames() {
        assert_eq!(temp_destination(".f_1.csv.tmp-12-0"), Some("f_1.csv"));
        assert_eq!(
            temp_destination(".a.tmp-b.csv.tmp-1-2"),
            Some("a.tmp-b.csv")
        );
        assert_eq!(temp_destination("f_1.csv"), None);
        assert_eq!(temp_destination(".hidden.csv"), None);
        assert_eq!(temp_destination(".tmp-1-2"), None);
        assert_eq!(temp_destination("é.tmp-1-2"), None);
        assert_eq!(temp_destination(".f.csv.tmp-1-2x"), None);
    }

    #[test]
    fn summary_lines_split_as_they_were_quoted() {
        assert_eq!(
            split_csv_line(r#"0,"a,b.csv",out/"x".csv,,"say ""hi""""#),
            Some(vec![
                "0".to_owned(),
                "a,b.csv".to_owned(),
                "out/\"x\".csv".to_owned(),
                String::new(),
                "say \"hi\"".to_owned()
            ])
        );
        assert_eq!(split_csv_line(r#"0,"open"#), None);
        assert_eq!(split_csv_line(""), Some(vec![String::new()]));
    }
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
