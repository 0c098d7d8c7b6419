//! `results.csv` and `report.md` from sweep rows.

use crate::published::{experiment_for, ACCURACY, EXPERIMENTS, TIMINGS};
use crate::scale::{ScaleOutcome, ScaleRow, ThreadRun};
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

    md.push_str(&domains_md(outcome));

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
    md.push_str(&speed_spread(outcome));
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
    if let Some(scale) = &outcome.scale {
        md.push('\n');
        md.push_str(&scale_md(scale));
    }

    md.push_str(&divr_md(&outcome.rows));
    md.push_str(&randles_md(&outcome.rows));

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

/// The value of `key` in a row's `key=value, …` parameter text.
fn param<'a>(params: &'a str, key: &str) -> Option<&'a str> {
    params
        .split(", ")
        .find_map(|kv| kv.strip_prefix(key)?.strip_prefix('='))
}

/// `divr` with each solver's published threshold, side by side per scene: what each code's
/// default costs in false positives and negatives against `exact`. Empty without `divr` rows.
fn divr_md(rows: &[Row]) -> String {
    let divr: Vec<&Row> = rows.iter().filter(|r| r.method == "divr").collect();
    if divr.is_empty() {
        return String::new();
    }
    let mut md = String::from(
        "\n## Divergence of position: each solver's threshold\n\n`divr` with the threshold \
         each code publishes (DualSPHysics, SPHinXsys with and without its second layer, \
         Chrono::FSI), against `exact`.\n\n| Scene | threshold | FP | FN | Rec | FPR | M |\n\
         |---|---|---|---|---|---|---|\n",
    );
    for row in divr {
        let threshold = param(&row.params, "threshold").unwrap_or("dualsphysics");
        let layers = match param(&row.params, "layers") {
            Some("1") => " + layer",
            _ => "",
        };
        let cells = match row.confusion {
            Some(c) => format!(
                "{} | {} | {:.4} | {:.4} | {:.4}",
                c.fp,
                c.fn_,
                c.recall(),
                c.fpr(),
                c.m()
            ),
            None => row.error.clone().unwrap_or_default(),
        };
        let _ = writeln!(md, "| `{}` | {threshold}{layers} | {cells} |", row.scene);
    }
    md
}

/// The `mu` a `randles` row used on its scene: `mu_2d` or `mu_3d` of its parameters.
fn randles_mu(row: &Row) -> Option<f64> {
    let key = if row.dim == 2 { "mu_2d=" } else { "mu_3d=" };
    row.params
        .split(", ")
        .find_map(|kv| kv.strip_prefix(key))
        .and_then(|v| v.parse().ok())
}

