//! `results.csv` and `report.md` from sweep rows.

use crate::published::{experiment_for, ACCURACY, EXPERIMENTS, TIMINGS};
use crate::{Outcome, Row};
use std::fmt::Write as _;

/// The CSV columns, in order.
pub const CSV_HEADER: &str =
    "scene,dim,n,r,method,parameters,TP,TN,FP,FN,Rec,FPR,M,seconds_1_thread,seconds_all_threads,threads,error";

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_owned()
    }
}

/// `results.csv`: one line per row.
pub fn results_csv(rows: &[Row]) -> String {
    let mut out = String::from(CSV_HEADER);
    out.push('\n');
    for row in rows {
        let (counts, scores) = match row.confusion {
            Some(c) => (
                format!("{},{},{},{}", c.tp, c.tn, c.fp, c.fn_),
                format!("{:.6},{:.6},{:.6}", c.recall(), c.fpr(), c.m()),
            ),
            None => (",,,".into(), ",,".into()),
        };
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{},{}",
            csv_field(&row.scene),
            row.dim,
            row.n,
            row.radius,
            row.method,
            csv_field(&row.params),
            counts,
            scores,
            row.seconds_1.map(|s| format!("{s:.6}")).unwrap_or_default(),
            format_args!("{:.6}", row.seconds_all),
            row.threads,
            csv_field(row.error.as_deref().unwrap_or("")),
        );
    }
    out
}

fn label(row: &Row) -> String {
    if row.params.is_empty() {
        row.method.clone()
    } else {
        format!("{} ({})", row.method, row.params)
    }
}

fn rate(n: usize, seconds: f64) -> String {
    if seconds > 0.0 {
        format!("{:.3e}", n as f64 / seconds)
    } else {
        "-".into()
    }
}

