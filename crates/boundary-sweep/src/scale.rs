//! The scale tier of the sweep: how each method's cost grows with the number of particles.
//!
//! The fixture scenes have a few thousand particles each, so their timings mostly measure
//! overhead. The scale tier generates larger sets at run time (never committed):
//!
//! - a size series of 3D jittered cubic-lattice balls, 10^4 .. 4·10^6 particles, and of 2D
//!   jittered square-lattice discs, 10^4 .. 10^7 (spacing a = 1, jitter ±0.15a, r = 1.2a: about
//!   58 neighbours within 2r in 3D, 18 in 2D; the sets of `cargo bench -p boundary`);
//! - the JCP Table 3 analogue: the Enright-deformed sphere of JCP Fig. 14 at about 1.9M
//!   particles ([`boundary_scenes::enright_sphere`], t = 0.75 of T = 3, r = 1.5h as in the
//!   `enright3d_*` fixtures).
//!
//! Every method runs at its default parameters on all threads; a timing is the **median of
//! [`ScaleOptions::runs`] runs** (one run when the first already exceeds the budget), and the
//! labels of the first run are scored against `exact`'s. The **peak memory** is the most heap
//! the detection held beyond what was allocated before it (the set itself is not counted), read
//! from a [`MemoryProbe`] around the first run; the sweep binary installs a counting global
//! allocator for it.
//!
//! **Budget.** Sizes run in increasing order per dimension. Before a run, a method's time is
//! projected linearly from its last measured lattice set of that dimension (`t · n / n_last`;
//! the Enright set is projected from the balls but does not feed the projection, its shape
//! being another); a method whose projection exceeds [`ScaleOptions::budget`] seconds stops
//! there, and the report says so with the projection. `exact` gives the reference labels:
//! where it stops, the larger scenes are skipped.
//!
//! **Threads.** On one scene ([`ScaleOptions::thread_scan`], the 10^6 ball by default) each method
//! is also timed on 1, 2, 4, … threads below the all-thread count (one run each), for the
//! parallel-speedup table.

use boundary::{AnyParticleSet, Confusion, Domain, Labels, ParticleSet, Radius};
use std::time::Instant;

/// Sizes of the 3D ball series.
pub const BALL_SIZES: [usize; 6] = [10_000, 30_000, 100_000, 300_000, 1_000_000, 4_000_000];
/// Sizes of the 2D disc series.
pub const DISC_SIZES: [usize; 7] = [
    10_000, 30_000, 100_000, 300_000, 1_000_000, 3_000_000, 10_000_000,
];
/// Size of the Enright scene (JCP Fig. 14: |P| = 1.9M).
pub const ENRIGHT_SIZE: usize = 1_900_000;
/// Default seconds one run may take (projected) before a method's series stops.
pub const DEFAULT_BUDGET: f64 = 60.0;
/// Default number of timed runs (the median is reported).
pub const DEFAULT_RUNS: usize = 3;
/// Size of the block in a tank (its fluid particles).
pub const TANK_SIZE: usize = 1_000_000;
/// The scene of the thread scan by default.
pub const THREAD_SCAN_SCENE: &str = "scale_ball3d_1M";

/// What a scale scene is made of.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Family {
    /// A 3D jittered cubic-lattice ball.
    Ball,
    /// A 2D jittered square-lattice disc.
    Disc,
    /// The Enright-deformed sphere.
    Enright,
    /// A jittered block resting in a tank of wall particles (`detect_in` with the walls):
    /// what walls cost.
    Tank,
    /// The same block and tank as one bare set (every particle classified): what the walls
    /// must not exceed.
    TankUnion,
}

/// A generated scene of the scale tier.
#[derive(Debug, Clone, PartialEq)]
pub struct ScaleScene {
    /// Unique name (`scale_ball3d_1M`, …).
    pub name: String,
    /// Dimension.
    pub dim: usize,
    /// The number of particles asked for (the generated set has about as many).
    pub target: usize,
    /// Its family.
    pub family: Family,
}