/// The Randles–Doring section: per dimension, mean M over the scenes for every `mu` run, the
/// best `mu` of each scene, and the mean loss of M at the best common `mu` against each
/// scene's own best. This is the measurement behind "could not find a suitable μ for 3D"
/// (Bubbles): a criterion unstable in 3D would show per-scene optima far apart and a large
/// loss. Empty without `randles` rows.
pub fn randles_md(rows: &[Row]) -> String {
    let mut md = String::new();
    // (dim, scene) -> [(mu, M)].
    type SceneRuns = ((usize, String), Vec<(f64, f64)>);
    let mut by_scene: Vec<SceneRuns> = Vec::new();
    for row in rows.iter().filter(|r| r.method == "randles") {
        let (Some(mu), Some(c)) = (randles_mu(row), row.confusion) else {
            continue;
        };
        let key = (row.dim, row.scene.clone());
        match by_scene.iter_mut().find(|(k, _)| *k == key) {
            Some((_, v)) => v.push((mu, c.m())),
            None => by_scene.push((key, vec![(mu, c.m())])),
        }
    }
    if by_scene.is_empty() {
        return md;
    }
    let _ = writeln!(
        md,
        "\n## Randles–Doring (`randles`) by dimension\n\nM against `exact` for each `mu` run \
         (free surface iff the smallest eigenvalue of the renormalisation matrix is at most \
         `mu`). The defaults were tuned on generated scenes disjoint from these \
         (boundary-randles' `tests/threshold.rs`).\n"
    );
    let _ = writeln!(
        md,
        "| dim | scenes | best common mu | its mean M | per-scene best mu | mean loss of M at the common mu | mean M at 0.45 (Bubbles, 2D) | mean M at 0.75 (Marrone's interior cut) |\n|---|---|---|---|---|---|---|---|"
    );
    let mut verdicts = Vec::new();
    for dim in [2, 3] {
        let scenes: Vec<&Vec<(f64, f64)>> = by_scene
            .iter()
            .filter(|((d, _), _)| *d == dim)
            .map(|(_, v)| v)
            .collect();
        if scenes.is_empty() {
            continue;
        }
        // The mus every scene ran, in increasing order.
        let mut mus: Vec<f64> = scenes[0].iter().map(|&(mu, _)| mu).collect();
        mus.retain(|mu| scenes.iter().all(|v| v.iter().any(|(m, _)| m == mu)));
        mus.sort_by(f64::total_cmp);
        mus.dedup();
        let m_at = |v: &Vec<(f64, f64)>, mu: f64| {
            v.iter().find(|(m, _)| *m == mu).map_or(0.0, |&(_, x)| x)
        };
        let mean_at =
            |mu: f64| scenes.iter().map(|v| m_at(v, mu)).sum::<f64>() / scenes.len() as f64;
        let Some(&common) = mus.iter().fold(None, |b: Option<&f64>, mu| match b {
            Some(b) if mean_at(*b) >= mean_at(*mu) => Some(b),
            _ => Some(mu),
        }) else {
            continue;
        };
        let best_of = |v: &Vec<(f64, f64)>| {
            v.iter().filter(|(m, _)| mus.contains(m)).fold(
                (0.0, f64::NEG_INFINITY),
                |b, &(m, x)| if x > b.1 { (m, x) } else { b },
            )
        };
        let lo = scenes
            .iter()
            .map(|v| best_of(v).0)
            .fold(f64::INFINITY, f64::min);
        let hi = scenes.iter().map(|v| best_of(v).0).fold(0.0, f64::max);
        let loss = scenes
            .iter()
            .map(|v| best_of(v).1 - m_at(v, common))
            .sum::<f64>()
            / scenes.len() as f64;
        let at = |mu: f64| {
            if mus.contains(&mu) {
                format!("{:.4}", mean_at(mu))
            } else {
                "–".to_owned()
            }
        };
        let _ = writeln!(
            md,
            "| {dim}D | {} | {common} | {:.4} | {lo} to {hi} | {loss:.4} | {} | {} |",
            scenes.len(),
            mean_at(common),
            at(0.45),
            at(0.75)
        );
        verdicts.push((dim, loss, hi - lo));
    }
    if let (Some(&(_, loss2, spread2)), Some(&(_, loss3, spread3))) = (
        verdicts.iter().find(|v| v.0 == 2),
        verdicts.iter().find(|v| v.0 == 3),
    ) {
        let stable = loss3 <= 2.0 * loss2.max(0.01) && spread3 <= 2.0 * spread2.max(0.05);
        let _ = writeln!(
            md,
            "\n{} One `mu` costs the 3D scenes {loss3:.4} of M on average against their own best \
             (2D: {loss2:.4}); their best `mu` spread over {spread3:.3} (2D: {spread2:.3}).",
            if stable {
                "**Not unstable in 3D on these scenes:** a suitable `mu` exists."
            } else {
                "**Unstable in 3D on these scenes:** no single `mu` serves them as one does in 2D."
            }
        );
    }
    md
}

/// The methods with a row at default parameters, in the order of their first row.
fn default_methods(outcome: &Outcome) -> Vec<&str> {
    let mut methods: Vec<&str> = Vec::new();
    for row in &outcome.rows {
        if row.is_default && !methods.contains(&row.method.as_str()) {
            methods.push(&row.method);
        }
    }
    methods
}

