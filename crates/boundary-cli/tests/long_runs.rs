//! Long runs over frames lose nothing: a run killed (SIGKILL) or stopped (SIGINT, SIGTERM) in
//! the middle leaves only complete outputs and a summary of the frames done, and `--resume`
//! then ends with what a run never stopped writes.
//!
//! What "equal" means here: every output file byte for byte, and the summary byte for byte
//! except its `seconds` column (each run times its own frames; a resumed run keeps the
//! seconds of the frames done before it, which the tests check too).

#![cfg(unix)]
#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

const FRAMES: usize = 36;
/// The side of each frame's lattice: 2744 particles, about ten milliseconds a frame, so that
/// a run stopped after its first frames has a third of a second of frames still to do.
const SIDE: usize = 14;
const PARTICLES: usize = SIDE * SIDE * SIDE;

/// Writes the frames `frames/f_0.csv` … of a run rooted at `root`: jittered lattices, each frame its own jitter (deterministic), with an `id` column that the outputs
/// carry through.
fn make_frames(root: &Path) {
    let dir = root.join("frames");
    std::fs::create_dir_all(&dir).unwrap();
    for f in 0..FRAMES {
        let mut text = String::from("x,y,z,id\n");
        for k in 0..PARTICLES {
            let jitter = |axis: usize| {
                let seed = (k * 31 + axis * 7 + f * 101) as f64;
                0.12 * (seed * 12.9898).sin()
            };
            text += &format!(
                "{},{},{},{k}\n",
                (k % SIDE) as f64 + jitter(0),
                ((k / SIDE) % SIDE) as f64 + jitter(1),
                (k / (SIDE * SIDE)) as f64 + jitter(2)
            );
        }
        std::fs::write(dir.join(format!("f_{f}.csv")), text).unwrap();
    }
}

/// `boundary detect` over the frames of `root`, one frame at a time (in frame order), with
/// paths relative to `root` so that two runs write identical summaries.
fn detect(root: &Path, extra: &[&str]) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_boundary"));
    command
        .current_dir(root)
        .args([
            "detect",
            "frames/*.csv",
            "--radius",
            "1.2",
            "--threads",
            "1",
            "--output-dir",
            "out",
            "--summary",
            "counts.csv",
        ])
        .args(extra);
    command
}

fn run(mut command: Command) -> Output {
    let output = command.output().unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

/// The summary's rows (after the header), or none while it does not exist.
fn summary_rows(root: &Path) -> Vec<String> {
    match std::fs::read_to_string(root.join("counts.csv")) {
        Ok(text) => {
            let mut lines = text.lines();
            let header = lines.next().unwrap();
            assert!(header.starts_with("frame,input,output,n,"), "{header}");
            assert!(text.ends_with('\n'), "a partial summary: {text:?}");
            lines.map(str::to_owned).collect()
        }
        Err(_) => Vec::new(),
    }
}

/// Starts a run of `root` and waits until its summary holds at least `rows` rows (the frames
/// take milliseconds each, so there are dozens still to do then).
fn start_and_wait_for_rows(root: &Path, rows: usize) -> Child {
    let mut command = detect(root, &[]);
    let mut child = command
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let deadline = Instant::now() + Duration::from_secs(60);
    while summary_rows(root).len() < rows {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before its summary had {rows} rows"
        );
        assert!(Instant::now() < deadline, "no {rows} summary rows in 60 s");
        std::thread::sleep(Duration::from_millis(2));
    }
    assert!(
        child.try_wait().unwrap().is_none(),
        "the run ended before it could be stopped"
    );
    child
}

/// The files of `root/out` by name, with their bytes.
fn outputs(root: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(root.join("out"))
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            (
                e.file_name().to_string_lossy().into_owned(),
                std::fs::read(e.path()).unwrap(),
            )
        })
        .collect()
}

/// Every output present parses completely (all particles, the labels and the input's column);
/// a hidden file may only be the temporary file of a write cut short. Returns the outputs.
fn check_outputs_complete(root: &Path) -> Vec<String> {
    let mut names = Vec::new();
    for name in outputs(root).into_keys() {
        if name.starts_with('.') {
            assert!(name.contains(".csv.tmp-"), "{name}");
            continue;
        }
        let path = root.join("out").join(&name);
        let file =
            boundary_io::read_particle_file(&path, &boundary_io::ReadOptions::default()).unwrap();
        assert_eq!(file.set.len(), PARTICLES, "{name}");
        let labels = boundary_io::read_csv_column(&path, "boundary").unwrap();
        assert_eq!(labels.len(), PARTICLES, "{name}");
        assert!(labels.iter().all(|&b| b == 0.0 || b == 1.0), "{name}");
        assert_eq!(
            boundary_io::read_csv_column(&path, "id").unwrap().last(),
            Some(&((PARTICLES - 1) as f64)),
            "{name}"
        );
        names.push(name);
    }
    names
}

