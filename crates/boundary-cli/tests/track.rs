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
