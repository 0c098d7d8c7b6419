//! `boundary-sweep`: runs every detector over every scene and writes `results.csv`,
//! `report.md` and the plots into its output folder; with `--benchmarks` also the summary page
//! `BENCHMARKS.md` (with `--benchmark-pictures` also its speed-against-error pictures), and
//! with `--frame-picture` the README's picture. Normally started by `cargo xtask sweep`,
//! which builds it in release mode and asks for all of them on a full run.

use boundary_sweep::benchmarks::{self, Provenance};
use boundary_sweep::{
    default_configs, plots, report, run, scale, sequence, Options, Progress, SceneSpec,
};
use clap::Parser;
use peakmem_alloc::PeakMemAllocTrait;
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Debug, Parser)]
#[command(
    name = "boundary-sweep",
    about = "Speed against error: every detector over every scene"
)]
struct Args {
    /// Output directory.
    #[arg(long, default_value = "target/sweep")]
    out: PathBuf,
    /// The scene manifest.
    #[arg(long, default_value = "fixtures/scenes.toml")]
    manifest: PathBuf,
    /// Directory of the shared data (default: $BOUNDARY_DATA_DIR, else ../shared/data).
    #[arg(long)]
    data_dir: Option<PathBuf>,
    /// Only scenes whose name contains one of these (comma-separated).
    #[arg(long, value_delimiter = ',')]
    scenes: Vec<String>,
    /// Only these methods (comma-separated; default: every registered method).
    #[arg(long, value_delimiter = ',')]
    methods: Vec<String>,
    /// Quick run: default parameters only, no single-thread timing, scenes of at most 10k particles.
    #[arg(long)]
    quick: bool,
    /// Skip the single-thread timing runs.
    #[arg(long)]
    no_single_thread: bool,
    /// Threads for the all-thread runs (default: all cores).
    #[arg(long, default_value_t = 0)]
    threads: usize,
    /// Add the scale tier: generated sets of 10^4 .. 10^7 particles, timed per method (about
    /// half an hour on a 2-core machine; a `--scenes` filter naming a `scale_` scene runs
    /// just those sets).
    #[arg(long)]
    scale: bool,
    /// The default: no scale tier (kept for scripts that said so).
    #[arg(long, hide = true, conflicts_with = "scale")]
    no_scale: bool,
    /// Scale tier: seconds one run may take, projected from the method's last size, before the
    /// method's series stops.
    #[arg(long, default_value_t = scale::DEFAULT_BUDGET)]
    scale_budget: f64,
    /// Scale tier: the largest set, in particles.
    #[arg(long, default_value_t = 10_000_000)]
    scale_max: usize,
    /// Scale tier: timed runs per method and set (the median is reported).
    #[arg(long, default_value_t = scale::DEFAULT_RUNS)]
    scale_runs: usize,
    /// Also write the summary page (date, commit, machine and command at the top) to this file.
    #[arg(long)]
    benchmarks: Option<PathBuf>,
    /// Also draw the exact labels of the scene `vortex2d_t4` into this PNG file.
    #[arg(long)]
    frame_picture: Option<PathBuf>,
    /// With --benchmarks: draw the summary page's speed-against-error pictures
    /// (`speed_vs_error_2d.png`, `speed_vs_error_3d.png`) into this folder, and embed them in
    /// the page by their path relative to the page's folder.
    #[arg(long, value_name = "DIR", requires = "benchmarks")]
    benchmark_pictures: Option<PathBuf>,
    /// Skip the sequence tier (the incremental tracker against full detections over 12 time
    /// steps of an advected sphere, and a second tracker on --threads for its thread
    /// speed-up; on by default, about 15 s; with --scale also the 10^6 sphere at 0.01 spacing
    /// per step).
    #[arg(long)]
    no_sequence: bool,
    /// Sequence tier: particles of the sphere.
    #[arg(long, default_value_t = sequence::DEFAULT_PARTICLES)]
    sequence_n: usize,
}

/// Counts the heap for the scale tier's peak memory (two atomic updates per allocation).
#[global_allocator]
static HEAP: &peakmem_alloc::PeakMemAlloc<std::alloc::System> = &peakmem_alloc::INSTRUMENTED_SYSTEM;

/// The scale tier's [`scale::MemoryProbe`] over the counting allocator.
struct HeapProbe;

