//! `boundary score`: compare a method with the truth (a labels file, or `exact`).

use crate::common::{
    detector_for, method_label, pool, radius, read_input, run_timed, InputArgs, RadiiUsed,
};
use crate::error::CliError;
use crate::output::outln;
use boundary::{detector_with_params, parse_param, Confusion};
use clap::Args;
use serde_json::json;
use std::path::{Path, PathBuf};

#[derive(Debug, Args)]
pub(crate) struct ScoreArgs {
    #[command(flatten)]
    input: InputArgs,
    #[command(flatten)]
    method: ScoreMethodArgs,
    /// Truth labels: a CSV with a `boundary` column (0/1) in input order. Default: the labels
    /// of the exact method (`--method exact` then scores exact against itself).
    #[arg(long)]
    truth: Option<PathBuf>,
}

/// The method of `score`: required, unlike `detect`'s (whose default is `exact`), because a
/// default would score `exact` against `exact` (M = 1) without a word.
#[derive(Debug, Args)]
pub(crate) struct ScoreMethodArgs {
    /// The method to score (see `boundary methods`), against --truth or the labels of
    /// `exact`. Required.
    #[arg(long, short, value_name = "NAME", required = true)]
    pub(crate) method: String,
    /// Method parameter, repeatable: `--set depth=4`.
    #[arg(long = "set", value_parser = parse_param, value_name = "KEY=VALUE")]
    pub(crate) params: Vec<(String, String)>,
}

pub(crate) fn score(args: ScoreArgs) -> Result<(), CliError> {
    let detector = detector_for(&args.method.method, &args.method.params, &args.input)?;
    let (set, r_value, radii) = read_input(&args.input)?;
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
            let exact = detector_with_params::<&str, &str>("exact", &[])?;
            let (truth, t) = run_timed(&pool, exact.as_ref(), &set, r)?;
            (truth.labels.into_vec(), "exact".to_owned(), Some(t))
        }
    };
    let c = Confusion::from_labels(detection.labels.as_slice(), &truth)?;
    if args.input.json {
        let object = json!({
            "method": detector.name(),
            "params": detector.describe().to_string(),
            "truth": truth_name,
            "input": args.input.input.display().to_string(),
            "n": set.len(),
            "dim": set.dim(),
            "radius": r_value,
            "radii": RadiiUsed::json(radii.as_ref()),
            "tp": c.tp, "tn": c.tn, "fp": c.fp, "fn": c.fn_,
            "recall": c.recall(), "fpr": c.fpr(), "m": c.m(),
            "precision": c.precision(), "f1": c.f1(),
            "seconds": seconds,
            "truth_seconds": truth_seconds,
            "threads": pool.current_num_threads(),
        });
        outln!("{object}")?;
    } else {
        outln!(
            "{} vs {truth_name} on {} ({} particles, {}D, {})",
            method_label(detector.as_ref()),
            args.input.input.display(),
            set.len(),
            set.dim(),
            match &radii {
                Some(radii) => radii.describe(),
                None => format!("r = {r_value}"),
            }
        )?;
        outln!("TP  {}\nTN  {}\nFP  {}\nFN  {}", c.tp, c.tn, c.fp, c.fn_)?;
        outln!(
            "Rec {:.6}\nFPR {:.6}\nM   {:.6}",
            c.recall(),
            c.fpr(),
            c.m()
        )?;
        match truth_seconds {
            Some(t) => outln!("time {seconds:.3} s (exact {t:.3} s)")?,
            None => outln!("time {seconds:.3} s")?,
        }
    }
    Ok(())
}

/// Truth labels from the `boundary` column of a CSV, checked against the particle count.
fn read_truth(path: &Path, n: usize) -> Result<Vec<bool>, CliError> {
    let values = boundary_io::read_csv_column(path, "boundary")?;
    if values.len() != n {
        return Err(CliError::TruthCount {
            path: path.to_path_buf(),
            found: values.len(),
            n,
        });
    }
    values
        .iter()
        .enumerate()
        .map(|(i, &v)| match v {
            0.0 => Ok(false),
            1.0 => Ok(true),
            _ => Err(CliError::TruthValue {
                path: path.to_path_buf(),
                index: i,
                value: v,
            }),
        })
        .collect()
}
