//! `boundary detect` in a simulation's domain: wall particles from other files (`--walls`) or
//! from the input itself (`--wall-attribute`), solid half-spaces (`--solid`), periodic axes
//! (`--periodic`) and phases (`--phase-attribute`), end to end through the binary.

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

/// The JSON object of a successful `detect ... --json`.
fn json(args: &[&str]) -> Value {
    let mut all = args.to_vec();
    all.push("--json");
    let out = boundary(&all);
    assert!(out.status.success(), "{args:?}: {}", stderr(&out));
    serde_json::from_slice(&out.stdout).unwrap()
}

/// The one-line error of a failed run with exit status `code` (1: the command failed; 2:
/// clap refused the arguments).
fn failure(args: &[&str], code: i32) -> String {
    let out = boundary(args);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(code), "{args:?}: {err}");
    assert!(out.stdout.is_empty(), "{args:?}");
    assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
    assert!(err.starts_with("error:"), "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{args:?}: {err}");
    err
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

fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// Writes `header` and one line per row to `dir/name`.
fn write_csv(dir: &Path, name: &str, header: &str, rows: &[Vec<f64>]) -> PathBuf {
    let mut text = format!("{header}\n");
    for row in rows {
        let fields: Vec<String> = row.iter().map(f64::to_string).collect();
        text += &fields.join(",");
        text.push('\n');
    }
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// The numeric columns of a CSV file written by `detect`, by header name.
fn read_columns(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_owned)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(|f| f.parse().unwrap()).collect())
        .collect();
    (header, rows)
}

/// The column `name` of a file written by `detect`.
fn column(path: &Path, name: &str) -> Vec<f64> {
    let (header, rows) = read_columns(path);
    let k = header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name} in {header:?}"));
    rows.iter().map(|r| r[k]).collect()
}

/// A deterministic jitter in [-a, a) (a small linear congruential generator).
struct Jitter(u64);

impl Jitter {
    fn next(&mut self, a: f64) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let unit = (self.0 >> 11) as f64 / (1u64 << 53) as f64;
        a * (2.0 * unit - 1.0)
    }
}

/// The table "Fluid with its walls" of `../shared/data/README.md`, reproduced by the exact
/// method: every row, fluid alone and with its wall file.
#[test]
fn the_walls_table_of_the_shared_data_is_reproduced_exactly() {
    // (case, wall file suffix, radius, fluid particles, boundary alone, boundary with walls,
    // wall particles)
    let table: [(&str, &str, &str, u64, u64, u64, u64); 6] = [
        ("dambreak3d_dp0.02", "walls", "0.02", 9600, 2580, 1088, 7846),
        ("dambreak3d_dp0.02", "walls", "0.03", 9600, 2580, 1088, 7846),
        (
            "stillwedge2d_dp0.01",
            "walls",
            "0.01",
            10085,
            532,
            219,
            1161,
        ),
        (
            "stillwedge2d_dp0.01",
            "walls",
            "0.015",
            10085,
            531,
            219,
            1161,
        ),
        (
            "dambreak2d_dp0.02",
            "walls_mdbc_three_layers",
            "0.02",
            4416,
            280,
            280,
            1527,
        ),
        (
            "dambreak2d_dp0.02",
            "walls_mdbc_three_layers",
            "0.03",
            4416,
            280,
            280,
            1527,
        ),
    ];
    for (case, walls, r, n, alone, with_walls, wall_count) in table {
        let Some(fluid) = shared(&format!("walls/dualsphysics_{case}_fluid.csv")) else {
            return;
        };
        let Some(wall_file) = shared(&format!("walls/dualsphysics_{case}_{walls}.csv")) else {
            return;
        };
        let dim = if case.contains("3d") { 3 } else { 2 };
        let v = json(&["detect", s(&fluid), "-r", r, "--method", "exact"]);
        assert_eq!((v["n"].as_u64(), v["dim"].as_u64()), (Some(n), Some(dim)));
        assert_eq!(
            v["boundary"].as_u64(),
            Some(alone),
            "{case} alone at r = {r}"
        );
        assert!(v["walls"].is_null(), "{v}");
        let v = json(&[
            "detect",
            s(&fluid),
            "-r",
            r,
            "--method",
            "exact",
            "--walls",
            s(&wall_file),
        ]);
        assert_eq!(v["n"].as_u64(), Some(n), "the walls are not classified");
        assert_eq!(
            v["boundary"].as_u64(),
            Some(with_walls),
            "{case} with walls at r = {r}"
        );
        assert_eq!(v["walls"].as_u64(), Some(wall_count));
    }
}