/// `report.md`: accuracy per scene (JCP Tables 1–2 layout), timings (JCP Table 3 layout),
/// depth sweeps, and the paper's figures where a scene corresponds.
pub fn report_md(outcome: &Outcome, header: &str) -> String {
    let mut md = String::new();
    let _ = writeln!(md, "# Boundary detection sweep\n\n{header}\n");
    let _ = writeln!(
        md,
        "Accuracy is measured against `exact` (restricted Voronoi cells): Rec = TP/(TP+FN), \
         FPR = FP/(FP+TN), M = Rec·(1−FPR). Times are detection only (no IO), best of one run; \
         the machine is shared, so compare ratios within this run.\n"
    );
    if !outcome.skipped.is_empty() {
        let _ = writeln!(md, "## Skipped scenes\n");
        for (scene, why) in &outcome.skipped {
            let _ = writeln!(md, "- `{scene}`: {why}");
        }
        md.push('\n');
    }
    if !outcome.count_mismatches.is_empty() {
        let _ = writeln!(md, "## Reference count mismatches\n");
        for (scene, got, expected) in &outcome.count_mismatches {
            let _ = writeln!(md, "- `{scene}`: exact found {got}, expected {expected}");
        }
        md.push('\n');
    }

    let scenes = scene_order(&outcome.rows);
    let _ = writeln!(
        md,
        "## Accuracy at default parameters (JCP Tables 1–2 layout)\n"
    );
    for (scene, dim, n, r) in &scenes {
        let _ = writeln!(md, "### `{scene}` ({dim}D, |P| = {n}, r = {r})\n");
        let _ = writeln!(
            md,
            "| Method | Rec | FPR | M | TP | FP | FN | s (1 thread) | s (all) |\n|---|---|---|---|---|---|---|---|---|"
        );
        for row in outcome
            .rows
            .iter()
            .filter(|row| &row.scene == scene && row.is_default)
        {
            let _ = writeln!(md, "{}", accuracy_line(row));
        }
        if let Some(exp) = experiment_for(scene, *dim) {
            let desc = EXPERIMENTS
                .iter()
                .find(|e| e.0 == exp)
                .map(|e| e.2)
                .unwrap_or("");
            let _ = writeln!(
                md,
                "\nPublished for the corresponding experiment, {exp} ({desc}):\n"
            );
            let _ = writeln!(md, "| Method | Rec | FPR | M |\n|---|---|---|---|");
            for p in ACCURACY.iter().filter(|p| p.experiment == exp) {
                let _ = writeln!(
                    md,
                    "| {} (paper) | {:.4} | {:.4} | {:.4} |",
                    p.method, p.rec, p.fpr, p.m
                );
            }
        }
        md.push('\n');
    }

    let pictures: Vec<(String, String)> = outcome
        .failure_pictures
        .iter()
        .map(|p| {
            (
                p.method.clone(),
                crate::plots::failure_file(&p.method, "png"),
            )
        })
        .collect();
    md.push_str(&crate::failures::section_md(
        &outcome.rows,
        &outcome.about,
        &pictures,
    ));

    let _ = writeln!(md, "## Timings (JCP Table 3 layout)\n");
    let _ = writeln!(
        md,
        "rate = time of `dilts` (the Haque–Dilts covering test, the papers' ground truth) over the \
         method's time, both on one thread; >1 means faster than dilts.\n"
    );
    let _ = writeln!(
        md,
        "| Scene | \\|P\\| | Method | 1 thread (s) | all threads (s) | speedup | particles/s (all) | rate vs dilts |\n|---|---|---|---|---|---|---|---|"
    );
    for (scene, _, n, _) in &scenes {
        let dilts = outcome
            .rows
            .iter()
            .find(|r| &r.scene == scene && r.method == "dilts" && r.is_default)
            .and_then(|r| r.seconds_1);
        for row in outcome
            .rows
            .iter()
            .filter(|row| &row.scene == scene && row.is_default)
        {
            let speedup = row
                .seconds_1
                .filter(|_| row.seconds_all > 0.0)
                .map(|s| format!("{:.2}", s / row.seconds_all))
                .unwrap_or_else(|| "-".into());
            let vs = match (dilts, row.seconds_1) {
                (Some(d), Some(s)) if s > 0.0 => format!("{:.2}", d / s),
                _ => "-".into(),
            };
            let _ = writeln!(
                md,
                "| `{scene}` | {n} | {} | {} | {:.4} | {speedup} | {} | {vs} |",
                row.method,
                row.seconds_1
                    .map(|s| format!("{s:.4}"))
                    .unwrap_or_else(|| "-".into()),
                row.seconds_all,
                rate(row.n, row.seconds_all),
            );
        }
    }
    md.push_str(&parallel_efficiency(outcome));
    let _ = writeln!(md, "\nPublished (JCP Table 3, i7-8750H, 1 and 6 cores):\n");
    let _ = writeln!(
        md,
        "| Experiment | Method | 1 core (s) | 6 cores (s) | speedup | rate |\n|---|---|---|---|---|---|"
    );
    for t in TIMINGS {
        let _ = writeln!(
            md,
            "| {} | {} | {:.2} | {} | {} | {:.2} |",
            t.experiment,
            t.method,
            t.one_core,
            t.six_core
                .map(|s| format!("{s:.2}"))
                .unwrap_or_else(|| "-".into()),
            t.speedup
                .map(|s| format!("{s:.2}"))
                .unwrap_or_else(|| "-".into()),
            t.rate
        );
    }

    let swept: Vec<&Row> = outcome.rows.iter().filter(|r| !r.is_default).collect();
    if !swept.is_empty() {
        let _ = writeln!(md, "\n## Parameter sweeps\n");
        let _ = writeln!(
            md,
            "| Scene | Method | FP | FN | Rec | FPR | M | s (all) |\n|---|---|---|---|---|---|---|---|"
        );
        for row in swept {
            let (fp, fn_, rec, fpr, m) = match row.confusion {
                Some(c) => (
                    c.fp.to_string(),
                    c.fn_.to_string(),
                    format!("{:.4}", c.recall()),
                    format!("{:.4}", c.fpr()),
                    format!("{:.4}", c.m()),
                ),
                None => Default::default(),
            };
            let _ = writeln!(
                md,
                "| `{}` | {} | {fp} | {fn_} | {rec} | {fpr} | {m} | {:.4} |",
                row.scene,
                label(row),
                row.seconds_all
            );
        }
    }
    let failures: Vec<&Row> = outcome
        .rows
        .iter()
        .filter(|r| r.error.is_some() && !r.unsupported)
        .collect();
    if !failures.is_empty() {
        let _ = writeln!(md, "\n## Failed runs\n");
        for row in failures {
            let _ = writeln!(
                md,
                "- `{}` {}: {}",
                row.scene,
                label(row),
                row.error.as_deref().unwrap_or("")
            );
        }
    }
    md
}