impl scale::MemoryProbe for HeapProbe {
    fn reset(&self) {
        HEAP.reset_peak_memory();
    }
    fn peak_bytes(&self) -> Option<usize> {
        Some(HEAP.get_peak_memory())
    }
}

fn main() {
    if let Err(e) = real_main() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn real_main() -> Result<(), String> {
    let args = Args::parse();
    if args.scale_budget.is_nan() || args.scale_budget <= 0.0 || args.scale_runs == 0 {
        return Err(format!(
            "--scale-budget must be a positive number of seconds (got {}) and --scale-runs at \
             least 1 (got {})",
            args.scale_budget, args.scale_runs
        ));
    }
    // Before the run: the tree as measured, the load the run starts under.
    let provenance = args.benchmarks.as_ref().map(|_| provenance());
    let data_dir = args
        .data_dir
        .clone()
        .unwrap_or_else(boundary_scenes::data_dir);
    let (mut scenes, mut skipped) = load_scenes(
        &args.manifest,
        &data_dir,
        &args.out.join("scenes"),
        &args.scenes,
    )?;
    if args.quick {
        scenes.retain(|s| file_lines(&s.path) <= 10_001);
    }
    let available = boundary::methods();
    for m in &args.methods {
        if !available.contains(&m.as_str()) {
            return Err(format!(
                "unknown method '{m}' (available: {})",
                available.join(", ")
            ));
        }
    }
    let methods: Vec<&str> = available
        .iter()
        .copied()
        .filter(|m| args.methods.is_empty() || args.methods.iter().any(|a| a == m))
        .collect();
    let opts = Options {
        scenes,
        configs: default_configs(&methods, args.quick),
        single_thread: !(args.quick || args.no_single_thread),
        threads: args.threads,
    };
    eprintln!(
        "sweep: {} scenes x {} configurations (+ exact), data from {}",
        opts.scenes.len(),
        opts.configs.len(),
        data_dir.display()
    );
    for (scene, why) in &skipped {
        eprintln!("sweep: skipped {scene}: {why}");
    }
    let start = Instant::now();
    let tty = std::io::stderr().is_terminal();
    let mut progress = |p: Progress<'_>| {
        let line = format!(
            "[{:>4}/{}] {:>6.1} s  {}",
            p.done,
            p.total,
            start.elapsed().as_secs_f64(),
            p.what
        );
        progress_line(tty, &line);
    };
    let mut outcome = run(&opts, &mut progress)?;
    if tty {
        eprintln!();
    }
    let scale_scenes: Vec<scale::ScaleScene> = scale::default_scenes(args.scale_max)
        .into_iter()
        .filter(|s| {
            args.scenes.is_empty() || args.scenes.iter().any(|f| s.name.contains(f.as_str()))
        })
        .collect();
    let scale_asked = args.scale || args.scenes.iter().any(|f| f.starts_with("scale_"));
    if scale_asked && !(args.quick || args.no_scale || scale_scenes.is_empty()) {
        let thread_scan = scale_scenes
            .iter()
            .any(|s| s.name == scale::THREAD_SCAN_SCENE)
            .then(|| scale::THREAD_SCAN_SCENE.to_owned());
        let scale_opts = scale::ScaleOptions {
            scenes: scale_scenes,
            methods: methods.iter().map(|m| m.to_string()).collect(),
            runs: args.scale_runs,
            budget: args.scale_budget,
            threads: args.threads,
            thread_scan,
        };
        eprintln!(
            "sweep: scale tier, {} generated sets up to {} particles, median of {} runs, budget {} s per run",
            scale_opts.scenes.len(),
            args.scale_max,
            scale_opts.runs,
            scale_opts.budget
        );
        let mut step = 0;
        let mut scale_progress = |what: &str| {
            step += 1;
            let line = format!(
                "[scale {step:>3}] {:>7.1} s  {what}",
                start.elapsed().as_secs_f64()
            );
            progress_line(tty, &line);
        };
        outcome.scale = Some(scale::run_scale(
            &scale_opts,
            &HeapProbe,
            &mut scale_progress,
        )?);
        if tty {
            eprintln!();
        }
    }
    skipped.append(&mut outcome.skipped);
    outcome.skipped = skipped;
    let mut sequence_points = Vec::new();
    if !(args.no_sequence || args.quick) {
        let mut seq_progress = |what: &str| {
            progress_line(
                tty,
                &format!(
                    "[sequence] {:>7.1} s  {what}",
                    start.elapsed().as_secs_f64()
                ),
            );
        };
        sequence_points = sequence::run_sequence(
            args.sequence_n,
            &sequence::DISPLACEMENTS,
            args.threads,
            &mut seq_progress,
        )?;
        if scale_asked {
            sequence_points.extend(sequence::run_sequence(
                1_000_000,
                &[0.01],
                args.threads,
                &mut seq_progress,
            )?);
        }
        if tty {
            eprintln!();
        }
    }

    std::fs::create_dir_all(&args.out)
        .map_err(|e| format!("cannot create {}: {e}", args.out.display()))?;
    let write = |name: &str, text: String| -> Result<PathBuf, String> {
        let path = args.out.join(name);
        // Atomic: a reader (or a killed sweep) never leaves a partial results file.
        boundary_io::write_atomic(&path, |out| out.write_all(text.as_bytes()))
            .map_err(|e| e.to_string())?;
        Ok(path)
    };
    let mut written = vec![write("results.csv", report::results_csv(&outcome.rows))?];
    if let Some(scale) = &outcome.scale {
        written.push(write("scale.csv", report::scale_csv(scale))?);
    }
    let header = format!(
        "{} scenes, {} runs, {} threads for the all-thread runs, {:.1} s in all.{}",
        report::scene_order(&outcome.rows).len(),
        outcome.rows.len(),
        outcome.rows.first().map(|r| r.threads).unwrap_or(0),
        start.elapsed().as_secs_f64(),
        if args.quick {
            " Quick run (--quick)."
        } else {
            ""
        }
    );
    let mut report_text = report::report_md(&outcome, &header);
    if !outcome.auto.is_empty() {
        report_text += &boundary_sweep::auto_radius::auto_md(&outcome.auto);
    }
    if !sequence_points.is_empty() {
        written.push(write(
            "sequence.csv",
            sequence::sequence_csv(&sequence_points),
        )?);
        report_text += &sequence::sequence_md(&sequence_points);
    }
    written.push(write("report.md", report_text)?);
    plots::register_font()?;
    written.extend(plots::write_all(&outcome, &args.out)?);
    if let (Some(path), Some(provenance)) = (&args.benchmarks, &provenance) {
        let mut pictures = Vec::new();
        if let Some(dir) = &args.benchmark_pictures {
            std::fs::create_dir_all(dir)
                .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
            let page_dir = path.parent().unwrap_or(Path::new(""));
            for (dim, file) in plots::write_benchmark_pictures(&outcome.rows, dir)? {
                pictures.push(benchmarks::PagePicture {
                    dim,
                    link: link_from(page_dir, &file),
                });
                written.push(file);
            }
        }
        let mut text = benchmarks::benchmarks_md(&outcome, provenance, &pictures);
        if !outcome.auto.is_empty() {
            text += &boundary_sweep::auto_radius::auto_md(&outcome.auto);
        }
        if !sequence_points.is_empty() {
            text += &sequence::sequence_md(&sequence_points);
        }
        boundary_io::write_atomic(path, |out| out.write_all(text.as_bytes()))
            .map_err(|e| e.to_string())?;
        written.push(path.clone());
    }
    if let Some(path) = &args.frame_picture {
        let pic = outcome
            .pictures
            .iter()
            .find(|p| p.scene == plots::FRAME_SCENE)
            .ok_or_else(|| {
                format!(
                    "--frame-picture: the scene {} was not run (is it filtered out?)",
                    plots::FRAME_SCENE
                )
            })?;
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir)
                .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
        }
        plots::write_frame(pic, path)?;
        written.push(path.clone());
    }
    written.extend(sequence::write_plot(&sequence_points, &args.out)?);
    for path in &written {
        println!("{}", path.display());
    }
    for (scene, got, expected) in &outcome.count_mismatches {
        eprintln!(
            "sweep: WARNING {scene}: exact found {got} boundary particles, expected {expected}"
        );
    }
    if !outcome.count_mismatches.is_empty() {
        return Err("exact labels disagree with the reference counts (see report.md)".into());
    }
    eprintln!(
        "sweep: done in {:.1} s; report: {}",
        start.elapsed().as_secs_f64(),
        args.out.join("report.md").display()
    );
    Ok(())
}

