//! A radius per particle from a point attribute (`--radius-attribute NAME`, `--radius-scale
//! F`): read from every input format, recorded in `--json` and `--summary`, written back with
//! the other attributes, and every way to get it wrong named with the file, the particle and
//! (CSV) the line.

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

fn stderr(o: &Output) -> String {
    String::from_utf8(o.stderr.clone()).unwrap()
}

/// The JSON object a successful `--json` run prints.
fn json(args: &[&str]) -> Value {
    let out = boundary(args);
    assert!(out.status.success(), "{args:?}: {}", stderr(&out));
    serde_json::from_str(String::from_utf8(out.stdout).unwrap().trim()).unwrap()
}

/// The one-line error of a run that fails with `status`.
fn failure(args: &[&str], status: i32) -> String {
    let out = boundary(args);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(status), "{args:?}: {err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    err
}

fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// A 7 x 7 x 7 cubic lattice of spacing 1 as CSV with a radius column `h` (value `h(k)` for
/// particle k) and a density column: at r = 1.2 its 5 x 5 x 5 core is interior, so 218 of 343
/// particles are boundary (`cli.rs` checks that count against the uniform run).
fn lattice_csv(path: &Path, h: impl Fn(usize) -> f64) -> PathBuf {
    let mut text = String::from("x,y,z,h,rho\n");
    for k in 0..343 {
        text += &format!("{},{},{},{},1000\n", k % 7, (k / 7) % 7, k / 49, h(k));
    }
    std::fs::write(path, text).unwrap();
    path.to_path_buf()
}

/// The `boundary` column of a CSV written by `detect --output`.
fn labels(path: &Path) -> Vec<f64> {
    boundary_io::read_csv_column(path, "boundary").unwrap()
}

#[test]
fn radii_of_one_scaled_by_r_give_the_uniform_labels_and_are_recorded_in_json() {
    let dir = tempfile::tempdir().unwrap();
    let input = lattice_csv(&dir.path().join("lattice.csv"), |_| 1.0);
    let (uniform, radii) = (dir.path().join("u.csv"), dir.path().join("r.csv"));
    let u = json(&[
        "detect",
        s(&input),
        "-r",
        "1.2",
        "-o",
        s(&uniform),
        "--json",
    ]);
    assert_eq!(u["radii"], Value::Null);
    let v = json(&[
        "detect",
        s(&input),
        "--radius-attribute",
        "h",
        "--radius-scale",
        "1.2",
        "-o",
        s(&radii),
        "--json",
    ]);
    assert_eq!(v["boundary"], 218);
    assert_eq!(
        v["radius"], 1.2,
        "the scale is the r passed to the detector"
    );
    assert_eq!(
        v["radii"],
        serde_json::json!({"attribute": "h", "scale": 1.2, "min": 1.2, "max": 1.2})
    );
    assert_eq!(labels(&radii), labels(&uniform));
    // The radius column is written back with the other attributes.
    assert_eq!(
        boundary_io::read_csv_column(&radii, "h").unwrap(),
        vec![1.0; 343]
    );
    assert_eq!(
        boundary_io::read_csv_column(&radii, "rho").unwrap(),
        vec![1000.0; 343]
    );
}

#[test]
fn radius_attribute_is_read_from_every_format_the_cli_writes() {
    let dir = tempfile::tempdir().unwrap();
    // 0.5 and 2.4 · 0.5 = 1.2 are exact in the 32-bit floats of BGEO too.
    let input = lattice_csv(&dir.path().join("lattice.csv"), |_| 0.5);
    for format in ["ply", "vtk", "vtu", "vtp", "bgeo", "bgeo.gz", "csv"] {
        // Written by `detect` with the input's attributes, then read back for its radii.
        let written = dir.path().join(format!("written.{format}"));
        let args = ["--radius-attribute", "H", "--radius-scale", "2.4", "--json"];
        let mut first = vec!["detect", s(&input), "-o", s(&written)];
        first.extend(args);
        assert_eq!(json(&first)["boundary"], 218, "{format}");
        let mut again = vec!["detect", s(&written)];
        again.extend(args);
        let v = json(&again);
        assert_eq!(v["boundary"], 218, "{format}");
        assert_eq!(
            v["radii"]["attribute"], "h",
            "{format}: found ignoring case"
        );
        assert_eq!(
            (v["radii"]["min"].as_f64(), v["radii"]["max"].as_f64()),
            (Some(1.2), Some(1.2)),
            "{format}"
        );
    }
}

