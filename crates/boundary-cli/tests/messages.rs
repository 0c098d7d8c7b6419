//! The CLI's error messages that `cli.rs` does not already pin, one per `CliError` variant
//! reachable from the command line, and the closed-pipe behaviour of every subcommand: a
//! reader that goes away (`boundary methods | head`) ends the command quietly, status 0.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

const BIN: &str = env!("CARGO_BIN_EXE_boundary");

fn boundary(args: &[&str]) -> Output {
    Command::new(BIN).args(args).output().unwrap()
}

/// The one-line error of a failed run (status 1).
fn failure(args: &[&str]) -> String {
    let out = boundary(args);
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
    stderr
}

/// A 5 x 5 square lattice of spacing 1 as CSV.
fn lattice(dir: &Path, name: &str) -> PathBuf {
    let mut text = String::from("x,y\n");
    for k in 0..25 {
        text.push_str(&format!("{},{}\n", k % 5, k / 5));
    }
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

#[test]
fn option_combinations_that_do_not_go_together_say_so() {
    let dir = tempfile::tempdir().unwrap();
    let input = lattice(dir.path(), "a.csv");
    let err = failure(&["detect", s(&input), "-r", "1", "--margin"]);
    assert!(
        err.starts_with("error: --margin and --normals need --output or --output-dir"),
        "{err}"
    );
    let pattern = dir.path().join("*.csv");
    let out = dir.path().join("o.csv");
    let err = failure(&["detect", s(&pattern), "-r", "1", "-o", s(&out)]);
    assert!(
        err.starts_with("error: several frames need --output-dir, not --output"),
        "{err}"
    );
    let err = failure(&[
        "detect",
        s(&pattern),
        "-r",
        "1",
        "--normals",
        "--summary",
        s(&out),
    ]);
    assert!(err.contains("need --output or --output-dir"), "{err}");
}

#[test]
fn a_method_without_a_margin_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let input = lattice(dir.path(), "a.csv");
    let out = dir.path().join("o.csv");
    let err = failure(&[
        "detect",
        s(&input),
        "-r",
        "1",
        "-m",
        "marrone",
        "--margin",
        "-o",
        s(&out),
    ]);
    assert!(
        err.contains("method 'marrone' reports no margin (drop --margin)"),
        "{err}"
    );
}

#[test]
fn frame_sequence_errors_name_the_pattern_the_frames_or_the_directory() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let err = failure(&["detect", &format!("{}/[", d.display()), "-r", "1"]);
    assert!(err.contains("error: invalid pattern"), "{err}");
    // Two frames with the same stem would overwrite each other.
    lattice(d, "a.csv");
    std::fs::copy(d.join("a.csv"), d.join("a.xyz")).unwrap();
    let out = d.join("out");
    let err = failure(&[
        "detect",
        &format!("{}/a.*", d.display()),
        "-r",
        "1",
        "--output-dir",
        s(&out),
        "--output-format",
        "csv",
    ]);
    assert!(err.contains("would both be written to"), "{err}");
    // A format that is only read is refused as --output-format, before any work (no .vtu
    // written in its place).
    let never = d.join("never");
    for format in ["hdf5", "npz"] {
        let run = boundary(&[
            "detect",
            s(&d.join("a.csv")),
            "-r",
            "1",
            "--output-dir",
            s(&never),
            "--output-format",
            format,
        ]);
        let err = String::from_utf8(run.stderr).unwrap();
        assert_eq!(run.status.code(), Some(2), "{err}");
        assert!(
            err.contains("--output-format") && err.contains("files are read, not written"),
            "{err}"
        );
        assert!(!never.exists(), "{err}");
    }
    // An output directory below a file cannot be created.
    let below_a_file = d.join("a.csv").join("sub");
    let err = failure(&[
        "detect",
        s(&d.join("a.csv")),
        "-r",
        "1",
        "--output-dir",
        s(&below_a_file),
    ]);
    assert!(err.contains("error: cannot create"), "{err}");
    // A summary that is a directory cannot be written.
    let err = failure(&["detect", s(&d.join("a.csv")), "-r", "1", "--summary", s(d)]);
    assert!(err.contains("error: cannot write"), "{err}");
    // A frame whose format nothing names is skipped with its reason.
    let other = tempfile::tempdir().unwrap();
    std::fs::copy(d.join("a.csv"), other.path().join("frame.zzz")).unwrap();
    let err = failure(&[
        "detect",
        &format!("{}/*.zzz", other.path().display()),
        "-r",
        "1",
        "--output-dir",
        s(&out),
    ]);
    assert!(
        err.contains("unknown format (name it with --format / --output-format)"),
        "{err}"
    );
    assert!(err.contains("error: all 1 frames failed"), "{err}");
    // --radius auto with no readable frame.
    std::fs::write(other.path().join("bad.csv"), "x,y\n0,nope\n").unwrap();
    let err = failure(&[
        "detect",
        &format!("{}/*.csv", other.path().display()),
        "-r",
        "auto",
    ]);
    assert!(
        err.contains("error: --radius auto: no frame could be read to estimate r"),
        "{err}"
    );
}

