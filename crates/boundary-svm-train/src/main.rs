//! `train-svm` (run by `cargo xtask train-svm`): trains the shipped models of `boundary-svm`
//! and scores them on scenes never seen in training.
//!
//! Thesis Sec. 3.2.3, adapted:
//! - **Frames.** The thesis samples 30% of a simulation's time steps for training. Our data
//!   are a few frames of several scenes, so the split is by scene, fixed here: the training
//!   frames ([`TRAIN_2D`], [`TRAIN_3D`]; each at one or more radii, so that the model sees
//!   several `r`/spacing ratios) and the held-out ones ([`HELD_OUT_2D`], [`HELD_OUT_3D`]:
//!   the splash frames and the author's vortex among them), which are only scored.
//! - **Particles.** From every training frame, a class-balanced sample (as many boundary as
//!   interior particles where the frame has them) of `TRAIN_PER_DIM / frames` particles;
//!   the rest of those frames forms the validation pool, from which `VALIDATION_PER_DIM`
//!   particles are drawn uniformly (the natural class mix).
//! - **Model.** C-SVC with an RBF kernel (linfa-svm's SMO), features standardised by the
//!   training sample's mean and standard deviation; `C` and `γ` from a grid, chosen by the
//!   measure M on the validation set, preferring fewer support vectors (faster prediction)
//!   among the choices within `M_SLACK` of the best.
//!
//! Everything is seeded (`SEED`): a rerun writes the same model files.
//!
//! Usage: `train-svm [--dim 2|3] [--out DIR] [--report FILE]`.

use boundary_core::{AnyParticleSet, BoundaryDetector, Confusion, Radius};
use boundary_exact::ExactDetector;
use boundary_scenes::{data_dir, fixtures_dir, Manifest};
use boundary_svm::{
    compute_features, Features, SvmDetector, SvmModel, FEATURE_VERSION, MODEL_FORMAT, N_FEATURES,
};
use linfa::prelude::*;
use linfa_svm::Svm;
use ndarray::{Array1, Array2};
use rand::rngs::StdRng;
use rand::seq::SliceRandom;
use rand::SeedableRng;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Training frames: a manifest scene and the multiples of its radius it is used at.
const TRAIN_2D: &[(&str, &[f64])] = &[
    ("vortex2d_t0", &[1.0, 2.0, 3.0]),
    ("vortex2d_t1", &[1.0, 2.0, 3.0]),
    ("vortex2d_t2", &[1.0, 2.0, 3.0]),
    ("vortex2d_t4", &[1.0, 2.0, 3.0]),
    ("vortex2d_t8", &[1.0, 2.0, 3.0]),
    ("zalesak2d_rot0", &[1.0, 2.0, 3.0]),
];
const TRAIN_3D: &[(&str, &[f64])] = &[
    ("enright3d_t0", &[1.0, 2.0]),
    ("enright3d_t0.75", &[1.0, 2.0]),
    ("enright3d_t1.5", &[1.0, 2.0]),
    ("ball_bubble3d", &[1.0]),
    ("sheet_ligament_droplets3d", &[1.0]),
    ("bunny14_r0.05", &[1.0]),
    ("bunny14_r0.1", &[1.0]),
    ("dambreak9_r0.05", &[1.0]),
    ("dambreak9_r0.1", &[1.0]),
];
/// Held-out scenes, at their manifest radius: never seen in training or validation.
const HELD_OUT_2D: &[&str] = &[
    "zalesak2d_rot45",
    "sandim_vortex_001",
    "sandim_vortex_050",
    "sandim_vortex_100",
    "dualsphysics_dambreak2d",
];
const HELD_OUT_3D: &[&str] = &[
    "dambreak23_r0.05",
    "dambreak23_r0.1",
    "double_dambreak26_r0.05",
    "double_dambreak26_r0.1",
    "fluid50_r0.05",
    "fluid50_r0.1",
    "pysph_case5",
    "dualsphysics_dambreak3d",
    "bunny_small_volume",
];

const SEED: u64 = 2020;
const TRAIN_PER_DIM: usize = 3000;
const VALIDATION_PER_DIM: usize = 5000;
const C_GRID: [f64; 3] = [1.0, 10.0, 100.0];
const GAMMA_GRID: [f64; 3] = [0.05, 0.2, 1.0];
const M_SLACK: f64 = 0.005;

/// One scene at one radius: features and exact labels of every particle.
struct Frame {
    name: String,
    set: AnyParticleSet,
    r: Radius,
    features: Vec<Features>,
    truth: Vec<bool>,
}