/// `--walls`: the summary line names the wall particles used.
#[test]
fn the_summary_line_counts_the_wall_particles() {
    let Some(fluid) = shared("walls/dualsphysics_dambreak3d_dp0.02_fluid.csv") else {
        return;
    };
    let Some(walls) = shared("walls/dualsphysics_dambreak3d_dp0.02_walls.csv") else {
        return;
    };
    let out = boundary(&[
        "detect",
        s(&fluid),
        "--walls",
        s(&walls),
        "--radius",
        "0.03",
    ]);
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains(
            "1088 of 9600 particles boundary (11.3%), 3D from x, y, z, 7846 wall particles"
        ),
        "{err}"
    );
}

/// The tank of half-spaces of `docs/USAGE.md` around the splashsurf dam-break frame: the floor's
/// particles are covered, and `ia` and `ge` (certified) label every particle `exact` labels
/// boundary.
#[test]
fn the_splashsurf_frame_in_its_tank_of_half_spaces() {
    let Some(frame) = shared("particles3d/splashsurf_dam_break_frame_23_24389.csv") else {
        return;
    };
    let tank = [
        "--solid", "y<0", "--solid", "x<-1.55", "--solid", "x>1.55", "--solid", "z<-0.8",
        "--solid", "z>0.8",
    ];
    let dir = tempfile::tempdir().unwrap();
    let mut labels = Vec::new();
    for method in ["exact", "ia", "ge"] {
        let out = dir.path().join(format!("{method}.csv"));
        let mut args = vec!["detect", s(&frame), "--radius", "0.1", "--method", method];
        args.extend(tank);
        args.extend(["-o", s(&out)]);
        let v = json(&args);
        assert_eq!(v["n"].as_u64(), Some(24389), "{method}");
        if method == "exact" {
            assert_eq!(v["boundary"].as_u64(), Some(2592));
        }
        labels.push(column(&out, "boundary"));
    }
    let y = column(&dir.path().join("exact.csv"), "y");
    let floor: Vec<usize> = (0..y.len())
        .filter(|&i| y[i] < 0.031_408_95 + 0.02)
        .collect();
    assert_eq!(floor.len(), 1710);
    assert_eq!(floor.iter().filter(|&&i| labels[0][i] == 1.0).count(), 15);
    for (k, method) in ["ia", "ge"].iter().enumerate() {
        for (i, (&got, &truth)) in labels[k + 1].iter().zip(&labels[0]).enumerate() {
            assert!(
                got == 1.0 || truth == 0.0,
                "{method}: particle {i} is a false negative"
            );
        }
    }
}

/// A 2D tank: a jittered block of fluid 12 x 8 at spacing 1 on a floor and between two side
/// walls of two layers each. Rows `[x, y, type]`, fluid (type 0) and walls (type 1: floor,
/// 2: sides) interleaved in file order.
fn tank() -> Vec<Vec<f64>> {
    let mut jitter = Jitter(7);
    let mut fluid = Vec::new();
    for j in 0..8 {
        for i in 0..12 {
            let (dx, dy) = (jitter.next(0.08), jitter.next(0.08));
            fluid.push(vec![f64::from(i) + dx, f64::from(j) + dy, 0.0]);
        }
    }
    let mut walls = Vec::new();
    for layer in 1..=2 {
        for i in -2..14 {
            walls.push(vec![f64::from(i), -f64::from(layer), 1.0]);
        }
        for j in 0..10 {
            walls.push(vec![-f64::from(layer), f64::from(j), 2.0]);
            walls.push(vec![f64::from(11 + layer), f64::from(j), 2.0]);
        }
    }
    // Interleave: three fluid rows, then one wall row, while both last.
    let mut rows = Vec::new();
    let (mut f, mut w) = (fluid.into_iter(), walls.into_iter());
    loop {
        let mut any = false;
        for row in f.by_ref().take(3) {
            rows.push(row);
            any = true;
        }
        if let Some(row) = w.next() {
            rows.push(row);
            any = true;
        }
        if !any {
            return rows;
        }
    }
}

