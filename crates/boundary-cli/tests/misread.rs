//! Inputs that cannot be misread (issue 42): a near-miss third coordinate is an error naming
//! the file, the column and the fix; the summary and the JSON name the columns used; a file
//! of no particle is an error naming it; `score` needs `--method`; `--band` is reported.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn boundary(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_boundary"))
        .args(args)
        .output()
        .unwrap()
}

fn stdout(o: &Output) -> String {
    String::from_utf8(o.stdout.clone()).unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8(o.stderr.clone()).unwrap()
}

/// The one `error:` line of a run that failed with `status`, nothing on stdout.
fn failure(args: &[&str], status: i32) -> String {
    let out = boundary(args);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(status), "{args:?}: {err}");
    assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
    assert!(err.starts_with("error: "), "{args:?}: {err}");
    assert!(stdout(&out).is_empty(), "{args:?}");
    err.trim_end().to_owned()
}

/// The JSON object of a successful run.
fn json(args: &[&str]) -> Value {
    let out = boundary(args);
    assert!(out.status.success(), "{args:?}: {}", stderr(&out));
    serde_json::from_str(stdout(&out).trim()).unwrap()
}

fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// The bundled 3D fixture, 7138 particles.
fn enright() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/enright3d_t0.csv")
}

/// `fixtures/enright3d_t0.csv` with its header `x,y,z` replaced by `header`.
fn enright_with_header(dir: &Path, name: &str, header: &str) -> PathBuf {
    let text = std::fs::read_to_string(enright()).unwrap();
    let (_, rows) = text.split_once('\n').unwrap();
    let path = dir.join(name);
    std::fs::write(&path, format!("{header}\n{rows}")).unwrap();
    path
}

/// A 5 x 5 square lattice of spacing 1 under `header` (two columns).
fn lattice(dir: &Path, name: &str, header: &str) -> PathBuf {
    let mut text = format!("{header}\n");
    for k in 0..25 {
        text += &format!("{},{}\n", k % 5, k / 5);
    }
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

const R: &str = "0.01875";

#[test]
fn a_near_miss_z_column_is_an_error_naming_the_file_the_column_and_the_fix() {
    let dir = tempfile::tempdir().unwrap();
    let typo = enright_with_header(dir.path(), "typo.csv", "x,y,zz");
    let err = failure(&["detect", s(&typo), "-r", R], 1);
    assert_eq!(
        err,
        format!(
            "error: column \"zz\" in {} line 1 column 3 looks like a misspelt z, and without a z \
             the file would be read as 2D from x, y: rename it to z, or pass --dim 2 (Python: \
             dim=2) to read it as 2D on purpose",
            typo.display()
        )
    );
    // score and the JSON mode refuse it alike.
    let err = failure(&["score", s(&typo), "-r", R, "-m", "dilts"], 1);
    assert!(err.contains("looks like a misspelt z"), "{err}");
    failure(&["detect", s(&typo), "-r", R, "--json"], 1);
    // Other near misses, one per kind of the rule.
    for (k, third) in ["z_", "z1", "ZZ", "Pos_zz", "z_coord"]
        .into_iter()
        .enumerate()
    {
        let path = enright_with_header(dir.path(), &format!("t{k}.csv"), &format!("x,y,{third}"));
        let err = failure(&["detect", s(&path), "-r", R], 1);
        assert!(
            err.contains(&format!("column {third:?} in ")) && err.contains("--dim 2"),
            "{err}"
        );
    }
}

#[test]
fn with_dim_2_the_near_miss_file_reads_as_2d_from_x_and_y_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let typo = enright_with_header(dir.path(), "typo.csv", "x,y,zz");
    let out = boundary(&["detect", s(&typo), "-r", R, "--dim", "2"]);
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("98 of 7138 particles boundary (1.4%), 2D from x, y, r = 0.01875"),
        "{err}"
    );
    let v = json(&["detect", s(&typo), "-r", R, "--dim", "2", "--json"]);
    assert_eq!(
        (v["dim"].clone(), v["boundary"].clone()),
        (2.into(), 98.into())
    );
    assert_eq!(v["position_columns"], serde_json::json!(["x", "y"]));
}