/// The summary's rows without the `seconds` column (the 8th).
fn without_seconds(rows: &[String]) -> Vec<String> {
    rows.iter()
        .map(|row| {
            let mut fields: Vec<&str> = row.split(',').collect();
            fields.remove(7);
            fields.join(",")
        })
        .collect()
}

/// The frame's output named in a summary row (`out/f_3.csv` gives `f_3.csv`).
fn row_output(row: &str) -> String {
    let output = row.split(',').nth(2).unwrap();
    output.strip_prefix("out/").unwrap().to_owned()
}

/// Runs `--resume` on `root` (whose run was stopped with `before` in its summary) and checks
/// that it ends with the outputs and summary of `clean`, keeping the rows it found.
fn resume_equals_clean(root: &Path, clean: &Path, before: &[String]) {
    let resumed = run(detect(root, &["--resume"]));
    let stderr = String::from_utf8_lossy(&resumed.stderr);
    assert!(
        stderr.contains(&format!("{FRAMES} of {FRAMES} frames done")),
        "{stderr}"
    );
    assert!(
        stderr.contains(&format!("({} kept from the run resumed)", before.len())),
        "{stderr}"
    );
    assert_eq!(outputs(root), outputs(clean), "the outputs differ");
    let rows = summary_rows(root);
    assert_eq!(rows.len(), FRAMES);
    assert_eq!(
        without_seconds(&rows),
        without_seconds(&summary_rows(clean))
    );
    // The frames done before were not done again: their rows, seconds included, are kept.
    for row in before {
        assert!(rows.contains(row), "row not kept: {row}");
    }
    let header = |p: &Path| {
        let text = std::fs::read_to_string(p.join("counts.csv")).unwrap();
        text.lines().next().unwrap().to_owned()
    };
    assert_eq!(header(root), header(clean));
}

/// A run never stopped, in `root`.
fn clean_run(root: &Path) {
    make_frames(root);
    run(detect(root, &[]));
    assert_eq!(summary_rows(root).len(), FRAMES);
    assert_eq!(check_outputs_complete(root).len(), FRAMES);
}

#[test]
fn a_killed_run_keeps_complete_outputs_and_resumes_to_the_clean_result() {
    let dir = tempfile::tempdir().unwrap();
    let clean = dir.path().join("clean");
    let killed = dir.path().join("killed");
    clean_run(&clean);
    make_frames(&killed);

    let mut child = start_and_wait_for_rows(&killed, 2);
    child.kill().unwrap(); // SIGKILL: no handler runs
    let status = child.wait().unwrap();
    assert_eq!(status.code(), None, "killed by a signal");

    let rows = summary_rows(&killed);
    assert!(
        (2..FRAMES).contains(&rows.len()),
        "{} summary rows",
        rows.len()
    );
    let present = check_outputs_complete(&killed);
    assert!(present.len() < FRAMES, "{} outputs", present.len());
    // Each frame in the summary has its output (written before its row).
    for row in &rows {
        assert!(present.contains(&row_output(row)), "{row}");
    }
    // What the summary says of a frame is what the clean run says.
    let clean_rows = without_seconds(&summary_rows(&clean));
    for row in without_seconds(&rows) {
        assert!(clean_rows.contains(&row), "{row}");
    }
    resume_equals_clean(&killed, &clean, &rows);
}

/// Stops a run with `signal` and checks the stop: the status, the message, the frames kept.
/// Returns the summary's rows then.
fn stop_with(root: &Path, signal: &str, status: i32) -> Vec<String> {
    let child = start_and_wait_for_rows(root, 2);
    let sent = Command::new("kill")
        .args([signal, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success());
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(status), "{stderr}");
    let rows = summary_rows(root);
    let present = check_outputs_complete(root);
    // The frame in flight was finished, not abandoned half-written: every output has its row,
    // and no temporary file is left.
    assert_eq!(present.len(), rows.len());
    assert!(outputs(root).keys().all(|name| !name.starts_with('.')));
    assert!(
        stderr.contains(&format!(
            "interrupted: {} of {FRAMES} frames done; rerun with --resume to finish",
            rows.len()
        )),
        "{stderr}"
    );
    assert!(!stderr.contains("error:"), "{stderr}");
    assert!(
        (2..FRAMES).contains(&rows.len()),
        "{} summary rows",
        rows.len()
    );
    rows
}

