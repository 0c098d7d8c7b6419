//! `boundary detect --track`: the frames of a sequence in order through the incremental
//! tracker, the labels of `exact` per frame, the time and the recomputed count per frame in
//! the summary.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use std::process::{Command, Output};

fn boundary(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_boundary"))
        .args(args)
        .output()
        .unwrap()
}

/// The `boundary` column of a CSV the CLI wrote.
fn labels(path: &std::path::Path) -> Vec<String> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let k = header.iter().position(|&h| h == "boundary").unwrap();
    lines
        .map(|l| l.split(',').nth(k).unwrap().to_owned())
        .collect()
}

#[test]
fn track_gives_the_labels_of_exact_and_the_recomputed_counts() {
    let dir = tempfile::tempdir().unwrap();
    for step in 0..6 {
        let mut text = String::from("x,y\n");
        for k in 0..400 {
            let j = ((k * 7919) % 97) as f64 / 97.0 - 0.5;
            let f = 1.0 + 0.002 * step as f64;
            text += &format!("{},{}\n", ((k % 20) as f64 + 0.2 * j) * f, (k / 20) as f64);
        }
        std::fs::write(dir.path().join(format!("frame_{step}.csv")), text).unwrap();
    }
    let pattern = dir.path().join("frame_*.csv");
    let pattern = pattern.to_str().unwrap();
    let (tracked, full) = (dir.path().join("tracked"), dir.path().join("full"));
    let summary = dir.path().join("summary.csv");
    let o = boundary(&[
        "detect",
        pattern,
        "--radius",
        "0.8",
        "--track",
        "--output-dir",
        tracked.to_str().unwrap(),
        "--summary",
        summary.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = boundary(&[
        "detect",
        pattern,
        "--radius",
        "0.8",
        "--output-dir",
        full.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for step in 0..6 {
        let name = format!("frame_{step}.csv");
        assert_eq!(
            labels(&tracked.join(&name)),
            labels(&full.join(&name)),
            "{name}"
        );
    }
    let text = std::fs::read_to_string(&summary).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let (seconds, recomputed) = (
        header.iter().position(|&h| h == "seconds").unwrap(),
        header.iter().position(|&h| h == "recomputed").unwrap(),
    );
    let rows: Vec<Vec<String>> = lines
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect();
    assert_eq!(rows.len(), 6);
    let counts: Vec<usize> = rows
        .iter()
        .map(|r| r[recomputed].parse().unwrap())
        .collect();
    assert_eq!(counts[0], 400, "{counts:?}");
    assert!(counts[1..].iter().all(|&c| c < 200), "{counts:?}");
    assert!(rows
        .iter()
        .all(|r| r[seconds].parse::<f64>().unwrap() >= 0.0));
}

#[test]
fn track_refuses_what_it_cannot_follow() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("f_1.csv");
    std::fs::write(&file, "x,y\n0,0\n1,0\n").unwrap();
    let pattern = dir.path().join("f_*.csv");
    let pattern = pattern.to_str().unwrap();
    let o = boundary(&[
        "detect", pattern, "--radius", "1", "--track", "--method", "ge",
    ]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("--method exact"));
    let o = boundary(&[
        "detect", pattern, "--radius", "1", "--track", "--solid", "y<0",
    ]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("--track takes no walls"));
}

/// The `recomputed` column of a summary.
fn recomputed(summary: &std::path::Path) -> Vec<usize> {
    let text = std::fs::read_to_string(summary).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let k = header.iter().position(|&h| h == "recomputed").unwrap();
    lines
        .map(|l| l.split(',').nth(k).unwrap().parse().unwrap())
        .collect()
}

/// `--track-ids`: frames that gain and lose particles and reorder them keep the labels of
/// `exact`, and the tracker follows the particles by id instead of starting over.
#[test]
fn track_ids_follow_inflow_outflow_and_reordering() {
    let dir = tempfile::tempdir().unwrap();
    for step in 0..5usize {
        // A 20 × 20 block drifting along x; each step the first column leaves and a new one
        // enters; every other frame lists the particles backwards.
        let mut rows: Vec<String> = vec![];
        for c in step..step + 20 {
            for k in 0..20 {
                let j = ((c * 20 + k) * 7919 % 97) as f64 / 97.0 - 0.5;
                let id = c * 20 + k;
                rows.push(format!(
                    "{},{},{id}",
                    c as f64 + 0.2 * j - 0.01 * step as f64,
                    k as f64
                ));
            }
        }
        if step % 2 == 1 {
            rows.reverse();
        }
        let text = format!("x,y,Idp\n{}\n", rows.join("\n"));
        std::fs::write(dir.path().join(format!("frame_{step}.csv")), text).unwrap();
    }
    let pattern = dir.path().join("frame_*.csv");
    let pattern = pattern.to_str().unwrap();
    let (tracked, full) = (dir.path().join("tracked"), dir.path().join("full"));
    let (with_ids, without) = (dir.path().join("ids.csv"), dir.path().join("plain.csv"));
    for (out, summary, ids) in [(&tracked, &with_ids, true), (&full, &without, false)] {
        let mut args = vec![
            "detect",
            pattern,
            "--radius",
            "0.8",
            "--track",
            "--output-dir",
            out.to_str().unwrap(),
            "--summary",
            summary.to_str().unwrap(),
        ];
        if ids {
            args.extend(["--track-ids", "Idp"]);
        }
        let o = boundary(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let exact = dir.path().join("exact");
    let o = boundary(&[
        "detect",
        pattern,
        "--radius",
        "0.8",
        "--output-dir",
        exact.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for step in 0..5 {
        let name = format!("frame_{step}.csv");
        assert_eq!(
            labels(&tracked.join(&name)),
            labels(&exact.join(&name)),
            "{name}"
        );
        assert_eq!(
            labels(&full.join(&name)),
            labels(&exact.join(&name)),
            "{name}"
        );
    }
    let (followed, plain) = (recomputed(&with_ids), recomputed(&without));
    assert_eq!(
        plain,
        vec![400; 5],
        "without ids every reordered frame starts over"
    );
    assert_eq!(followed[0], 400);
    assert!(followed[1..].iter().all(|&c| c < 150), "{followed:?}");
}

/// Bad ids are refused with the file, the particle and its line; repeated ids name both.
#[test]
fn track_ids_refuse_bad_ids() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("f_1.csv");
    std::fs::write(&file, "x,y,id\n0,0,1\n1,0,-4\n").unwrap();
    let pattern = dir.path().join("f_*.csv");
    let pattern = pattern.to_str().unwrap();
    let args = [
        "detect",
        pattern,
        "--radius",
        "1",
        "--track",
        "--track-ids",
        "id",
        "--json",
    ];
    let o = boundary(&args);
    let out = String::from_utf8_lossy(&o.stdout).into_owned() + &String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(out.contains("particle 1 (line 3): -4 is negative"), "{out}");
    std::fs::write(&file, "x,y,id\n0,0,1\n1,0,2.5\n").unwrap();
    let o = boundary(&args);
    let out = String::from_utf8_lossy(&o.stdout).into_owned() + &String::from_utf8_lossy(&o.stderr);
    assert!(out.contains("2.5 is not a whole number"), "{out}");
    std::fs::write(&file, "x,y,id\n0,0,7\n1,0,7\n").unwrap();
    let o = boundary(&args);
    let out = String::from_utf8_lossy(&o.stdout).into_owned() + &String::from_utf8_lossy(&o.stderr);
    assert!(out.contains("f_1.csv"), "{out}");
    assert!(out.contains("id 7 is given to particles 0 and 1"), "{out}");
    std::fs::write(&file, "x,y,id\n0,0,7\n1,0,8\n").unwrap();
    let o = boundary(&[
        "detect",
        pattern,
        "--radius",
        "1",
        "--track",
        "--track-ids",
        "Idp",
    ]);
    let out = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(out.contains("Idp"), "{out}");
    let o = boundary(&["detect", pattern, "--radius", "1", "--track-ids", "id"]);
    assert!(!o.status.success(), "--track-ids without --track");
    assert!(String::from_utf8_lossy(&o.stderr).contains("--track"));
}