#[test]
fn wall_rows_of_the_input_label_as_walls_from_another_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let rows = tank();
    let mixed = write_csv(d, "tank.csv", "x,y,type", &rows);
    let fluid_rows: Vec<Vec<f64>> = rows.iter().filter(|r| r[2] == 0.0).cloned().collect();
    let wall_rows: Vec<Vec<f64>> = rows
        .iter()
        .filter(|r| r[2] != 0.0)
        .map(|r| r[..2].to_vec())
        .collect();
    let fluid = write_csv(d, "fluid.csv", "x,y,type", &fluid_rows);
    let walls = write_csv(d, "walls.csv", "x,y", &wall_rows);
    let (split_out, mixed_out) = (d.join("split.csv"), d.join("mixed.csv"));
    for method in ["exact", "dilts", "marrone"] {
        let split = json(&[
            "detect",
            s(&fluid),
            "-r",
            "0.8",
            "-m",
            method,
            "--walls",
            s(&walls),
            "-o",
            s(&split_out),
        ]);
        let mixed = json(&[
            "detect",
            s(&mixed),
            "-r",
            "0.8",
            "-m",
            method,
            "--wall-attribute",
            "type=1,2",
            "-o",
            s(&mixed_out),
        ]);
        // The counts are of the fluid particles only, the walls those of both kinds.
        assert_eq!(mixed["n"].as_u64(), Some(fluid_rows.len() as u64));
        assert_eq!(mixed["walls"].as_u64(), Some(wall_rows.len() as u64));
        assert_eq!(mixed["boundary"], split["boundary"], "{method}");
        assert_eq!(mixed["domain"]["wall_attribute"], "type=1,2");
        // Every input row is written back, in input order, with `wall` and `boundary` = 0
        // for the wall rows; the fluid rows carry the labels of the split run.
        let (header, written) = read_columns(&mixed_out);
        assert_eq!(header, ["x", "y", "boundary", "wall", "type"]);
        assert_eq!(written.len(), rows.len());
        let split_labels = column(&split_out, "boundary");
        let mut fluid_labels = Vec::new();
        for (row, out) in rows.iter().zip(&written) {
            assert_eq!(&out[..2], &row[..2]);
            assert_eq!(out[4], row[2], "the type column is kept");
            if row[2] == 0.0 {
                assert_eq!(out[3], 0.0);
                fluid_labels.push(out[2]);
            } else {
                assert_eq!((out[2], out[3]), (0.0, 1.0), "a wall row");
            }
        }
        assert_eq!(fluid_labels, split_labels, "{method}");
    }
    // The walls matter: without them the bottom and the sides of the block are boundary.
    let alone = json(&["detect", s(&fluid), "-r", "0.8"]);
    let with = json(&["detect", s(&fluid), "-r", "0.8", "--walls", s(&walls)]);
    assert!(
        alone["boundary"].as_u64().unwrap() > with["boundary"].as_u64().unwrap() + 20,
        "{alone} {with}"
    );
    // Walls from the input and from a file together: the floor in the input, the sides in a
    // file, as the tank with both in the input.
    let floor_only: Vec<Vec<f64>> = rows.iter().filter(|r| r[2] != 2.0).cloned().collect();
    let sides: Vec<Vec<f64>> = rows
        .iter()
        .filter(|r| r[2] == 2.0)
        .map(|r| r[..2].to_vec())
        .collect();
    let floor_only = write_csv(d, "floor.csv", "x,y,type", &floor_only);
    let sides = write_csv(d, "sides.csv", "x,y", &sides);
    let both = json(&[
        "detect",
        s(&floor_only),
        "-r",
        "0.8",
        "--wall-attribute",
        "type=1",
        "--walls",
        s(&sides),
    ]);
    assert_eq!(both["boundary"], with["boundary"]);
    assert_eq!(both["walls"], with["walls"]);
    // Values that select no row: a warning, and the fluid alone.
    let out = boundary(&[
        "detect",
        s(&fluid),
        "-r",
        "0.8",
        "--wall-attribute",
        "type=9",
    ]);
    assert!(out.status.success());
    assert!(
        stderr(&out).starts_with("warning: ")
            && stderr(&out).contains("fluid.csv: no row has --wall-attribute type=9"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn frames_share_the_walls_and_the_summary_counts_them() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let rows = tank();
    let fluid_rows: Vec<Vec<f64>> = rows
        .iter()
        .filter(|r| r[2] == 0.0)
        .map(|r| r[..2].to_vec())
        .collect();
    let wall_rows: Vec<Vec<f64>> = rows
        .iter()
        .filter(|r| r[2] != 0.0)
        .map(|r| r[..2].to_vec())
        .collect();
    let frames = d.join("frames");
    std::fs::create_dir(&frames).unwrap();
    write_csv(&frames, "fluid_1.csv", "x,y", &fluid_rows);
    write_csv(&frames, "fluid_2.csv", "x,y", &fluid_rows[..48]);
    let walls = write_csv(d, "walls.csv", "x,y", &wall_rows);
    let single = json(&["detect", s(&frames.join("fluid_1.csv")), "-r", "0.8"]);
    let with = json(&[
        "detect",
        s(&frames.join("fluid_1.csv")),
        "-r",
        "0.8",
        "--walls",
        s(&walls),
    ]);
    let out = d.join("out");
    let summary = d.join("summary.csv");
    let pattern = format!("{}/fluid_*.csv", frames.display());
    let v = json(&[
        "detect",
        &pattern,
        "-r",
        "0.8",
        "--walls",
        s(&walls),
        "--output-dir",
        s(&out),
        "--summary",
        s(&summary),
    ]);
    assert_eq!(v["failed"], 0);
    assert_eq!(v["frames"][0]["boundary"], with["boundary"]);
    assert_ne!(v["frames"][0]["boundary"], single["boundary"]);
    assert_eq!(
        v["frames"][1]["walls"].as_u64(),
        Some(wall_rows.len() as u64)
    );
    let text = std::fs::read_to_string(&summary).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "frame,input,output,n,dim,radius,boundary,seconds,walls,interface,error"
    );
    let first: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(first[6], with["boundary"].to_string());
    assert_eq!(first[8], wall_rows.len().to_string());
    assert_eq!(first[9], "", "no phases: no interface count");
    // Each output holds its frame's particles only.
    assert_eq!(column(&out.join("fluid_2.csv"), "boundary").len(), 48);
}