#[test]
fn radius_property_of_a_hand_written_ply_and_legacy_vtk_is_read() {
    let dir = tempfile::tempdir().unwrap();
    let ply = dir.path().join("two.ply");
    std::fs::write(
        &ply,
        "ply\nformat ascii 1.0\nelement vertex 2\nproperty double x\nproperty double y\n\
         property float radius\nend_header\n0 0 0.5\n1 0 0.25\n",
    )
    .unwrap();
    let v = json(&["detect", s(&ply), "--radius-attribute", "radius", "--json"]);
    assert_eq!(
        v["radii"],
        serde_json::json!({"attribute": "radius", "scale": 1.0, "min": 0.25, "max": 0.5})
    );
    let vtk = dir.path().join("two.vtk");
    std::fs::write(
        &vtk,
        "# vtk DataFile Version 3.0\ntwo\nASCII\nDATASET POLYDATA\nPOINTS 2 double\n\
         0 0 0\n1 1 1\nPOINT_DATA 2\nSCALARS h double 1\nLOOKUP_TABLE default\n3\n4\n",
    )
    .unwrap();
    let v = json(&[
        "detect",
        s(&vtk),
        "--radius-attribute",
        "h",
        "--radius-scale",
        "0.5",
        "--json",
    ]);
    assert_eq!(
        (v["radii"]["min"].clone(), v["radii"]["max"].clone()),
        (1.5.into(), 2.0.into())
    );
}

#[test]
fn graded_radii_are_scaled_and_score_records_them() {
    let dir = tempfile::tempdir().unwrap();
    // Radius factors 1 and 2 alternating; scale 0.5: radii 0.5 and 1.
    let input = lattice_csv(&dir.path().join("graded.csv"), |k| 1.0 + (k % 2) as f64);
    let v = json(&[
        "score",
        s(&input),
        "--radius-attribute",
        "h",
        "--radius-scale",
        "0.5",
        "-m",
        "exact",
        "--json",
    ]);
    assert_eq!(
        v["radii"],
        serde_json::json!({"attribute": "h", "scale": 0.5, "min": 0.5, "max": 1.0})
    );
    assert_eq!(v["n"], 343);
    // exact against exact on the same radii: no disagreement.
    assert_eq!((v["fp"].clone(), v["fn"].clone()), (0.into(), 0.into()));
    let out = boundary(&["score", s(&input), "--radius-attribute", "h", "-m", "dilts"]);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("r_i = 1 x h in [1, 2]"), "{text}");
}