/// `n` in short form: 10k, 1.9M, 10M.
pub fn short_count(n: usize) -> String {
    let (value, unit) = if n >= 1_000_000 {
        (n as f64 / 1e6, "M")
    } else if n >= 1_000 {
        (n as f64 / 1e3, "k")
    } else {
        (n as f64, "")
    };
    let text = format!("{value:.1}");
    format!("{}{unit}", text.trim_end_matches(".0"))
}

impl ScaleScene {
    /// A scene of `family` with about `target` particles.
    pub fn new(family: Family, target: usize) -> Self {
        let (stem, dim) = match family {
            Family::Ball => ("ball3d", 3),
            Family::Disc => ("disc2d", 2),
            Family::Enright => ("enright3d", 3),
            Family::Tank => ("tank3d", 3),
            Family::TankUnion => ("tankunion3d", 3),
        };
        ScaleScene {
            name: format!("scale_{stem}_{}", short_count(target)),
            dim,
            target,
            family,
        }
    }

    /// Generates the particles; returns them with the resolution r and a description.
    pub fn generate(&self) -> (AnyParticleSet, f64, String) {
        let (set, _, r, about) = self.generate_in_domain();
        (set, r, about)
    }

    /// Generates the particles and their domain (bare but for [`Family::Tank`]); returns them
    /// with the resolution r and a description.
    pub fn generate_in_domain(&self) -> (AnyParticleSet, Domain, f64, String) {
        let tank = "jittered block (a = 1, jitter ±0.15a, s x s x 2s cells, z up) in an \
                    open tank of 3 layers of wall particles, r = 1.2a, seed 7";
        let (set, r, about) = match self.family {
            Family::Tank => {
                let (fluid, walls, _) = boundary_scenes::block_in_tank(self.target, 7);
                let domain = Domain::new().with_walls(walls.into());
                return (
                    fluid.into(),
                    domain,
                    1.2,
                    format!("{tank}: the fluid classified, the walls covering"),
                );
            }
            Family::TankUnion => {
                let (fluid, walls, _) = boundary_scenes::block_in_tank(self.target, 7);
                let mut all = fluid.positions().to_vec();
                all.extend(walls.positions());
                let set = ParticleSet::new(all).expect("generated coordinates are finite");
                (
                    set.into(),
                    1.2,
                    format!("{tank}: fluid and walls as one set, every particle classified"),
                )
            }
            Family::Ball => {
                let (set, _) = boundary_scenes::jittered_lattice_ball(self.target, 0.15, 7);
                (
                    set.into(),
                    1.2,
                    "jittered cubic lattice ball: a = 1, jitter ±0.15a, r = 1.2a, seed 7".into(),
                )
            }
            Family::Disc => {
                let radius = (self.target as f64 / std::f64::consts::PI).sqrt();
                let set = boundary_scenes::jittered_lattice_disc(radius, 0.15, 7);
                (
                    set.into(),
                    1.2,
                    "jittered square lattice disc: a = 1, jitter ±0.15a, r = 1.2a, seed 7".into(),
                )
            }
            Family::Enright => {
                let (set, h) = boundary_scenes::enright_sphere(self.target, 0.75, 0.025);
                (
                    set.into(),
                    1.5 * h,
                    format!(
                        "Enright deformation (T = 3) of the sphere R = 0.15 at t = 0.75, \
                         h = {h:.3e}, jitter ±0.05h, r = 1.5h, RK4 dt = 0.025, seed 3 \
                         (the JCP Fig. 14 / Table 3 analogue)"
                    ),
                )
            }
        };
        (set, Domain::new(), r, about)
    }
}