#[test]
fn case_and_spaces_name_the_axis_the_summary_shows_the_names_read() {
    let dir = tempfile::tempdir().unwrap();
    let exact = json(&["detect", s(&enright()), "-r", R, "--json"]);
    assert_eq!(
        exact["position_columns"],
        serde_json::json!(["x", "y", "z"])
    );
    assert_eq!(exact["dropped_column"], Value::Null);
    let upper = enright_with_header(dir.path(), "upper.csv", "x, y, Z");
    let out = boundary(&["detect", s(&upper), "-r", R]);
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains(&format!(
            "{} of 7138 particles boundary ({:.1}%), 3D from x, y, Z, r = 0.01875",
            exact["boundary"],
            100.0 * exact["boundary"].as_f64().unwrap() / 7138.0
        )),
        "{err}"
    );
}

#[test]
fn the_summary_and_the_json_name_the_columns_of_every_layout() {
    let dir = tempfile::tempdir().unwrap();
    // DualSPHysics' CSV names, with units.
    let dsph = lattice(dir.path(), "d.csv", "Pos.x [m],Pos.y [m]");
    let out = boundary(&["detect", s(&dsph), "-r", "1"]);
    assert!(
        stderr(&out).contains("2D from Pos.x [m], Pos.y [m], r = 1,"),
        "{}",
        stderr(&out)
    );
    // A headerless file: its leading columns.
    let headerless = dir.path().join("h.csv");
    std::fs::write(&headerless, "0,0,0\n1,0,0\n0,1,0\n0,0,1\n").unwrap();
    let out = boundary(&["detect", s(&headerless), "-r", "1"]);
    assert!(
        stderr(&out).contains("3D from columns 1, 2, 3, r = 1,"),
        "{}",
        stderr(&out)
    );
    // A 2D set stored as x, y, z with z = 0, read with --dim 2: the dropped axis is named.
    let flat = dir.path().join("flat.csv");
    std::fs::write(&flat, "x,y,z\n0,0,0\n1,0,0\n0,1,0\n1,1,0\n").unwrap();
    let out = boundary(&["detect", s(&flat), "-r", "1", "--dim", "2"]);
    assert!(
        stderr(&out).contains("2D from x, y (z dropped: constant), r = 1,"),
        "{}",
        stderr(&out)
    );
    let v = json(&["detect", s(&flat), "-r", "1", "--dim", "2", "--json"]);
    assert_eq!(v["position_columns"], serde_json::json!(["x", "y"]));
    assert_eq!(v["dropped_column"], "z");
    // A vector format: the array's name.
    let vtu = dir.path().join("p.vtu");
    let out = boundary(&["detect", s(&dsph), "-r", "1", "-o", s(&vtu)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let out = boundary(&["detect", s(&vtu), "-r", "1"]);
    assert!(
        stderr(&out).contains("2D from Points (z dropped: constant), r = 1,"),
        "{}",
        stderr(&out)
    );
    // Every frame of a run names its columns, in its line and its JSON record.
    let frames = dir.path().join("frames");
    std::fs::create_dir(&frames).unwrap();
    lattice(&frames, "f_1.csv", "x,y");
    lattice(&frames, "f_2.csv", "px,py");
    let pattern = frames.join("f_*.csv");
    let out = boundary(&["detect", s(&pattern), "-r", "1"]);
    let err = stderr(&out);
    let line = |frame: &str| {
        err.lines()
            .find(|l| l.contains(frame))
            .unwrap_or_default()
            .to_owned()
    };
    assert!(line("f_1.csv: ").contains("%), 2D from x, y, "), "{err}");
    assert!(line("f_2.csv: ").contains("%), 2D from px, py, "), "{err}");
    let v = json(&["detect", s(&pattern), "-r", "1", "--json"]);
    assert_eq!(
        v["frames"][1]["position_columns"],
        serde_json::json!(["px", "py"])
    );
}

#[test]
fn header_only_and_empty_files_are_errors_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(&str, &[u8], &str); 6] = [
        ("h2.csv", b"x,y\n", "the header on line 1 (x, y) is followed by no data row"),
        ("h3.csv", b"x,y,z\n\n", "the header on line 1 (x, y, z) is followed by no data row"),
        ("e.csv", b"", "the file holds no header and no data row (empty file)"),
        ("e.xyz", b"# x y z\n", "the names line 1 (# x y z) is followed by no particle line"),
        (
            "v.ply",
            b"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nend_header\n",
            "its header declares element vertex 0",
        ),
        (
            "p.vtk",
            b"# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 0 double\n",
            "its POINTS section holds 0 points",
        ),
    ];
    for (name, bytes, detail) in cases {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        let expected = format!("error: no particles in {}: {detail}", path.display());
        for args in [
            vec!["detect", s(&path), "-r", "1"],
            vec!["detect", s(&path), "-r", "1", "--json"],
            vec!["detect", s(&path), "-r", "auto"],
            vec!["score", s(&path), "-r", "1", "-m", "dilts"],
        ] {
            assert_eq!(failure(&args, 1), expected, "{args:?}");
        }
    }
    // A frame of no particle among good ones: skipped, naming its file; the others are done.
    let frames = dir.path().join("frames");
    std::fs::create_dir(&frames).unwrap();
    lattice(&frames, "f_1.csv", "x,y");
    std::fs::write(frames.join("f_2.csv"), "x,y\n").unwrap();
    let pattern = frames.join("f_*.csv");
    let out = boundary(&["detect", s(&pattern), "-r", "1"]);
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains(&format!(
            "frame 2/2: skipped: no particles in {}: the header on line 1 (x, y) is followed by \
             no data row",
            frames.join("f_2.csv").display()
        )),
        "{err}"
    );
    assert!(err.contains("1 of 2 frames failed"), "{err}");
    let v = json(&["detect", s(&pattern), "-r", "1", "--json"]);
    assert!(
        v["frames"][1]["error"]
            .as_str()
            .unwrap()
            .starts_with("no particles in "),
        "{v}"
    );
    // Every frame empty: the run fails.
    std::fs::write(frames.join("f_1.csv"), "x,y\n").unwrap();
    let out = boundary(&["detect", s(&pattern), "-r", "1"]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("all 2 frames failed"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn score_needs_a_method() {
    let dir = tempfile::tempdir().unwrap();
    let input = lattice(dir.path(), "a.csv", "x,y");
    let err = failure(&["score", s(&input), "-r", "1"], 2);
    assert_eq!(
        err,
        "error: the following required arguments were not provided: --method <NAME>"
    );
    // With one, the first line says what is scored against what.
    let out = boundary(&["score", s(&input), "-r", "1", "-m", "exact"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stdout(&out).starts_with(&format!("exact (tie=0) vs exact on {}", input.display())),
        "{}",
        stdout(&out)
    );
    let help = boundary(&["score", "--help"]);
    assert!(stdout(&help).contains("Required"), "{}", stdout(&help));
}

#[test]
fn band_appears_in_the_summary_and_the_json() {
    let dir = tempfile::tempdir().unwrap();
    let input = lattice(dir.path(), "a.csv", "x,y");
    let out = boundary(&["detect", s(&input), "-r", "1.2", "--band", "1.5"]);
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert!(err.contains(", r = 1.2, band: 1.5, exact"), "{err}");
    let v = json(&["detect", s(&input), "-r", "1.2", "--band", "1.5", "--json"]);
    assert_eq!(v["band"], 1.5);
    // Without --band: no band in the summary, null in the JSON.
    let out = boundary(&["detect", s(&input), "-r", "1.2"]);
    assert!(!stderr(&out).contains("band"), "{}", stderr(&out));
    let v = json(&["detect", s(&input), "-r", "1.2", "--json"]);
    assert!(v.get("band").is_some_and(Value::is_null), "{v}");
    // Over frames: the last line and the JSON's top level.
    let pattern = dir.path().join("*.csv");
    let out = boundary(&["detect", s(&pattern), "-r", "1.2", "--band", "2"]);
    assert!(
        stderr(&out).contains("1 of 1 frames done with exact (tie=0), band: 2"),
        "{}",
        stderr(&out)
    );
    let v = json(&["detect", s(&pattern), "-r", "1.2", "--band", "2", "--json"]);
    assert_eq!(v["band"], 2.0);
}
