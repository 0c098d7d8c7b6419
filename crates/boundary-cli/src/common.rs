//! What the subcommands share: the input and method arguments, `--radius` or
//! `--radius-attribute` (a radius per particle), reading the input, the worker pool, timing a
//! detection.

use crate::error::CliError;
use crate::output::errln;
use boundary::{
    parse_param, AnyParticleSet, BoundaryDetector, CoreError, Detection, Domain, DomainDetection,
    Radius,
};
use boundary_io::{read_frame, Attribute, AttributeValues, Format, Frame, FrameParts, ReadOptions};
use clap::Args;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Debug, Args)]
pub(crate) struct InputArgs {
    /// Particle file: .csv (header x,y[,z]), .xyz/.txt, .ply, .vtk (legacy), .vtu, .vtp,
    /// .bgeo[.gz], PySPH's .hdf5 and .npz (its `fluid` array, or its only one).
    /// `detect` also takes a glob pattern of frames ('frames/fluid_*.vtu', quoted).
    pub(crate) input: PathBuf,
    /// Particle resolution r (positive, in the file's length unit), or `auto`: k times the
    /// particle spacing measured in the bulk (volume per particle), k = 1.45 (an estimate;
    /// the spacing found and the r chosen are printed). In SPH r is the smoothing length h:
    /// --smoothing-length says it in those terms. One of --radius, --smoothing-length,
    /// --spacing and --radius-attribute is required.
    #[arg(
        long,
        short,
        value_parser = parse_radius,
        value_name = "R|auto",
        allow_negative_numbers = true,
        required_unless_present_any = ["radius_attribute", "smoothing_length", "spacing"],
        conflicts_with_all = ["radius_attribute", "smoothing_length", "spacing"]
    )]
    pub(crate) radius: Option<RadiusArg>,
    /// The SPH smoothing length h of the solver that wrote the particles: r = h (the
    /// definition's resolution), and the SPH-sum methods (marrone, muller, divr, asymmetry,
    /// randles) use h itself as their smoothing length.
    #[arg(
        long,
        value_name = "H",
        value_parser = parse_length,
        allow_negative_numbers = true,
        conflicts_with_all = ["radius_attribute", "spacing"]
    )]
    pub(crate) smoothing_length: Option<f64>,
    /// The initial particle spacing dp of the solver (its `dp`, `dx`, particle diameter):
    /// r = k·dp with k = 1.45, between the smoothing lengths solvers use by default
    /// (1.3 to 1.73 dp; docs/USAGE.md lists them).
    #[arg(
        long,
        value_name = "DP",
        value_parser = parse_length,
        allow_negative_numbers = true,
        conflicts_with = "radius_attribute"
    )]
    pub(crate) spacing: Option<f64>,
    /// A radius per particle (adaptive resolution) instead of --radius: particle i gets the
    /// factor s_i from the input's point attribute NAME (a CSV column, PLY property, VTK /
    /// VTU / VTP array or BGEO attribute; one positive value per particle) and the radius
    /// r_i = F·s_i, F from --radius-scale. Read from every frame.
    #[arg(long, value_name = "NAME")]
    pub(crate) radius_attribute: Option<String>,
    /// With --radius-attribute: the resolution F that scales every radius, r_i = F·s_i
    /// (default 1: the attribute's values as they are).
    #[arg(
        long,
        value_name = "F",
        value_parser = parse_scale,
        allow_negative_numbers = true
    )]
    pub(crate) radius_scale: Option<f64>,
    /// Dimension of the scene; 2 on a file with x,y,z drops the constant axis.
    #[arg(long, value_parser = clap::value_parser!(u8).range(2..=3))]
    pub(crate) dim: Option<u8>,
    /// Input format, when the extension does not say it.
    #[arg(long, value_parser = parse_format, value_name = "FMT")]
    pub(crate) format: Option<Format>,
    /// The particle array of a PySPH input (.hdf5, .npz) to label (default: `fluid`, or the
    /// file's only array); other formats hold no named arrays. `detect --wall-array` names
    /// the walls beside it.
    #[arg(long = "array", value_name = "NAME")]
    pub(crate) array: Option<String>,
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

