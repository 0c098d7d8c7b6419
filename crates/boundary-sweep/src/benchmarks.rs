//! `BENCHMARKS.md`: the short, committed summary of a sweep. Where `report.md` gives every
//! scene's confusion matrix, parameter grid and failure analysis, this page gives one table per
//! question a user asks (how accurate is each method, how fast, on which scene does it fail)
//! and says once, at the top, when, from which commit and on which machine the numbers were
//! measured, and the command that measures them again.

use crate::{report, Outcome, Row};
use std::fmt::Write as _;

/// When, where and how a sweep ran: the header of `BENCHMARKS.md`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Provenance {
    /// The UTC date of the run, `YYYY-MM-DD` ([`utc_date`]).
    pub date: String,
    /// The commit measured, as `git` names it, with a note when the tree had changes.
    pub commit: String,
    /// The machine in words: processor, cores, memory, operating system, load at the start.
    pub machine: String,
    /// The command that produced the page (and reproduces it).
    pub command: String,
}

/// The UTC calendar date (`YYYY-MM-DD`) of `secs` seconds after the Unix epoch, by the
/// proleptic Gregorian calendar (days to civil date: 400-year eras of 146097 days, with
/// March-based years so that the leap day falls at a year's end).
pub fn utc_date(secs: u64) -> String {
    let days = (secs / 86_400) as i64;
    let z = days + 719_468; // days from 0000-03-01 to 1970-01-01
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097); // day of era, 0..=146096
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365; // year of era
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100); // day of the March-based year
    let mp = (5 * doy + 2) / 153; // month from March = 0
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02}")
}

/// The default-parameter row of each (scene, method), in the sweep's order.
fn default_rows(outcome: &Outcome) -> impl Iterator<Item = &Row> {
    outcome.rows.iter().filter(|r| r.is_default)
}

/// Methods in first-seen order.
fn methods(outcome: &Outcome) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for row in default_rows(outcome) {
        if !names.contains(&row.method) {
            names.push(row.method.clone());
        }
    }
    names
}

/// Whether every default row that ran has a one-thread time (rows that failed or do not
/// apply have none, whatever the sweep's options).
fn has_one_thread(outcome: &Outcome) -> bool {
    default_rows(outcome)
        .filter(|r| r.confusion.is_some())
        .all(|r| r.seconds_1.is_some())
}

/// A resolution as the page shows it: six significant digits, trailing zeros dropped.
fn short(r: f64) -> String {
    let text = format!("{r:.5e}");
    match text.split_once('e') {
        Some((mantissa, exp)) => {
            let value: f64 = format!("{mantissa}e{exp}").parse().unwrap_or(r);
            let plain = format!("{value}");
            if plain.len() <= 12 {
                plain
            } else {
                text
            }
        }
        None => text,
    }
}

/// The time a summary compares: one thread when every row has it, else all threads.
fn seconds(row: &Row, one_thread: bool) -> Option<f64> {
    let s = if one_thread {
        row.seconds_1?
    } else {
        row.seconds_all
    };
    (s > 0.0 && row.confusion.is_some()).then_some(s)
}

fn median(mut values: Vec<f64>) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    values.sort_by(f64::total_cmp);
    let k = values.len() / 2;
    Some(if values.len() % 2 == 1 {
        values[k]
    } else {
        0.5 * (values[k - 1] + values[k])
    })
}

fn mean(values: &[f64]) -> Option<f64> {
    (!values.is_empty()).then(|| values.iter().sum::<f64>() / values.len() as f64)
}

fn or_dash(value: Option<String>) -> String {
    value.unwrap_or_else(|| "–".to_owned())
}

/// A cell of the per-scene tables: the value, `n/a` where the method does not apply to the
/// scene (it refuses the scene's domain or per-particle radii), `error` where it failed.
fn cell(row: Option<&Row>, value: impl Fn(&Row) -> Option<String>) -> String {
    match row {
        None => "–".to_owned(),
        Some(r) if r.unsupported => "n/a".to_owned(),
        Some(r) if r.error.is_some() => "error".to_owned(),
        Some(r) => or_dash(value(r)),
    }
}

