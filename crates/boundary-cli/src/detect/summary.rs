//! What a run of many frames reports: the `--summary` CSV (a row per frame, rewritten after
//! each frame) and the closing report (a line, or the JSON object of `--json`).

use super::frame::FrameOutcome;
use super::frames::{FrameResult, Output};
use super::{band_text, domain_json, DetectArgs};
use crate::common::{
    method_label, percent, radius_note, RadiiUsed, RadiusArg, RadiusMode, ResolvedRadius,
};
use crate::domain::DomainSetup;
use crate::error::CliError;
use crate::output::{errln, outln};
use boundary::BoundaryDetector;
use serde_json::json;
use std::path::{Path, PathBuf};

/// Quotes a CSV field when it needs it.
pub(super) fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_owned()
    }
}

/// The `--summary` file of a run: its header, and each frame's row once the frame is done.
pub(super) struct Summary {
    pub(super) path: PathBuf,
    pub(super) header: String,
    /// Per frame, its row after the frame number.
    pub(super) rows: Vec<Option<String>>,
}

impl Summary {
    /// Writes the header and the rows there are, in frame order, atomically.
    pub(super) fn save(&self) -> Result<(), CliError> {
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

/// The summary's header (without its newline), with the optional columns of radii (per
/// particle), domain counts and the tracker's recomputed particles.
pub(super) fn summary_header((per_particle, domain, track): (bool, bool, bool)) -> String {
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
pub(super) fn summary_row(
    input: &Path,
    output: &Output,
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

/// What a finished run of many frames reports.
pub(super) struct RunReport<'a> {
    pub(super) args: &'a DetectArgs,
    pub(super) detector: &'a dyn BoundaryDetector,
    /// The pattern as given.
    pub(super) pattern: &'a str,
    pub(super) paths: &'a [PathBuf],
    pub(super) outputs: &'a [Output],
    pub(super) results: &'a [FrameResult],
    /// The radius used (`auto` resolved).
    pub(super) radius_mode: &'a RadiusMode,
    /// The spacing `--radius auto` measured.
    pub(super) auto_spacing: Option<f64>,
    pub(super) setup: Option<&'a DomainSetup>,
    pub(super) threads: usize,
}

impl RunReport<'_> {
    /// The frames.
    pub(super) fn total(&self) -> usize {
        self.paths.len()
    }

    /// The frames done, by this run or the one resumed.
    pub(super) fn done(&self) -> usize {
        self.count(|r| matches!(r, FrameResult::Done(_) | FrameResult::Kept))
    }

    fn count(&self, which: impl Fn(&FrameResult) -> bool) -> usize {
        self.results.iter().filter(|r| which(r)).count()
    }

    /// Prints the report: the JSON object with `--json`, else one line; a warning when
    /// frames failed, and an error when all did.
    pub(super) fn print(&self) -> Result<(), CliError> {
        let args = self.args;
        let (done, total) = (self.done(), self.total());
        let kept = self.count(|r| matches!(r, FrameResult::Kept));
        let failed = self.count(|r| matches!(r, FrameResult::Failed(_)));
        if args.input.json {
            self.print_json(failed, kept)?;
        } else {
            errln!(
                "{done} of {total} frames done with {}{}{}{}",
                method_label(self.detector),
                band_text(args.band),
                match &args.output_dir {
                    Some(dir) => format!(", written to {}", dir.display()),
                    None => String::new(),
                },
                if kept > 0 {
                    format!(" ({kept} kept from the run resumed)")
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

    /// The JSON object of the run, with a record per frame.
    fn print_json(&self, failed: usize, kept: usize) -> Result<(), CliError> {
        let args = self.args;
        let radius_mode = self.radius_mode;
        let frames: Vec<_> = self
            .paths
            .iter()
            .zip(self.outputs)
            .zip(self.results)
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
            "method": self.detector.name(),
            "params": self.detector.describe().to_string(),
            "input": self.pattern,
            "radius": match radius_mode {
                RadiusMode::Uniform(arg) => arg.fixed().unwrap_or(f64::NAN),
                RadiusMode::PerParticle { scale, .. } => *scale,
            },
            "radius_from": match &args.input.radius_mode()? {
                RadiusMode::Uniform(arg) => arg.source(),
                RadiusMode::PerParticle { .. } => "radius_attribute",
            },
            "spacing": self.auto_spacing,
            "radius_estimated": matches!(args.input.radius, Some(RadiusArg::Auto)),
            "radius_attribute": match radius_mode {
                RadiusMode::PerParticle { attribute, .. } => Some(attribute.as_str()),
                RadiusMode::Uniform(_) => None,
            },
            "domain": domain_json(self.setup),
            "band": args.band,
            "frames": frames,
            "failed": failed,
            "kept": kept,
            "threads": self.threads,
        });
        outln!("{object}")?;
        Ok(())
    }
}

/// Prints what `detect` did on one file: the notes and warnings about the radius, the wall
/// rows and the attributes not written back, then the JSON object of `--json` or one line.
pub(super) fn report_one(
    args: &DetectArgs,
    detector: &dyn BoundaryDetector,
    outcome: &FrameOutcome,
    setup: Option<&DomainSetup>,
    threads: usize,
) -> Result<(), CliError> {
    if let Some(note) = outcome
        .resolved
        .as_ref()
        .and_then(|resolved| radius_note(resolved, &args.input.input))
    {
        errln!("{note}");
    }
    if let (Some(0), Some(selector)) = (outcome.wall_rows, setup) {
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
            "params": detector.describe().to_string(),
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
            "threads": threads,
            "domain": domain_json(setup),
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
            method_label(detector),
            outcome.seconds,
            threads,
            if threads == 1 { "" } else { "s" },
            match &args.output {
                Some(p) => format!(", written to {}", p.display()),
                None => String::new(),
            }
        );
    }
    Ok(())
}
