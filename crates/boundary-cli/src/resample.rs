//! `boundary resample`: classify the boundary particles by feature and resample thin ones.

use crate::common::{
    detector_for, method_label, output_format, pool, radius, read_input, run_timed, InputArgs,
    MethodArgs,
};
use crate::error::CliError;
use crate::output::{errln, outln};
use boundary::AnyParticleSet;
use boundary_io::{write_particles, Column, Format};
use clap::Args;
use serde_json::json;
use std::path::PathBuf;

#[derive(Debug, Args)]
pub(crate) struct ResampleArgs {
    #[command(flatten)]
    input: InputArgs,
    #[command(flatten)]
    method: MethodArgs,
    /// Output file (.csv, .xyz, .ply, .vtk, .vtu, .vtp, .bgeo, .bgeo.gz, by extension): every
    /// particle of the resampled set with a `feature` column (-1 interior, 0 droplet,
    /// 1 ligament, 2 sheet, 3 regular boundary) and a `source` column (the input index it
    /// comes from); PLY and VTK also get `red`, `green`, `blue` in the colours of thesis
    /// Fig. 15.
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

pub(crate) fn resample(args: ResampleArgs) -> Result<(), CliError> {
    use boundary_resample::{ResampleConfig, Resampled};
    let detector = detector_for(&args.method.method, &args.method.params, &args.input)?;
    let format = output_format(&args.output)?;
    let config = ResampleConfig {
        k: args.k,
        alpha: args.alpha,
        shift: args.shift,
        ..ResampleConfig::default()
    };
    if args.input.radius_attribute.is_some() {
        return Err(CliError::Usage(
            "resample needs a uniform --radius (it moves particles by distances in units of r); \
             it does not take --radius-attribute",
        ));
    }
    let (set, r_value, _) = read_input(&args.input)?;
    let r = radius(r_value)?;
    let pool = pool(args.input.threads)?;
    let (detection, seconds) = run_timed(&pool, detector.as_ref(), &set, r)?;
    let labels = &detection.labels;
    let (out, feature, source): (AnyParticleSet, Vec<i8>, Vec<usize>) =
        pool.install(|| match &set {
            AnyParticleSet::D2(s) => boundary_resample::resample(s, r, labels, &config)
                .map(|o: Resampled<2>| (o.set.into(), o.feature, o.source)),
            AnyParticleSet::D3(s) => boundary_resample::resample(s, r, labels, &config)
                .map(|o: Resampled<3>| (o.set.into(), o.feature, o.source)),
        })?;
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
    write_particles(&args.output, Some(format), &out, &columns)?;
    if args.input.json {
        let object = json!({
            "method": detector.name(),
            "params": detector.describe().to_string(),
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
        outln!("{object}")?;
    } else {
        errln!(
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