/// Per method, pooled over the scenes timed both ways at default parameters: the speedup
/// `Σ t(1 thread) / Σ t(all threads)` and the parallel efficiency `speedup / threads`, flagged
/// where more threads made the method slower.
fn parallel_efficiency(outcome: &Outcome) -> String {
    let mut md = String::new();
    let mut methods: Vec<&str> = Vec::new();
    for row in &outcome.rows {
        if row.is_default && !methods.contains(&row.method.as_str()) {
            methods.push(&row.method);
        }
    }
    let mut lines = Vec::new();
    for method in methods {
        let timed: Vec<&Row> = outcome
            .rows
            .iter()
            .filter(|r| r.method == method && r.is_default && r.seconds_1.is_some())
            .collect();
        let one: f64 = timed.iter().filter_map(|r| r.seconds_1).sum();
        let all: f64 = timed.iter().map(|r| r.seconds_all).sum();
        let Some(threads) = timed.first().map(|r| r.threads) else {
            continue;
        };
        if all <= 0.0 || threads < 2 {
            continue;
        }
        let speedup = one / all;
        lines.push(format!(
            "| {method} | {} | {one:.3} | {all:.3} | {threads} | {speedup:.2} | {:.2}{} |",
            timed.len(),
            speedup / threads as f64,
            if speedup < 1.0 {
                " (slower with more threads)"
            } else {
                ""
            }
        ));
    }
    if lines.is_empty() {
        return md;
    }
    let _ = writeln!(
        md,
        "\nParallel efficiency per method, pooled over the scenes above (small scenes: the \
         thread start-up weighs; one run):\n\n| Method | scenes | 1 thread (s) | all threads (s) | \
         threads | speedup | efficiency |\n|---|---|---|---|---|---|---|"
    );
    for line in lines {
        let _ = writeln!(md, "{line}");
    }
    md
}

fn accuracy_line(row: &Row) -> String {
    let t1 = row
        .seconds_1
        .map(|s| format!("{s:.4}"))
        .unwrap_or_else(|| "-".into());
    match (row.confusion, &row.error) {
        (Some(c), _) => format!(
            "| {} | {:.4} | {:.4} | {:.4} | {} | {} | {} | {t1} | {:.4} |",
            label(row),
            c.recall(),
            c.fpr(),
            c.m(),
            c.tp,
            c.fp,
            c.fn_,
            row.seconds_all
        ),
        (None, _) if row.unsupported => format!(
            "| {} | n/a: no per-particle radii | | | | | | | |",
            label(row)
        ),
        (None, error) => format!(
            "| {} | failed: {} | | | | | | | |",
            label(row),
            error.as_deref().unwrap_or("")
        ),
    }
}

/// Scenes in first-seen order with (name, dim, n, r).
pub fn scene_order(rows: &[Row]) -> Vec<(String, usize, usize, f64)> {
    let mut seen: Vec<(String, usize, usize, f64)> = Vec::new();
    for row in rows {
        if !seen.iter().any(|s| s.0 == row.scene) {
            seen.push((row.scene.clone(), row.dim, row.n, row.radius));
        }
    }
    seen
}