fn load_frame(manifest: &Manifest, name: &str, factor: f64) -> Result<Frame, String> {
    let entry = manifest
        .scene
        .iter()
        .find(|s| s.name == name)
        .ok_or_else(|| format!("scene '{name}' is not in fixtures/scenes.toml"))?;
    let set = entry.load(&fixtures_dir(), &data_dir())?;
    let r = Radius::new(entry.radius * factor).map_err(|e| e.to_string())?;
    let features = match &set {
        AnyParticleSet::D2(s) => compute_features(s, s.len(), r),
        AnyParticleSet::D3(s) => compute_features(s, s.len(), r),
    }
    .map_err(|e| format!("{name}: {e}"))?;
    let truth = ExactDetector
        .detect(&set, r)
        .map_err(|e| format!("{name}: {e}"))?
        .labels
        .into_vec();
    let name = if factor == 1.0 {
        name.to_owned()
    } else {
        format!("{name}@{factor}r")
    };
    Ok(Frame {
        name,
        set,
        r,
        features,
        truth,
    })
}

struct Sample {
    x: Vec<Features>,
    y: Vec<bool>,
}

/// Class-balanced training sample and uniform validation sample (see the module docs).
fn split(frames: &[Frame], rng: &mut StdRng) -> (Sample, Sample) {
    let per_frame = TRAIN_PER_DIM / frames.len();
    let mut train = Sample {
        x: vec![],
        y: vec![],
    };
    let mut pool = vec![];
    for f in frames {
        let mut boundary: Vec<usize> = (0..f.truth.len()).filter(|&i| f.truth[i]).collect();
        let mut interior: Vec<usize> = (0..f.truth.len()).filter(|&i| !f.truth[i]).collect();
        boundary.shuffle(rng);
        interior.shuffle(rng);
        // Half each, topped up from the other class where one is short.
        let nb = (per_frame / 2).min(boundary.len());
        let ni = (per_frame - nb).min(interior.len());
        let nb = (per_frame - ni).min(boundary.len());
        for &i in boundary[..nb].iter().chain(&interior[..ni]) {
            train.x.push(f.features[i]);
            train.y.push(f.truth[i]);
        }
        for &i in boundary[nb..].iter().chain(&interior[ni..]) {
            pool.push((f.features[i], f.truth[i]));
        }
    }
    pool.shuffle(rng);
    pool.truncate(VALIDATION_PER_DIM);
    let validation = Sample {
        x: pool.iter().map(|p| p.0).collect(),
        y: pool.iter().map(|p| p.1).collect(),
    };
    (train, validation)
}

fn standardisation(x: &[Features]) -> (Features, Features) {
    let n = x.len().max(1) as f64;
    let mean: Features = std::array::from_fn(|k| x.iter().map(|f| f[k]).sum::<f64>() / n);
    let scale: Features = std::array::from_fn(|k| {
        let var = x.iter().map(|f| (f[k] - mean[k]).powi(2)).sum::<f64>() / n;
        // A constant feature carries no information; a unit scale keeps it harmless.
        if var > 0.0 {
            var.sqrt()
        } else {
            1.0
        }
    });
    (mean, scale)
}

/// Trains one C-SVC and exports it; checks that the export decides the validation set as
/// linfa does.
fn train(
    dim: usize,
    train: &Sample,
    validation: &Sample,
    mean: &Features,
    scale: &Features,
    c: f64,
    gamma: f64,
) -> Result<SvmModel, String> {
    let z: Vec<Features> = train
        .x
        .iter()
        .map(|f| std::array::from_fn(|k| (f[k] - mean[k]) / scale[k]))
        .collect();
    let records = Array2::from_shape_fn((z.len(), N_FEATURES), |(i, k)| z[i][k]);
    let targets = Array1::from_vec(train.y.clone());
    let dataset = Dataset::new(records, targets);
    let svm = Svm::<f64, bool>::params()
        .pos_neg_weights(c, c)
        .gaussian_kernel(1.0 / gamma)
        .fit(&dataset)
        .map_err(|e| format!("linfa-svm: {e}"))?;
    // linfa keeps the rows with |α| > 100 ε as support vectors, in training order, and
    // decides by Σ α_k K(s_k, x) − ρ >= 0 with α already signed (true = +).
    let keep = |a: &f64| a.abs() > 100.0 * f64::EPSILON;
    let mut support_vectors = vec![];
    let mut coefficients = vec![];
    for (i, a) in svm.alpha.iter().enumerate() {
        if keep(a) {
            support_vectors.push(z[i]);
            coefficients.push(*a);
        }
    }
    let model = SvmModel {
        format: MODEL_FORMAT.to_owned(),
        feature_version: FEATURE_VERSION,
        dim,
        gamma,
        c,
        bias: -svm.rho,
        feature_mean: *mean,
        feature_scale: *scale,
        support_vectors,
        coefficients,
        provenance: String::new(),
    };
    model.validate().map_err(|e| e.0)?;
    let vz = Array2::from_shape_fn((validation.x.len(), N_FEATURES), |(i, k)| {
        (validation.x[i][k] - mean[k]) / scale[k]
    });
    let linfa_labels = svm.predict(&vz);
    let mut worst: f64 = 0.0;
    for (i, f) in validation.x.iter().enumerate() {
        let ours = model.decision(f);
        let theirs = svm.weighted_sum(&vz.row(i)) - svm.rho;
        worst = worst.max((ours - theirs).abs());
        if (ours >= 0.0) != linfa_labels[i] && ours.abs() > 1e-9 {
            return Err(format!(
                "exported model disagrees with linfa on validation row {i}: {ours} vs {theirs}"
            ));
        }
    }
    if worst > 1e-9 {
        return Err(format!(
            "exported decision values differ from linfa by {worst:e}"
        ));
    }
    Ok(model)
}