#[test]
fn wall_files_take_their_radii_from_the_radius_attribute_when_they_have_it() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let rows = tank();
    let with_h = |keep: &dyn Fn(&[f64]) -> bool, h: f64| -> Vec<Vec<f64>> {
        rows.iter()
            .filter(|r| keep(r))
            .map(|r| vec![r[0], r[1], h])
            .collect()
    };
    let fluid = write_csv(d, "fluid.csv", "x,y,h", &with_h(&|r| r[2] == 0.0, 1.0));
    let walls_h1 = write_csv(d, "walls_h1.csv", "x,y,h", &with_h(&|r| r[2] != 0.0, 1.0));
    let walls_small = write_csv(d, "walls_h.csv", "x,y,h", &with_h(&|r| r[2] != 0.0, 0.5));
    let walls_bare: Vec<Vec<f64>> = rows
        .iter()
        .filter(|r| r[2] != 0.0)
        .map(|r| r[..2].to_vec())
        .collect();
    let walls_bare = write_csv(d, "walls_bare.csv", "x,y", &walls_bare);
    let uniform = json(&["detect", s(&fluid), "-r", "0.8", "--walls", s(&walls_h1)]);
    let per = |walls: &Path| {
        json(&[
            "detect",
            s(&fluid),
            "--radius-attribute",
            "h",
            "--radius-scale",
            "0.8",
            "--walls",
            s(walls),
        ])
    };
    // Factor 1 from the file, or factor 1 for a file without the attribute: the uniform run.
    assert_eq!(per(&walls_h1)["boundary"], uniform["boundary"]);
    assert_eq!(per(&walls_bare)["boundary"], uniform["boundary"]);
    // Smaller wall balls cover less.
    let small = per(&walls_small)["boundary"].as_u64().unwrap();
    assert!(small > uniform["boundary"].as_u64().unwrap(), "{small}");
    // A bad radius in a wall file names the wall file and its line.
    let mut bad = with_h(&|r| r[2] != 0.0, 1.0);
    bad[3][2] = -1.0;
    let bad = write_csv(d, "walls_bad.csv", "x,y,h", &bad);
    let err = failure(
        &[
            "detect",
            s(&fluid),
            "--radius-attribute",
            "h",
            "--walls",
            s(&bad),
        ],
        1,
    );
    assert!(
        err.contains("walls_bad.csv") && err.contains("particle 3 (line 5)"),
        "{err}"
    );
}