/// The uniform resolution asked for: `--radius R`, `--radius auto` (estimated from the
/// particles), `--smoothing-length H` (r = H) or `--spacing DP` (r = k·DP).
#[derive(Debug, Clone, Copy)]
pub(crate) enum RadiusArg {
    Value(f64),
    Auto,
    SmoothingLength(f64),
    Spacing(f64),
}

impl RadiusArg {
    /// The radius it gives without looking at the particles (`None` for `auto`).
    pub(crate) fn fixed(self) -> Option<f64> {
        match self {
            RadiusArg::Value(v) | RadiusArg::SmoothingLength(v) => Some(v),
            RadiusArg::Spacing(dp) => Some(boundary::RADIUS_PER_SPACING * dp),
            RadiusArg::Auto => None,
        }
    }

    /// The option that gave it, for the summaries (`"radius"`, `"auto"`, …).
    pub(crate) fn source(self) -> &'static str {
        match self {
            RadiusArg::Value(_) => "radius",
            RadiusArg::Auto => "auto",
            RadiusArg::SmoothingLength(_) => "smoothing_length",
            RadiusArg::Spacing(_) => "spacing",
        }
    }
}

/// The resolution of one input: `r`, how it was given, the particle spacing measured in the
/// bulk of the set (`None` for fewer than two distinct positions), and what looks wrong about
/// `r` for that spacing.
#[derive(Debug, Clone)]
pub(crate) struct ResolvedRadius {
    pub(crate) r: f64,
    pub(crate) arg: RadiusArg,
    pub(crate) spacing: Option<f64>,
    pub(crate) concern: Option<boundary::RadiusConcern>,
}

impl ResolvedRadius {
    /// Whether `r` was estimated from the particles (`--radius auto`).
    pub(crate) fn estimated(&self) -> bool {
        matches!(self.arg, RadiusArg::Auto)
    }
}

/// The resolution of a run: one `--radius` for every particle, or a radius per particle from
/// a point attribute (`--radius-attribute`, `--radius-scale`).
#[derive(Debug, Clone)]
pub(crate) enum RadiusMode {
    Uniform(RadiusArg),
    PerParticle { attribute: String, scale: f64 },
}

impl InputArgs {
    /// The resolution the arguments ask for (clap requires exactly one of `--radius` and
    /// `--radius-attribute`).
    pub(crate) fn radius_mode(&self) -> Result<RadiusMode, CliError> {
        let uniform = match (self.radius, self.smoothing_length, self.spacing) {
            (Some(r), None, None) => Some(r),
            (None, Some(h), None) => Some(RadiusArg::SmoothingLength(h)),
            (None, None, Some(dp)) => Some(RadiusArg::Spacing(dp)),
            (None, None, None) => None,
            _ => {
                return Err(CliError::Usage(
                    "give one of --radius, --smoothing-length and --spacing",
                ))
            }
        };
        match (&uniform, &self.radius_attribute) {
            (Some(_), None) if self.radius_scale.is_some() => Err(CliError::Usage(
                "--radius-scale scales the radii of --radius-attribute; with a uniform radius \
                 give --radius, --smoothing-length or --spacing alone",
            )),
            (Some(r), None) => Ok(RadiusMode::Uniform(*r)),
            (None, Some(attribute)) => Ok(RadiusMode::PerParticle {
                attribute: attribute.clone(),
                scale: self.radius_scale.unwrap_or(1.0),
            }),
            _ => Err(CliError::Usage(
                "give either --radius or --radius-attribute (not both)",
            )),
        }
    }
}

/// The per-particle radii a run used: the attribute, the scale F, and the smallest and
/// largest radius r_i = F·s_i.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RadiiUsed {
    pub(crate) attribute: String,
    pub(crate) scale: f64,
    pub(crate) min: f64,
    pub(crate) max: f64,
}

impl RadiiUsed {
    /// The JSON record of the radii (`null` for a uniform run).
    pub(crate) fn json(radii: Option<&RadiiUsed>) -> serde_json::Value {
        match radii {
            None => serde_json::Value::Null,
            Some(r) => serde_json::json!({
                "attribute": r.attribute, "scale": r.scale, "min": r.min, "max": r.max,
            }),
        }
    }