/// Per method, pooled over the scenes timed both ways at default parameters: the speedup
/// `Σ t(1 thread) / Σ t(all threads)` and the parallel efficiency `speedup / threads`, flagged
/// where more threads made the method slower.
fn parallel_efficiency(outcome: &Outcome) -> String {
    let mut md = String::new();
    let methods = default_methods(outcome);
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

/// Scenes below this size are left out of the report's speed spread (each method's slowest
/// scene against its median rate): their times are mostly start-up (grid, thread pool), not
/// the method.
pub const SPREAD_MIN_PARTICLES: usize = 1000;
/// The spread a method may show: its slowest scene within this factor of its median
/// rate over the scenes.
pub const SPREAD_BOUND: f64 = 3.0;

/// The median of `v` (the mean of the middle two for an even count); `None` when empty.
fn median(mut v: Vec<f64>) -> Option<f64> {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    match n {
        0 => None,
        _ if n % 2 == 1 => Some(v[n / 2]),
        _ => Some(0.5 * (v[n / 2 - 1] + v[n / 2])),
    }
}

/// Per method, its one-thread rate (particles/s, default parameters) over the scenes of at
/// least [`SPREAD_MIN_PARTICLES`]: the median, the slowest scene and the ratio between them,
/// flagged beyond [`SPREAD_BOUND`]; beside it, how much denser that scene's neighbourhoods
/// are than the median scene's (mean neighbours within `2r`), since every method reads them.
fn speed_spread(outcome: &Outcome) -> String {
    let neighbours = |scene: &str| {
        outcome
            .neighbours
            .iter()
            .find(|(s, _)| s == scene)
            .map(|&(_, k)| k)
    };
    let methods = default_methods(outcome);
    let mut lines = Vec::new();
    for method in methods {
        let timed: Vec<(&Row, f64)> = outcome
            .rows
            .iter()
            .filter(|r| {
                r.method == method
                    && r.is_default
                    && r.error.is_none()
                    && r.n >= SPREAD_MIN_PARTICLES
            })
            .filter_map(|r| {
                r.seconds_1
                    .filter(|&s| s > 0.0)
                    .map(|s| (r, r.n as f64 / s))
            })
            .collect();
        let Some(mid) = median(timed.iter().map(|&(_, rate)| rate).collect()) else {
            continue;
        };
        let Some(&(slowest, low)) = timed.iter().min_by(|a, b| a.1.total_cmp(&b.1)) else {
            continue;
        };
        let ratio = mid / low;
        let density = match (
            neighbours(&slowest.scene),
            median(
                timed
                    .iter()
                    .filter_map(|(r, _)| neighbours(&r.scene))
                    .collect(),
            ),
        ) {
            (Some(k), Some(k_mid)) if k_mid > 0.0 => {
                format!("{k:.0} / {k_mid:.0} = {:.2}", k / k_mid)
            }
            _ => "-".into(),
        };
        lines.push(format!(
            "| {method} | {} | {mid:.3e} | `{}` | {low:.3e} | {ratio:.2}{} | {density} |",
            timed.len(),
            slowest.scene,
            if ratio > SPREAD_BOUND {
                format!(" (> {SPREAD_BOUND}x)")
            } else {
                String::new()
            }
        ));
    }
    if lines.is_empty() {
        return String::new();
    }
    let mut md = String::new();
    let _ = writeln!(
        md,
        "
Speed across scenes: one-thread particles/s at default parameters over the scenes of \
         at least {SPREAD_MIN_PARTICLES} particles; the goal is the slowest within \
         {SPREAD_BOUND}x of the median. Neighbours: mean number of particles within 2r on the \
         slowest scene / the median over the same scenes (one run):\n\n| Method | scenes | \
         median | slowest scene | its particles/s | median / slowest | neighbours |\n\
         |---|---|---|---|---|---|---|"
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
            "| {} | n/a: {} | | | | | | | |",
            label(row),
            row.error.as_deref().unwrap_or("does not apply")
        ),
        (None, error) => format!(
            "| {} | failed: {} | | | | | | | |",
            label(row),
            error.as_deref().unwrap_or("")
        ),
    }
}