/// A jittered strip 10 wide (x in [0, 10)) and 6 high at spacing 1, inside [0, 10] x [0, 6].
fn strip() -> Vec<Vec<f64>> {
    let mut jitter = Jitter(11);
    let mut rows = Vec::new();
    for j in 0..6 {
        for i in 0..10 {
            let x = (f64::from(i) + 0.5 + jitter.next(0.1)).clamp(0.0, 10.0);
            let y = f64::from(j) + 0.5 + jitter.next(0.1);
            rows.push(vec![x, y]);
        }
    }
    rows
}

/// `rows` shifted by every combination of `shifts` (one per axis, `[-L, 0, L]` or `[0]`),
/// except the zero shift.
fn images(rows: &[Vec<f64>], shifts: [&[f64]; 2]) -> Vec<Vec<f64>> {
    let mut out = Vec::new();
    for &sx in shifts[0] {
        for &sy in shifts[1] {
            if sx == 0.0 && sy == 0.0 {
                continue;
            }
            out.extend(rows.iter().map(|r| vec![r[0] + sx, r[1] + sy]));
        }
    }
    out
}

#[test]
fn periodic_axes_label_as_explicit_images_given_as_walls() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let rows = strip();
    let input = write_csv(d, "strip.csv", "x,y", &rows);
    let period = [-10.0, 0.0, 10.0];
    let cases: [(&[&str], [&[f64]; 2]); 2] = [
        (&["--periodic", "x:0:10"], [&period, &[0.0]]),
        (
            &["--periodic", "x:0:10", "--periodic", "y:0:6"],
            [&period, &[-6.0, 0.0, 6.0]],
        ),
    ];
    for (k, (options, shifts)) in cases.into_iter().enumerate() {
        let walls = write_csv(d, &format!("images_{k}.csv"), "x,y", &images(&rows, shifts));
        for method in ["exact", "ge"] {
            let (a, b) = (d.join("periodic.csv"), d.join("images.csv"));
            let mut args = vec!["detect", s(&input), "-r", "0.85", "-m", method, "-o", s(&a)];
            args.extend_from_slice(options);
            let periodic = json(&args);
            let explicit = json(&[
                "detect",
                s(&input),
                "-r",
                "0.85",
                "-m",
                method,
                "--walls",
                s(&walls),
                "-o",
                s(&b),
            ]);
            assert_eq!(
                column(&a, "boundary"),
                column(&b, "boundary"),
                "{options:?}"
            );
            assert_eq!(periodic["boundary"], explicit["boundary"], "{options:?}");
            assert!(periodic["walls"].is_null(), "images are not wall particles");
        }
    }
    // Along x only, the rows at the top and bottom stay boundary and the ends do not.
    let v = json(&["detect", s(&input), "-r", "0.85", "--periodic", "x:0:10"]);
    let alone = json(&["detect", s(&input), "-r", "0.85"]);
    assert!(v["boundary"].as_u64() < alone["boundary"].as_u64(), "{v}");
    assert_eq!(v["domain"]["periodic"][0], "x:0:10");
}

#[test]
fn phases_add_an_interface_column_between_the_phases() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A 6 x 4 lattice at spacing 1: phase 0 for x < 3, phase 1 for x >= 3. At r = 0.8 the
    // outer ring (16) is the free surface; of the interior 4 x 2, the columns x = 2 and x = 3
    // face the other phase: those 4 are the interface.
    let rows: Vec<Vec<f64>> = (0..24)
        .map(|k| {
            let (x, y) = (f64::from(k % 6), f64::from(k / 6));
            vec![x, y, if x < 3.0 { 0.0 } else { 1.0 }]
        })
        .collect();
    let input = write_csv(d, "phases.csv", "x,y,phase", &rows);
    let out = d.join("out.csv");
    let v = json(&[
        "detect",
        s(&input),
        "-r",
        "0.8",
        "--phase-attribute",
        "phase",
        "-o",
        s(&out),
    ]);
    assert_eq!(
        (v["boundary"].as_u64(), v["interface"].as_u64()),
        (Some(16), Some(4))
    );
    let (header, written) = read_columns(&out);
    assert_eq!(header, ["x", "y", "boundary", "interface", "phase"]);
    for (row, out) in rows.iter().zip(&written) {
        let (x, y) = (row[0], row[1]);
        let ring = x == 0.0 || x == 5.0 || y == 0.0 || y == 3.0;
        let interface = !ring && (x == 2.0 || x == 3.0);
        assert_eq!(out[2], f64::from(u8::from(ring)), "({x}, {y})");
        assert_eq!(out[3], f64::from(u8::from(interface)), "({x}, {y})");
    }
    // The human summary counts the interface particles.
    let human = boundary(&[
        "detect",
        s(&input),
        "-r",
        "0.8",
        "--phase-attribute",
        "phase",
    ]);
    assert!(
        stderr(&human).contains(
            "16 of 24 particles boundary (66.7%), 2D from x, y, 4 interface particles, r = 0.8"
        ),
        "{}",
        stderr(&human)
    );
    // One phase only: no interface.
    let one = write_csv(
        d,
        "one.csv",
        "x,y,phase",
        &rows
            .iter()
            .map(|r| vec![r[0], r[1], 3.0])
            .collect::<Vec<_>>(),
    );
    let v = json(&["detect", s(&one), "-r", "0.8", "--phase-attribute", "phase"]);
    assert_eq!(v["interface"], 0);
    // Wall rows need no phase number: phases are read for the classified rows only.
    let mut with_walls = rows.clone();
    for i in 0..6 {
        with_walls.push(vec![f64::from(i), -1.0, -7.5]);
    }
    let header = "x,y,phase";
    let input = write_csv(d, "walls.csv", header, &with_walls);
    let v = json(&[
        "detect",
        s(&input),
        "-r",
        "0.8",
        "--phase-attribute",
        "phase",
        "--wall-attribute",
        "phase=-7.5",
    ]);
    assert_eq!(
        (v["boundary"].as_u64(), v["interface"].as_u64()),
        (Some(12), Some(6))
    );
}