/// The scale scenes of at most `max_n` particles: the ball series and the Enright scene (3D),
/// then the disc series (2D), each dimension in increasing size.
pub fn default_scenes(max_n: usize) -> Vec<ScaleScene> {
    let mut three: Vec<ScaleScene> = BALL_SIZES
        .iter()
        .map(|&n| ScaleScene::new(Family::Ball, n))
        .chain([
            ScaleScene::new(Family::Enright, ENRIGHT_SIZE),
            ScaleScene::new(Family::Tank, TANK_SIZE),
            ScaleScene::new(Family::TankUnion, TANK_SIZE),
        ])
        .filter(|s| s.target <= max_n)
        .collect();
    three.sort_by_key(|s| s.target);
    three.extend(
        DISC_SIZES
            .iter()
            .filter(|&&n| n <= max_n)
            .map(|&n| ScaleScene::new(Family::Disc, n)),
    );
    three
}

/// Measures the heap a detection holds at its peak.
pub trait MemoryProbe {
    /// Starts a measurement: the peak is counted from here.
    fn reset(&self);
    /// The most bytes held beyond the heap at the last [`MemoryProbe::reset`] (`None` when
    /// this probe cannot measure).
    fn peak_bytes(&self) -> Option<usize>;
}

/// A probe that measures nothing (peak memory reported as "-").
#[derive(Debug, Clone, Copy, Default)]
pub struct NoProbe;

impl MemoryProbe for NoProbe {
    fn reset(&self) {}
    fn peak_bytes(&self) -> Option<usize> {
        None
    }
}

/// Options of the scale tier.
#[derive(Debug, Clone)]
pub struct ScaleOptions {
    /// Scenes, in the order to run (increasing size per dimension for the budget).
    pub scenes: Vec<ScaleScene>,
    /// Methods at default parameters (`exact` is always run first, as the reference).
    pub methods: Vec<String>,
    /// Timed runs per (scene, method); the median is reported.
    pub runs: usize,
    /// Seconds a run may take (projected from the last size) before a method's series stops.
    pub budget: f64,
    /// Threads of the timed runs (0: rayon's default, every core).
    pub threads: usize,
    /// Scene of the thread scan (`None`: no scan).
    pub thread_scan: Option<String>,
}

/// One (scene, method) result of the scale tier.
#[derive(Debug, Clone, PartialEq)]
pub struct ScaleRow {
    /// Scene name.
    pub scene: String,
    /// Dimension.
    pub dim: usize,
    /// Number of particles.
    pub n: usize,
    /// Resolution r.
    pub radius: f64,
    /// Method (default parameters).
    pub method: String,
    /// Seconds of each timed run, in run order (empty when not run).
    pub seconds: Vec<f64>,
    /// Threads of the timed runs.
    pub threads: usize,
    /// Confusion of the first run's labels against `exact`'s.
    pub confusion: Option<Confusion>,
    /// Peak heap bytes of the first run beyond the heap before it.
    pub peak_bytes: Option<usize>,
    /// Why it did not run (budget, error).
    pub skipped: Option<String>,
}

/// The median of `values` (the mean of the middle two for an even count; `None` if empty).
pub fn median(values: &[f64]) -> Option<f64> {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let k = v.len();
    match k {
        0 => None,
        _ if k % 2 == 1 => Some(v[k / 2]),
        _ => Some(0.5 * (v[k / 2 - 1] + v[k / 2])),
    }
}

impl ScaleRow {
    /// Median seconds over the runs.
    pub fn median(&self) -> Option<f64> {
        median(&self.seconds)
    }

    /// Particles per second at the median time.
    pub fn rate(&self) -> Option<f64> {
        self.median()
            .filter(|&t| t > 0.0)
            .map(|t| self.n as f64 / t)
    }

    /// Peak heap bytes per particle.
    pub fn bytes_per_particle(&self) -> Option<f64> {
        self.peak_bytes
            .filter(|_| self.n > 0)
            .map(|b| b as f64 / self.n as f64)
    }
}

/// One timing of the thread scan.
#[derive(Debug, Clone, PartialEq)]
pub struct ThreadRun {
    /// Method.
    pub method: String,
    /// Threads.
    pub threads: usize,
    /// Seconds (`None`: skipped, see `skipped`).
    pub seconds: Option<f64>,
    /// Why it did not run.
    pub skipped: Option<String>,
}