    /// `r_i = F x h in [min, max]` for the human summaries.
    pub(crate) fn describe(&self) -> String {
        format!(
            "r_i = {} x {} in [{}, {}]",
            short(self.scale),
            self.attribute,
            short(self.min),
            short(self.max)
        )
    }
}

/// `x` as `{}` prints it, or in exponent form outside 1e-5..1e16 (no hundred-digit numbers).
pub(crate) fn short(x: f64) -> String {
    if x == 0.0 || (1e-5..1e16).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// The attribute `name` of `frame` for the option `option` (`--radius-attribute`, …), which
/// needs one scalar per particle: `what` it is to the option ("a radius"). Errors name the
/// frame's file: a missing attribute lists the available ones; a vector (`name:0` …
/// `name:k-1`) is not a scalar.
pub(crate) fn point_attribute<'a>(
    frame: &'a Frame,
    name: &str,
    option: &'static str,
    what: &'static str,
) -> Result<&'a Attribute, CliError> {
    if let Some(a) = frame.attribute(name) {
        return Ok(a);
    }
    let input = frame.path.as_path();
    let attributes = &frame.attributes;
    let components = attributes
        .iter()
        .filter(|a| vector_base(&a.name).is_some_and(|b| b.eq_ignore_ascii_case(name)))
        .count();
    if components > 0 {
        return Err(CliError::AttributeVector {
            path: input.to_path_buf(),
            name: name.to_owned(),
            components,
            option,
            what,
        });
    }
    // The available attributes, a vector once with its component count.
    let mut available: Vec<String> = Vec::new();
    let mut k = 0;
    while k < attributes.len() {
        let run = match vector_base(&attributes[k].name) {
            Some(base) => attributes[k..]
                .iter()
                .take_while(|a| vector_base(&a.name) == Some(base))
                .count(),
            None => 0,
        };
        if run > 0 {
            let base = vector_base(&attributes[k].name).unwrap_or_default();
            available.push(format!("{base} (vector of {run})"));
            k += run;
        } else {
            available.push(attributes[k].name.clone());
            k += 1;
        }
    }
    let mut available = if available.is_empty() {
        "none".to_owned()
    } else {
        available.join(", ")
    };
    for skipped in &frame.skipped {
        available.push_str(&format!("; not read: {skipped}"));
    }
    Err(CliError::AttributeMissing {
        path: input.to_path_buf(),
        name: name.to_owned(),
        option,
        available,
    })
}

/// `name` of a vector component `name:k`, else `None`.
fn vector_base(name: &str) -> Option<&str> {
    let (base, k) = name.rsplit_once(':')?;
    (!base.is_empty() && !k.is_empty() && k.bytes().all(|b| b.is_ascii_digit())).then_some(base)
}

/// Gives the particle set of `frame` the radii of its attribute `name`, scaled by `scale`,
/// and returns what was used. Errors name the file, the particle and, in a CSV file, its line.
pub(crate) fn attach_radii(
    frame: Frame,
    name: &str,
    scale: f64,
) -> Result<(Frame, RadiiUsed), CliError> {
    let attribute = point_attribute(&frame, name, "--radius-attribute", "a radius")?;
    let attribute_name = attribute.name.clone();
    let values: Vec<f64> = match &attribute.values {
        AttributeValues::Float(v) => v.clone(),
        AttributeValues::Int(v) => v.iter().map(|&i| i as f64).collect(),
    };
    let Frame {
        path,
        set,
        attributes,
        skipped,
        position_columns,
        lines,
    } = frame;
    let bad_value = |error: CoreError, scaled: bool| -> CliError {
        let (index, problem) = match &error {
            CoreError::InvalidParticleRadius { index, .. }
            | CoreError::ParticleRadiusOutOfRange { index, .. } => {
                let text = error.to_string();
                let problem = text
                    .strip_prefix(&format!("particle {index}: "))
                    .unwrap_or(&text)
                    .to_owned();
                (Some(*index), problem)
            }
            _ => (None, error.to_string()),
        };
        let Some(index) = index else {
            return CliError::Core(error);
        };
        let problem = if scaled {
            format!("{problem} (with --radius-scale {})", short(scale))
        } else {
            problem
        };
        CliError::RadiusValue {
            path: path.clone(),
            attribute: attribute_name.clone(),
            index,
            line: lines.line(index),
            problem,
        }
    };
    let set = set.with_radii(values).map_err(|e| bad_value(e, false))?;
    let resolved = match &set {
        AnyParticleSet::D2(s) => s.resolved_radii(radius(scale)?),
        AnyParticleSet::D3(s) => s.resolved_radii(radius(scale)?),
    }
    .map_err(|e| bad_value(e, true))?
    .unwrap_or_default();
    let (min, max) = resolved
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &r| {
            (lo.min(r), hi.max(r))
        });
    let used = RadiiUsed {
        attribute: attribute_name.clone(),
        scale,
        min: if resolved.is_empty() { scale } else { min },
        max: if resolved.is_empty() { scale } else { max },
    };
    let frame = Frame {
        path,
        set,
        attributes,
        skipped,
        position_columns,
        lines,
    };
    Ok((frame, used))
}

