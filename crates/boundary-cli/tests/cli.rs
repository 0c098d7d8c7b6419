//! The `boundary` binary end to end: the contract of the CLI (fields of `--json`, output
//! columns, one-line errors with a non-zero status).

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

/// A file of the shared data folder, through the one helper that makes a missing folder a
/// failure (or, with `BOUNDARY_ALLOW_MISSING_DATA=1`, a skip printed on stderr: `None`).
fn shared(rel: &str) -> Option<PathBuf> {
    let data = boundary_scenes::SharedData::from_env();
    let path = data.dir().join(rel);
    let found = std::fs::metadata(&path)
        .map_err(|e| format!("{}: {e}", path.display()))
        .map(|_| path);
    data.outcome(rel, found).unwrap()
}

const VORTEX: &str = "particles2d/sandim_vortex_spin_frame_001_1698.csv";
const VORTEX_R: &str = "0.022105";

/// A 7 x 7 x 7 cubic lattice of spacing 1 written as CSV: at r = 1.2 its 5 x 5 x 5 core is
/// interior (each inner particle's sphere is covered by its 6 axis neighbours and the 12 at
/// distance √2), so 343 − 125 = 218 are boundary.
fn lattice_csv(dir: &Path) -> PathBuf {
    let mut text = String::from("x,y,z\n");
    for k in 0..343 {
        text += &format!("{},{},{}\n", k % 7, (k / 7) % 7, k / 49);
    }
    let path = dir.join("lattice.csv");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn detect_json_has_the_contract_fields() {
    let dir = tempfile::tempdir().unwrap();
    let input = lattice_csv(dir.path());
    let out = boundary(&[
        "detect",
        input.to_str().unwrap(),
        "--radius",
        "1.2",
        "--json",
        "--threads",
        "2",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v: Value = serde_json::from_str(stdout(&out).trim()).unwrap();
    assert_eq!(v["method"], "exact");
    assert_eq!(v["n"], 343);
    assert_eq!(v["dim"], 3);
    assert_eq!(v["radius"], 1.2);
    assert_eq!(v["boundary"], 343 - 125);
    assert_eq!(v["threads"], 2);
    assert!(v["seconds"].as_f64().unwrap() >= 0.0);
}

#[test]
fn detect_writes_a_boundary_column_in_input_order() {
    let dir = tempfile::tempdir().unwrap();
    let input = lattice_csv(dir.path());
    let output = dir.path().join("labels.csv");
    let out = boundary(&[
        "detect",
        input.to_str().unwrap(),
        "-r",
        "1.2",
        "--method",
        "dilts",
        "--output",
        output.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    // Human summary: one line on stderr, nothing on stdout.
    assert_eq!(stderr(&out).lines().count(), 1, "{}", stderr(&out));
    assert!(stderr(&out).contains("218 of 343"), "{}", stderr(&out));
    assert!(stdout(&out).is_empty());
    let text = std::fs::read_to_string(&output).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next().unwrap(), "x,y,z,boundary");
    for (k, line) in lines.enumerate() {
        let fields: Vec<f64> = line.split(',').map(|f| f.parse().unwrap()).collect();
        let (x, y, z) = ((k % 7) as f64, ((k / 7) % 7) as f64, (k / 49) as f64);
        assert_eq!(&fields[..3], &[x, y, z], "row {k} out of order");
        let inner = [x, y, z].iter().all(|&c| (1.0..=5.0).contains(&c));
        assert_eq!(fields[3], if inner { 0.0 } else { 1.0 }, "row {k}");
    }
}

#[test]
fn detect_on_shared_data_matches_the_reference_count() {
    let Some(input) = shared(VORTEX) else {
        return;
    };
    let out = boundary(&["detect", input.to_str().unwrap(), "-r", VORTEX_R, "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v: Value = serde_json::from_str(stdout(&out).trim()).unwrap();
    // ../shared/data/README.md: 202 boundary particles at r = 0.022105.
    assert_eq!((v["n"].clone(), v["dim"].clone()), (1698.into(), 2.into()));
    assert_eq!(v["boundary"], 202);
}

#[test]
fn score_against_exact_and_against_a_truth_file() {
    let dir = tempfile::tempdir().unwrap();
    let input = lattice_csv(dir.path());
    let out = boundary(&[
        "score",
        input.to_str().unwrap(),
        "-r",
        "1.2",
        "--method",
        "dilts",
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v: Value = serde_json::from_str(stdout(&out).trim()).unwrap();
    assert_eq!((v["tp"].clone(), v["fn"].clone()), (218.into(), 0.into()));
    assert_eq!((v["tn"].clone(), v["fp"].clone()), (125.into(), 0.into()));
    assert_eq!(v["m"], 1.0);

    // A truth file claiming every particle is boundary: dilts then has 125 false negatives.
    let truth = dir.path().join("truth.csv");
    let mut text = String::from("x,y,z,boundary\n");
    for k in 0..343 {
        text += &format!("{},{},{},1\n", k % 7, (k / 7) % 7, k / 49);
    }
    std::fs::write(&truth, text).unwrap();
    let out = boundary(&[
        "score",
        input.to_str().unwrap(),
        "-r",
        "1.2",
        "--method",
        "dilts",
        "--truth",
        truth.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(
        text.contains("FN  125") && text.contains("TP  218"),
        "{text}"
    );
}

#[test]
fn methods_lists_every_registered_method() {
    let out = boundary(&["methods", "--json"]);
    assert!(out.status.success());
    let v: Value = serde_json::from_str(stdout(&out).trim()).unwrap();
    let names: Vec<&str> = v
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, boundary::methods());
    let text = stdout(&boundary(&["methods"]));
    assert!(text.contains("exact [certified]"), "{text}");
}

/// A failing command: non-zero status, nothing on stdout, exactly one line on stderr starting
/// with `error:` and containing `needle`.
/// `--band K`: the exact boundary of the 7^3 lattice at r = 1.2 widened by K·r. With K = 1
/// (1.2) the next shell (depth 1, distance 1 from the outer one) joins, leaving the 3^3
/// core; with K = 0.5 (0.6) no other particle is that close: the labels of the plain run;
/// with K = 10 every particle. `--json` counts the band.
#[test]
fn detect_band_widens_the_boundary_by_k_radii() {
    let dir = tempfile::tempdir().unwrap();
    let input = lattice_csv(dir.path());
    let input = input.to_str().unwrap();
    for (k, min_interior_depth) in [("1", 2), ("0.5", 1), ("10", 4)] {
        let output = dir.path().join(format!("band{k}.csv"));
        let out = boundary(&[
            "detect",
            input,
            "-r",
            "1.2",
            "--band",
            k,
            "--json",
            "-o",
            output.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{}", stderr(&out));
        let text = std::fs::read_to_string(&output).unwrap();
        let mut boundary_rows = 0;
        for (i, line) in text.lines().skip(1).enumerate() {
            let (x, y, z) = (i % 7, (i / 7) % 7, i / 49);
            let depth = [x, y, z, 6 - x, 6 - y, 6 - z].into_iter().min().unwrap();
            let inner = depth >= min_interior_depth;
            boundary_rows += usize::from(!inner);
            assert!(
                line.ends_with(if inner { ",0" } else { ",1" }),
                "K {k} row {i}: {line}"
            );
        }
        let v: Value = serde_json::from_str(stdout(&out).trim()).unwrap();
        assert_eq!(v["boundary"], boundary_rows, "K = {k}");
    }
    assert_one_line_error(&["detect", input, "-r", "1.2", "--band", "0"], "--band");
    assert_one_line_error(&["detect", input, "-r", "1.2", "--band", "nan"], "nan");
}

fn assert_one_line_error(args: &[&str], needle: &str) {
    let out = boundary(args);
    assert!(!out.status.success(), "{args:?} succeeded");
    assert!(stdout(&out).is_empty(), "{args:?}: {}", stdout(&out));
    let err = stderr(&out);
    assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
    assert!(err.starts_with("error:"), "{args:?}: {err}");
    assert!(
        err.contains(needle),
        "{args:?}: expected '{needle}' in {err}"
    );
}

#[test]
fn bad_arguments_give_one_clear_line() {
    let dir = tempfile::tempdir().unwrap();
    let input = lattice_csv(dir.path());
    let input = input.to_str().unwrap();
    assert_one_line_error(&["detect", input, "-r", "0"], "radius");
    assert_one_line_error(&["detect", input, "-r", "-1"], "radius");
    assert_one_line_error(&["detect", input, "-r", "nan"], "radius");
    assert_one_line_error(&["detect", input, "-r", "inf"], "radius");
    assert_one_line_error(&["detect", input, "-r", "abc"], "abc");
    assert_one_line_error(&["detect", input], "--radius");
    assert_one_line_error(&["detect", input, "-r", "1", "--method", "nope"], "nope");
    assert_one_line_error(&["detect", input, "-r", "1", "--set", "depth=3"], "depth");
    assert_one_line_error(&["detect", input, "-r", "1", "--set", "depth"], "KEY=VALUE");
    assert_one_line_error(&["detect", input, "-r", "1", "--dim", "4"], "4");
    let missing = dir.path().join("missing.csv");
    assert_one_line_error(
        &["detect", missing.to_str().unwrap(), "-r", "1"],
        "missing.csv",
    );
    let out = dir.path().join("labels.unknown");
    assert_one_line_error(
        &["detect", input, "-r", "1", "-o", out.to_str().unwrap()],
        "labels.unknown",
    );
    // A malformed file: the error names the file and the line.
    let bad = dir.path().join("bad.csv");
    std::fs::write(&bad, "x,y\n0,0\n1,zz\n").unwrap();
    assert_one_line_error(&["detect", bad.to_str().unwrap(), "-r", "1"], "bad.csv");
    let out = boundary(&["detect", bad.to_str().unwrap(), "-r", "1"]);
    assert!(stderr(&out).contains('3'), "line number: {}", stderr(&out));
}

/// A 3D scene of the four feature kinds, far apart at r = 1: one lone particle (droplet), a
/// straight line of 20 particles at spacing 0.5 (ligament), a single-layer 10 x 10 sheet at
/// spacing 0.5 (sheet), and the 7 x 7 x 7 lattice block (218 regular boundary, 125 interior).
fn features_csv(dir: &Path) -> PathBuf {
    let mut text = String::from("x,y,z\n");
    text += "100,100,100\n";
    for k in 0..20 {
        text += &format!("{},-50,0\n", f64::from(k) * 0.5);
    }
    for k in 0..100 {
        text += &format!(
            "{},{},50\n",
            f64::from(k % 10) * 0.5,
            f64::from(k / 10) * 0.5
        );
    }
    for k in 0..343 {
        text += &format!("{},{},{}\n", k % 7 + 200, (k / 7) % 7, k / 49);
    }
    let path = dir.join("features.csv");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn resample_labels_features_and_writes_the_new_set() {
    let dir = tempfile::tempdir().unwrap();
    let input = features_csv(dir.path());
    let output = dir.path().join("out.csv");
    let o = boundary(&[
        "resample",
        input.to_str().unwrap(),
        "--radius",
        "1.2",
        "--output",
        output.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value = serde_json::from_str(stdout(&o).trim()).unwrap();
    assert_eq!(v["n"], 464);
    assert_eq!(v["droplet"], 1, "{v}");
    assert_eq!(v["ligament"], 20, "{v}");
    assert_eq!(v["sheet"], 100, "{v}");
    assert_eq!(v["regular"], 218, "{v}");
    assert_eq!(v["interior"], 125, "{v}");
    // droplet -> 6, ligament -> 4 each, sheet -> 2 each, the others kept.
    let n_out = 6 + 20 * 4 + 100 * 2 + 218 + 125;
    assert_eq!(v["n_out"], n_out);
    let text = std::fs::read_to_string(&output).unwrap();
    assert_eq!(text.lines().next(), Some("x,y,z,feature,source"));
    assert_eq!(text.lines().count(), n_out + 1);
    // The droplet's six replacements come first, at ±0.5r along the axes.
    let first: Vec<&str> = text.lines().nth(1).unwrap().split(',').collect();
    assert_eq!(first[3..], ["0", "0"]);
    // PLY output carries the colours of thesis Fig. 15 (droplet cyan).
    let ply = dir.path().join("out.ply");
    let o = boundary(&[
        "resample",
        input.to_str().unwrap(),
        "-r",
        "1.2",
        "-o",
        ply.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("1 droplet, 20 ligament, 100 sheet, 218 regular"));
    let text = std::fs::read_to_string(&ply).unwrap();
    assert!(text.contains("property uchar red\nproperty uchar green\nproperty uchar blue\n"));
    let droplet_row = text
        .lines()
        .find(|l| l.ends_with(" 0 0 0 255 255"))
        .is_some();
    assert!(droplet_row, "{}", &text[..600]);
}

#[test]
fn resample_rejects_bad_parameters_and_outputs_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let input = lattice_csv(dir.path());
    let input = input.to_str().unwrap();
    let out = dir.path().join("o.csv");
    let out = out.to_str().unwrap();
    assert_one_line_error(
        &["resample", input, "-r", "1.2", "-o", "o.pdb"],
        "unknown output format",
    );
    assert_one_line_error(
        &["resample", input, "-r", "1.2", "-o", out, "--alpha", "-1"],
        "alpha",
    );
    assert_one_line_error(
        &["resample", input, "-r", "1.2", "-o", out, "--shift", "nan"],
        "shift",
    );
    assert_one_line_error(&["resample", input, "-r", "1.2"], "--output");
}

// Bad input at the command line. The readers' own messages are checked in
// boundary-io/tests/errors.rs; here the binary must turn each into one `error:` line naming
// the file (and the line or element), with a non-zero status and no panic.

/// Writes `bytes` to `dir/name` and returns the path as a string.
fn write_input(dir: &Path, name: &str, bytes: &[u8]) -> String {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path.to_str().unwrap().to_owned()
}

#[test]
fn non_finite_coordinates_name_the_file_the_particle_and_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let nan = write_input(dir.path(), "nan.csv", b"x,y\n0,0\n1,1\n2,NaN\n");
    assert_one_line_error(&["detect", &nan, "-r", "1"], "nan.csv");
    assert_one_line_error(&["detect", &nan, "-r", "1"], "line 4");
    assert_one_line_error(&["detect", &nan, "-r", "1"], "particle 2");
    let inf = write_input(dir.path(), "inf.xyz", b"0 0 0\n1 -inf 0\n");
    assert_one_line_error(&["detect", &inf, "-r", "1"], "inf.xyz");
    assert_one_line_error(&["detect", &inf, "-r", "1"], "line 2");
}

#[test]
fn a_csv_row_longer_than_its_header_is_an_error_naming_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let wide = write_input(dir.path(), "wide.csv", b"x,y\n0,0\n1,1,7\n");
    assert_one_line_error(&["detect", &wide, "-r", "1"], "wide.csv");
    assert_one_line_error(&["detect", &wide, "-r", "1"], "line 3");
    assert_one_line_error(&["detect", &wide, "-r", "1"], "too many values: 3");
}

/// A header-only file is refused, not read as an empty set that would report "0 of 0" (the
/// library's empty sets are tested in `boundary/tests/every_detector.rs`); more in
/// `misread.rs`.
#[test]
fn a_header_only_csv_is_an_error_naming_the_file_not_an_empty_set() {
    let dir = tempfile::tempdir().unwrap();
    for (name, header) in [("e2.csv", "x,y\n"), ("e3.csv", "x,y,z\n")] {
        let input = write_input(dir.path(), name, header.as_bytes());
        for method in boundary::methods() {
            assert_one_line_error(
                &["detect", &input, "-r", "1", "--method", method, "--json"],
                &format!("no particles in {input}: the header on line 1"),
            );
        }
    }
}

#[test]
fn a_row_with_the_wrong_number_of_columns_names_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let short = write_input(dir.path(), "mixed.csv", b"x,y,z\n0,0,0\n1,1,1\n2,2\n");
    assert_one_line_error(&["detect", &short, "-r", "1"], "mixed.csv");
    assert_one_line_error(&["detect", &short, "-r", "1"], "line 4");
    let short = write_input(dir.path(), "mixed.xyz", b"0 0 0\n1 1\n");
    assert_one_line_error(&["detect", &short, "-r", "1"], "mixed.xyz");
    assert_one_line_error(&["detect", &short, "-r", "1"], "line 2");
}

#[test]
fn truncated_binary_files_name_the_file_and_the_element() {
    let dir = tempfile::tempdir().unwrap();
    let mut ply = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\nend_header\n".to_vec();
    for v in [0.0f64, 0.0, 0.0, 1.0, 1.0, 1.0, 2.0] {
        ply.extend_from_slice(&v.to_le_bytes());
    }
    let ply = write_input(dir.path(), "cut.ply", &ply);
    assert_one_line_error(&["detect", &ply, "-r", "1"], "cut.ply");
    assert_one_line_error(&["detect", &ply, "-r", "1"], "vertex 2");
    let mut vtk =
        b"# vtk DataFile Version 3.0\nt\nBINARY\nDATASET POLYDATA\nPOINTS 2 double\n".to_vec();
    for v in [0.0f64, 0.0, 0.0, 1.0] {
        vtk.extend_from_slice(&v.to_be_bytes());
    }
    let vtk = write_input(dir.path(), "cut.vtk", &vtk);
    assert_one_line_error(&["detect", &vtk, "-r", "1"], "cut.vtk");
}

/// Headers declaring 10^12 (or 2^64 - 1) particles over a few bytes of data: the readers check
/// the count against the bytes that follow before allocating, so each command fails at once
/// (an allocation of the declared size would abort the process or exhaust the test machine).
#[test]
fn enormous_declared_counts_fail_without_allocating() {
    let dir = tempfile::tempdir().unwrap();
    let mut ply = b"ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\nproperty float x\nproperty float y\nproperty float z\nend_header\n".to_vec();
    ply.extend_from_slice(&[0u8; 24]);
    let ply = write_input(dir.path(), "huge.ply", &ply);
    assert_one_line_error(&["detect", &ply, "-r", "1"], "huge.ply");
    let max = write_input(
        dir.path(),
        "max.ply",
        b"ply\nformat ascii 1.0\nelement vertex 18446744073709551615\nproperty float x\nproperty float y\nend_header\n0 0\n",
    );
    assert_one_line_error(&["detect", &max, "-r", "1"], "max.ply");
    let vtk = write_input(
        dir.path(),
        "huge.vtk",
        b"# vtk DataFile Version 3.0\nt\nBINARY\nDATASET POLYDATA\nPOINTS 1000000000000 double\n\0\0\0\0\0\0\0\0",
    );
    assert_one_line_error(&["detect", &vtk, "-r", "1"], "huge.vtk");
    let xyz = write_input(dir.path(), "huge.xyz", b"1000000000000\ncomment\n0 0 0\n");
    assert_one_line_error(&["detect", &xyz, "-r", "1"], "huge.xyz");
}

/// The 7 x 7 x 7 lattice with extra columns `vx` (the index) and `kind` (text), as a frame.
fn lattice_with_fields(path: &Path, shift: f64) {
    let mut text = String::from("x,y,z,vx,kind\n");
    for k in 0..343 {
        text += &format!(
            "{},{},{},{k},fluid\n",
            f64::from(k % 7) + shift,
            (k / 7) % 7,
            k / 49
        );
    }
    std::fs::write(path, text).unwrap();
}

#[test]
fn detect_writes_back_the_input_attributes_next_to_boundary() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("f.csv");
    lattice_with_fields(&input, 0.0);
    let output = dir.path().join("f.vtu");
    let out = boundary(&[
        "detect",
        input.to_str().unwrap(),
        "-r",
        "1.2",
        "-o",
        output.to_str().unwrap(),
        "--normals",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    // The text column is reported, not written.
    assert!(stderr(&out).contains("\"kind\""), "{}", stderr(&out));
    let back = boundary_io::read_particle_file(&output, &Default::default()).unwrap();
    let names: Vec<&str> = back.attributes.iter().map(|a| a.name.as_str()).collect();
    assert_eq!(
        names,
        ["boundary", "normal:0", "normal:1", "normal:2", "vx"]
    );
    assert_eq!(
        back.attributes[4].values,
        boundary_io::AttributeValues::Int((0..343).collect())
    );
    let boundary_io::AttributeValues::Int(flags) = &back.attributes[0].values else {
        panic!("boundary is not an integer column");
    };
    assert_eq!(flags.iter().sum::<i64>(), 218);
    // Normals: unit on the boundary, pointing out of the lattice; zero inside.
    let component = |k: usize| match &back.attributes[1 + k].values {
        boundary_io::AttributeValues::Float(v) => v.clone(),
        other => panic!("{other:?}"),
    };
    let (nx, ny, nz) = (component(0), component(1), component(2));
    for i in 0..343 {
        let norm = (nx[i] * nx[i] + ny[i] * ny[i] + nz[i] * nz[i]).sqrt();
        if flags[i] == 1 {
            assert!((norm - 1.0).abs() < 1e-12, "particle {i}: {norm}");
        } else {
            assert_eq!(norm, 0.0, "particle {i}");
        }
    }
    // The middle of the x = 0 face (particle 3·7 + 3·49 = 168) points to −x.
    assert!(
        (nx[168] + 1.0).abs() < 1e-9 && ny[168].abs() < 1e-9,
        "{}",
        nx[168]
    );
}

#[test]
fn frames_are_processed_in_natural_order_and_a_bad_frame_is_skipped() {
    let dir = tempfile::tempdir().unwrap();
    let frames = dir.path().join("frames");
    std::fs::create_dir(&frames).unwrap();
    for k in [1, 2, 10] {
        lattice_with_fields(&frames.join(format!("fluid_{k}.csv")), f64::from(k));
    }
    std::fs::write(frames.join("fluid_3.csv"), "x,y,z\n1,2\n").unwrap();
    let out_dir = dir.path().join("out");
    let summary = dir.path().join("counts.csv");
    let pattern = frames.join("fluid_*.csv");
    let out = boundary(&[
        "detect",
        pattern.to_str().unwrap(),
        "--radius",
        "1.2",
        "--output-dir",
        out_dir.to_str().unwrap(),
        "--output-format",
        "vtp",
        "--summary",
        summary.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(err.contains("fluid_3.csv"), "{err}");
    assert!(err.contains("1 of 4 frames failed"), "{err}");
    let mut written: Vec<String> = std::fs::read_dir(&out_dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    written.sort();
    assert_eq!(written, ["fluid_1.vtp", "fluid_10.vtp", "fluid_2.vtp"]);
    let text = std::fs::read_to_string(&summary).unwrap();
    let rows: Vec<Vec<&str>> = text.lines().map(|l| l.split(',').collect()).collect();
    assert_eq!(
        rows[0],
        ["frame", "input", "output", "n", "dim", "radius", "boundary", "seconds", "error"]
    );
    // Natural order: 1, 2, 3, 10.
    let inputs: Vec<&str> = rows[1..].iter().map(|r| r[1]).collect();
    assert!(inputs[0].ends_with("fluid_1.csv") && inputs[3].ends_with("fluid_10.csv"));
    assert!(inputs[2].ends_with("fluid_3.csv"), "{inputs:?}");
    for row in [&rows[1], &rows[2], &rows[4]] {
        assert_eq!(&row[3..7], &["343", "3", "1.2", "218"], "{row:?}");
        assert!(row[8].is_empty());
    }
    // The error is one quoted field naming the file and the line.
    let bad = text.lines().nth(3).unwrap();
    assert!(bad.contains(",\"too few columns: 2, need 3 in "), "{bad}");
    assert!(bad.ends_with("fluid_3.csv line 2\""), "{bad}");
    // Attributes survive into every frame's output.
    let back = boundary_io::read_particle_file(&out_dir.join("fluid_10.vtp"), &Default::default())
        .unwrap();
    assert_eq!(back.set.coords(0), &[10.0, 0.0, 0.0]);
    assert_eq!(back.attributes[1].name, "vx");
}

#[test]
fn all_frames_failing_is_an_error_and_no_match_too() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("a_1.csv"), "nothing\n").unwrap();
    let pattern = dir.path().join("a_*.csv");
    let out = boundary(&["detect", pattern.to_str().unwrap(), "-r", "1"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        stderr(&out).contains("all 1 frames failed"),
        "{}",
        stderr(&out)
    );
    let pattern = dir.path().join("b_*.csv");
    let out = boundary(&["detect", pattern.to_str().unwrap(), "-r", "1"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("no file matches"), "{}", stderr(&out));
}

#[test]
fn radius_auto_is_k_times_the_bulk_spacing_reported_with_a_note() {
    let dir = tempfile::tempdir().unwrap();
    let input = lattice_csv(dir.path());
    let out = boundary(&[
        "detect",
        input.to_str().unwrap(),
        "--radius",
        "auto",
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v: Value = serde_json::from_str(&stdout(&out)).unwrap();
    let spacing = v["spacing"].as_f64().unwrap();
    // The lattice's spacing is 1; the probe ball of the surface particles is partly empty.
    assert!((spacing - 1.0).abs() < 0.1, "{v}");
    assert!(
        (v["radius"].as_f64().unwrap() / (1.45 * spacing) - 1.0).abs() < 1e-12,
        "{v}"
    );
    assert_eq!(v["radius_estimated"], true);
    assert_eq!(v["radius_from"], "auto");
    assert_eq!(v["radius_warning"], Value::Null);
    let err = stderr(&out);
    assert!(
        err.contains("--radius auto: particle spacing")
            && err.contains("--smoothing-length H")
            && err.contains("estimate"),
        "{err}"
    );
    // The score and resample commands take it too.
    let out = boundary(&[
        "score",
        input.to_str().unwrap(),
        "-r",
        "auto",
        "--json",
        "-m",
        "dilts",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let w: Value = serde_json::from_str(&stdout(&out)).unwrap();
    assert_eq!(w["radius"], v["radius"]);
    // One particle has no spacing.
    let one = dir.path().join("one.csv");
    std::fs::write(&one, "x,y\n0,0\n").unwrap();
    let out = boundary(&["detect", one.to_str().unwrap(), "-r", "auto"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("two distinct"), "{}", stderr(&out));
}

#[test]
fn radius_auto_on_a_solver_lattice_finds_its_spacing() {
    // DualSPHysics' 2D dam break: dp = 0.02, h = 0.0283 (the data README).
    let Some(input) = shared("particles2d/dualsphysics_dambreak2d_dp0.02_fluid_4416.csv") else {
        return;
    };
    let out = boundary(&["detect", input.to_str().unwrap(), "-r", "auto", "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v: Value = serde_json::from_str(&stdout(&out)).unwrap();
    let spacing = v["spacing"].as_f64().unwrap();
    assert!((spacing / 0.02 - 1.0).abs() < 0.1, "{v}");
    let ratio = v["radius"].as_f64().unwrap() / 0.0283;
    assert!((0.6..=1.67).contains(&ratio), "{v}");
}

/// The `boundary` column of a CSV written by `detect --output`.
fn labels_of(path: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = header.iter().position(|h| *h == "boundary").unwrap();
    lines
        .map(|l| l.split(',').nth(col).unwrap().to_owned())
        .collect()
}

#[test]
fn smoothing_length_is_the_radius_and_the_sph_sums_h() {
    let dir = tempfile::tempdir().unwrap();
    let input = "../../fixtures/vortex2d_t4.csv";
    for method in ["exact", "marrone", "divr"] {
        let mut labels = Vec::new();
        for (flag, value) in [("--smoothing-length", "0.0075"), ("--radius", "0.0075")] {
            let output = dir.path().join(format!("{method}{flag}.csv"));
            let out = boundary(&[
                "detect",
                input,
                flag,
                value,
                "-m",
                method,
                "-o",
                output.to_str().unwrap(),
                "--json",
            ]);
            assert!(out.status.success(), "{}", stderr(&out));
            let v: Value = serde_json::from_str(&stdout(&out)).unwrap();
            assert_eq!(v["radius"], 0.0075);
            assert_eq!(v["radius_from"], flag[2..].replace('-', "_"));
            labels.push(labels_of(&output));
        }
        assert_eq!(labels[0], labels[1], "{method}");
        assert!(labels[0].iter().any(|l| l == "1") && labels[0].iter().any(|l| l == "0"));
    }
    // h_over_r would make the sums' h a multiple of the smoothing length given.
    let out = boundary(&[
        "detect",
        input,
        "--smoothing-length",
        "0.0075",
        "-m",
        "muller",
        "--set",
        "h_over_r=2",
    ]);
    assert_eq!(out.status.code(), Some(1));
    let err = stderr(&out);
    assert!(
        err.contains("h_over_r=2") && err.contains("--smoothing-length"),
        "{err}"
    );
    // With h_over_r=1 (the default, said aloud) it runs.
    let out = boundary(&[
        "detect",
        input,
        "--smoothing-length",
        "0.0075",
        "-m",
        "muller",
        "--set",
        "h_over_r=1",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    // One resolution option at a time, and a positive length.
    let out = boundary(&[
        "detect",
        input,
        "--smoothing-length",
        "0.0075",
        "--spacing",
        "0.005",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("cannot be used with"),
        "{}",
        stderr(&out)
    );
    let out = boundary(&["detect", input, "--smoothing-length", "-1"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("not a positive length"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn spacing_gives_k_times_dp() {
    let input = "../../fixtures/vortex2d_t4.csv";
    let out = boundary(&["detect", input, "--spacing", "0.005", "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v: Value = serde_json::from_str(&stdout(&out)).unwrap();
    // (JSON's decimal text read back: equal to a few ulps.)
    assert!(
        (v["radius"].as_f64().unwrap() / (1.45 * 0.005) - 1.0).abs() < 1e-12,
        "{v}"
    );
    assert_eq!(v["radius_from"], "spacing");
    assert_eq!(v["radius_estimated"], false);
}

#[test]
fn implausible_radius_is_flagged_with_the_numbers_and_the_run_goes_on() {
    let input = "../../fixtures/vortex2d_t4.csv";
    // 1000 x the spacing: one blob.
    let out = boundary(&["detect", input, "--radius", "7.5", "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v: Value = serde_json::from_str(&stdout(&out)).unwrap();
    let warning = v["radius_warning"].as_str().unwrap();
    assert!(
        warning.contains("r = 7.5") && warning.contains("one blob"),
        "{v}"
    );
    assert!(stderr(&out).contains("warning:") && stderr(&out).contains("one blob"));
    // Below the spacing: almost every particle boundary.
    let out = boundary(&["detect", input, "--radius", "0.002"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("almost every particle will be boundary"),
        "{}",
        stderr(&out)
    );
    // A documented r says nothing.
    let out = boundary(&["detect", input, "--smoothing-length", "0.0075"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(!stderr(&out).contains("warning"), "{}", stderr(&out));
}

#[test]
fn summary_of_a_single_file_is_a_sequence_of_one_frame() {
    let dir = tempfile::tempdir().unwrap();
    let input = lattice_csv(dir.path());
    let summary = dir.path().join("one.csv");
    let out = boundary(&[
        "detect",
        input.to_str().unwrap(),
        "-r",
        "1.2",
        "--summary",
        summary.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = std::fs::read_to_string(&summary).unwrap();
    let row: Vec<&str> = text.lines().nth(1).unwrap().split(',').collect();
    assert_eq!(&row[3..7], &["343", "3", "1.2", "218"], "{text}");
}
