//! The comparison sweep: every detector over every scene, scored against `exact`, timed on one
//! thread and on all threads. `cargo xtask sweep` runs the `boundary-sweep` binary, which
//! writes `results.csv`, `scale.csv`, `report.md` and the plots (SVG and PNG) into its output
//! folder, and the summary page [`benchmarks`]; [`scale`] is the tier of large generated sets.
//!
//! The library half (this file) runs the sweep and returns rows; [`report`] and [`plots`]
//! turn rows into files. Scenes come from `fixtures/scenes.toml` (our generated scenes and
//! references into `../shared/data`).

pub mod auto_radius;
pub mod benchmarks;
pub mod failures;
pub mod plots;
pub mod published;
pub mod report;
pub mod scale;
pub mod sequence;

use boundary::implement::NeighbourGrid;
use boundary::{
    AnyParticleSet, BoundaryDetector, Confusion, DetectError, Domain, Labels, ParticleSet, Radius,
};
use boundary_scenes::SceneDomain;
use std::path::PathBuf;
use std::time::Instant;

/// A scene to sweep: a particle file and its resolution.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneSpec {
    /// Short unique name.
    pub name: String,
    /// Dimension declared by the manifest (2 or 3).
    pub dim: usize,
    /// The particle file.
    pub path: PathBuf,
    /// The resolution r.
    pub radius: f64,
    /// The independently known boundary count, when there is one (shared data).
    pub expected_boundary: Option<usize>,
    /// `fixture` or `shared`.
    pub origin: String,
    /// What the scene is: its generator and parameters, or its provenance (for the report).
    pub about: String,
    /// The point attribute of the file holding the per-particle radius factors, if any.
    pub radius_attribute: Option<String>,
    /// Walls, solids, periodic axes and phases (bare for most scenes): every method, `exact`
    /// included, classifies the scene in this domain.
    pub domain: SceneDomain,
}

/// A detector with parameter values.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MethodConfig {
    /// Registry name.
    pub method: String,
    /// `--set` style overrides (empty: the method's defaults).
    pub params: Vec<(String, String)>,
}

impl MethodConfig {
    /// The method at its default parameters.
    pub fn default_for(method: &str) -> Self {
        MethodConfig {
            method: method.to_owned(),
            params: Vec::new(),
        }
    }

    /// The method with one parameter set.
    pub fn with(method: &str, key: &str, value: &str) -> Self {
        MethodConfig {
            method: method.to_owned(),
            params: vec![(key.to_owned(), value.to_owned())],
        }
    }
}

