//! The sequence tier: `exact`'s incremental tracker against full detections over time steps.
//!
//! The Enright-advected jittered sphere ([`boundary_scenes::enright_sequence`], `r = 1.5h`),
//! 12 steps after its first frame at each displacement of the fastest particle per step
//! (units of the spacing `h`), one thread: per displacement the time of the full detections,
//! the time of the tracker's updates (first update excluded), their ratio and the particles
//! recomputed per step. A second tracker runs the same steps on the sweep's threads, for the
//! updates' 1-to-N-thread speed-up. Every update's labels, of both trackers, are checked
//! against the full detection (a difference is an error). Written as `sequence.csv`, a section of `report.md` and the plot
//! `sequence.svg` (ratio against displacement).

use boundary::{BoundaryDetector, Domain, ExactDetector, Radius, Tracker};
use plotters::prelude::*;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The displacements of the curve, in spacings per step.
pub const DISPLACEMENTS: [f64; 8] = [0.001, 0.003, 0.01, 0.03, 0.05, 0.1, 0.2, 0.5];

/// Steps after the first frame.
pub const STEPS: usize = 12;

/// The default tier's sphere: short enough to run by default (about 10 s on one core).
pub const DEFAULT_PARTICLES: usize = 10_000;

/// One point of the curve.
#[derive(Debug, Clone, PartialEq)]
pub struct SequencePoint {
    /// Particles of the sphere.
    pub n: usize,
    /// Fastest particle's displacement per step, in spacings.
    pub displacement: f64,
    /// Seconds of the full detections of steps 1..=12.
    pub full_seconds: f64,
    /// Seconds of the tracker's updates of steps 1..=12, one thread.
    pub tracker_seconds: f64,
    /// Threads of the second tracker, and the seconds of its updates of steps 1..=12 (`None`
    /// where the sweep has one thread only).
    pub parallel: Option<(usize, f64)>,
    /// Particles the tracker recomputed at each step 0..=12 (all of them at step 0).
    pub recomputed: Vec<usize>,
}

impl SequencePoint {
    /// Full detection time over tracker time.
    pub fn ratio(&self) -> f64 {
        self.full_seconds / self.tracker_seconds.max(f64::MIN_POSITIVE)
    }

    /// The tracker's speed-up from one thread to [`SequencePoint::parallel`]'s threads.
    pub fn thread_speedup(&self) -> Option<f64> {
        self.parallel
            .map(|(_, seconds)| self.tracker_seconds / seconds.max(f64::MIN_POSITIVE))
    }
}

/// Runs the sphere of about `n` particles at each of `displacements`: the full detections
/// and a tracker on one thread, and a second tracker on `threads` threads (0: every core; no
/// second tracker where that is one).
pub fn run_sequence(
    n: usize,
    displacements: &[f64],
    threads: usize,
    progress: &mut dyn FnMut(&str),
) -> Result<Vec<SequencePoint>, String> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .map_err(|e| format!("sequence tier: {e}"))?;
    let threads = match threads {
        0 => std::thread::available_parallelism().map_or(1, usize::from),
        t => t,
    };
    let mut points = Vec::new();
    for &d in displacements {
        progress(&format!("sequence: {n} particles, {d} spacing per step"));
        let (frames, h) = boundary_scenes::enright_sequence(n, d, STEPS);
        let r = Radius::new(1.5 * h).map_err(|e| e.to_string())?;
        let mut tracker = Tracker::new(r, Some(1), Domain::new()).map_err(|e| e.to_string())?;
        let mut parallel = match threads {
            1 => None,
            t => Some(Tracker::new(r, Some(t), Domain::new()).map_err(|e| e.to_string())?),
        };
        let (mut full_seconds, mut tracker_seconds, mut recomputed) = (0.0, 0.0, vec![]);
        let mut parallel_seconds = 0.0;
        for (step, frame) in frames.iter().enumerate() {
            let set = frame.to_any();
            let start = Instant::now();
            let full = pool
                .install(|| ExactDetector::default().detect(&set, r))
                .map_err(|e| e.to_string())?;
            let full_time = start.elapsed().as_secs_f64();
            let start = Instant::now();
            let labels = tracker.update(&set).map_err(|e| e.to_string())?;
            let tracker_time = start.elapsed().as_secs_f64();
            let differ = |threads: usize| {
                format!(
                    "sequence tier: the tracker's labels ({threads} threads) differ from exact \
                     at step {step} ({d} spacing per step)"
                )
            };
            if *labels != full.labels {
                return Err(differ(1));
            }
            let mut parallel_time = 0.0;
            if let Some(tracker) = parallel.as_mut() {
                let start = Instant::now();
                let labels = tracker.update(&set).map_err(|e| e.to_string())?;
                parallel_time = start.elapsed().as_secs_f64();
                if *labels != full.labels {
                    return Err(differ(threads));
                }
            }
            if step > 0 {
                full_seconds += full_time;
                tracker_seconds += tracker_time;
                parallel_seconds += parallel_time;
            }
            recomputed.push(tracker.recomputed());
        }
        points.push(SequencePoint {
            n: frames[0].len(),
            displacement: d,
            full_seconds,
            tracker_seconds,
            parallel: parallel.map(|_| (threads, parallel_seconds)),
            recomputed,
        });
    }
    Ok(points)
}