#[test]
fn frames_read_their_own_radii_and_the_summary_records_them() {
    let dir = tempfile::tempdir().unwrap();
    let frames = dir.path().join("frames");
    std::fs::create_dir(&frames).unwrap();
    lattice_csv(&frames.join("f_1.csv"), |_| 1.0);
    lattice_csv(&frames.join("f_2.csv"), |k| if k == 0 { 0.5 } else { 1.0 });
    // A frame without the attribute is reported and skipped.
    std::fs::write(frames.join("f_3.csv"), "x,y,z\n0,0,0\n1,1,1\n").unwrap();
    let summary = dir.path().join("counts.csv");
    let pattern = frames.join("f_*.csv");
    let v = json(&[
        "detect",
        s(&pattern),
        "--radius-attribute",
        "h",
        "--radius-scale",
        "1.2",
        "--summary",
        s(&summary),
        "--json",
    ]);
    assert_eq!(v["radius_attribute"], "h");
    assert_eq!(v["radius"], 1.2);
    assert_eq!(v["failed"], 1);
    let frames_json = v["frames"].as_array().unwrap();
    assert_eq!(frames_json[0]["radii"]["min"], 1.2);
    assert_eq!(frames_json[1]["radii"]["min"], 0.6);
    assert_eq!(frames_json[1]["radii"]["max"], 1.2);
    let error = frames_json[2]["error"].as_str().unwrap();
    assert!(
        error.contains("f_3.csv") && error.contains("no point attribute \"h\""),
        "{error}"
    );
    let text = std::fs::read_to_string(&summary).unwrap();
    let rows: Vec<Vec<&str>> = text.lines().map(|l| l.split(',').collect()).collect();
    assert_eq!(
        rows[0],
        [
            "frame",
            "input",
            "output",
            "n",
            "dim",
            "radius",
            "boundary",
            "seconds",
            "radius_min",
            "radius_max",
            "error"
        ]
    );
    assert_eq!(&rows[1][8..], ["1.2", "1.2", ""]);
    assert_eq!(&rows[2][8..], ["0.6", "1.2", ""]);
    assert_eq!(&rows[3][3..10], ["", "", "", "", "", "", ""]);
}

#[test]
fn a_missing_attribute_is_named_with_the_ones_the_file_has() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("a.csv");
    std::fs::write(&input, "x,y,v:0,v:1,rho,kind\n0,0,1,2,3,a\n1,0,1,2,3,b\n").unwrap();
    let err = failure(&["detect", s(&input), "--radius-attribute", "h"], 1);
    assert!(
        err.starts_with(&format!(
            "error: {}: no point attribute \"h\" for --radius-attribute (the file has: v \
             (vector of 2), rho; not read: column \"kind\"",
            input.display()
        )),
        "{err}"
    );
    // A vector is not a radius.
    let err = failure(&["detect", s(&input), "--radius-attribute", "v"], 1);
    assert!(
        err.contains("a.csv: point attribute \"v\" is a vector of 2 components, not a radius"),
        "{err}"
    );
    // A file without attributes says so.
    let bare = dir.path().join("bare.csv");
    std::fs::write(&bare, "x,y\n0,0\n").unwrap();
    let err = failure(
        &["score", s(&bare), "--radius-attribute", "h", "-m", "ia"],
        1,
    );
    assert!(err.contains("bare.csv: no point attribute \"h\""), "{err}");
    assert!(err.contains("(the file has: none)"), "{err}");
}