/// When, where and how this run was made, for `BENCHMARKS.md`: the UTC date, the commit
/// (`git`, from the current folder; the generated pages themselves do not count as changes),
/// the machine, and the command as `cargo xtask sweep` plus this run's arguments (less the
/// output files of the summary pages, which the xtask adds).
fn provenance() -> Provenance {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs())
        .unwrap_or(0);
    let git = |args: &[&str]| {
        std::process::Command::new("git")
            .args(args)
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_owned())
    };
    let commit = match git(&["rev-parse", "--short=12", "HEAD"]) {
        Some(hash) => {
            let changes = git(&[
                "status",
                "--porcelain",
                "--untracked-files=no",
                "--",
                ".",
                ":!BENCHMARKS.md",
                ":!docs/img",
            ]);
            match changes {
                Some(c) if c.is_empty() => format!("`{hash}`"),
                Some(_) => format!("`{hash}` with uncommitted changes"),
                None => format!("`{hash}`"),
            }
        }
        None => "unknown (not a git checkout)".to_owned(),
    };
    let mut command = vec!["cargo xtask sweep".to_owned()];
    let mut args = std::env::args().skip(1);
    const PAGE_OUTPUTS: [&str; 3] = ["--benchmarks", "--frame-picture", "--benchmark-pictures"];
    while let Some(arg) = args.next() {
        if PAGE_OUTPUTS.contains(&arg.as_str()) {
            args.next();
        } else if !PAGE_OUTPUTS
            .iter()
            .any(|flag| arg.starts_with(&format!("{flag}=")))
        {
            command.push(arg);
        }
    }
    Provenance {
        date: benchmarks::utc_date(secs),
        commit,
        machine: machine(),
        command: command.join(" "),
    }
}