/// A picture of the page: its dimension and its link, relative to the page's folder.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PagePicture {
    /// 2 or 3: the scenes it pools.
    pub dim: usize,
    /// The image's path as the page links it (`docs/img/speed_vs_error_2d.png`).
    pub link: String,
}

/// The text of `BENCHMARKS.md` for `outcome`, embedding the speed/error `pictures`
/// ([`crate::plots::write_benchmark_pictures`]) after the summary.
///
/// Accuracy is that of each method at its default parameters against `exact` on the same
/// scene; speed is particles per second on one thread (all threads when the sweep skipped the
/// one-thread runs), and the ratio to `exact` is taken per scene before its median, so that
/// large scenes do not dominate it. Scenes a method does not apply to are left out of its
/// means and medians and shown as `n/a`.
pub fn benchmarks_md(
    outcome: &Outcome,
    provenance: &Provenance,
    pictures: &[PagePicture],
) -> String {
    let mut md = String::new();
    let one_thread = has_one_thread(outcome);
    let threads = default_rows(outcome).map(|r| r.threads).max().unwrap_or(0);
    let scenes = report::scene_order(&outcome.rows);
    let methods = methods(outcome);
    let row_of = |scene: &str, method: &str| {
        default_rows(outcome).find(|r| r.scene == scene && r.method == method)
    };
    let _ = writeln!(md, "# Benchmarks\n");
    let _ = writeln!(
        md,
        "Generated by `{}` on {}, commit {}.  \nMachine: {}.\n",
        provenance.command, provenance.date, provenance.commit, provenance.machine
    );
    let _ = writeln!(
        md,
        "Run the same command to measure again: the accuracy is the same on every machine, the \
         times are this machine's (compare ratios rather than seconds). Every method runs at its \
         default parameters on {} scenes ({} 2D, {} 3D) of `fixtures/scenes.toml`, and is scored \
         against `exact` on the same scene: Rec = TP/(TP+FN), FPR = FP/(FP+TN), \
         M = Rec·(1−FPR), so M = 1 is a perfect score. Times are detection only (no file \
         reading), {}.\n",
        scenes.len(),
        scenes.iter().filter(|s| s.1 == 2).count(),
        scenes.iter().filter(|s| s.1 == 3).count(),
        if one_thread {
            "on one thread".to_owned()
        } else {
            format!("on {threads} threads")
        }
    );
    if !outcome.skipped.is_empty() {
        let _ = writeln!(md, "Skipped scenes (not in the tables):\n");
        for (scene, why) in &outcome.skipped {
            let _ = writeln!(md, "- `{scene}`: {why}");
        }
        md.push('\n');
    }

    let _ = writeln!(md, "## Summary per method\n");
    let _ = writeln!(
        md,
        "| method | certified | scenes | mean M (2D) | mean M (3D) | lowest M (scene) | scenes with a miss | median particles/s | median speed vs exact |\n\
         |---|---|---|---|---|---|---|---|---|"
    );
    for method in &methods {
        let rows: Vec<&Row> = default_rows(outcome)
            .filter(|r| &r.method == method && !r.unsupported && r.confusion.is_some())
            .collect();
        let m_of = |dim: usize| -> Vec<f64> {
            rows.iter()
                .filter(|r| r.dim == dim)
                .filter_map(|r| r.confusion.map(|c| c.m()))
                .collect()
        };
        let lowest = rows
            .iter()
            .filter_map(|r| r.confusion.map(|c| (c.m(), &r.scene)))
            .min_by(|a, b| a.0.total_cmp(&b.0));
        let missed = rows
            .iter()
            .filter(|r| r.confusion.is_some_and(|c| c.fn_ > 0))
            .count();
        let rates: Vec<f64> = rows
            .iter()
            .filter_map(|r| seconds(r, one_thread).map(|s| r.n as f64 / s))
            .collect();
        let ratios: Vec<f64> = rows
            .iter()
            .filter_map(|r| {
                let own = seconds(r, one_thread)?;
                let exact = seconds(row_of(&r.scene, "exact")?, one_thread)?;
                Some(exact / own)
            })
            .collect();
        let _ = writeln!(
            md,
            "| `{method}` | {} | {} | {} | {} | {} | {missed} | {} | {} |",
            if rows.first().is_some_and(|r| r.certified) {
                "yes"
            } else {
                "no"
            },
            rows.len(),
            or_dash(mean(&m_of(2)).map(|m| format!("{m:.4}"))),
            or_dash(mean(&m_of(3)).map(|m| format!("{m:.4}"))),
            or_dash(lowest.map(|(m, s)| {
                if m < 1.0 {
                    format!("{m:.4} (`{s}`)")
                } else {
                    "1 (every scene)".to_owned()
                }
            })),
            or_dash(median(rates).map(|v| format!("{v:.3e}"))),
            or_dash(median(ratios).map(|v| format!("{v:.2}"))),
        );
    }
    let _ = writeln!(
        md,
        "\n*certified*: the method promises no false negative (a missed boundary particle). \
         *Speed vs exact*: `exact`'s time over the method's on the same scene, the median over \
         the scenes; above 1 is faster than `exact`.\n"
    );
    if !pictures.is_empty() {
        let _ = writeln!(md, "## Speed against error\n");
        let _ = writeln!(
            md,
            "Each marker is a method at one parameter setting: its speed, the particles of the \
             scenes of one dimension over their total detection time ({}), against its error \
             1 − M, M of the confusion pooled over those scenes (a perfect score is drawn at \
             1e-5). Large labelled markers are the default parameters, as in the tables; \
             small outlines of the same marker are the other parameter values the sweep runs \
             (depths, thresholds, γ, tolerances). Lower right is better.\n",
            if has_one_thread(outcome) {
                "one thread"
            } else {
                "all threads"
            }
        );
        for picture in pictures {
            let _ = writeln!(
                md,
                "![{d}D: particles per second against 1 − M, one marker per method and \
                 parameter setting]({})\n",
                picture.link,
                d = picture.dim
            );
        }
    }

    let _ = writeln!(md, "## M per scene\n");
    table(&mut md, &scenes, &methods, &row_of, |r| {
        r.confusion.map(|c| format!("{:.4}", c.m()))
    });
    let _ = writeln!(
        md,
        "\n## Time per scene ({}, milliseconds)\n",
        if one_thread {
            "one thread".to_owned()
        } else {
            format!("{threads} threads")
        }
    );
    table(&mut md, &scenes, &methods, &row_of, |r| {
        seconds(r, one_thread).map(|s| format!("{:.2}", s * 1e3))
    });
    if let Some(scale) = &outcome.scale {
        md.push('\n');
        md.push_str(&report::scale_md(scale));
    }
    let _ = writeln!(
        md,
        "\nThe sweep's full report (`report.md` in its output folder, `target/sweep` by \
         default) adds each scene's confusion matrix, the parameter grids (depths, thresholds, \
         γ), timings on all threads, where each approximate method fails and the plots."
    );
    md
}