/// Parameter grids swept besides the defaults: depth 1..8 for the interval methods (the JCP
/// paper's Fig. 7 / thesis Fig. 27), a gamma grid, no cavity viewpoints, two viewpoint
/// grids and the 2D protrusion tolerance everywhere for the visibility method, thresholds
/// around the default 0.375 for the colour field of `muller` (how sensitive M is to it), the
/// published thresholds of `divr` (DualSPHysics by default, SPHinXsys with and without its
/// second layer, Chrono::FSI), three `asymmetry` thresholds, a `mu` grid for `randles`
/// ([`RANDLES_MU_GRID`]), Bubbles' 2D `delta` and the fast variant for `lnm`, and the `svm`
/// cascades `refine=exact|ge`.
pub fn default_configs(methods: &[&str], quick: bool) -> Vec<MethodConfig> {
    let mut out = Vec::new();
    for &m in methods {
        out.push(MethodConfig::default_for(m));
        if quick {
            continue;
        }
        match m {
            "ia" | "ge" => {
                for depth in 1..=8 {
                    out.push(MethodConfig::with(m, "depth", &depth.to_string()));
                }
            }
            "hpr" => {
                for gamma in ["1.1", "1.2", "1.5", "1.75", "2.0"] {
                    out.push(MethodConfig::with(m, "gamma", gamma));
                }
                // The effect of the cavity viewpoints (thesis Eq. 2.3, Fig. 5).
                out.push(MethodConfig::with(m, "cavity", "off"));
                // A second viewpoint grid shifted by r (boundary when seen under both).
                out.push(MethodConfig::with(m, "grids", "2"));
                // 3D with the 2D default's protrusion tolerance (docs/METHODS.md, `hpr`).
                out.push(MethodConfig::with(m, "protrusion", "1e-3"));
            }
            "muller" => {
                for threshold in ["0.1", "0.2", "0.3", "0.5", "0.6"] {
                    out.push(MethodConfig::with(m, "threshold", threshold));
                }
            }
            // Every code's published threshold (the default is DualSPHysics'), and SPHinXsys'
            // with its second layer: what each code's default costs against exact.
            "divr" => {
                for threshold in ["sphinxsys", "chrono"] {
                    out.push(MethodConfig::with(m, "threshold", threshold));
                }
                out.push(MethodConfig {
                    method: m.to_owned(),
                    params: vec![
                        ("threshold".to_owned(), "sphinxsys".to_owned()),
                        ("layers".to_owned(), "1".to_owned()),
                    ],
                });
            }
            // The asymmetry threshold's best value grows with r/dx (boundary-asymmetry docs).
            "asymmetry" => {
                for threshold in ["0.075", "0.2", "0.3"] {
                    out.push(MethodConfig::with(m, "threshold", threshold));
                }
            }
            // One mu for both dimensions per row: the report's Randles–Doring section compares
            // how M depends on mu in 2D and in 3D (Bubbles' 0.45 and Marrone's 0.75 included).
            "randles" => {
                for mu in RANDLES_MU_GRID {
                    out.push(MethodConfig {
                        method: m.to_owned(),
                        params: vec![
                            ("mu_2d".to_owned(), mu.to_owned()),
                            ("mu_3d".to_owned(), mu.to_owned()),
                        ],
                    });
                }
            }
            // Bubbles' 2D rule (delta one below the count of a full cell), and the variant
            // that keeps every L2 particle without re-checking it.
            "lnm" => {
                out.push(MethodConfig::with(m, "delta", "3"));
                out.push(MethodConfig::with(m, "variant", "fast"));
            }
            // The cascades of thesis Sec. 3.4: the SVM's boundary particles re-tested.
            "svm" => {
                for refine in ["exact", "ge"] {
                    out.push(MethodConfig::with(m, "refine", refine));
                }
            }
            _ => {}
        }
    }
    out
}

/// The `mu` values swept for `randles` (both dimensions), besides its defaults.
pub const RANDLES_MU_GRID: [&str; 6] = ["0.45", "0.5", "0.55", "0.65", "0.7", "0.75"];

/// One (scene, method, parameters) result.
#[derive(Debug, Clone)]
pub struct Row {
    /// Scene name.
    pub scene: String,
    /// Dimension.
    pub dim: usize,
    /// Number of particles.
    pub n: usize,
    /// Resolution.
    pub radius: f64,
    /// Method name.
    pub method: String,
    /// The detector's parameters as `key=value, …` (all of them, defaults included).
    pub params: String,
    /// Whether this row ran the method's default parameters.
    pub is_default: bool,
    /// Whether the method promises no false negatives (`BoundaryDetector::certified`).
    pub certified: bool,
    /// Where the misses lie (default rows of methods without a certificate; see [`failures`]).
    pub misses: Option<failures::MissProfile>,
    /// Confusion against `exact` (`None` if the detection failed).
    pub confusion: Option<Confusion>,
    /// Seconds on one thread (`None` when not measured).
    pub seconds_1: Option<f64>,
    /// Seconds on all threads.
    pub seconds_all: f64,
    /// Number of threads of the all-thread run.
    pub threads: usize,
    /// The error, when the detection failed.
    pub error: Option<String>,
    /// The method does not apply to the scene (per-particle radii, or a solid region, it
    /// cannot honour): not a failure; `error` says why in a few words.
    pub unsupported: bool,
    /// With phases: the number of particles the method puts on an interface between phases.
    pub interface: Option<usize>,
    /// With phases: the interface labels against those of `exact`.
    pub interface_confusion: Option<Confusion>,
}