/// How a page in `page_dir` links `file`: its path relative to `page_dir` when `file` lies
/// below it (`/` between components, as Markdown wants), else `file` as given.
fn link_from(page_dir: &Path, file: &Path) -> String {
    let relative = if page_dir.as_os_str().is_empty() {
        Some(file)
    } else {
        file.strip_prefix(page_dir).ok()
    };
    match relative {
        Some(rel) => rel
            .components()
            .map(|c| c.as_os_str().to_string_lossy())
            .collect::<Vec<_>>()
            .join("/"),
        None => file.display().to_string(),
    }
}

/// The machine in words, from what Linux exposes (`/proc`); parts it cannot read are left out.
fn machine() -> String {
    let read = |path: &str| std::fs::read_to_string(path).unwrap_or_default();
    let field = |text: &str, key: &str| {
        text.lines()
            .find(|l| l.starts_with(key))
            .and_then(|l| l.split_once(':'))
            .map(|(_, v)| v.trim().to_owned())
    };
    let mut parts = Vec::new();
    if let Some(cpu) = field(&read("/proc/cpuinfo"), "model name") {
        parts.push(cpu);
    }
    if let Ok(n) = std::thread::available_parallelism() {
        parts.push(format!("{n} cores available"));
    }
    if let Some(kib) = field(&read("/proc/meminfo"), "MemTotal")
        .and_then(|v| v.split_whitespace().next().map(str::to_owned))
        .and_then(|v| v.parse::<f64>().ok())
    {
        parts.push(format!("{:.0} GiB memory", kib / 1024.0 / 1024.0));
    }
    parts.push(format!(
        "{} {}",
        std::env::consts::OS,
        std::env::consts::ARCH
    ));
    if let Some(load) = read("/proc/loadavg").split_whitespace().next() {
        parts.push(format!("load average {load} at the start"));
    }
    parts.join(", ")
}

/// Prints a progress line on stderr: rewritten in place on a terminal, one per line otherwise.
fn progress_line(tty: bool, line: &str) {
    let mut err = std::io::stderr();
    if tty {
        let _ = write!(err, "\r\x1b[2K{line}");
        let _ = err.flush();
    } else {
        let _ = writeln!(err, "{line}");
    }
}

/// Number of lines of a text file (a cheap size estimate for `--quick`).
fn file_lines(path: &Path) -> usize {
    std::fs::read(path)
        .map(|b| b.iter().filter(|&&c| c == b'\n').count())
        .unwrap_or(usize::MAX)
}