#[test]
fn a_vector_array_of_a_vtu_file_is_not_a_radius() {
    let dir = tempfile::tempdir().unwrap();
    let input = lattice_csv(&dir.path().join("l.csv"), |_| 1.0);
    let vtu = dir.path().join("l.vtu");
    // --normals writes the vector array `normal`.
    let out = boundary(&["detect", s(&input), "-r", "1.2", "--normals", "-o", s(&vtu)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let err = failure(&["detect", s(&vtu), "--radius-attribute", "normal"], 1);
    assert!(
        err.contains("l.vtu: point attribute \"normal\" is a vector of 3 components"),
        "{err}"
    );
}

#[test]
fn bad_radii_name_the_file_the_particle_and_the_csv_line() {
    let dir = tempfile::tempdir().unwrap();
    for (value, problem) in [
        ("-1", "radius must be positive and finite, got -1"),
        ("0", "radius must be positive and finite, got 0"),
        ("NaN", "radius must be positive and finite, got NaN"),
        ("inf", "radius must be positive and finite, got inf"),
        ("1e-200", "radius 1e-200 is outside the supported range"),
    ] {
        let input = dir.path().join("bad.csv");
        // Particle 2 is on line 6: a comment and a blank line do not count.
        std::fs::write(
            &input,
            format!("x,y,h\n0,0,1\n# comment\n1,0,1\n\n2,0,{value}\n3,0,1\n"),
        )
        .unwrap();
        let err = failure(&["detect", s(&input), "--radius-attribute", "h"], 1);
        let want = format!(
            "error: {}: radius attribute \"h\": particle 2 (line 6): {problem}",
            input.display()
        );
        assert!(err.starts_with(&want), "{err}\nwanted {want}");
    }
    // A radius in range whose scaled value is not.
    let input = dir.path().join("big.csv");
    std::fs::write(&input, "x,y,h\n0,0,1\n1,0,1e99\n").unwrap();
    let err = failure(
        &[
            "detect",
            s(&input),
            "--radius-attribute",
            "h",
            "--radius-scale",
            "100",
        ],
        1,
    );
    assert!(
        err.contains("particle 1 (line 3): radius 1e101 is outside the supported range")
            && err.contains("(with --radius-scale 100)"),
        "{err}"
    );
    // A binary-free format without lines: the particle alone.
    let ply = dir.path().join("bad.ply");
    std::fs::write(
        &ply,
        "ply\nformat ascii 1.0\nelement vertex 2\nproperty double x\nproperty double y\n\
         property double h\nend_header\n0 0 1\n1 0 -3\n",
    )
    .unwrap();
    let err = failure(&["detect", s(&ply), "--radius-attribute", "h"], 1);
    assert!(
        err.ends_with("bad.ply: radius attribute \"h\": particle 1: radius must be positive and finite, got -3\n"),
        "{err}"
    );
}

#[test]
fn radius_options_that_do_not_go_together_say_so() {
    let dir = tempfile::tempdir().unwrap();
    let input = lattice_csv(&dir.path().join("l.csv"), |_| 1.0);
    let input = s(&input);
    for r in ["1.2", "auto"] {
        let err = failure(&["detect", input, "-r", r, "--radius-attribute", "h"], 2);
        assert!(
            err.contains("'--radius <R|auto>' cannot be used with '--radius-attribute <NAME>'"),
            "{err}"
        );
    }
    let err = failure(&["detect", input, "-r", "1", "--radius-scale", "2"], 1);
    assert!(
        err.starts_with("error: --radius-scale scales the radii of --radius-attribute"),
        "{err}"
    );
    let err = failure(&["detect", input], 2);
    assert!(err.contains("--radius <R|auto>"), "{err}");
    for bad in ["0", "-1", "nan", "1e300"] {
        let err = failure(
            &[
                "detect",
                input,
                "--radius-attribute",
                "h",
                "--radius-scale",
                bad,
            ],
            2,
        );
        assert!(err.contains("invalid value"), "{bad}: {err}");
    }
    let out = dir.path().join("o.csv");
    let err = failure(
        &[
            "detect",
            input,
            "--radius-attribute",
            "h",
            "--normals",
            "-o",
            s(&out),
        ],
        1,
    );
    assert!(
        err.starts_with("error: --normals needs a uniform --radius"),
        "{err}"
    );
    let err = failure(
        &["resample", input, "--radius-attribute", "h", "-o", s(&out)],
        1,
    );
    assert!(
        err.starts_with("error: resample needs a uniform --radius"),
        "{err}"
    );
}

/// `exact` with per-particle radii: p0 = (0, 0) with r0 = 1 and
/// p1 = (0.5, 0) with r1 = 2: S0 lies inside B1 (its farthest point from p1 is at 1.5 <= 2),
/// so particle 0 is interior; S1 reaches (2.5, 0), 2.5 from p0 > r0, so particle 1 is
/// boundary. With one radius r = 1 both would be boundary (S0's point (-1, 0) is 1.5 from p1).
#[test]
fn exact_labels_two_particles_with_radii_1_and_2_interior_and_boundary() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("two.csv");
    std::fs::write(&input, "x,y,r\n0,0,1\n0.5,0,2\n").unwrap();
    let output = dir.path().join("labels.csv");
    let out = boundary(&[
        "detect",
        s(&input),
        "--radius-attribute",
        "r",
        "-m",
        "exact",
        "-o",
        s(&output),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(labels(&output), [0.0, 1.0], "[interior, boundary]");
}