/// What the scale tier produced.
#[derive(Debug, Clone, Default)]
pub struct ScaleOutcome {
    /// One row per (scene, method), scenes in run order, `exact` first.
    pub rows: Vec<ScaleRow>,
    /// (scene, description, seconds to generate it).
    pub scenes: Vec<(String, String, f64)>,
    /// Scene of the thread scan, its particle count and the runs (the all-thread run is the
    /// scene's row).
    pub thread_scan: Option<(String, usize, Vec<ThreadRun>)>,
    /// Runs per timing.
    pub runs: usize,
    /// The budget in seconds.
    pub budget: f64,
}

/// Per (dimension, method) the last measured lattice set `(n, median seconds)`, from which the
/// next size is projected.
#[derive(Debug, Default)]
struct Projections(Vec<((usize, String), (usize, f64))>);

impl Projections {
    fn last(&self, dim: usize, method: &str) -> Option<(usize, f64)> {
        self.0
            .iter()
            .find(|((d, m), _)| *d == dim && m == method)
            .map(|(_, v)| *v)
    }

    /// Records a measurement; the Enright set and the tank (other shapes than the lattice
    /// series) are projected from them but do not update them.
    fn record(&mut self, scene: &ScaleScene, method: &str, n: usize, seconds: f64) {
        if !matches!(scene.family, Family::Ball | Family::Disc) {
            return;
        }
        match self
            .0
            .iter_mut()
            .find(|((d, m), _)| *d == scene.dim && m == method)
        {
            Some(slot) => slot.1 = (n, seconds),
            None => self.0.push(((scene.dim, method.to_owned()), (n, seconds))),
        }
    }
}

/// The projected seconds of a run of `n` particles from the last measured `(n, seconds)`.
pub fn projected(last: Option<(usize, f64)>, n: usize) -> Option<f64> {
    last.filter(|&(m, _)| m > 0)
        .map(|(m, t)| t * n as f64 / m as f64)
}

fn pool(threads: usize) -> Result<rayon::ThreadPool, String> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| e.to_string())
}

/// Runs `method` on `set`: the first run measured by `probe`, then up to `runs - 1` more unless
/// the first exceeded `budget`. Returns the first run's labels, the seconds and the peak.
#[allow(clippy::too_many_arguments)] // one call site; the arguments are the run's inputs
fn time_runs(
    method: &str,
    set: &AnyParticleSet,
    domain: &Domain,
    r: Radius,
    pool: &rayon::ThreadPool,
    runs: usize,
    budget: f64,
    probe: &dyn MemoryProbe,
) -> Result<(Labels, Vec<f64>, Option<usize>), String> {
    let detector = boundary::detector_by_name(method).map_err(|e| e.to_string())?;
    let mut seconds = Vec::with_capacity(runs);
    probe.reset();
    let start = Instant::now();
    let labels = pool
        .install(|| detector.detect_in(set, domain, r))
        .map_err(|e| e.to_string())?
        .detection
        .labels;
    seconds.push(start.elapsed().as_secs_f64());
    let peak = probe.peak_bytes();
    while seconds.len() < runs.max(1) && seconds[0] <= budget {
        let start = Instant::now();
        let again = pool.install(|| detector.detect_in(set, domain, r));
        seconds.push(start.elapsed().as_secs_f64());
        again.map_err(|e| e.to_string())?;
    }
    Ok((labels, seconds, peak))
}