#[test]
fn bad_phase_numbers_name_the_particle_and_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (bad, shown) in [(1.5, "1.5"), (-1.0, "-1"), (5e9, "5000000000")] {
        let rows = vec![
            vec![0.0, 0.0, 0.0],
            vec![1.0, 0.0, 0.0],
            vec![2.0, 0.0, bad],
        ];
        let input = write_csv(d, "p.csv", "x,y,phase", &rows);
        let err = failure(
            &[
                "detect",
                s(&input),
                "-r",
                "0.8",
                "--phase-attribute",
                "phase",
            ],
            1,
        );
        assert!(
            err.contains(&format!(
                "p.csv: --phase-attribute \"phase\": particle 2 (line 4): {shown} is not a phase \
                 number"
            )),
            "{err}"
        );
    }
    let rows = vec![vec![0.0, 0.0, 0.0]];
    let input = write_csv(d, "q.csv", "x,y,kind", &rows);
    let err = failure(
        &[
            "detect",
            s(&input),
            "-r",
            "0.8",
            "--phase-attribute",
            "phase",
        ],
        1,
    );
    assert!(
        err.contains(
            "q.csv: no point attribute \"phase\" for --phase-attribute (the file has: kind)"
        ),
        "{err}"
    );
}

#[test]
fn bad_domain_options_and_wall_files_give_one_clear_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let rows: Vec<Vec<f64>> = (0..25)
        .map(|k| vec![f64::from(k % 5), f64::from(k / 5), f64::from(k % 2)])
        .collect();
    let input = write_csv(d, "a.csv", "x,y,type", &rows);
    let input = s(&input);
    // Malformed options: clap names the option (status 2).
    for (option, value, needle) in [
        ("--solid", "w<0", "unknown axis"),
        ("--solid", "y=0", "missing '<' or '>'"),
        ("--solid", "y<abc", "not a number"),
        ("--periodic", "x:1:0", "not finite and increasing"),
        ("--periodic", "x:0", "AXIS:MIN:MAX"),
        ("--periodic", "q:0:1", "unknown axis"),
        ("--wall-attribute", "type", "NAME=V"),
        ("--wall-attribute", "type=", "empty value"),
        ("--wall-attribute", "type=1,x", "'x' is not a finite number"),
    ] {
        let err = failure(&["detect", input, "-r", "1", option, value], 2);
        assert!(err.contains(option) && err.contains(needle), "{err}");
    }
    // A method that cannot honour a solid says so and names the option.
    let err = failure(
        &[
            "detect", input, "-r", "1", "--method", "muller", "--solid", "y<0",
        ],
        1,
    );
    assert!(
        err.contains("method 'muller' cannot honour solid half-spaces (--solid):")
            && err.contains("give the walls as wall particles (--walls)"),
        "{err}"
    );
    // Options that do not fit the particles.
    let err = failure(&["detect", input, "-r", "1", "--solid", "z<0"], 1);
    assert!(err.contains("solid 'z<0': a 2D set has no z axis"), "{err}");
    let err = failure(&["detect", input, "-r", "1", "--periodic", "x:0:3"], 1);
    assert!(
        err.contains("particle 4: x = 4 lies outside the periodic range 0..3"),
        "{err}"
    );
    let err = failure(&["detect", input, "-r", "3", "--periodic", "x:0:4"], 1);
    assert!(
        err.contains("periodic 'x:0:4': the period 4 is shorter than the reach 6"),
        "{err}"
    );
    let err = failure(
        &[
            "detect",
            input,
            "-r",
            "1",
            "--periodic",
            "x:0:8",
            "--periodic",
            "x:0:9",
        ],
        1,
    );
    assert!(err.contains("the axis is given twice"), "{err}");
    let err = failure(
        &["detect", input, "-r", "1", "--wall-attribute", "kind=1"],
        1,
    );
    assert!(
        err.contains(
            "a.csv: no point attribute \"kind\" for --wall-attribute (the file has: type)"
        ),
        "{err}"
    );
    // Wall files: missing, malformed, empty, of the wrong dimension.
    let missing = d.join("missing.csv");
    let err = failure(&["detect", input, "-r", "1", "--walls", s(&missing)], 1);
    assert!(err.contains("missing.csv"), "{err}");
    let malformed = d.join("malformed.csv");
    std::fs::write(&malformed, "x,y\n0,-1\n1,oops\n").unwrap();
    let err = failure(&["detect", input, "-r", "1", "--walls", s(&malformed)], 1);
    assert!(err.contains("malformed.csv") && err.contains('3'), "{err}");
    let empty = d.join("empty.csv");
    std::fs::write(&empty, "x,y\n").unwrap();
    let err = failure(&["detect", input, "-r", "1", "--walls", s(&empty)], 1);
    assert!(
        err.ends_with(
            "empty.csv: --walls: the file holds no particle: the header on line 1 (x, y) is \
             followed by no data row\n"
        ),
        "{err}"
    );
    let walls3d = write_csv(d, "walls3d.csv", "x,y,z", &[vec![0.0, -1.0, 0.5]]);
    let err = failure(&["detect", input, "-r", "1", "--walls", s(&walls3d)], 1);
    assert!(
        err.contains("walls3d.csv: --walls: 3D particles beside the 2D particles of")
            && err.contains("a.csv"),
        "{err}"
    );
    // --dim 2 drops the constant axis of a 3D wall file, as of the input.
    let v = json(&[
        "detect",
        input,
        "-r",
        "1",
        "--walls",
        s(&walls3d),
        "--dim",
        "2",
    ]);
    assert_eq!(v["walls"], 1);
    let walls2d = write_csv(d, "walls2d.csv", "x,y", &[vec![0.0, -1.0]]);
    let walls3d_b = write_csv(
        d,
        "walls3d_b.csv",
        "x,y,z",
        &[vec![0.0, -1.0, 0.5], vec![1.0, -1.0, 0.25]],
    );
    let err = failure(
        &[
            "detect",
            input,
            "-r",
            "1",
            "--walls",
            s(&walls2d),
            "--walls",
            s(&walls3d_b),
        ],
        1,
    );
    assert!(
        err.contains("walls3d_b.csv: --walls: 3D particles, but")
            && err.contains("walls2d.csv holds 2D particles"),
        "{err}"
    );
}