/// `--radius-scale`: a resolution (positive, finite, within the supported range).
fn parse_scale(text: &str) -> Result<f64, String> {
    let value: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("'{text}' is not a number"))?;
    Radius::new(value).map_err(|e| e.to_string())?;
    Ok(value)
}

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

/// The detector `method` with `params`, checked against the resolution options: with
/// `--smoothing-length H` the SPH-sum methods take `h = H` itself, so an `h_over_r` other than
/// 1 (which would make their `h` a multiple of `H`) is refused.
pub(crate) fn detector_for(
    method: &str,
    params: &[(String, String)],
    input: &InputArgs,
) -> Result<Box<dyn BoundaryDetector>, CliError> {
    if let Some(h) = input.smoothing_length {
        for (key, value) in params {
            let one = value.trim().parse::<f64>().is_ok_and(|v| v == 1.0);
            if key == "h_over_r" && !one {
                return Err(CliError::SmoothingLengthRatio {
                    h,
                    value: value.clone(),
                });
            }
        }
    }
    Ok(boundary::detector_with_params(method, params)?)
}

/// `--smoothing-length`, `--spacing`: a positive, finite length.
fn parse_length(text: &str) -> Result<f64, String> {
    let value: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("'{text}' is not a number"))?;
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(format!("'{text}' is not a positive length"))
    }
}

/// The radius to use on `set`: the value given, `r = H`, `r = k·DP`, or the estimate of
/// `auto`; with the spacing measured in the bulk of `set` and what looks wrong about `r`.
pub(crate) fn resolve_radius(
    arg: RadiusArg,
    set: &AnyParticleSet,
    input: &Path,
) -> Result<ResolvedRadius, CliError> {
    let (r, spacing) = match arg {
        RadiusArg::Value(v) | RadiusArg::SmoothingLength(v) => {
            (Radius::new(v)?.get(), boundary::bulk_spacing(set)?)
        }
        RadiusArg::Spacing(dp) => (
            boundary::radius_from_spacing(dp)?.get(),
            boundary::bulk_spacing(set)?,
        ),
        RadiusArg::Auto => {
            let auto = boundary::auto_radius(set)?
                .ok_or_else(|| CliError::AutoRadiusTooFew(input.to_path_buf()))?;
            (auto.radius.get(), Some(auto.spacing))
        }
    };
    Ok(ResolvedRadius {
        r,
        arg,
        spacing,
        concern: spacing.and_then(|dp| boundary::radius_concern(r, dp)),
    })
}

/// What is printed about a resolved radius: for `auto`, the spacing found, the r chosen and
/// how to override it; for an implausible r, why, with the numbers. `None` when there is
/// nothing to say.
pub(crate) fn radius_note(resolved: &ResolvedRadius, input: &Path) -> Option<String> {
    if let (RadiusArg::Auto, Some(dp)) = (resolved.arg, resolved.spacing) {
        return Some(format!(
            "note: {}: --radius auto: particle spacing {dp:.6} (volume per particle in the \
             bulk), r = {} x {dp:.6} = {}; this is an estimate: give the solver's smoothing \
             length with --smoothing-length H (r = h), its spacing with --spacing DP, or \
             --radius R",
            input.display(),
            boundary::RADIUS_PER_SPACING,
            resolved.r
        ));
    }
    resolved
        .concern
        .map(|concern| format!("warning: {}: {concern}", input.display()))
}