/// The exact labels of a scene with a domain, for its picture: in 2D every particle, in 3D the
/// slab of half-width `r/2` across the middle of the fluid along y, drawn in the x–z plane.
#[derive(Debug, Clone)]
pub struct DomainPicture {
    /// Scene name.
    pub scene: String,
    /// Dimension of the scene.
    pub dim: usize,
    /// The drawn plane's axes (x and y in 2D, x and z in 3D).
    pub axes: [usize; 2],
    /// The fluid particles drawn, in the drawn plane.
    pub points: Vec<[f64; 2]>,
    /// Exact free-surface label of each drawn particle.
    pub boundary: Vec<bool>,
    /// Exact interface label of each drawn particle (empty without phases).
    pub interface: Vec<bool>,
    /// Phase of each drawn particle (empty without phases).
    pub phases: Vec<u32>,
    /// The wall particles drawn, in the drawn plane.
    pub walls: Vec<[f64; 2]>,
    /// Solid half-spaces bounding the drawn plane: (0 or 1 for the plane's axis, the bound,
    /// whether the solid lies below it).
    pub solids: Vec<(usize, f64, bool)>,
    /// Periodic axes in the drawn plane: (0 or 1, min, max).
    pub periodic: Vec<(usize, f64, f64)>,
    /// The domain in words.
    pub about: String,
}

/// Labels of one 2D scene for the pictures: positions, exact labels, each default method's.
#[derive(Debug, Clone)]
pub struct Picture {
    /// Scene name.
    pub scene: String,
    /// 2D positions.
    pub points: Vec<[f64; 2]>,
    /// Exact labels.
    pub truth: Labels,
    /// (method, labels) at default parameters.
    pub methods: Vec<(String, Labels)>,
    /// Feature code of each particle from the exact labels (thesis Sec. 2.6, default
    /// parameters): -1 interior, 0 droplet, 1 ligament, 3 regular; empty if it failed.
    pub features: Vec<i8>,
}

/// What a sweep produced.
#[derive(Debug, Default)]
pub struct Outcome {
    /// One row per (scene, configuration).
    pub rows: Vec<Row>,
    /// Scenes skipped, with the reason (missing data directory, unreadable file).
    pub skipped: Vec<(String, String)>,
    /// Label pictures of the 2D scenes.
    pub pictures: Vec<Picture>,
    /// Scenes whose exact boundary count differs from the expected one.
    pub count_mismatches: Vec<(String, usize, usize)>,
    /// (scene, what it is), in run order.
    pub about: Vec<(String, String)>,
    /// Per method without a certificate, its worst scene (lowest M at default parameters, the
    /// first on ties) with labels for the picture; none for a method without any miss.
    pub failure_pictures: Vec<failures::FailurePicture>,
    /// The scale tier, when it ran ([`scale`]).
    pub scale: Option<scale::ScaleOutcome>,
    /// (scene, mean number of other particles within `2r` of a particle), in run order: the
    /// density of the neighbourhoods every method reads, beside its timings.
    pub neighbours: Vec<(String, f64)>,
    /// (scene, its domain in words) for the scenes with a domain, in run order.
    pub domains: Vec<(String, String)>,
    /// The exact labels of each scene with a domain, for its picture.
    pub domain_pictures: Vec<DomainPicture>,
    /// How well `auto` chooses r on each physical scene ([`auto_radius`]).
    pub auto: Vec<auto_radius::AutoRow>,
}

/// The mean number of other particles within `2r` of a particle of `set` (the scene's uniform
/// `r`; coincident duplicates count). `None` for an empty set or where the grid fails.
pub fn mean_neighbours(set: &AnyParticleSet, r: f64) -> Option<f64> {
    fn mean<const D: usize>(set: &ParticleSet<D>, r: f64) -> Option<f64> {
        if set.is_empty() {
            return None;
        }
        let grid = NeighbourGrid::new(set, 2.0 * r).ok()?;
        let reach2 = 4.0 * r * r;
        let mut total = 0usize;
        for (i, p) in set.positions().iter().enumerate() {
            grid.for_each_within(p, 2.0 * r, |j, d2| {
                if j != i && d2 <= reach2 {
                    total += 1;
                }
            });
        }
        Some(total as f64 / set.len() as f64)
    }
    match set {
        AnyParticleSet::D2(s) => mean(s, r),
        AnyParticleSet::D3(s) => mean(s, r),
    }
}

/// Options of a sweep run.
#[derive(Debug, Clone)]
pub struct Options {
    /// Scenes to run.
    pub scenes: Vec<SceneSpec>,
    /// Configurations to run on every scene (`exact` is always run first as the reference).
    pub configs: Vec<MethodConfig>,
    /// Also time every configuration on one thread.
    pub single_thread: bool,
    /// Threads of the all-thread run (0: rayon's default).
    pub threads: usize,
}