#[test]
fn truth_files_with_the_wrong_count_or_values_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let input = lattice(dir.path(), "a.csv");
    let truth = dir.path().join("truth.csv");
    std::fs::write(&truth, "boundary\n1\n0\n").unwrap();
    let err = failure(&[
        "score",
        s(&input),
        "-r",
        "1",
        "-m",
        "dilts",
        "--truth",
        s(&truth),
    ]);
    assert!(
        err.contains("truth.csv: 2 truth labels for 25 particles"),
        "{err}"
    );
    let mut text = String::from("boundary\n");
    for k in 0..25 {
        text.push_str(if k == 7 { "2\n" } else { "1\n" });
    }
    std::fs::write(&truth, text).unwrap();
    let err = failure(&[
        "score",
        s(&input),
        "-r",
        "1",
        "-m",
        "dilts",
        "--truth",
        s(&truth),
    ]);
    assert!(
        err.contains("truth.csv: particle 7: boundary must be 0 or 1, got 2"),
        "{err}"
    );
}

/// Runs the binary with stdout (or stderr) the write end of a pipe whose read end is already
/// closed: every write to it fails with EPIPE.
fn with_closed_pipe(args: &[&str], close_stderr: bool) -> Output {
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    let mut command = Command::new(BIN);
    command.args(args).stdin(Stdio::null());
    if close_stderr {
        command.stderr(Stdio::from(writer)).stdout(Stdio::piped());
    } else {
        command.stdout(Stdio::from(writer)).stderr(Stdio::piped());
    }
    command.spawn().unwrap().wait_with_output().unwrap()
}