/// The section on the scenes with a domain (walls, solids, periodic axes, phases): what each
/// holds, its picture, and per method at default parameters the free-surface score against
/// `exact` in the same domain and, with phases, the interface count and score.
pub fn domains_md(outcome: &Outcome) -> String {
    let mut md = String::new();
    if outcome.domains.is_empty() {
        return md;
    }
    let _ = writeln!(
        md,
        "## Scenes with a domain
"
    );
    let _ = writeln!(
        md,
        "Walls and periodic images cover and get no label; solid half-spaces cover what lies \
         in them. Every method runs in the scene's domain and is scored against `exact` in the \
         same domain; `n/a` marks a method that cannot honour part of it (it refuses rather \
         than ignoring it). With phases, a particle is on an interface when only its own \
         phase (and the walls) leave its sphere uncovered.\n"
    );
    for (scene, about) in &outcome.domains {
        let Some(exact) = outcome
            .rows
            .iter()
            .find(|r| &r.scene == scene && r.method == "exact" && r.is_default)
        else {
            continue;
        };
        let truth = exact.confusion.map_or(0, |c| c.tp + c.fn_);
        let _ = writeln!(
            md,
            "### `{scene}` ({}D, |P| = {}, r = {}): {about}\n",
            exact.dim, exact.n, exact.radius
        );
        let mut line = format!("`exact`: {truth} free-surface particles");
        if let Some(k) = exact.interface {
            let _ = write!(line, ", {k} on an interface");
        }
        let _ = writeln!(
            md,
            "{line}. ![exact labels]({})\n",
            crate::plots::domain_file(scene, "png")
        );
        let phases = exact.interface.is_some();
        let _ = writeln!(
            md,
            "| Method | Rec | FPR | M | FP | FN |{}\n|---|---|---|---|---|---|{}",
            if phases {
                " interface | interface M |"
            } else {
                ""
            },
            if phases { "---|---|" } else { "" }
        );
        for row in outcome
            .rows
            .iter()
            .filter(|r| &r.scene == scene && r.is_default)
        {
            let extra = if phases {
                format!(
                    " {} | {} |",
                    row.interface.map_or("".into(), |k| k.to_string()),
                    row.interface_confusion
                        .map_or("".into(), |c| format!("{:.4}", c.m()))
                )
            } else {
                String::new()
            };
            let _ = match (row.confusion, &row.error) {
                (Some(c), _) => writeln!(
                    md,
                    "| {} | {:.4} | {:.4} | {:.4} | {} | {} |{extra}",
                    row.method,
                    c.recall(),
                    c.fpr(),
                    c.m(),
                    c.fp,
                    c.fn_
                ),
                (None, error) => writeln!(
                    md,
                    "| {} | {}: {} | | | | |{}",
                    row.method,
                    if row.unsupported { "n/a" } else { "failed" },
                    error.as_deref().unwrap_or(""),
                    if phases { " | |" } else { "" }
                ),
            };
        }
        md.push('\n');
    }
    md
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

/// The columns of `scale.csv`, in order.
pub const SCALE_CSV_HEADER: &str = "scene,dim,n,r,method,threads,runs,seconds_median,seconds_runs,particles_per_s,peak_bytes,bytes_per_particle,TP,TN,FP,FN,Rec,FPR,M,skipped";

/// `scale.csv`: one line per (scale scene, method); `seconds_runs` lists every run, `;`-separated.
pub fn scale_csv(scale: &ScaleOutcome) -> String {
    let mut out = String::from(SCALE_CSV_HEADER);
    out.push('\n');
    for row in &scale.rows {
        let opt =
            |v: Option<f64>, digits: usize| v.map(|v| format!("{v:.digits$}")).unwrap_or_default();
        let runs: Vec<String> = row.seconds.iter().map(|s| format!("{s:.6}")).collect();
        let scores = match row.confusion {
            Some(c) => format!(
                "{},{},{},{},{:.6},{:.6},{:.6}",
                c.tp,
                c.tn,
                c.fp,
                c.fn_,
                c.recall(),
                c.fpr(),
                c.m()
            ),
            None => ",,,,,,".into(),
        };
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            row.scene,
            row.dim,
            row.n,
            row.radius,
            row.method,
            row.threads,
            row.seconds.len(),
            opt(row.median(), 6),
            runs.join(";"),
            opt(row.rate(), 1),
            row.peak_bytes.map(|b| b.to_string()).unwrap_or_default(),
            opt(row.bytes_per_particle(), 1),
            scores,
            csv_field(row.skipped.as_deref().unwrap_or("")),
        );
    }
    out
}

/// The methods of the scale rows, in first-seen order.
fn scale_methods(scale: &ScaleOutcome) -> Vec<&str> {
    let mut methods: Vec<&str> = Vec::new();
    for row in &scale.rows {
        if !methods.contains(&row.method.as_str()) {
            methods.push(&row.method);
        }
    }
    methods
}