/// A progress event: `done` of `total` runs finished, the one just finished described.
#[derive(Debug, Clone)]
pub struct Progress<'a> {
    /// Runs finished.
    pub done: usize,
    /// Runs planned.
    pub total: usize,
    /// What just finished.
    pub what: &'a str,
}

fn pool(threads: usize) -> Result<rayon::ThreadPool, String> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| e.to_string())
}

/// Free-surface labels and, with phases, interface labels.
type Classified = (Labels, Option<Labels>);

/// One detection, timed: the bare cloud through `detect`, a domain through `detect_in`.
fn timed(
    detector: &dyn BoundaryDetector,
    set: &AnyParticleSet,
    domain: Option<&Domain>,
    r: Radius,
    pool: &rayon::ThreadPool,
) -> (Result<Classified, DetectError>, f64) {
    let start = Instant::now();
    let result = pool.install(|| match domain {
        None => detector.detect(set, r).map(|d| (d.labels, None)),
        Some(domain) => detector
            .detect_in(set, domain, r)
            .map(|d| (d.detection.labels, d.interface)),
    });
    let seconds = start.elapsed().as_secs_f64();
    (result, seconds)
}

/// For a method that does not apply to the scene, why, in a few words (the report's `n/a`);
/// `None` for a real failure.
fn unsupported_reason(e: &DetectError) -> Option<String> {
    match e {
        DetectError::PerParticleRadii { .. } => Some("no per-particle radii".into()),
        DetectError::UnsupportedOption { option, .. } => Some(format!("cannot honour {option}")),
        _ => None,
    }
}