#[test]
fn solid_half_spaces_cover_like_walls_with_exact() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A 6 x 4 lattice at spacing 1, r = 0.8: alone, its outer ring (16) is boundary.
    let rows: Vec<Vec<f64>> = (0..24)
        .map(|k| vec![f64::from(k % 6), f64::from(k / 6)])
        .collect();
    let input = write_csv(d, "block.csv", "x,y", &rows);
    let input = s(&input);
    // A floor half a spacing below the bottom row: the 4 inner particles of that row are
    // covered; the corners still face the free sides.
    let v = json(&["detect", input, "-r", "0.8", "--solid", "y<-0.5"]);
    assert_eq!(v["boundary"], 12);
    assert_eq!(v["domain"]["solids"][0], "y<-0.5");
    // A tank (floor and both sides): only the top row is boundary.
    let out = d.join("tank.csv");
    let v = json(&[
        "detect",
        input,
        "-r",
        "0.8",
        "--solid",
        "y<-0.5",
        "--solid",
        "x<-0.5",
        "--solid",
        "x > 5.5",
        "-o",
        s(&out),
    ]);
    assert_eq!(v["boundary"], 6);
    let labels = column(&out, "boundary");
    for (row, label) in rows.iter().zip(labels) {
        assert_eq!(label, f64::from(u8::from(row[1] == 3.0)), "{row:?}");
    }
}