/// A scene × method table of `cell(row)` ("—" where the method did not run).
fn scale_matrix(scale: &ScaleOutcome, cell: impl Fn(&ScaleRow) -> Option<String>) -> String {
    let methods = scale_methods(scale);
    let mut md = format!("| Scene | \\|P\\| | {} |\n|---|---|", methods.join(" | "));
    md.push_str(&"---|".repeat(methods.len()));
    md.push('\n');
    for (scene, _, _) in &scale.scenes {
        let rows: Vec<&ScaleRow> = scale.rows.iter().filter(|r| &r.scene == scene).collect();
        let Some(first) = rows.first() else { continue };
        let cells: Vec<String> = methods
            .iter()
            .map(|m| {
                rows.iter()
                    .find(|r| r.method == *m)
                    .and_then(|r| cell(r))
                    .unwrap_or_else(|| "—".into())
            })
            .collect();
        let _ = writeln!(md, "| `{scene}` | {} | {} |", first.n, cells.join(" | "));
    }
    md
}

/// A "Not run (—)" list of (what, why); empty when there is none.
fn not_run<'a>(items: impl Iterator<Item = (String, &'a str)>) -> String {
    let mut md = String::new();
    for (what, why) in items {
        if md.is_empty() {
            md.push_str("\nNot run (—):\n\n");
        }
        let _ = writeln!(md, "- {what}: {why}");
    }
    md
}