#[test]
fn an_interrupted_run_stops_cleanly_and_resumes_to_the_clean_result() {
    let dir = tempfile::tempdir().unwrap();
    let clean = dir.path().join("clean");
    let stopped = dir.path().join("stopped");
    clean_run(&clean);
    make_frames(&stopped);
    let rows = stop_with(&stopped, "-INT", 130);
    resume_equals_clean(&stopped, &clean, &rows);

    // SIGTERM stops it the same way, with its own status.
    let terminated = dir.path().join("terminated");
    make_frames(&terminated);
    stop_with(&terminated, "-TERM", 143);
}

#[test]
fn resume_redoes_a_frame_whose_row_is_missing_and_removes_stale_temporaries() {
    let dir = tempfile::tempdir().unwrap();
    let clean = dir.path().join("clean");
    clean_run(&clean);
    let root = dir.path().join("crashed");
    make_frames(&root);
    std::fs::create_dir_all(root.join("out")).unwrap();
    // A crash after frame 0's output was renamed into place but before its row was written,
    // and a temporary file of frame 1 cut short.
    std::fs::copy(clean.join("out/f_0.csv"), root.join("out/f_0.csv")).unwrap();
    std::fs::write(root.join("out/.f_1.csv.tmp-99999-3"), "x,y,z,boun").unwrap();
    let header = std::fs::read_to_string(clean.join("counts.csv")).unwrap();
    let header = header.lines().next().unwrap();
    std::fs::write(root.join("counts.csv"), format!("{header}\n")).unwrap();
    let resumed = run(detect(&root, &["--resume"]));
    let stderr = String::from_utf8_lossy(&resumed.stderr);
    assert!(!stderr.contains("kept"), "{stderr}");
    assert_eq!(outputs(&root), outputs(&clean));
    assert_eq!(
        without_seconds(&summary_rows(&root)),
        without_seconds(&summary_rows(&clean))
    );
}

#[test]
fn resume_refuses_a_summary_of_other_columns_and_needs_somewhere_to_look() {
    let dir = tempfile::tempdir().unwrap();
    make_frames(dir.path());
    std::fs::write(dir.path().join("counts.csv"), "frame,input,other\n").unwrap();
    let output = detect(dir.path(), &["--resume"]).output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1));
    assert!(
        stderr.starts_with("error: counts.csv: --resume: its columns are not those"),
        "{stderr}"
    );
    let output = Command::new(env!("CARGO_BIN_EXE_boundary"))
        .current_dir(dir.path())
        .args(["detect", "frames/*.csv", "--radius", "1.2", "--resume"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1));
    assert!(
        stderr.contains("--resume needs --output-dir or --summary"),
        "{stderr}"
    );
}

#[test]
fn an_output_that_cannot_be_written_fails_its_frame_only_and_leaves_no_file() {
    let dir = tempfile::tempdir().unwrap();
    make_frames(dir.path());
    // A directory where frame 2's output goes: its rename fails; the other frames go on.
    std::fs::create_dir_all(dir.path().join("out/f_2.csv")).unwrap();
    let output = detect(dir.path(), &[]).output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(stderr.contains("cannot write out/f_2.csv"), "{stderr}");
    assert!(
        stderr.contains(&format!("1 of {FRAMES} frames failed")),
        "{stderr}"
    );
    let names: Vec<String> = std::fs::read_dir(dir.path().join("out"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.len(), FRAMES);
    assert!(names.iter().all(|n| !n.starts_with('.')), "{names:?}");
    let rows = summary_rows(dir.path());
    assert_eq!(rows.len(), FRAMES);
    assert!(rows[2].ends_with(",cannot write out/f_2.csv: Is a directory (os error 21)"));

    // A summary that cannot be written stops the run at once, naming the file.
    let output = Command::new(env!("CARGO_BIN_EXE_boundary"))
        .current_dir(dir.path())
        .args([
            "detect",
            "frames/*.csv",
            "--radius",
            "1.2",
            "--threads",
            "1",
            "--summary",
            "missing/counts.csv",
        ])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("error: cannot write missing/counts.csv: "),
        "{stderr}"
    );
    assert!(
        stderr.contains("1 of 36 frames done; rerun with --resume"),
        "{stderr}"
    );
}