/// Runs the scale tier. A method that fails or exceeds the budget is recorded, never fatal.
pub fn run_scale(
    opts: &ScaleOptions,
    probe: &dyn MemoryProbe,
    progress: &mut dyn FnMut(&str),
) -> Result<ScaleOutcome, String> {
    let all = pool(opts.threads)?;
    let threads = all.current_num_threads();
    let mut out = ScaleOutcome {
        runs: opts.runs.max(1),
        budget: opts.budget,
        ..Default::default()
    };
    let mut methods = vec!["exact".to_owned()];
    methods.extend(opts.methods.iter().filter(|m| *m != "exact").cloned());
    let mut last = Projections::default();
    for scene in &opts.scenes {
        let start = Instant::now();
        let (set, domain, radius, about) = scene.generate_in_domain();
        out.scenes
            .push((scene.name.clone(), about, start.elapsed().as_secs_f64()));
        let n = set.len();
        let r = Radius::new(radius).map_err(|e| format!("{}: {e}", scene.name))?;
        let mut truth: Option<Labels> = None;
        for method in &methods {
            let before = last.last(scene.dim, method);
            let mut row = ScaleRow {
                scene: scene.name.clone(),
                dim: scene.dim,
                n,
                radius,
                method: method.clone(),
                seconds: Vec::new(),
                threads,
                confusion: None,
                peak_bytes: None,
                skipped: None,
            };
            let projection = projected(before, n);
            if let Some(t) = projection.filter(|&t| t > opts.budget) {
                row.skipped = Some(format!(
                    "projected {t:.0} s > budget {:.0} s (from {:.2} s at n = {})",
                    opts.budget,
                    before.map_or(0.0, |b| b.1),
                    before.map_or(0, |b| b.0)
                ));
            } else if method != "exact" && truth.is_none() {
                row.skipped = Some("no reference: exact did not run".into());
            } else {
                progress(&format!("{} ({n} particles) {method}", scene.name));
                match time_runs(method, &set, &domain, r, &all, out.runs, opts.budget, probe) {
                    Ok((labels, seconds, peak)) => {
                        if method == "exact" {
                            truth = Some(labels.clone());
                        }
                        row.confusion = truth.as_ref().and_then(|t| {
                            Confusion::from_labels(labels.as_slice(), t.as_slice()).ok()
                        });
                        row.seconds = seconds;
                        row.peak_bytes = peak;
                        last.record(scene, method, n, row.median().unwrap_or(0.0));
                    }
                    Err(e) => row.skipped = Some(format!("failed: {e}")),
                }
            }
            out.rows.push(row);
        }
        if opts.thread_scan.as_deref() == Some(scene.name.as_str()) {
            let runs = thread_scan(
                &out.rows,
                &scene.name,
                &set,
                r,
                threads,
                opts.budget,
                progress,
            )?;
            out.thread_scan = Some((scene.name.clone(), n, runs));
        }
    }
    Ok(out)
}

/// Thread counts of the scan: 1, 2, 4, … below `all`.
pub fn scan_counts(all: usize) -> Vec<usize> {
    std::iter::successors(Some(1usize), |t| t.checked_mul(2))
        .take_while(|&t| t < all)
        .collect()
}