/// A scene left out, with the reason.
type Skipped = (String, String);

/// Scenes of the manifest whose name contains one of `filter` (all if empty), resolved against
/// the fixtures folder (beside the manifest) and the data directory; mesh scenes are sampled
/// into `samples_dir` (in the output folder). Scenes whose file is missing are returned as skipped
/// with the reason.
fn load_scenes(
    manifest: &Path,
    data_dir: &Path,
    samples_dir: &Path,
    filter: &[String],
) -> Result<(Vec<SceneSpec>, Vec<Skipped>), String> {
    let parsed = boundary_scenes::Manifest::load(manifest).map_err(|e| e.to_string())?;
    let fixtures = manifest.parent().unwrap_or(Path::new("."));
    let mut scenes = Vec::new();
    let mut skipped = Vec::new();
    for entry in parsed.scene {
        if !filter.is_empty() && !filter.iter().any(|f| entry.name.contains(f.as_str())) {
            continue;
        }
        let mut path = entry.path(fixtures, data_dir);
        if !path.is_file() {
            let why = match entry.origin {
                boundary_scenes::Origin::Shared | boundary_scenes::Origin::Mesh => format!(
                    "{} not found (data directory {}; set {} to use another)",
                    path.display(),
                    data_dir.display(),
                    boundary_scenes::DATA_DIR_VAR
                ),
                boundary_scenes::Origin::Fixture => {
                    format!("{} not found (run `cargo xtask fixtures`)", path.display())
                }
            };
            skipped.push((entry.name, why));
            continue;
        }
        if entry.origin == boundary_scenes::Origin::Mesh {
            match sample_mesh(&entry, fixtures, data_dir, samples_dir) {
                Ok(sample) => path = sample,
                Err(why) => {
                    skipped.push((entry.name, why));
                    continue;
                }
            }
        }
        let about = match (&entry.generator, &entry.params, &entry.provenance) {
            (Some(g), Some(p), _) if entry.origin == boundary_scenes::Origin::Mesh => {
                format!("{g} of {}: {p}", entry.file)
            }
            (Some(g), Some(p), _) => format!("{g}: {p}"),
            (_, _, Some(p)) => p.clone(),
            (Some(g), None, None) => g.clone(),
            (None, Some(p), None) => p.clone(),
            (None, None, None) => String::new(),
        };
        let domain = match entry.scene_domain(fixtures, data_dir) {
            Ok(d) => d,
            Err(why) => {
                skipped.push((entry.name, why));
                continue;
            }
        };
        if let Some(walls) = domain.walls.as_ref().filter(|w| !w.is_file()) {
            skipped.push((
                entry.name,
                format!("{} not found (run `cargo xtask fixtures`)", walls.display()),
            ));
            continue;
        }
        scenes.push(SceneSpec {
            radius_attribute: entry.radius_attribute.clone(),
            domain,
            about,
            name: entry.name,
            dim: entry.dim,
            path,
            radius: entry.radius,
            expected_boundary: entry.expected_boundary,
            origin: match entry.origin {
                boundary_scenes::Origin::Shared => "shared".into(),
                boundary_scenes::Origin::Fixture => "fixture".into(),
                boundary_scenes::Origin::Mesh => "mesh".into(),
            },
        });
    }
    Ok((scenes, skipped))
}

/// Samples a mesh scene into `samples_dir/<name>.csv`; returns the file.
fn sample_mesh(
    entry: &boundary_scenes::SceneEntry,
    fixtures: &Path,
    data_dir: &Path,
    samples_dir: &Path,
) -> Result<PathBuf, String> {
    let set = entry.load(fixtures, data_dir)?;
    if set.len() != entry.n {
        return Err(format!(
            "sampled {} particles, the manifest says {} (run `cargo xtask fixtures`)",
            set.len(),
            entry.n
        ));
    }
    std::fs::create_dir_all(samples_dir)
        .map_err(|e| format!("cannot create {}: {e}", samples_dir.display()))?;
    let path = samples_dir.join(format!("{}.csv", entry.name));
    boundary_io::write_particles(&path, Some(boundary_io::Format::Csv), &set, &[])
        .map_err(|e| e.to_string())?;
    Ok(path)
}