pub(crate) fn parse_format(text: &str) -> Result<Format, String> {
    text.parse()
}

/// A format to write (`--output-format`): one that is only read (PySPH's `hdf5`, `npz`) is
/// refused here, before any work.
pub(crate) fn parse_output_format(text: &str) -> Result<Format, String> {
    let format = parse_format(text)?;
    if format.can_write() {
        Ok(format)
    } else {
        Err(format!(
            "{format} files are read, not written; write vtu (ParaView), csv or another format"
        ))
    }
}

pub(crate) fn read_options(args: &InputArgs) -> ReadOptions {
    ReadOptions {
        dim: args.dim.map(usize::from),
        format: args.format,
    }
}

/// The frame at `path`: the particle array `array` of a PySPH file when one is named
/// (`--array`), else the file's particles (a PySPH file's `fluid`, or its only array).
pub(crate) fn read_input_frame(
    path: &Path,
    options: &ReadOptions,
    array: Option<&str>,
    parts: FrameParts,
) -> Result<Frame, boundary_io::IoError> {
    match array {
        Some(array) => boundary_io::read_array_frame(path, array, options, parts),
        None => read_frame(path, options, parts),
    }
}

/// The particle set of `args.input` and the radius to use on it (a warning printed when it was
/// estimated); with `--radius-attribute`, the set carries its radii, the radius is the scale
/// F, and the radii used come third.
pub(crate) fn read_input(
    args: &InputArgs,
) -> Result<(AnyParticleSet, f64, Option<RadiiUsed>), CliError> {
    let options = read_options(args);
    match args.radius_mode()? {
        RadiusMode::Uniform(arg) => {
            let frame = read_input_frame(
                &args.input,
                &options,
                args.array.as_deref(),
                FrameParts::Positions,
            )?;
            refuse_flat(&frame, &options)?;
            let resolved = resolve_radius(arg, &frame.set, &args.input)?;
            if let Some(note) = radius_note(&resolved, &args.input) {
                errln!("{note}");
            }
            Ok((frame.set, resolved.r, None))
        }
        RadiusMode::PerParticle { attribute, scale } => {
            let frame = read_input_frame(
                &args.input,
                &options,
                args.array.as_deref(),
                FrameParts::WithAttributes,
            )?;
            refuse_flat(&frame, &options)?;
            let (frame, used) = attach_radii(frame, &attribute, scale)?;
            Ok((frame.set, scale, Some(used)))
        }
    }
}

/// Refuses a flat 3D set read without `--dim` (see [`CliError::Flat`]): read as 3D, every
/// particle of a flat set is boundary, which is never what a 2D scene stored as x,y,z means.
/// `--dim 3` keeps it 3D.
pub(crate) fn refuse_flat(frame: &Frame, options: &ReadOptions) -> Result<(), CliError> {
    match (options.dim, frame.set.flatness()) {
        (None, Some(flatness)) => Err(CliError::Flat {
            path: frame.path.clone(),
            flatness,
        }),
        _ => Ok(()),
    }
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

/// [`run_timed`] in a domain: walls, solids, periodic axes, phases.
pub(crate) fn run_timed_in(
    pool: &rayon::ThreadPool,
    detector: &dyn BoundaryDetector,
    set: &AnyParticleSet,
    domain: &Domain,
    r: Radius,
) -> Result<(DomainDetection, f64), CliError> {
    pool.install(|| {
        let start = Instant::now();
        let detection = detector.detect_in(set, domain, r)?;
        Ok((detection, start.elapsed().as_secs_f64()))
    })
}

pub(crate) fn radius(value: f64) -> Result<Radius, CliError> {
    Ok(Radius::new(value)?)
}

/// The format of an output file, from its extension: checked before the work, not after it.
pub(crate) fn output_format(path: &Path) -> Result<Format, CliError> {
    match Format::from_path(path) {
        None => Err(CliError::UnknownOutputFormat(path.to_path_buf())),
        Some(format) if !format.can_write() => Err(boundary_io::IoError::ReadOnlyFormat {
            file: path.display().to_string(),
            format,
        }
        .into()),
        Some(format) => Ok(format),
    }
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