/// A scenes × methods table of `value` (see [`cell`]).
fn table<'a>(
    md: &mut String,
    scenes: &[(String, usize, usize, f64)],
    methods: &[String],
    row_of: &impl Fn(&str, &str) -> Option<&'a Row>,
    value: impl Fn(&Row) -> Option<String> + Copy,
) {
    let _ = write!(md, "| scene | D | \\|P\\| | r |");
    for m in methods {
        let _ = write!(md, " `{m}` |");
    }
    let _ = write!(md, "\n|---|---|---|---|");
    for _ in methods {
        md.push_str("---|");
    }
    md.push('\n');
    for (scene, dim, n, r) in scenes {
        let _ = write!(md, "| `{scene}` | {dim} | {n} | {} |", short(*r));
        for m in methods {
            let _ = write!(md, " {} |", cell(row_of(scene, m), value));
        }
        md.push('\n');
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use boundary::Confusion;

    #[test]
    fn utc_dates_across_leap_days_and_centuries() {
        assert_eq!(utc_date(0), "1970-01-01");
        assert_eq!(utc_date(86_399), "1970-01-01");
        assert_eq!(utc_date(86_400), "1970-01-02");
        // 2000 is a leap year (divisible by 400): 29 February exists.
        assert_eq!(utc_date(951_782_400), "2000-02-29");
        assert_eq!(utc_date(951_868_800), "2000-03-01");
        assert_eq!(utc_date(1_709_164_800), "2024-02-29");
        assert_eq!(utc_date(1_735_603_200), "2024-12-31");
        assert_eq!(utc_date(1_735_689_600), "2025-01-01");
        // 2100 is not a leap year: 28 February is followed by 1 March.
        assert_eq!(utc_date(4_107_456_000), "2100-02-28");
        assert_eq!(utc_date(4_107_542_400), "2100-03-01");
    }

    fn row(scene: &str, dim: usize, method: &str, c: Option<Confusion>, s1: f64) -> Row {
        Row {
            scene: scene.into(),
            dim,
            n: 1000,
            radius: 0.1,
            method: method.into(),
            params: String::new(),
            is_default: true,
            certified: method == "exact",
            misses: None,
            confusion: c,
            seconds_1: Some(s1),
            seconds_all: s1 / 2.0,
            threads: 2,
            error: None,
            unsupported: false,
            interface: None,
            interface_confusion: None,
        }
    }

    fn confusion(tp: u64, fp: u64, fn_: u64, tn: u64) -> Option<Confusion> {
        Some(Confusion { tp, fp, fn_, tn })
    }

    fn provenance() -> Provenance {
        Provenance {
            date: "2026-01-02".into(),
            commit: "abc123".into(),
            machine: "test machine, 2 cores".into(),
            command: "cargo xtask sweep".into(),
        }
    }

    #[test]
    fn summary_scores_each_method_against_exact_and_states_provenance_once() {
        let mut hpr_on_b = row("b", 3, "hpr", None, 1.0);
        hpr_on_b.unsupported = true;
        hpr_on_b.error = Some("refuses solids".into());
        let outcome = Outcome {
            rows: vec![
                row("a", 2, "exact", confusion(100, 0, 0, 900), 0.010),
                row("a", 2, "hpr", confusion(90, 100, 10, 800), 0.020),
                row("b", 3, "exact", confusion(50, 0, 0, 950), 0.040),
                hpr_on_b,
            ],
            ..Outcome::default()
        };
        let md = benchmarks_md(&outcome, &provenance(), &[]);
        assert_eq!(md.matches("commit abc123").count(), 1, "{md}");
        assert!(!md.contains("## Speed against error"), "{md}");
        assert!(md.contains("Generated by `cargo xtask sweep` on 2026-01-02"));
        assert!(md.contains("Machine: test machine, 2 cores."));
        // hpr on `a`: Rec 0.9, FPR 100/900, M = 0.9 · 8/9 = 0.8; half exact's speed; one
        // scene with a miss; `b` left out of its summary and shown as n/a.
        assert!(
            md.contains("| `hpr` | no | 1 | 0.8000 | – | 0.8000 (`a`) | 1 | 5.000e4 | 0.50 |"),
            "{md}"
        );
        assert!(
            md.contains("| `exact` | yes | 2 | 1.0000 | 1.0000 | 1 (every scene) | 0 |"),
            "{md}"
        );
        assert!(
            md.contains("| `b` | 3 | 1000 | 0.1 | 1.0000 | n/a |"),
            "{md}"
        );
        // Time table in milliseconds, one thread.
        assert!(md.contains("## Time per scene (one thread, milliseconds)"));
        assert!(
            md.contains("| `a` | 2 | 1000 | 0.1 | 10.00 | 20.00 |"),
            "{md}"
        );
    }

    #[test]
    fn rows_that_did_not_run_do_not_turn_the_times_to_all_threads() {
        let mut refused = row("a", 2, "hpr", None, 0.0);
        refused.seconds_1 = None;
        refused.unsupported = true;
        let md = benchmarks_md(
            &Outcome {
                rows: vec![row("a", 2, "exact", confusion(1, 0, 0, 1), 0.003), refused],
                ..Outcome::default()
            },
            &provenance(),
            &[],
        );
        assert!(
            md.contains("## Time per scene (one thread, milliseconds)"),
            "{md}"
        );
        assert!(md.contains("| 3.00 | n/a |"), "{md}");
    }

    #[test]
    fn the_speed_pictures_are_embedded_after_the_summary() {
        let outcome = Outcome {
            rows: vec![row("a", 2, "exact", confusion(1, 0, 0, 1), 0.003)],
            ..Outcome::default()
        };
        let pictures = [2, 3].map(|dim| PagePicture {
            dim,
            link: format!("docs/img/speed_vs_error_{dim}d.png"),
        });
        let md = benchmarks_md(&outcome, &provenance(), &pictures);
        let section = md.find("## Speed against error").expect("the section");
        assert!(md.find("## Summary per method").unwrap() < section, "{md}");
        assert!(section < md.find("## M per scene").unwrap(), "{md}");
        assert!(md.contains("(docs/img/speed_vs_error_2d.png)"), "{md}");
        assert!(md.contains("(docs/img/speed_vs_error_3d.png)"), "{md}");
        assert!(md.contains("one thread"), "{md}");
    }

    #[test]
    fn resolutions_are_shown_with_six_significant_digits() {
        assert_eq!(short(0.018750000000000003), "0.01875");
        assert_eq!(short(std::f64::consts::FRAC_1_SQRT_2), "0.707107");
        assert_eq!(short(0.0075), "0.0075");
        assert_eq!(short(1.2), "1.2");
        assert_eq!(short(2.5e-12), "2.50000e-12");
    }

    #[test]
    fn without_one_thread_runs_the_all_thread_times_are_compared_and_said_so() {
        let mut exact = row("a", 2, "exact", confusion(1, 0, 0, 1), 0.0);
        exact.seconds_1 = None;
        exact.seconds_all = 0.004;
        let md = benchmarks_md(
            &Outcome {
                rows: vec![exact],
                ..Outcome::default()
            },
            &provenance(),
            &[],
        );
        assert!(
            md.contains("## Time per scene (2 threads, milliseconds)"),
            "{md}"
        );
        assert!(md.contains("| `a` | 2 | 1000 | 0.1 | 4.00 |"), "{md}");
    }

    #[test]
    fn skipped_scenes_and_failed_runs_are_listed_not_averaged() {
        let mut failed = row("a", 2, "ia", None, 0.01);
        failed.error = Some("out of memory".into());
        let md = benchmarks_md(
            &Outcome {
                rows: vec![row("a", 2, "exact", confusion(1, 0, 0, 1), 0.01), failed],
                skipped: vec![("vortex".into(), "file not found".into())],
                ..Outcome::default()
            },
            &provenance(),
            &[],
        );
        assert!(md.contains("- `vortex`: file not found"), "{md}");
        assert!(
            md.contains("| `ia` | no | 0 | – | – | – | 0 | – | – |"),
            "{md}"
        );
        assert!(md.contains("| 1.0000 | error |"), "{md}");
    }
}