/// `sequence.csv`: one row per point, the recomputed counts `;`-separated.
pub fn sequence_csv(points: &[SequencePoint]) -> String {
    let mut text = String::from(
        "n,displacement,full_seconds,tracker_seconds,ratio,threads,tracker_seconds_threads,\
         thread_speedup,recomputed_per_step\n",
    );
    for p in points {
        let counts: Vec<String> = p.recomputed.iter().map(|c| c.to_string()).collect();
        let (threads, seconds, speedup) = match (p.parallel, p.thread_speedup()) {
            (Some((t, s)), Some(x)) => (t.to_string(), format!("{s:.6}"), format!("{x:.3}")),
            _ => ("1".into(), String::new(), String::new()),
        };
        text += &format!(
            "{},{},{:.6},{:.6},{:.3},{threads},{seconds},{speedup},{}\n",
            p.n,
            p.displacement,
            p.full_seconds,
            p.tracker_seconds,
            p.ratio(),
            counts.join(";")
        );
    }
    text
}

/// The section of `report.md`.
pub fn sequence_md(points: &[SequencePoint]) -> String {
    let mut text = String::from(
        "\n## Time steps: the incremental tracker\n\nThe Enright-advected jittered sphere \
         (r = 1.5h), 12 steps after its first frame, one thread: full `exact` detections \
         against `boundary::Tracker` updates (identical labels, checked at every step; first \
         update excluded). Displacement: the fastest particle's, per step, in spacings. The \
         last two columns: a second tracker on the sweep's N threads over the same steps, and \
         its speed-up over the one-thread tracker. An update runs on the calling thread and \
         hands only its large parts to the workers (the passes over 16,384 particles and more, \
         128 evaluations and more in a step, a full detection): below that the two trackers \
         do the same work on one thread.\n\n\
         | n | displacement | full (s) | tracker (s) | ratio | recomputed per step (mean of steps 1-12) | tracker, N threads (s) | speed-up |\n\
         |---|---|---|---|---|---|---|---|\n",
    );
    for p in points {
        let later = &p.recomputed[1.min(p.recomputed.len())..];
        let mean = later.iter().sum::<usize>() as f64 / later.len().max(1) as f64;
        let (parallel, speedup) = match (p.parallel, p.thread_speedup()) {
            (Some((t, s)), Some(x)) => (format!("{s:.3} (N = {t})"), format!("{x:.2}")),
            _ => ("-".into(), "-".into()),
        };
        text += &format!(
            "| {} | {} | {:.3} | {:.3} | {:.2} | {:.0} ({:.1}%) | {parallel} | {speedup} |\n",
            p.n,
            p.displacement,
            p.full_seconds,
            p.tracker_seconds,
            p.ratio(),
            mean,
            100.0 * mean / p.n.max(1) as f64
        );
    }
    text
}