#[test]
fn every_subcommand_exits_quietly_when_its_reader_closes_the_pipe() {
    let dir = tempfile::tempdir().unwrap();
    let input = lattice(dir.path(), "a.csv");
    let out = dir.path().join("o.csv");
    let pattern = format!("{}/*.csv", dir.path().display());
    let runs: [&[&str]; 8] = [
        &["methods"],
        &["methods", "--json"],
        &["score", s(&input), "-r", "1", "-m", "dilts"],
        &["score", s(&input), "-r", "1", "-m", "dilts", "--json"],
        &["detect", s(&input), "-r", "1", "--json"],
        &["detect", &pattern, "-r", "1", "--json"],
        &["resample", s(&input), "-r", "1", "-o", s(&out), "--json"],
        &["detect", s(&input), "-r", "1"],
    ];
    for args in runs {
        let result = with_closed_pipe(args, false);
        let stderr = String::from_utf8_lossy(&result.stderr);
        assert_eq!(result.status.code(), Some(0), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        assert!(!stderr.contains("Broken pipe"), "{args:?}: {stderr}");
        // A closed stderr is no failure either (the human summaries go there).
        let result = with_closed_pipe(args, true);
        assert_eq!(result.status.code(), Some(0), "{args:?} with stderr closed");
    }
}

/// A 10 x 10 square lattice of spacing 1 stored as x,y,z with the coordinate `flat` (0 x,
/// 1 y, 2 z) equal to `value` for every particle.
fn flat_lattice(dir: &Path, name: &str, flat: usize, value: f64) -> PathBuf {
    let mut text = String::from("x,y,z\n");
    for k in 0..100 {
        let (a, b) = (k % 10, k / 10);
        let row = match flat {
            0 => format!("{value},{a},{b}"),
            1 => format!("{a},{value},{b}"),
            _ => format!("{a},{b},{value}"),
        };
        text.push_str(&row);
        text.push('\n');
    }
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn a_flat_3d_set_is_refused_with_the_axis_and_the_fix() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let flat_z = flat_lattice(d, "z.csv", 2, 0.0);
    let err = failure(&["detect", s(&flat_z), "-r", "1"]);
    assert_eq!(
        err,
        format!(
            "error: {}: all 100 particles have z = 0: a flat set is 2D, and read as 3D every \
             particle would be boundary; pass --dim 2 to drop z (--dim 3 detects in 3D \
             anyway)\n",
            s(&flat_z)
        )
    );
    // The fix it names gives the 2D labels: the 8 x 8 inner particles are interior at r = 1.
    let summary = |args: &[&str]| {
        let out = boundary(args);
        assert!(out.status.success(), "{args:?}");
        String::from_utf8(out.stderr).unwrap()
    };
    let text = summary(&["detect", s(&flat_z), "-r", "1", "--dim", "2"]);
    assert!(text.contains("36 of 100 particles boundary"), "{text}");
    // --dim 3 asks for the 3D reading: every particle is boundary there.
    let text = summary(&["detect", s(&flat_z), "-r", "1", "--dim", "3"]);
    assert!(text.contains("100 of 100 particles boundary"), "{text}");

    // Another flat axis is named, with the axes --dim 2 keeps.
    let flat_y = flat_lattice(d, "y.csv", 1, -2.5);
    let err = failure(&["detect", s(&flat_y), "-r", "1"]);
    assert!(
        err.contains("y.csv: all 100 particles have y = -2.5: a flat set is 2D")
            && err.contains("pass --dim 2 to drop y (it keeps x and z)"),
        "{err}"
    );
    let text = summary(&["detect", s(&flat_y), "-r", "1", "--dim", "2"]);
    assert!(text.contains("36 of 100 particles boundary"), "{text}");
    let flat_x = flat_lattice(d, "x.csv", 0, 3.0);
    let err = failure(&["score", s(&flat_x), "-r", "1", "-m", "ia"]);
    assert!(
        err.contains("all 100 particles have x = 3")
            && err.contains("pass --dim 2 to drop x (it keeps y and z)"),
        "{err}"
    );
    let out = d.join("o.csv");
    let err = failure(&["resample", s(&flat_x), "-r", "1", "-o", s(&out)]);
    assert!(err.contains("all 100 particles have x = 3"), "{err}");

    // Every particle at one place; a single particle is no flat set.
    let same = d.join("same.csv");
    std::fs::write(&same, "x,y,z\n1,2,3\n1,2,3\n1,2,3\n").unwrap();
    let err = failure(&["detect", s(&same), "-r", "1"]);
    assert!(
        err.contains("same.csv: all 3 particles are at (1, 2, 3): the set has no extent"),
        "{err}"
    );
    let one = d.join("one.csv");
    std::fs::write(&one, "x,y,z\n1,2,3\n").unwrap();
    let text = summary(&["detect", s(&one), "-r", "1"]);
    assert!(text.contains("1 of 1 particles boundary"), "{text}");

    // In a frame sequence, the flat frame is reported and skipped like any bad frame.
    let frames = d.join("frames");
    std::fs::create_dir(&frames).unwrap();
    std::fs::copy(&flat_z, frames.join("f_1.csv")).unwrap();
    let mut text = String::from("x,y,z\n");
    for k in 0..27 {
        text.push_str(&format!("{},{},{}\n", k % 3, (k / 3) % 3, k / 9));
    }
    std::fs::write(frames.join("f_2.csv"), text).unwrap();
    let pattern = format!("{}/f_*.csv", frames.display());
    let out = boundary(&["detect", &pattern, "-r", "1"]);
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert!(stderr.contains("all 100 particles have z = 0"), "{stderr}");
}