/// Runs the sweep. Failures of one scene or one detector are recorded, never fatal.
pub fn run(opts: &Options, progress: &mut dyn FnMut(Progress<'_>)) -> Result<Outcome, String> {
    let all = pool(opts.threads)?;
    let one = pool(1)?;
    let threads = all.current_num_threads();
    let mut out = Outcome::default();
    let total = opts.scenes.len() * (opts.configs.len() + 1);
    let mut done = 0;
    for scene in &opts.scenes {
        let read = boundary_scenes::load_scene(
            &scene.path,
            scene.dim,
            scene.radius_attribute.as_deref(),
            &scene.domain,
        );
        let (set, domain) = match read {
            Ok((set, domain)) if set.dim() == scene.dim => (set, domain),
            Ok((set, _)) => {
                out.skipped.push((
                    scene.name.clone(),
                    format!("file is {}D, manifest says {}D", set.dim(), scene.dim),
                ));
                done += opts.configs.len() + 1;
                continue;
            }
            Err(e) => {
                out.skipped.push((scene.name.clone(), e));
                done += opts.configs.len() + 1;
                continue;
            }
        };
        let domain = (!domain.is_bare()).then_some(domain);
        let domain = domain.as_ref();
        let r = Radius::new(scene.radius).map_err(|e| format!("{}: {e}", scene.name))?;
        let exact = boundary::detector_by_name("exact").map_err(|e| e.to_string())?;
        let (truth, t_all) = timed(exact.as_ref(), &set, domain, r, &all);
        let (truth, truth_interface) = match truth {
            Ok(t) => t,
            // Without the reference a scene with a domain has nothing to score against.
            Err(e) if domain.is_some() => {
                out.skipped
                    .push((scene.name.clone(), format!("exact cannot classify it: {e}")));
                done += opts.configs.len() + 1;
                continue;
            }
            Err(e) => return Err(format!("{}: exact failed: {e}", scene.name)),
        };
        let t_one = opts
            .single_thread
            .then(|| timed(exact.as_ref(), &set, domain, r, &one).1);
        if let Some(row) = all.install(|| auto_radius::auto_row(scene, &set, domain, &truth))? {
            out.auto.push(row);
        }
        if let Some(expected) = scene.expected_boundary {
            if truth.boundary_count() != expected {
                out.count_mismatches
                    .push((scene.name.clone(), truth.boundary_count(), expected));
            }
        }
        out.rows.push(Row {
            scene: scene.name.clone(),
            dim: scene.dim,
            n: set.len(),
            radius: scene.radius,
            method: "exact".into(),
            params: String::new(),
            is_default: true,
            certified: exact.certified(),
            misses: None,
            confusion: Confusion::from_labels(truth.as_slice(), truth.as_slice()).ok(),
            seconds_1: t_one,
            seconds_all: t_all,
            threads,
            error: None,
            unsupported: false,
            interface: truth_interface.as_ref().map(Labels::boundary_count),
            interface_confusion: truth_interface
                .as_ref()
                .and_then(|t| Confusion::from_labels(t.as_slice(), t.as_slice()).ok()),
        });
        done += 1;
        progress(Progress {
            done,
            total,
            what: &format!("{} exact", scene.name),
        });
        out.about.push((scene.name.clone(), scene.about.clone()));
        if let Some(k) = mean_neighbours(&set, scene.radius) {
            out.neighbours.push((scene.name.clone(), k));
        }
        if let Some(domain) = domain {
            out.domains
                .push((scene.name.clone(), scene.domain.describe()));
            out.domain_pictures.push(domain_picture(
                &scene.name,
                &set,
                domain,
                &truth,
                truth_interface.as_ref(),
                scene.radius,
                scene.domain.describe(),
            ));
        }
        // Classes of the particles for the miss profiles, computed once on first need.
        let mut classes: Option<Result<failures::SceneClasses, String>> = None;
        let mut picture_methods = Vec::new();
        for config in &opts.configs {
            if config.method == "exact" && config.params.is_empty() {
                done += 1;
                continue;
            }
            let detector = boundary::detector_with_params(&config.method, &config.params)
                .map_err(|e| e.to_string())?;
            let (classified, t_all) = timed(detector.as_ref(), &set, domain, r, &all);
            let t_one = (opts.single_thread && classified.is_ok())
                .then(|| timed(detector.as_ref(), &set, domain, r, &one).1);
            let (confusion, error) = match &classified {
                Ok((l, _)) => (
                    Confusion::from_labels(l.as_slice(), truth.as_slice()).ok(),
                    None,
                ),
                Err(e) => (None, Some(unsupported_reason(e).unwrap_or(e.to_string()))),
            };
            let unsupported = classified
                .as_ref()
                .is_err_and(|e| unsupported_reason(e).is_some());
            let (interface, interface_confusion) = match (&classified, &truth_interface) {
                (Ok((_, Some(i))), Some(t)) => (
                    Some(i.boundary_count()),
                    Confusion::from_labels(i.as_slice(), t.as_slice()).ok(),
                ),
                _ => (None, None),
            };
            let labels = classified.map(|(l, _)| l);
            if config.params.is_empty() {
                if let (Ok(l), AnyParticleSet::D2(_)) = (&labels, &set) {
                    picture_methods.push((config.method.clone(), l.clone()));
                }
            }
            let certified = detector.certified();
            let mut misses = None;
            if let (Ok(l), Some(c), true) =
                (&labels, confusion, config.params.is_empty() && !certified)
            {
                let classes =
                    classes.get_or_insert_with(|| failures::scene_classes(&set, r, &truth));
                if let Ok(classes) = classes {
                    misses = failures::MissProfile::of(classes, l, &truth).ok();
                }
                keep_if_worst(
                    &mut out.failure_pictures,
                    &config.method,
                    scene,
                    &set,
                    &truth,
                    l,
                    c.m(),
                );
            }
            let params = detector.describe().to_string();
            done += 1;
            progress(Progress {
                done,
                total,
                what: &format!("{} {} {}", scene.name, config.method, params),
            });
            out.rows.push(Row {
                scene: scene.name.clone(),
                dim: scene.dim,
                n: set.len(),
                radius: scene.radius,
                method: config.method.clone(),
                params,
                is_default: config.params.is_empty(),
                certified,
                misses,
                confusion,
                seconds_1: t_one,
                seconds_all: t_all,
                threads,
                error,
                unsupported,
                interface,
                interface_confusion,
            });
        }
        if let AnyParticleSet::D2(s) = &set {
            let config = boundary_resample::ResampleConfig::default();
            let features = boundary_resample::classify(s, r, &truth, &config)
                .map(|classes| {
                    classes
                        .iter()
                        .map(|c| {
                            c.feature
                                .map_or(boundary_resample::INTERIOR_CODE, |f| f.code())
                        })
                        .collect()
                })
                .unwrap_or_default();
            out.pictures.push(Picture {
                scene: scene.name.clone(),
                points: s.positions().iter().map(|p| [p.x, p.y]).collect(),
                truth,
                methods: picture_methods,
                features,
            });
        }
    }
    Ok(out)
}

/// The picture of the exact labels of a scene with a domain (see [`DomainPicture`]).
fn domain_picture(
    scene: &str,
    set: &AnyParticleSet,
    domain: &Domain,
    truth: &Labels,
    interface: Option<&Labels>,
    r: f64,
    about: String,
) -> DomainPicture {
    let dim = set.dim();
    let axes = [0, dim - 1];
    // In 3D, the slab across the middle of the fluid along y.
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..set.len() {
        let y = set.coords(i)[1];
        lo = lo.min(y);
        hi = hi.max(y);
    }
    let middle = 0.5 * (lo + hi);
    let kept = |c: &[f64]| dim == 2 || (c[1] - middle).abs() <= 0.5 * r;
    let mut picture = DomainPicture {
        scene: scene.to_owned(),
        dim,
        axes,
        points: Vec::new(),
        boundary: Vec::new(),
        interface: Vec::new(),
        phases: Vec::new(),
        walls: Vec::new(),
        solids: Vec::new(),
        periodic: Vec::new(),
        about,
    };
    for i in 0..set.len() {
        let c = set.coords(i);
        if !kept(c) {
            continue;
        }
        picture.points.push([c[axes[0]], c[axes[1]]]);
        picture.boundary.push(truth.is_boundary(i));
        if let Some(t) = interface {
            picture.interface.push(t.is_boundary(i));
        }
        if let Some(p) = domain.phases() {
            picture.phases.push(p[i]);
        }
    }
    if let Some(w) = domain.walls() {
        for i in 0..w.len() {
            let c = w.coords(i);
            if kept(c) {
                picture.walls.push([c[axes[0]], c[axes[1]]]);
            }
        }
    }
    for h in domain.solids().half_spaces() {
        if let Some(k) = axes.iter().position(|&a| a == h.axis()) {
            picture.solids.push((k, h.value(), h.solid_below()));
        }
    }
    for p in domain.periodic() {
        if let Some(k) = axes.iter().position(|&a| a == p.axis()) {
            picture.periodic.push((k, p.min(), p.max()));
        }
    }
    picture
}

/// Makes (scene, labels) the failure picture of `method` when the method has a miss there and
/// no earlier scene of lower or equal M.
fn keep_if_worst(
    pictures: &mut Vec<failures::FailurePicture>,
    method: &str,
    scene: &SceneSpec,
    set: &AnyParticleSet,
    truth: &Labels,
    labels: &Labels,
    m: f64,
) {
    if labels.as_slice() == truth.as_slice() {
        return;
    }
    let slot = pictures.iter().position(|p| p.method == method);
    if slot.is_some_and(|k| pictures[k].m <= m) {
        return;
    }
    let coords = (0..set.len())
        .flat_map(|i| set.coords(i).to_vec())
        .collect();
    let picture = failures::FailurePicture {
        method: method.to_owned(),
        scene: scene.name.clone(),
        dim: set.dim(),
        radius: scene.radius,
        coords,
        truth: truth.clone(),
        labels: labels.clone(),
        m,
    };
    match slot {
        Some(k) => pictures[k] = picture,
        None => pictures.push(picture),
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test
mod tests {
    use super::*;

    /// A 3 × 3 unit lattice at r = 0.5 (2r = 1: the axis neighbours, at distance exactly 2r,
    /// count; the diagonal ones, at √2, do not): the centre has 4, edge midpoints 3,
    /// corners 2, so the mean is (4 + 4·3 + 4·2)/9; a duplicate adds one for each of a pair.
    #[test]
    fn mean_neighbours_counts_others_within_2r() {
        let mut rows: Vec<[f64; 2]> = (0..9).map(|k| [(k % 3) as f64, (k / 3) as f64]).collect();
        let lattice = AnyParticleSet::D2(ParticleSet::from_rows(&rows).unwrap());
        assert_eq!(mean_neighbours(&lattice, 0.5), Some(24.0 / 9.0));
        rows.push([0.0, 0.0]);
        let with_duplicate = AnyParticleSet::D2(ParticleSet::from_rows(&rows).unwrap());
        // The new particle sees its twin and the twin's two axis neighbours (3); the twin
        // and those two neighbours each gain it (3): (24 + 6)/10.
        assert_eq!(mean_neighbours(&with_duplicate, 0.5), Some(3.0));
        let empty = AnyParticleSet::D3(ParticleSet::new(vec![]).unwrap());
        assert_eq!(mean_neighbours(&empty, 1.0), None);
    }
}