/// `sequence.svg`: the ratio against the displacement, one line per sphere size.
pub fn write_plot(points: &[SequencePoint], dir: &Path) -> Result<Vec<PathBuf>, String> {
    if points.is_empty() {
        return Ok(vec![]);
    }
    let err = |e: &dyn std::fmt::Display| format!("sequence plot: {e}");
    let path = dir.join("sequence.svg");
    let root = SVGBackend::new(&path, (900, 600)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let top = points.iter().map(SequencePoint::ratio).fold(1.0, f64::max) * 1.5;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Tracker: full exact detection time / update time",
            ("sans-serif", 22),
        )
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d((0.0005f64..1.0).log_scale(), (0.5f64..top).log_scale())
        .map_err(|e| err(&e))?;
    chart
        .configure_mesh()
        .x_desc("fastest particle's displacement per step (spacings)")
        .y_desc("speed-up (full / tracker)")
        .x_label_formatter(&|x| format!("{x}"))
        .y_label_formatter(&|y| format!("{y:.1}"))
        .draw()
        .map_err(|e| err(&e))?;
    let mut sizes: Vec<usize> = points.iter().map(|p| p.n).collect();
    sizes.sort_unstable();
    sizes.dedup();
    for (k, n) in sizes.iter().enumerate() {
        let colour = Palette99::pick(k).to_rgba();
        let line: Vec<(f64, f64)> = points
            .iter()
            .filter(|p| p.n == *n)
            .map(|p| (p.displacement, p.ratio()))
            .collect();
        chart
            .draw_series(LineSeries::new(line.clone(), colour.stroke_width(2)))
            .map_err(|e| err(&e))?
            .label(format!("{n} particles"))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour));
        chart
            .draw_series(line.iter().map(|&p| Circle::new(p, 4, colour.filled())))
            .map_err(|e| err(&e))?;
    }
    chart
        .configure_series_labels()
        .border_style(BLACK)
        .background_style(WHITE)
        .draw()
        .map_err(|e| err(&e))?;
    root.present().map_err(|e| err(&e))?;
    drop(chart);
    drop(root);
    Ok(vec![path])
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test
mod tests {
    use super::*;

    #[test]
    fn a_small_sequence_runs_checks_and_reports() {
        let points = run_sequence(2_000, &[0.01, 0.5], 2, &mut |_| {}).unwrap();
        assert_eq!(points.len(), 2);
        for p in &points {
            assert_eq!(p.recomputed.len(), STEPS + 1);
            assert_eq!(p.recomputed[0], p.n);
            assert!(p.full_seconds > 0.0 && p.tracker_seconds > 0.0);
            let (threads, seconds) = p.parallel.unwrap();
            assert_eq!(threads, 2);
            assert!(seconds > 0.0 && p.thread_speedup().unwrap() > 0.0);
        }
        // One thread asked: no second tracker, and the report says so.
        let single = run_sequence(2_000, &[0.01], 1, &mut |_| {}).unwrap();
        assert_eq!(single[0].parallel, None);
        assert!(sequence_md(&single).contains("| - | - |"));
        assert!(sequence_csv(&single)
            .lines()
            .nth(1)
            .unwrap()
            .contains(",1,,,"));
        // Small steps recompute far fewer particles than large ones.
        let total = |p: &SequencePoint| p.recomputed[1..].iter().sum::<usize>();
        assert!(total(&points[0]) * 4 < total(&points[1]));
        let csv = sequence_csv(&points);
        assert_eq!(csv.lines().count(), 3);
        assert!(sequence_md(&points).contains("| 0.5 |"));
        crate::plots::register_font().unwrap();
        let dir = tempfile::tempdir().unwrap();
        let written = write_plot(&points, dir.path()).unwrap();
        assert!(std::fs::metadata(&written[0]).unwrap().len() > 1000);
    }
}
