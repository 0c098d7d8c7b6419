//! `detect` over many frames: the frames a pattern matches and their outputs, one radius for
//! all (`--radius auto`), the frames run in parallel (in order with `--track`), each read
//! once, and the report of the run.

use super::frame::{check_normals, frame_parts, reads_attributes, FrameJob, FrameOutcome};
use super::resume::{is_temp_file, resumable};
use super::summary::{summary_header, summary_row, RunReport, Summary};
use super::DetectArgs;
use crate::common::{
    percent, pool, radius_note, read_input_frame, read_options, resolve_radius, RadiusArg,
    RadiusMode,
};
use crate::domain::DomainSetup;
use crate::error::CliError;
use crate::interrupt::Interrupt;
use crate::output::errln;
use boundary::BoundaryDetector;
use boundary_io::{Format, Frame, ReadOptions};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// A frame's output: `Some((path, format))`, `None` (no output), or the input whose format
/// is unknown.
pub(super) type Output = Result<Option<(PathBuf, Format)>, PathBuf>;

/// What became of one frame of a run.
#[derive(Debug)]
pub(super) enum FrameResult {
    /// Detected (and written) by this run.
    Done(FrameOutcome),
    /// Done by the run that `--resume` goes on with: its output and summary row are kept.
    Kept,
    /// Failed, and skipped.
    Failed(CliError),
    /// Not started: the run was stopped first (a signal, or a summary that cannot be written).
    NotRun,
}

/// Frames read before the run (by `--radius auto`), each taken by the frame's run: no frame
/// is read twice.
type ReadBefore = Vec<Mutex<Option<Result<Frame, CliError>>>>;

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