#[cfg(test)]
mod tests {
    use super::*;
    use boundary::Confusion;

    fn row(method: &str, params: &str, c: Confusion, t1: f64, t: f64) -> Row {
        Row {
            scene: "sandim_vortex_spin_frame_001_1698".into(),
            dim: 2,
            n: 10,
            radius: 0.5,
            method: method.into(),
            params: params.into(),
            is_default: params.is_empty() || params == "depth=6",
            certified: method != "svm",
            misses: None,
            confusion: Some(c),
            seconds_1: Some(t1),
            seconds_all: t,
            threads: 2,
            error: None,
            unsupported: false,
        }
    }

    fn sample() -> Outcome {
        let c = Confusion {
            tp: 3,
            tn: 6,
            fp: 1,
            fn_: 0,
        };
        Outcome {
            rows: vec![
                row("exact", "", c, 0.2, 0.1),
                row("dilts", "", c, 2.0, 1.0),
                row("ia", "depth=6", c, 0.5, 0.25),
                row("ia", "depth=2", c, 0.1, 0.05),
            ],
            skipped: vec![("gone".into(), "no such file".into())],
            ..Default::default()
        }
    }

    #[test]
    fn csv_has_one_line_per_row_and_the_documented_columns() {
        let csv = results_csv(&sample().rows);
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines.len(), 5);
        assert_eq!(lines[0], CSV_HEADER);
        let cols = CSV_HEADER.split(',').count();
        for line in &lines[1..] {
            // "depth=6" has no comma; every line has the header's column count.
            assert_eq!(line.split(',').count(), cols, "{line}");
        }
        assert!(
            lines[3].starts_with("sandim_vortex_spin_frame_001_1698,2,10,0.5,ia,depth=6,3,6,1,0,")
        );
    }

    #[test]
    fn report_has_rates_against_dilts_and_the_published_rows() {
        let md = report_md(&sample(), "test");
        // ia: dilts 2.0 s / ia 0.5 s on one thread = 4.00, speedup 0.5/0.25 = 2.00.
        assert!(
            md.contains("| ia | 0.5000 | 0.2500 | 2.00 | 4.000e1 | 4.00 |"),
            "{md}"
        );
        assert!(md.contains("Published for the corresponding experiment, JCP Fig. 9"));
        assert!(md.contains("| ge (paper) | 1.0000 | 0.0472 | 0.9528 |"));
        assert!(md.contains("`gone`: no such file"));
        assert!(md.contains("## Parameter sweeps"));
        assert!(md.contains("ia (depth=2)"));
    }

    /// The pooled speedup is Σ t1 / Σ t over the default rows of a method, and a method that
    /// got slower with more threads is flagged.
    #[test]
    fn parallel_efficiency_pools_the_scenes_and_flags_slowdowns() {
        let c = Confusion {
            tp: 1,
            tn: 1,
            fp: 0,
            fn_: 0,
        };
        let mut outcome = sample();
        let mut other = row("exact", "", c, 0.6, 0.3);
        other.scene = "second".into();
        outcome.rows.push(other);
        outcome.rows.push(row("hpr", "", c, 0.1, 0.2));
        let md = report_md(&outcome, "test");
        // exact: (0.2 + 0.6) / (0.1 + 0.3) = 2.00 on 2 threads: efficiency 1.00.
        assert!(
            md.contains("| exact | 2 | 0.800 | 0.400 | 2 | 2.00 | 1.00 |"),
            "{md}"
        );
        assert!(
            md.contains("| ia | 1 | 0.500 | 0.250 | 2 | 2.00 | 1.00 |"),
            "{md}"
        );
        assert!(
            md.contains("| hpr | 1 | 0.100 | 0.200 | 2 | 0.50 | 0.25 (slower with more threads) |"),
            "{md}"
        );
    }
}