/// Times every method that ran on `scene` at 1, 2, 4, … threads (one run each); a run whose
/// projection (the all-thread median times `all / threads`) exceeds `budget` is skipped.
fn thread_scan(
    rows: &[ScaleRow],
    scene: &str,
    set: &AnyParticleSet,
    r: Radius,
    all: usize,
    budget: f64,
    progress: &mut dyn FnMut(&str),
) -> Result<Vec<ThreadRun>, String> {
    let mut runs = Vec::new();
    for row in rows.iter().filter(|row| row.scene == scene) {
        let Some(median) = row.median() else {
            continue;
        };
        for threads in scan_counts(all) {
            let projection = median * all as f64 / threads as f64;
            let mut run = ThreadRun {
                method: row.method.clone(),
                threads,
                seconds: None,
                skipped: None,
            };
            if projection > budget {
                run.skipped = Some(format!(
                    "projected {projection:.0} s > budget {budget:.0} s"
                ));
            } else {
                progress(&format!("{scene} {} on {threads} thread(s)", row.method));
                let detector =
                    boundary::detector_by_name(&row.method).map_err(|e| e.to_string())?;
                let pool = pool(threads)?;
                let start = Instant::now();
                match pool.install(|| detector.detect(set, r)) {
                    Ok(_) => run.seconds = Some(start.elapsed().as_secs_f64()),
                    Err(e) => run.skipped = Some(format!("failed: {e}")),
                }
            }
            runs.push(run);
        }
    }
    Ok(runs)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_counts_name_the_scenes() {
        assert_eq!(short_count(10_000), "10k");
        assert_eq!(short_count(1_900_000), "1.9M");
        assert_eq!(short_count(10_000_000), "10M");
        assert_eq!(short_count(300_000), "300k");
        assert_eq!(short_count(999), "999");
        assert_eq!(
            ScaleScene::new(Family::Ball, 1_000_000).name,
            THREAD_SCAN_SCENE
        );
    }

    #[test]
    fn the_tank_scenes_are_one_block_with_its_walls_as_ghosts_or_as_particles() {
        let tank = ScaleScene::new(Family::Tank, 2_000);
        let union = ScaleScene::new(Family::TankUnion, 2_000);
        assert_eq!(tank.name, "scale_tank3d_2k");
        let (fluid, domain, r, _) = tank.generate_in_domain();
        let (all, bare, r2, _) = union.generate_in_domain();
        assert!(bare.is_bare() && r == r2);
        let walls = domain.walls().unwrap().len();
        assert!(walls > 0 && all.len() == fluid.len() + walls);
        let r = Radius::new(r).unwrap();
        let exact = boundary::detector_by_name("exact").unwrap();
        let with_walls = exact
            .detect_in(&fluid, &domain, r)
            .unwrap()
            .detection
            .labels;
        let whole = exact.detect(&all, r).unwrap().labels;
        assert_eq!(with_walls.as_slice(), &whole.as_slice()[..fluid.len()]);
        assert!(
            with_walls.boundary_count() < exact.detect(&fluid, r).unwrap().labels.boundary_count()
        );
    }

    #[test]
    fn default_scenes_are_capped_and_in_increasing_size_per_dimension() {
        let all = default_scenes(usize::MAX);
        assert_eq!(all.len(), BALL_SIZES.len() + 3 + DISC_SIZES.len());
        for dim in [2, 3] {
            let sizes: Vec<usize> = all
                .iter()
                .filter(|s| s.dim == dim)
                .map(|s| s.target)
                .collect();
            assert!(sizes.windows(2).all(|w| w[0] <= w[1]), "{sizes:?}");
        }
        assert_eq!(
            all.iter()
                .filter(|s| s.dim == 2)
                .max_by_key(|s| s.target)
                .unwrap()
                .target,
            10_000_000
        );
        let capped = default_scenes(1_000_000);
        assert!(capped.iter().all(|s| s.target <= 1_000_000));
        assert!(capped.iter().all(|s| s.family != Family::Enright));
        assert_eq!(
            capped.len(),
            5 + 2 + 5,
            "the tank and its union are 10^6 scenes"
        );
    }

    #[test]
    fn generated_scenes_have_about_the_asked_size() {
        for family in [Family::Ball, Family::Disc, Family::Enright] {
            let scene = ScaleScene::new(family, 20_000);
            let (set, r, about) = scene.generate();
            assert_eq!(set.dim(), scene.dim);
            let ratio = set.len() as f64 / 20_000.0;
            assert!((0.9..1.1).contains(&ratio), "{family:?}: {}", set.len());
            assert!(r > 0.0 && !about.is_empty());
        }
    }

    #[test]
    fn median_takes_the_middle_and_projection_is_linear() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&[4.0, 1.0]), Some(2.5));
        assert_eq!(median(&[]), None);
        assert_eq!(projected(Some((1000, 2.0)), 4000), Some(8.0));
        assert_eq!(projected(None, 4000), None);
        assert_eq!(scan_counts(8), vec![1, 2, 4]);
        assert_eq!(scan_counts(6), vec![1, 2, 4]);
        assert_eq!(scan_counts(1), Vec::<usize>::new());
    }

    fn tiny(budget: f64) -> ScaleOutcome {
        let opts = ScaleOptions {
            scenes: vec![
                ScaleScene::new(Family::Ball, 2_000),
                ScaleScene::new(Family::Ball, 8_000),
                ScaleScene::new(Family::Disc, 3_000),
            ],
            methods: vec!["marrone".into(), "exact".into()],
            runs: 3,
            budget,
            threads: 2,
            thread_scan: Some("scale_ball3d_2k".into()),
        };
        let mut lines = Vec::new();
        let out = run_scale(&opts, &NoProbe, &mut |s| lines.push(s.to_owned())).unwrap();
        assert!(!lines.is_empty());
        out
    }

    #[test]
    fn every_method_is_timed_three_times_and_scored_against_exact() {
        let out = tiny(1e9);
        assert_eq!(out.rows.len(), 3 * 2);
        for row in &out.rows {
            assert_eq!(row.seconds.len(), 3, "{row:?}");
            assert!(row.skipped.is_none());
            let c = row.confusion.unwrap();
            assert_eq!((c.tp + c.tn + c.fp + c.fn_) as usize, row.n);
            assert_eq!(row.peak_bytes, None);
        }
        // exact first, scored against itself.
        assert_eq!(out.rows[0].method, "exact");
        let c = out.rows[0].confusion.unwrap();
        assert_eq!((c.fp, c.fn_), (0, 0));
        assert!(c.tp > 0 && c.tn > 0);
        // marrone differs from exact somewhere on a jittered lattice.
        let m = out.rows[1].confusion.unwrap();
        assert!(m.fp + m.fn_ > 0, "{m:?}");
        let (scene, n, runs) = out.thread_scan.unwrap();
        assert_eq!((scene.as_str(), n), ("scale_ball3d_2k", out.rows[0].n));
        // 2 threads: one single-thread run per method.
        assert_eq!(runs.len(), 2);
        assert!(runs.iter().all(|r| r.threads == 1 && r.seconds.is_some()));
    }

    /// The lattice series feed the projection per dimension and method; the Enright set is
    /// projected from the ball before it but does not feed the projection.
    #[test]
    fn the_enright_set_does_not_feed_the_ball_projection() {
        let mut p = Projections::default();
        let ball = ScaleScene::new(Family::Ball, 1_000);
        p.record(&ball, "exact", 1_000, 2.0);
        p.record(&ScaleScene::new(Family::Disc, 1_000), "exact", 1_000, 0.5);
        p.record(
            &ScaleScene::new(Family::Enright, 5_000),
            "exact",
            5_000,
            900.0,
        );
        assert_eq!(p.last(3, "exact"), Some((1_000, 2.0)));
        assert_eq!(p.last(2, "exact"), Some((1_000, 0.5)));
        assert_eq!(p.last(3, "ia"), None);
        p.record(&ScaleScene::new(Family::Ball, 4_000), "exact", 4_000, 9.0);
        assert_eq!(p.last(3, "exact"), Some((4_000, 9.0)));
    }

    #[test]
    fn a_zero_budget_stops_each_series_after_its_first_size() {
        let out = tiny(0.0);
        let ball_8k: Vec<&ScaleRow> = out
            .rows
            .iter()
            .filter(|r| r.scene == "scale_ball3d_8k")
            .collect();
        assert_eq!(ball_8k.len(), 2);
        for row in ball_8k {
            let why = row.skipped.as_deref().unwrap();
            assert!(why.contains("budget 0 s"), "{why}");
            assert!(row.seconds.is_empty());
        }
        // The first size of each dimension runs, once (its first run is over the budget).
        for scene in ["scale_ball3d_2k", "scale_disc2d_3k"] {
            for row in out.rows.iter().filter(|r| r.scene == scene) {
                assert_eq!(row.seconds.len(), 1, "{row:?}");
            }
        }
        let (_, _, runs) = out.thread_scan.unwrap();
        assert!(runs.iter().all(|r| r.skipped.is_some()));
    }
}