/// The output path and format of each frame in `--output-dir` (created here), named after its
/// input; `Err(frame)` for the frames whose format is unknown. Two frames that would write
/// the same output are an error. Without `--output-dir`, no output.
fn plan_outputs(args: &DetectArgs, paths: &[PathBuf]) -> Result<Vec<Output>, CliError> {
    let Some(dir) = &args.output_dir else {
        return Ok(paths.iter().map(|_| Ok(None)).collect());
    };
    std::fs::create_dir_all(dir).map_err(|source| CliError::CreateDir {
        path: dir.clone(),
        source,
    })?;
    let mut outputs = Vec::with_capacity(paths.len());
    let mut taken = std::collections::HashMap::new();
    for path in paths {
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
    Ok(outputs)
}

/// The radius of every frame: `--radius auto` is estimated once, on the first frame that
/// reads, and used for all, so that the counts of the frames are comparable (with the spacing
/// measured, for the JSON report); any other mode is kept. The frames read for the estimate
/// are left in `read_before` for their run.
fn one_radius(
    args: &DetectArgs,
    mode: RadiusMode,
    paths: &[PathBuf],
    outputs: &[Output],
    options: &ReadOptions,
    read_before: &ReadBefore,
) -> Result<(RadiusMode, Option<f64>), CliError> {
    if !matches!(mode, RadiusMode::Uniform(RadiusArg::Auto)) {
        return Ok((mode, None));
    }
    let reads = reads_attributes(args, &mode);
    for (k, path) in paths.iter().enumerate() {
        // A frame of unknown format is not read (nor run).
        let Ok(output) = &outputs[k] else {
            continue;
        };
        let read = read_input_frame(
            path,
            options,
            args.input.array.as_deref(),
            frame_parts(output.is_some(), reads),
        )
        .map_err(CliError::from);
        let resolved = read
            .as_ref()
            .ok()
            .and_then(|frame| resolve_radius(RadiusArg::Auto, &frame.set, path).ok());
        if let Ok(mut slot) = read_before[k].lock() {
            *slot = Some(read);
        }
        if let Some(resolved) = resolved {
            if let Some(note) = radius_note(&resolved, path) {
                errln!("{note} (used for every frame)");
            }
            let mode = RadiusMode::Uniform(RadiusArg::Value(resolved.r));
            return Ok((mode, resolved.spacing));
        }
    }
    Err(CliError::NoFrameForAutoRadius)
}

/// The progress bar of a run of `total` frames (hidden with `--json`).
fn progress_bar(json: bool, total: usize) -> indicatif::ProgressBar {
    let bar = if json {
        indicatif::ProgressBar::hidden()
    } else {
        indicatif::ProgressBar::new(total as u64)
    };
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{bar:40} {pos}/{len} frames, {elapsed} (eta {eta})",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar
}

/// `--track` labels as `exact` does, at one radius, on a bare cloud.
fn check_track(
    detector: &dyn BoundaryDetector,
    mode: &RadiusMode,
    domain: bool,
) -> Result<(), CliError> {
    if detector.name() != "exact" || detector.describe().0.iter().any(|p| p.value != p.default) {
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

/// What the frames of a run share while they run: the job, what `--resume` kept, the
/// summary, the signals and the progress bar.
struct FrameRun<'a> {
    json: bool,
    job: &'a FrameJob<'a>,
    radius_mode: &'a RadiusMode,
    total: usize,
    /// Per frame, `Some` when `--resume` keeps it.
    kept: &'a [Option<Option<String>>],
    read_before: &'a ReadBefore,
    summary: Option<&'a Mutex<Summary>>,
    /// The summary's optional columns: radii, domain counts, recomputed.
    columns: (bool, bool, bool),
    /// Set when the summary cannot be written: no frame starts after that, as its row could
    /// not be kept.
    summary_error: &'a Mutex<Option<CliError>>,
    interrupt: &'a Interrupt,
    bar: &'a indicatif::ProgressBar,
}

impl FrameRun<'_> {
    /// Runs frame `k` (`path`, its `output`): kept, not run, or read once, detected and
    /// written; its summary row saved, then its line printed.
    fn frame(&self, k: usize, path: &Path, output: &Output) -> FrameResult {
        let total = self.total;
        if self.kept[k].is_some() {
            if !self.json {
                self.bar.suspend(|| {
                    errln!(
                        "frame {}/{total} {}: done before, kept",
                        k + 1,
                        path.display()
                    );
                });
            }
            self.bar.inc(1);
            return FrameResult::Kept;
        }
        let stopped = self.summary_error.lock().map_or(true, |e| e.is_some());
        if stopped || self.interrupt.received().is_some() {
            return FrameResult::NotRun;
        }
        let result = match output {
            Ok(out) => {
                let read_before = self.read_before[k]
                    .lock()
                    .ok()
                    .and_then(|mut slot| slot.take());
                read_before
                    .unwrap_or_else(|| self.job.read(path, out.is_some()))
                    .and_then(|frame| {
                        self.job.run(
                            frame,
                            self.radius_mode,
                            out.as_ref().map(|(p, f)| (p.as_path(), *f)),
                        )
                    })
            }
            Err(frame) => Err(CliError::UnknownFrameFormat(frame.clone())),
        };
        // The frame's row is on the disk before its line is printed.
        if let Some(summary) = self.summary {
            let row = summary_row(path, output, &result, self.columns);
            let saved = match summary.lock() {
                Ok(mut summary) => {
                    summary.rows[k] = Some(row);
                    summary.save()
                }
                Err(_) => Ok(()),
            };
            if let (Err(e), Ok(mut first)) = (saved, self.summary_error.lock()) {
                first.get_or_insert(e);
            }
        }
        if !self.json {
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
            self.bar.suspend(|| errln!("{line}"));
        }
        self.bar.inc(1);
        match result {
            Ok(o) => FrameResult::Done(o),
            Err(e) => FrameResult::Failed(e),
        }
    }
}

/// `detect` over a sequence of frames: one output per frame in `--output-dir`, a line (or CSV
/// row) per frame; a frame that fails is reported and skipped.
pub(super) fn detect_frames(
    args: &DetectArgs,
    detector: &dyn BoundaryDetector,
) -> Result<(), CliError> {
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
    let outputs = plan_outputs(args, &paths)?;
    let read_before: ReadBefore = paths.iter().map(|_| Mutex::new(None)).collect();
    let (radius_mode, auto_spacing) =
        one_radius(args, radius_mode, &paths, &outputs, &options, &read_before)?;
    let setup = DomainSetup::new(&args.domain, &args.input, &radius_mode)?;
    if args.track {
        check_track(detector, &radius_mode, setup.is_some())?;
    }
    let pool = pool(args.input.threads)?;
    let tracker = Mutex::new(None);
    let job = FrameJob {
        detector,
        domain: setup.as_ref(),
        options,
        array: args.input.array.as_deref(),
        margin: args.margin,
        normals: args.normals,
        band: args.band,
        pool: &pool,
        tracker: args.track.then_some(&tracker),
        track_ids: args.track_ids.as_deref(),
        reads_attributes: reads_attributes(args, &radius_mode),
    };
    let total = paths.len();
    let per_particle = matches!(radius_mode, RadiusMode::PerParticle { .. });
    let columns = (per_particle, setup.is_some(), args.track);
    let header = summary_header(columns);
    // `--resume`: the frames done before, each with its summary row (when there is a summary).
    let kept: Vec<Option<Option<String>>> = if args.resume {
        resumable(args, &paths, &outputs, &header)?
    } else {
        vec![None; total]
    };
    let summary = args.summary.as_ref().map(|path| {
        Mutex::new(Summary {
            path: path.clone(),
            header: header.clone(),
            rows: kept.iter().map(|row| row.clone().flatten()).collect(),
        })
    });
    let summary_error: Mutex<Option<CliError>> = Mutex::new(None);
    let interrupt = Interrupt::install()?;
    let bar = progress_bar(args.input.json, total);
    let run = FrameRun {
        json: args.input.json,
        job: &job,
        radius_mode: &radius_mode,
        total,
        kept: &kept,
        read_before: &read_before,
        summary: summary.as_ref(),
        columns,
        summary_error: &summary_error,
        interrupt: &interrupt,
        bar: &bar,
    };
    let process = |(k, (path, output)): (usize, (&PathBuf, &Output))| run.frame(k, path, output);
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
    let report = RunReport {
        args,
        detector,
        pattern: &pattern,
        paths: &paths,
        outputs: &outputs,
        results: &results,
        radius_mode: &radius_mode,
        auto_spacing,
        setup: setup.as_ref(),
        threads: pool.current_num_threads(),
    };
    let (done, total) = (report.done(), report.total());
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
    report.print()
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