/// The scale tier's section of `report.md`.
pub fn scale_md(scale: &ScaleOutcome) -> String {
    let mut md = String::new();
    let threads = scale.rows.first().map_or(0, |r| r.threads);
    let _ = writeln!(md, "## Scale tier (generated at run time)\n");
    let _ = writeln!(
        md,
        "How each method's cost grows with |P|: generated sets (never committed), every method \
         at its default parameters on {threads} threads. A time is the **median of {} runs** \
         (one run where the first already took longer than the budget); the labels of the first \
         run are scored against `exact`. A method's series stops where its time, projected \
         linearly from its last size, exceeds the budget of {:.0} s per run (`--scale-budget`). \
         Peak memory is the most heap the first run held beyond what was allocated before it \
         (the particle set itself not counted). Plots: `scale_3d.png`, `scale_2d.png` (seconds \
         against |P|, log-log, one line per method).\n",
        scale.runs, scale.budget
    );
    for (scene, about, seconds) in &scale.scenes {
        let n = scale
            .rows
            .iter()
            .find(|r| &r.scene == scene)
            .map_or(0, |r| r.n);
        let _ = writeln!(
            md,
            "- `{scene}`: {n} particles, {about}; generated in {seconds:.1} s"
        );
    }
    let _ = writeln!(
        md,
        "\n### Particles per second (median time, {threads} threads)\n"
    );
    md.push_str(&scale_matrix(scale, |r| {
        r.rate().map(|v| format!("{v:.3e}"))
    }));
    let _ = writeln!(md, "\n### Seconds (median)\n");
    md.push_str(&scale_matrix(scale, |r| {
        r.median().map(|v| format!("{v:.3}"))
    }));
    let _ = writeln!(md, "\n### Peak memory (bytes per particle)\n");
    md.push_str(&scale_matrix(scale, |r| {
        r.bytes_per_particle().map(|v| format!("{v:.0}"))
    }));
    let _ = writeln!(md, "\n### Accuracy at scale (M against `exact`)\n");
    md.push_str(&scale_matrix(scale, |r| {
        r.confusion.map(|c| format!("{:.4}", c.m()))
    }));
    md.push_str(&not_run(scale.rows.iter().filter_map(|r| {
        let why = r.skipped.as_deref()?;
        Some((format!("`{}` {}", r.scene, r.method), why))
    })));
    if let Some((scene, _, _)) = scale
        .scenes
        .iter()
        .find(|(s, _, _)| s.starts_with("scale_enright3d"))
    {
        let rows: Vec<&ScaleRow> = scale.rows.iter().filter(|r| &r.scene == scene).collect();
        let dilts = rows
            .iter()
            .find(|r| r.method == "dilts")
            .and_then(|r| r.median());
        let _ = writeln!(
            md,
            "\n### JCP Table 3 analogue: `{scene}`\n\nrate = `dilts`'s time over the method's, both \
             on {threads} threads (the paper's rate is on one core; its rows are in the published \
             table above, JCP Fig. 14).\n\n| Method | s (median) | runs (s) | particles/s | rate vs \
             dilts | M | bytes/particle |\n|---|---|---|---|---|---|---|"
        );
        for row in rows {
            let Some(t) = row.median() else { continue };
            let runs: Vec<String> = row.seconds.iter().map(|s| format!("{s:.2}")).collect();
            let _ = writeln!(
                md,
                "| {} | {t:.3} | {} | {:.3e} | {} | {} | {} |",
                row.method,
                runs.join(", "),
                row.n as f64 / t,
                dilts.map_or("-".into(), |d| format!("{:.2}", d / t)),
                row.confusion
                    .map_or("-".into(), |c| format!("{:.4}", c.m())),
                row.bytes_per_particle()
                    .map_or("-".into(), |b| format!("{b:.0}")),
            );
        }
    }
    if let Some((scene, n, runs)) = &scale.thread_scan {
        let counts: Vec<usize> = {
            let mut c: Vec<usize> = runs.iter().map(|r| r.threads).collect();
            c.sort_unstable();
            c.dedup();
            c
        };
        let _ = writeln!(
            md,
            "\n### Parallel speedup on `{scene}` ({n} particles)\n\nOne run per thread count below \
             {threads}; the {threads}-thread time is the median above. speedup = t(1) / \
             t({threads}), efficiency = speedup / {threads}.\n"
        );
        let head: Vec<String> = counts.iter().map(|c| format!("{c} thr. (s)")).collect();
        let _ = writeln!(
            md,
            "| Method | {} | {threads} thr. (s) | speedup | efficiency |\n|---|{}---|---|---|",
            head.join(" | "),
            "---|".repeat(counts.len())
        );
        for row in scale.rows.iter().filter(|r| &r.scene == scene) {
            let Some(t_all) = row.median() else { continue };
            let mine: Vec<&ThreadRun> = runs.iter().filter(|r| r.method == row.method).collect();
            let cells: Vec<String> = counts
                .iter()
                .map(|c| {
                    mine.iter()
                        .find(|r| r.threads == *c)
                        .and_then(|r| r.seconds)
                        .map_or("—".into(), |s| format!("{s:.3}"))
                })
                .collect();
            let one = mine.iter().find(|r| r.threads == 1).and_then(|r| r.seconds);
            let (speedup, efficiency) = match one {
                Some(t1) if t_all > 0.0 => {
                    let s = t1 / t_all;
                    (
                        format!("{s:.2}"),
                        format!(
                            "{:.2}{}",
                            s / threads as f64,
                            if s < 1.0 {
                                " (slower with more threads)"
                            } else {
                                ""
                            }
                        ),
                    )
                }
                _ => ("-".into(), "-".into()),
            };
            let _ = writeln!(
                md,
                "| {} | {} | {t_all:.3} | {speedup} | {efficiency} |",
                row.method,
                cells.join(" | ")
            );
        }
        md.push_str(&not_run(runs.iter().filter_map(|r| {
            let why = r.skipped.as_deref()?;
            Some((format!("{} on {} thread(s)", r.method, r.threads), why))
        })));
    }
    md.push('\n');
    md
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
            interface: None,
            interface_confusion: None,
        }
    }

    /// The Randles–Doring section reads the `mu` of each row's dimension, finds the best
    /// common `mu` per dimension and the per-scene optima, and says whether 3D is unstable.
    #[test]
    fn randles_section_measures_each_dimension() {
        let mut rows = Vec::new();
        // 2D: two scenes, both best at 0.6. 3D: best at 0.5 and 0.7, M 0.9 there, 0.5 at the
        // other: the common mu loses 0.4 on one scene of two, 0.2 on average.
        for (dim, scene, mu, tp) in [
            (2, "a", 0.6, 9),
            (2, "a", 0.45, 5),
            (2, "b", 0.6, 9),
            (2, "b", 0.45, 4),
            (3, "c", 0.5, 9),
            (3, "c", 0.7, 5),
            (3, "d", 0.5, 5),
            (3, "d", 0.7, 9),
        ] {
            let c = Confusion {
                tp,
                tn: 10,
                fp: 0,
                fn_: 10 - tp,
            };
            let mut r = row(
                "randles",
                &format!("mu_2d={mu}, mu_3d={mu}, kernel=wendland, h_over_r=1"),
                c,
                0.1,
                0.1,
            );
            r.dim = dim;
            r.scene = scene.into();
            rows.push(r);
        }
        let md = randles_md(&rows);
        assert!(
            md.contains("| 2D | 2 | 0.6 | 0.9000 | 0.6 to 0.6 | 0.0000 | 0.4500 | – |"),
            "{md}"
        );
        assert!(
            md.contains("| 3D | 2 | 0.5 | 0.7000 | 0.5 to 0.7 | 0.2000 | – | – |"),
            "{md}"
        );
        assert!(md.contains("**Unstable in 3D"), "{md}");
        assert!(randles_md(&rows[..0]).is_empty());
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

    /// The spread takes one-thread rates of default rows on scenes of at least
    /// SPREAD_MIN_PARTICLES, flags a slowest scene beyond SPREAD_BOUND and sets its
    /// neighbour count beside the median scene's.
    #[test]
    fn speed_spread_reports_the_slowest_scene_against_the_median() {
        let c = Confusion {
            tp: 1,
            tn: 1,
            fp: 0,
            fn_: 0,
        };
        let mut rows = Vec::new();
        let mut neighbours = Vec::new();
        // ge: 1000/0.01 = 1e5, 2000/0.01 = 2e5, 4000/0.01 = 4e5 and 3000/0.1 = 3e4 per s:
        // median (1e5 + 2e5)/2 = 1.5e5, slowest 3e4: 5.00x. A small scene (very slow) and a
        // swept row (slower still) are left out.
        for (scene, n, t1, k) in [
            ("a", 1000, 0.01, 20.0),
            ("b", 2000, 0.01, 30.0),
            ("c", 4000, 0.01, 40.0),
            ("dense", 3000, 0.1, 140.0),
            ("tiny", 10, 1.0, 5.0),
        ] {
            let mut r = row("ge", "depth=6", c, t1, t1);
            r.scene = scene.into();
            r.n = n;
            rows.push(r);
            let mut swept = row("ge", "depth=8", c, 100.0, 100.0);
            swept.scene = scene.into();
            swept.n = n;
            rows.push(swept);
            neighbours.push((scene.to_owned(), k));
        }
        let outcome = Outcome {
            rows,
            neighbours,
            ..Default::default()
        };
        let md = report_md(&outcome, "test");
        // Neighbours: 140 against the median of 20, 30, 40, 140 = 35.
        assert!(
            md.contains("| ge | 4 | 1.500e5 | `dense` | 3.000e4 | 5.00 (> 3x) | 140 / 35 = 4.00 |"),
            "{md}"
        );
        // Within the bound: no flag.
        let mut fast = outcome;
        for r in &mut fast.rows {
            if r.scene == "dense" {
                r.seconds_1 = Some(0.03);
            }
        }
        // 3000/0.03 = 1e5: median of 1e5, 1e5, 2e5, 4e5 = 1.5e5, slowest 1e5: 1.50.
        assert!(report_md(&fast, "test").contains("| ge | 4 | 1.500e5 | `a` | 1.000e5 | 1.50 |"));
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
        assert!(
            !md.contains("each solver's threshold"),
            "no divr rows, no section"
        );
    }

    #[test]
    fn divr_rows_get_one_line_per_threshold() {
        let c = Confusion {
            tp: 3,
            tn: 5,
            fp: 2,
            fn_: 1,
        };
        let mut outcome = sample();
        outcome.rows.push(row("divr", "", c, 0.1, 0.1));
        outcome.rows.push(row(
            "divr",
            "threshold=sphinxsys, kernel=wendland, h_over_r=1, layers=1, min_neighbours=auto",
            c,
            0.1,
            0.1,
        ));
        let md = report_md(&outcome, "test");
        assert!(md.contains("## Divergence of position: each solver's threshold"));
        let scene = "`sandim_vortex_spin_frame_001_1698`";
        assert!(
            md.contains(&format!(
                "| {scene} | dualsphysics | 2 | 1 | 0.7500 | 0.2857 | 0.5357 |"
            )),
            "{md}"
        );
        assert!(
            md.contains(&format!("| {scene} | sphinxsys + layer | 2 | 1 |")),
            "{md}"
        );
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

    fn scale_row(scene: &str, method: &str, seconds: &[f64], peak: Option<usize>) -> ScaleRow {
        ScaleRow {
            scene: scene.into(),
            dim: 3,
            n: 1000,
            radius: 1.2,
            method: method.into(),
            seconds: seconds.to_vec(),
            threads: 2,
            confusion: (!seconds.is_empty()).then_some(Confusion {
                tp: 100,
                tn: 890,
                fp: 10,
                fn_: 0,
            }),
            peak_bytes: peak,
            skipped: seconds
                .is_empty()
                .then(|| "projected 90 s > budget 60 s".to_owned()),
        }
    }

    fn scale_sample() -> ScaleOutcome {
        let e = "scale_enright3d_1k";
        ScaleOutcome {
            rows: vec![
                scale_row("scale_ball3d_1k", "exact", &[0.5, 0.1, 0.2], Some(64_000)),
                scale_row("scale_ball3d_1k", "dilts", &[1.0, 1.2, 0.8], None),
                scale_row(e, "exact", &[0.4, 0.2, 0.25], Some(32_000)),
                scale_row(e, "dilts", &[], None),
            ],
            scenes: vec![
                ("scale_ball3d_1k".into(), "a ball".into(), 0.1),
                (e.into(), "the Enright sphere".into(), 0.2),
            ],
            thread_scan: Some((
                "scale_ball3d_1k".into(),
                1000,
                vec![
                    ThreadRun {
                        method: "exact".into(),
                        threads: 1,
                        seconds: Some(0.36),
                        skipped: None,
                    },
                    ThreadRun {
                        method: "dilts".into(),
                        threads: 1,
                        seconds: Some(0.5),
                        skipped: None,
                    },
                    ThreadRun {
                        method: "dilts".into(),
                        threads: 4,
                        seconds: None,
                        skipped: Some("projected 99 s > budget 60 s".into()),
                    },
                ],
            )),
            runs: 3,
            budget: 60.0,
        }
    }

    /// The scale section reports medians (not the first or the best run), rates from them,
    /// bytes per particle, the skipped runs with their reason, and speedups from the scan.
    #[test]
    fn scale_section_reports_medians_memory_skips_and_speedups() {
        let md = scale_md(&scale_sample());
        // exact on the ball: runs 0.5, 0.1, 0.2: median 0.2 s, 1000 / 0.2 = 5e3 particles/s.
        assert!(
            md.contains("| `scale_ball3d_1k` | 1000 | 5.000e3 | 1.000e3 |"),
            "{md}"
        );
        assert!(
            md.contains("| `scale_ball3d_1k` | 1000 | 0.200 | 1.000 |"),
            "{md}"
        );
        // 64,000 bytes over 1000 particles.
        assert!(md.contains("| `scale_ball3d_1k` | 1000 | 64 | — |"), "{md}");
        assert!(
            md.contains("| `scale_enright3d_1k` | 1000 | 4.000e3 | — |"),
            "{md}"
        );
        assert!(md.contains("- `scale_enright3d_1k` dilts: projected 90 s > budget 60 s"));
        assert!(md.contains("median of 3 runs"));
        // The Enright analogue: exact only (dilts did not run, so no rate against it).
        assert!(
            md.contains("| exact | 0.250 | 0.40, 0.20, 0.25 | 4.000e3 | - | 0.9889 | 32 |"),
            "{md}"
        );
        // Scan: exact 0.36 s on one thread, 0.2 s on two: 1.80x, efficiency 0.90; dilts got
        // slower with two threads (0.5 s against 1.0 s).
        assert!(
            md.contains("| exact | 0.360 | — | 0.200 | 1.80 | 0.90 |"),
            "{md}"
        );
        assert!(
            md.contains("| dilts | 0.500 | — | 1.000 | 0.50 | 0.25 (slower with more threads) |"),
            "{md}"
        );
        assert!(md.contains("- dilts on 4 thread(s): projected 99 s > budget 60 s"));
        // Inside the report, after the published timings.
        let outcome = Outcome {
            scale: Some(scale_sample()),
            ..sample()
        };
        let full = report_md(&outcome, "test");
        let published = full.find("Published (JCP Table 3").unwrap();
        let section = full.find("## Scale tier").unwrap();
        assert!(published < section);
        assert!(!report_md(&sample(), "test").contains("## Scale tier"));
    }

    #[test]
    fn scale_csv_has_every_run_and_the_header_columns() {
        let csv = scale_csv(&scale_sample());
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines.len(), 5);
        let cols = SCALE_CSV_HEADER.split(',').count();
        for line in &lines[1..] {
            assert_eq!(line.split(',').count(), cols, "{line}");
        }
        assert!(
            lines[1].starts_with(
                "scale_ball3d_1k,3,1000,1.2,exact,2,3,0.200000,0.500000;0.100000;0.200000,5000.0,64000,64.0,100,890,10,0,"
            ),
            "{}",
            lines[1]
        );
        assert!(
            lines[4].ends_with(",,,,,,,projected 90 s > budget 60 s"),
            "{}",
            lines[4]
        );
    }
}