fn confusion(predicted: &[bool], truth: &[bool]) -> Confusion {
    Confusion::from_labels(predicted, truth).unwrap_or_default()
}

fn row(name: &str, n: usize, c: &Confusion) -> String {
    format!(
        "| {name} | {n} | {} | {} | {} | {} | {:.4} | {:.4} | {:.4} |",
        c.tp,
        c.fn_,
        c.fp,
        c.tn,
        c.recall(),
        c.fpr(),
        c.m()
    )
}

fn run_dim(dim: usize, out: &Path, report: &mut String) -> Result<(), String> {
    let manifest_path = fixtures_dir().join("scenes.toml");
    let manifest = Manifest::load(&manifest_path).map_err(|e| e.to_string())?;
    let (train_list, held_out) = if dim == 2 {
        (TRAIN_2D, HELD_OUT_2D)
    } else {
        (TRAIN_3D, HELD_OUT_3D)
    };
    let t = Instant::now();
    let mut frames = vec![];
    for (name, factors) in train_list {
        for &factor in *factors {
            frames.push(load_frame(&manifest, name, factor)?);
        }
    }
    eprintln!(
        "train-svm {dim}D: {} training frames with features and exact labels in {:.1} s",
        frames.len(),
        t.elapsed().as_secs_f64()
    );
    let mut rng = StdRng::seed_from_u64(SEED + dim as u64);
    let (train_set, validation) = split(&frames, &mut rng);
    let (mean, scale) = standardisation(&train_set.x);
    let n_boundary = train_set.y.iter().filter(|&&b| b).count();
    let _ = writeln!(
        report,
        "\n## {dim}D\n\nTraining frames: {}.\n\nTraining sample: {} particles ({} boundary, {} \
         interior); validation: {} particles drawn uniformly from the rest of those frames.\n\n\
         | C | γ | support vectors | validation Rec | FPR | M | training time (s) |\n|---|---|---|---|---|---|---|",
        frames.iter().map(|f| f.name.as_str()).collect::<Vec<_>>().join(", "),
        train_set.y.len(),
        n_boundary,
        train_set.y.len() - n_boundary,
        validation.y.len()
    );
    let mut candidates = vec![];
    for &c in &C_GRID {
        for &gamma in &GAMMA_GRID {
            let t = Instant::now();
            let model = train(dim, &train_set, &validation, &mean, &scale, c, gamma)?;
            let secs = t.elapsed().as_secs_f64();
            let predicted: Vec<bool> = validation
                .x
                .iter()
                .map(|f| model.decision(f) >= 0.0)
                .collect();
            let conf = confusion(&predicted, &validation.y);
            eprintln!(
                "train-svm {dim}D: C={c} gamma={gamma}: {} support vectors, validation M={:.4} \
                 ({secs:.1} s)",
                model.support_vectors.len(),
                conf.m()
            );
            let _ = writeln!(
                report,
                "| {c} | {gamma} | {} | {:.4} | {:.4} | {:.4} | {secs:.1} |",
                model.support_vectors.len(),
                conf.recall(),
                conf.fpr(),
                conf.m()
            );
            candidates.push((conf.m(), model));
        }
    }
    let best_m = candidates.iter().map(|c| c.0).fold(f64::MIN, f64::max);
    let (m, mut model) = candidates
        .into_iter()
        .filter(|c| c.0 >= best_m - M_SLACK)
        .min_by_key(|c| c.1.support_vectors.len())
        .ok_or("no candidate model")?;
    model.provenance = format!(
        "cargo xtask train-svm (linfa-svm 0.8 C-SVC, RBF); seed {SEED}; {} class-balanced \
         training particles from {}; C and gamma by validation M on {} particles (M = {m:.4})",
        train_set.y.len(),
        frames
            .iter()
            .map(|f| f.name.as_str())
            .collect::<Vec<_>>()
            .join(", "),
        validation.y.len()
    );
    let _ = writeln!(
        report,
        "\nChosen: C = {}, γ = {}, {} support vectors (validation M = {m:.4}).\n",
        model.c,
        model.gamma,
        model.support_vectors.len()
    );
    let path = out.join(format!("svm{dim}d.json"));
    std::fs::write(&path, model.to_json() + "\n")
        .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    eprintln!("train-svm {dim}D: wrote {}", path.display());

    // Held-out scenes.
    let svm = SvmDetector::with_model(model, "trained").map_err(|e| e.0)?;
    let mut cascade = svm.clone();
    cascade
        .set_param("refine", "exact")
        .map_err(|e| e.to_string())?;
    let mut table = String::from(
        "| scene | n | TP | FN | FP | TN | Rec | FPR | M |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    let mut cascade_table = table.clone();
    let mut times = String::from(
        "| scene | n | svm (s) | exact (s) | svm+exact cascade (s) |\n|---|---|---|---|---|\n",
    );
    let mut total = Confusion::default();
    let mut total_cascade = Confusion::default();
    for name in held_out {
        let frame = load_frame(&manifest, name, 1.0)?;
        let n = frame.truth.len();
        let timed = |d: &dyn BoundaryDetector| -> Result<(Vec<bool>, f64), String> {
            let t = Instant::now();
            let labels = d
                .detect(&frame.set, frame.r)
                .map_err(|e| e.to_string())?
                .labels
                .into_vec();
            Ok((labels, t.elapsed().as_secs_f64()))
        };
        let (svm_labels, t_svm) = timed(&svm)?;
        let (_, t_exact) = timed(&ExactDetector)?;
        let (cascade_labels, t_cascade) = timed(&cascade)?;
        let c = confusion(&svm_labels, &frame.truth);
        let cc = confusion(&cascade_labels, &frame.truth);
        eprintln!(
            "train-svm {dim}D: held out {}: Rec {:.4} FPR {:.4} M {:.4}; cascade M {:.4}",
            frame.name,
            c.recall(),
            c.fpr(),
            c.m(),
            cc.m()
        );
        let _ = writeln!(table, "{}", row(&frame.name, n, &c));
        let _ = writeln!(cascade_table, "{}", row(&frame.name, n, &cc));
        let _ = writeln!(
            times,
            "| {} | {n} | {t_svm:.4} | {t_exact:.4} | {t_cascade:.4} |",
            frame.name
        );
        for (sum, add) in [(&mut total, &c), (&mut total_cascade, &cc)] {
            sum.tp += add.tp;
            sum.fn_ += add.fn_;
            sum.fp += add.fp;
            sum.tn += add.tn;
        }
    }
    let _ = writeln!(
        table,
        "{}",
        row("**all held out**", total.total() as usize, &total)
    );
    let _ = writeln!(
        cascade_table,
        "{}",
        row(
            "**all held out**",
            total_cascade.total() as usize,
            &total_cascade
        )
    );
    let _ = writeln!(
        report,
        "### Held-out scenes, svm\n\n{table}\n### Held-out scenes, cascade svm + exact \
         (`refine=exact`)\n\n{cascade_table}\n### Wall time (all threads, release)\n\n{times}"
    );
    Ok(())
}

fn main() {
    let mut dims = vec![2, 3];
    let root = fixtures_dir()
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default();
    let mut out = root.join("crates/boundary-svm/models");
    let mut report_path = root.join("target/svm/training.md");
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        let value = args.next();
        match (arg.as_str(), value) {
            ("--dim", Some(v)) if v == "2" || v == "3" => dims = vec![v.parse().unwrap_or(2)],
            ("--out", Some(v)) => out = PathBuf::from(v),
            ("--report", Some(v)) => report_path = PathBuf::from(v),
            _ => {
                eprintln!("usage: train-svm [--dim 2|3] [--out DIR] [--report FILE]");
                std::process::exit(2);
            }
        }
    }
    let mut report = String::from("# SVM training and held-out scores (cargo xtask train-svm)\n");
    for dim in dims {
        if let Err(e) = run_dim(dim, &out, &mut report) {
            eprintln!("train-svm: error: {e}");
            std::process::exit(1);
        }
    }
    if let Some(dir) = report_path.parent() {
        let _ = std::fs::create_dir_all(dir);
    }
    match std::fs::write(&report_path, &report) {
        Ok(()) => eprintln!("train-svm: wrote {}", report_path.display()),
        Err(e) => eprintln!("train-svm: cannot write {}: {e}", report_path.display()),
    }
    println!("{report}");
}