/// An axis-aligned box `[lo, hi]` as a closed OBJ mesh, outward faces.
fn box_obj(dir: &Path, name: &str, lo: [f64; 3], hi: [f64; 3]) -> PathBuf {
    let mut text = String::new();
    for k in 0..8 {
        let c = |axis: usize| {
            if k >> axis & 1 == 1 {
                hi[axis]
            } else {
                lo[axis]
            }
        };
        text += &format!("v {} {} {}\n", c(0), c(1), c(2));
    }
    // Corner k has bit a set when at the upper end of axis a; faces counter-clockwise seen
    // from outside.
    for face in [
        [1, 3, 7, 5], // x = hi
        [0, 4, 6, 2], // x = lo
        [2, 6, 7, 3], // y = hi
        [0, 1, 5, 4], // y = lo
        [4, 5, 7, 6], // z = hi
        [0, 2, 3, 1], // z = lo
    ] {
        text += &format!("f {} {} {}\n", face[0] + 1, face[1] + 1, face[2] + 1);
        text += &format!("f {} {} {}\n", face[0] + 1, face[2] + 1, face[3] + 1);
    }
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// A solid slab given as a mesh labels a block resting on it as the half-space of its top face
/// does, and the methods that cannot honour a mesh, a 2D input and an open mesh are refused by
/// name.
#[test]
fn a_solid_mesh_covers_like_the_half_space_of_its_face() {
    let dir = tempfile::tempdir().unwrap();
    let mut jitter = Jitter(17);
    let mut rows = Vec::new();
    for x in 0..6 {
        for y in 0..4 {
            for z in 0..6 {
                rows.push(vec![
                    f64::from(x) + jitter.next(0.15),
                    f64::from(y) + 0.5 + jitter.next(0.15),
                    f64::from(z) + jitter.next(0.15),
                ]);
            }
        }
    }
    let block = write_csv(dir.path(), "block.csv", "x,y,z", &rows);
    let slab = box_obj(
        dir.path(),
        "slab.obj",
        [-20.0, -20.0, -20.0],
        [20.0, 0.0, 20.0],
    );
    let with_mesh = dir.path().join("mesh.csv");
    let with_plane = dir.path().join("plane.csv");
    let bare = json(&["detect", s(&block), "--radius", "1.0"]);
    let v = json(&[
        "detect",
        s(&block),
        "--radius",
        "1.0",
        "--solid-mesh",
        s(&slab),
        "-o",
        s(&with_mesh),
    ]);
    assert_eq!(v["domain"]["solid_meshes"][0].as_str(), Some(s(&slab)));
    json(&[
        "detect",
        s(&block),
        "--radius",
        "1.0",
        "--solid",
        "y<0",
        "-o",
        s(&with_plane),
    ]);
    let (a, b) = (
        column(&with_mesh, "boundary"),
        column(&with_plane, "boundary"),
    );
    assert_eq!(a, b);
    assert!(
        v["boundary"].as_u64().unwrap() < bare["boundary"].as_u64().unwrap(),
        "the slab covers the block's floor layer"
    );

    let err = failure(
        &[
            "detect",
            s(&block),
            "--radius",
            "1.0",
            "--method",
            "ge",
            "--solid-mesh",
            s(&slab),
        ],
        1,
    );
    assert!(
        err.contains("method 'ge' cannot honour solid meshes (--solid-mesh):"),
        "{err}"
    );
    let flat = write_csv(
        dir.path(),
        "flat.csv",
        "x,y",
        &[vec![0.0, 0.0], vec![1.0, 0.0]],
    );
    let err = failure(
        &[
            "detect",
            s(&flat),
            "--radius",
            "1.0",
            "--solid-mesh",
            s(&slab),
        ],
        1,
    );
    assert!(err.contains("2D"), "{err}");
    let open = dir.path().join("open.obj");
    std::fs::write(&open, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let err = failure(
        &[
            "detect",
            s(&block),
            "--radius",
            "1.0",
            "--solid-mesh",
            s(&open),
        ],
        1,
    );
    assert!(
        err.contains("open.obj: --solid-mesh:") && err.contains("edge"),
        "{err}"
    );
}
