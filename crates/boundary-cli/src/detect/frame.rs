//! `detect` on one frame: read once, the radius resolved, detected (in its domain when
//! there is one), widened, and written back with the input's attributes.

use super::DetectArgs;
use crate::common::{
    attach_radii, point_attribute, radius, read_input_frame, refuse_flat, resolve_radius,
    run_timed, run_timed_in, RadiiUsed, RadiusMode, ResolvedRadius,
};
use crate::domain::DomainSetup;
use crate::error::CliError;
use boundary::{AnyParticleSet, BoundaryDetector, Detection, Domain, Tracker};
use boundary_io::{
    write_particles, AttributeValues, Column, Format, Frame, FrameParts, PositionColumns,
    ReadOptions,
};
use std::path::Path;

/// What one frame gave.
#[derive(Debug)]
pub(super) struct FrameOutcome {
    pub(super) n: usize,
    pub(super) dim: usize,
    /// The input's coordinates the positions were read from ("2D from x, y").
    pub(super) columns: PositionColumns,
    pub(super) radius: f64,
    /// The uniform radius as resolved (`None` with `--radius-attribute`).
    pub(super) resolved: Option<ResolvedRadius>,
    /// The per-particle radii used (`--radius-attribute`); `radius` is then their scale.
    pub(super) radii: Option<RadiiUsed>,
    pub(super) boundary: usize,
    /// The wall particles used (`--walls` or `--wall-attribute` given).
    pub(super) walls: Option<usize>,
    /// The particles on an interface between phases (`--phase-attribute`).
    pub(super) interface: Option<usize>,
    /// The wall rows of the input (`--wall-attribute`).
    pub(super) wall_rows: Option<usize>,
    pub(super) seconds: f64,
    /// With `--track`: the particles the tracker recomputed for this frame.
    pub(super) recomputed: Option<usize>,
    /// Attributes of the input not written back, with the reason.
    pub(super) skipped: Vec<String>,
}

impl FrameOutcome {
    /// `, 7846 wall particles, 12 interface` for the human summaries (empty for a bare cloud).
    pub(super) fn domain_facts(&self) -> String {
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
pub(super) struct FrameJob<'a> {
    pub(super) detector: &'a dyn BoundaryDetector,
    /// Walls, solids, periodic axes, phases; `None` for the bare cloud.
    pub(super) domain: Option<&'a DomainSetup>,
    pub(super) options: ReadOptions,
    /// `--array`: the particle array of a PySPH input to label.
    pub(super) array: Option<&'a str>,
    pub(super) margin: bool,
    pub(super) normals: bool,
    /// `--band K`.
    pub(super) band: Option<f64>,
    pub(super) pool: &'a rayon::ThreadPool,
    /// With `--track`: the tracker, created at the first frame (frames run in order).
    pub(super) tracker: Option<&'a std::sync::Mutex<Option<Tracker>>>,
    /// `--track-ids`: the attribute of the particles' ids.
    pub(super) track_ids: Option<&'a str>,
    /// Whether an option reads point attributes of every frame (radii, ids, walls, phases).
    pub(super) reads_attributes: bool,
}

/// Whether an option reads point attributes of every frame (radii, ids, wall rows, phases).
pub(super) fn reads_attributes(args: &DetectArgs, mode: &RadiusMode) -> bool {
    matches!(mode, RadiusMode::PerParticle { .. })
        || args.track_ids.is_some()
        || args.domain.reads_attributes()
}

/// What to read of a frame: its point attributes too when they are written back (`output`)
/// or an option reads one.
pub(super) fn frame_parts(output: bool, reads_attributes: bool) -> FrameParts {
    if output || reads_attributes {
        FrameParts::WithAttributes
    } else {
        FrameParts::Positions
    }
}

impl FrameJob<'_> {
    /// Reads the frame at `input`, once: with its attributes when they are written back
    /// (`output`) or an option reads one.
    pub(super) fn read(&self, input: &Path, output: bool) -> Result<Frame, CliError> {
        let parts = frame_parts(output, self.reads_attributes);
        Ok(read_input_frame(input, &self.options, self.array, parts)?)
    }

    /// Detects on `file`, and writes `output` (when given) with `boundary`, the optional
    /// `margin` and normals, and every attribute of the input it keeps.
    pub(super) fn run(
        &self,
        file: Frame,
        radius_mode: &RadiusMode,
        output: Option<(&Path, Format)>,
    ) -> Result<FrameOutcome, CliError> {
        refuse_flat(&file, &self.options)?;
        let (file, r_value, resolved, radii) = match radius_mode {
            RadiusMode::Uniform(arg) => {
                let resolved = resolve_radius(*arg, &file.set, &file.path)?;
                (file, resolved.r, Some(resolved), None)
            }
            RadiusMode::PerParticle { attribute, scale } => {
                let (file, used) = attach_radii(file, attribute, *scale)?;
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
            return self.run_in(setup, file, outcome, output);
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
                    Some(name) => Some(particle_ids(&file, name)?),
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
                        path: file.path.clone(),
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
        file: Frame,
        mut outcome: FrameOutcome,
        output: Option<(&Path, Format)>,
    ) -> Result<FrameOutcome, CliError> {
        let frame = setup.frame_domain(&file)?;
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
        file: &Frame,
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

/// The stable ids of `--track-ids` (whole numbers >= 0), or an error naming the particle.
fn particle_ids(frame: &Frame, name: &str) -> Result<Vec<u64>, CliError> {
    let attribute = point_attribute(frame, name, "--track-ids", "an id")?;
    let bad = |index: usize, problem: String| CliError::IdValue {
        path: frame.path.clone(),
        attribute: attribute.name.clone(),
        index,
        line: frame.line(index),
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
pub(super) fn check_normals(normals: bool, mode: &RadiusMode) -> Result<(), CliError> {
    if normals && matches!(mode, RadiusMode::PerParticle { .. }) {
        return Err(CliError::Usage(
            "--normals needs a uniform --radius (the colour field's smoothing length h = r); \
             it does not take --radius-attribute",
        ));
    }
    Ok(())
}
