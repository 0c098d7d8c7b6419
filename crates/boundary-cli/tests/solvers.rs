//! Each solver's own output, end to end: the commands of `docs/SOLVERS.md`, run on the shared
//! data (`../shared/data`) and on files laid out as each solver writes them, reproducing the
//! boundary counts the data README gives.

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

/// The rows of a CSV with a header (`x,y[,z]`), as numbers.
fn csv_rows(path: &Path) -> Vec<Vec<f64>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.split(',').map(|v| v.trim().parse().unwrap()).collect())
        .collect()
}

/// The rows of a summary CSV written by `--summary`, as maps from column to value.
fn summary(path: &Path) -> Vec<std::collections::BTreeMap<String, String>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_owned)
        .collect();
    lines
        .map(|l| {
            header
                .iter()
                .cloned()
                .zip(l.split(',').map(str::to_owned))
                .collect()
        })
        .collect()
}

/// One column of a CSV written by `--output`.
fn column(path: &Path, name: &str) -> Vec<f64> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let at = header.iter().position(|h| *h == name).unwrap();
    lines
        .map(|l| l.split(',').nth(at).unwrap().parse().unwrap())
        .collect()
}

// ---------------------------------------------------------------------------------------------
// SPHinXsys: VTP frames as written, 3D positions with z = 0, fixed wall particles in their own
// file. Counts from ../shared/data/solvers/README.md at r = h = 1.3 dp = 0.026.

const SPHINXSYS: &str = "solvers/sphinxsys";
const SPHINXSYS_WALLS: &str = "solvers/sphinxsys/WallBoundary_0000000000.vtp";
/// (frame, n, boundary of the fluid alone, boundary with the walls).
const SPHINXSYS_FRAMES: [(&str, u64, u64, u64); 3] = [
    ("WaterBlock_0000000000.vtp", 1858, 263, 153),
    ("WaterBlock_0010014653.vtp", 2233, 387, 238),
    ("WaterBlock_0021029012.vtp", 2042, 404, 263),
];

#[test]
fn sphinxsys_frames_read_as_written_give_the_readme_counts() {
    let Some(walls) = shared(SPHINXSYS_WALLS) else {
        return;
    };
    for (frame, n, alone, with_walls) in SPHINXSYS_FRAMES {
        let Some(input) = shared(&format!("{SPHINXSYS}/{frame}")) else {
            return;
        };
        let args = [
            "detect",
            s(&input),
            "--smoothing-length",
            "0.026",
            "--dim",
            "2",
        ];
        let v = json(&args);
        assert_eq!(v["n"].as_u64(), Some(n), "{frame}");
        assert_eq!(v["dim"], 2, "{frame}");
        assert_eq!(v["dropped_column"], "z", "{frame}");
        assert_eq!(v["boundary"].as_u64(), Some(alone), "{frame} alone");
        let mut args = args.to_vec();
        args.extend(["--walls", s(&walls)]);
        let v = json(&args);
        assert_eq!(v["walls"].as_u64(), Some(2012), "{frame}");
        assert_eq!(
            v["boundary"].as_u64(),
            Some(with_walls),
            "{frame} with walls"
        );
    }
}

#[test]
fn sphinxsys_frame_sequence_with_fixed_walls() {
    let Some(walls) = shared(SPHINXSYS_WALLS) else {
        return;
    };
    let Some(dir) = shared(SPHINXSYS) else {
        return;
    };
    let out = tempfile::tempdir().unwrap();
    let pattern = dir.join("WaterBlock_*.vtp");
    let counts = out.path().join("counts.csv");
    let run = boundary(&[
        "detect",
        s(&pattern),
        "--smoothing-length",
        "0.026",
        "--dim",
        "2",
        "--walls",
        s(&walls),
        "--output-dir",
        s(&out.path().join("labels")),
        "--summary",
        s(&counts),
    ]);
    assert!(run.status.success(), "{}", stderr(&run));
    let rows = summary(&counts);
    assert_eq!(rows.len(), 3);
    for (row, (frame, n, _, with_walls)) in rows.iter().zip(SPHINXSYS_FRAMES) {
        assert!(row["input"].ends_with(frame), "{row:?}");
        assert_eq!(row["n"], n.to_string(), "{frame}");
        assert_eq!(row["walls"], "2012", "{frame}");
        assert_eq!(row["boundary"], with_walls.to_string(), "{frame}");
        assert_eq!(row["error"], "", "{frame}");
        assert!(out.path().join("labels").join(frame).is_file(), "{frame}");
    }
}

/// The fluid count changes between frames; the tracker follows SPHinXsys' `OriginalID` and
/// gives the labels of a full detection of each frame.
#[test]
fn sphinxsys_frames_tracked_by_original_id_equal_full_detection() {
    let Some(dir) = shared(SPHINXSYS) else {
        return;
    };
    let out = tempfile::tempdir().unwrap();
    let pattern = dir.join("WaterBlock_*.vtp");
    let common = [
        s(&pattern),
        "--smoothing-length",
        "0.026",
        "--dim",
        "2",
        "--output-format",
        "csv",
    ];
    let tracked = out.path().join("tracked");
    let full = out.path().join("full");
    let counts = out.path().join("tracked.csv");
    let mut args = vec!["detect"];
    args.extend(common);
    args.extend([
        "--track",
        "--track-ids",
        "OriginalID",
        "--output-dir",
        s(&tracked),
        "--summary",
        s(&counts),
    ]);
    let run = boundary(&args);
    assert!(run.status.success(), "{}", stderr(&run));
    let mut args = vec!["detect"];
    args.extend(common);
    args.extend(["--output-dir", s(&full)]);
    let run = boundary(&args);
    assert!(run.status.success(), "{}", stderr(&run));
    let rows = summary(&counts);
    assert_eq!(rows.len(), 3);
    for (row, (frame, n, alone, _)) in rows.iter().zip(SPHINXSYS_FRAMES) {
        assert_eq!(row["n"], n.to_string(), "{frame}");
        assert_eq!(row["boundary"], alone.to_string(), "{frame}");
        let name = frame.replace(".vtp", ".csv");
        let t = column(&tracked.join(&name), "boundary");
        let f = column(&full.join(&name), "boundary");
        assert_eq!(t.len() as u64, n, "{frame}");
        assert_eq!(
            t, f,
            "{frame}: tracked labels differ from the full detection"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// DualSPHysics: one legacy VTK file of fluid and walls as DualSPHysics v5 writes it (GenCase's
// `_All.vtk`, PartVTK's output): binary, big-endian, POLYDATA with one vertex per particle,
// `Idp` as SCALARS unsigned_int, then a FIELD with `Vel`, `Rhop`, `Type` and `Mk`
// (unsigned_char; Type 3 is fluid, 0 a fixed boundary). Walls come first, as DualSPHysics
// numbers them.

const DSPH_FLUID_TYPE: u8 = 3;
const DSPH_FIXED_TYPE: u8 = 0;

/// Writes walls then fluid as a DualSPHysics legacy VTK; `flat_y` puts 2D rows (x, z) at a
/// constant y, as DualSPHysics writes a 2D case.
fn write_dualsphysics_vtk(path: &Path, walls: &[Vec<f64>], fluid: &[Vec<f64>], flat_y: bool) {
    let rows: Vec<(&Vec<f64>, u8)> = walls
        .iter()
        .map(|r| (r, DSPH_FIXED_TYPE))
        .chain(fluid.iter().map(|r| (r, DSPH_FLUID_TYPE)))
        .collect();
    let n = rows.len();
    let mut f = format!(
        "# vtk DataFile Version 3.0\nDualSPHysics particles\nBINARY\nDATASET POLYDATA\nPOINTS {n} float\n"
    )
    .into_bytes();
    for (r, _) in &rows {
        let p = if flat_y {
            [r[0], 0.0, r[1]]
        } else {
            [r[0], r[1], r[2]]
        };
        for c in p {
            f.extend_from_slice(&(c as f32).to_be_bytes());
        }
    }
    f.extend_from_slice(format!("\nVERTICES {n} {}\n", 2 * n).as_bytes());
    for i in 0..n {
        f.extend_from_slice(&1i32.to_be_bytes());
        f.extend_from_slice(&(i as i32).to_be_bytes());
    }
    f.extend_from_slice(
        format!("\nPOINT_DATA {n}\nSCALARS Idp unsigned_int\nLOOKUP_TABLE default\n").as_bytes(),
    );
    for i in 0..n {
        f.extend_from_slice(&(i as u32).to_be_bytes());
    }
    f.extend_from_slice(format!("\nFIELD FieldData 4\nVel 3 {n} float\n").as_bytes());
    f.extend(std::iter::repeat_n(0u8, 12 * n));
    f.extend_from_slice(format!("\nRhop 1 {n} float\n").as_bytes());
    for _ in 0..n {
        f.extend_from_slice(&1000f32.to_be_bytes());
    }
    f.extend_from_slice(format!("\nType 1 {n} unsigned_char\n").as_bytes());
    f.extend(rows.iter().map(|(_, t)| *t));
    f.extend_from_slice(format!("\nMk 1 {n} unsigned_char\n").as_bytes());
    f.extend(rows.iter().map(|(_, t)| u8::from(*t == DSPH_FLUID_TYPE)));
    f.push(b'\n');
    std::fs::write(path, f).unwrap();
}

#[test]
fn dualsphysics_partvtk_with_type_walls_gives_the_readme_counts() {
    let Some(fluid) = shared("walls/dualsphysics_dambreak3d_dp0.02_fluid.csv") else {
        return;
    };
    let Some(walls) = shared("walls/dualsphysics_dambreak3d_dp0.02_walls.csv") else {
        return;
    };
    let (fluid, walls) = (csv_rows(&fluid), csv_rows(&walls));
    assert_eq!((fluid.len(), walls.len()), (9600, 7846));
    let dir = tempfile::tempdir().unwrap();
    let part = dir.path().join("PartAll_0000.vtk");
    write_dualsphysics_vtk(&part, &walls, &fluid, false);
    for r in ["0.02", "0.03"] {
        let v = json(&[
            "detect",
            s(&part),
            "--smoothing-length",
            r,
            "--wall-attribute",
            "Type=0,1,2",
        ]);
        assert_eq!(v["n"], 9600, "r = {r}");
        assert_eq!(v["walls"], 7846, "r = {r}");
        assert_eq!(v["boundary"], 1088, "r = {r}");
    }
}

#[test]
fn dualsphysics_2d_partvtk_flat_in_y_with_type_walls() {
    let Some(fluid) = shared("walls/dualsphysics_stillwedge2d_dp0.01_fluid.csv") else {
        return;
    };
    let Some(walls) = shared("walls/dualsphysics_stillwedge2d_dp0.01_walls.csv") else {
        return;
    };
    let (fluid, walls) = (csv_rows(&fluid), csv_rows(&walls));
    let dir = tempfile::tempdir().unwrap();
    let part = dir.path().join("PartAll_0000.vtk");
    write_dualsphysics_vtk(&part, &walls, &fluid, true);
    for r in ["0.01", "0.015"] {
        let v = json(&[
            "detect",
            s(&part),
            "--smoothing-length",
            r,
            "--dim",
            "2",
            "--wall-attribute",
            "Type=0,1,2",
        ]);
        assert_eq!(v["dropped_column"], "y", "r = {r}");
        assert_eq!(v["n"], 10085, "r = {r}");
        assert_eq!(v["walls"], 1161, "r = {r}");
        assert_eq!(v["boundary"], 219, "r = {r}");
    }
}

// ---------------------------------------------------------------------------------------------
// SPlisHSPlasH: partio BGEO. The shared frame came from a SPlisHSPlasH .bgeo (splashsurf's
// dam_break_frame_9_6859_particles.bgeo); written back as BGEO and read again it gives the
// README's count.

#[test]
fn splishsplash_bgeo_round_trip_gives_the_readme_count() {
    let Some(csv) = shared("particles3d/splashsurf_dam_break_frame_9_6859.csv") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    for name in ["ParticleData_Fluid_9.bgeo", "ParticleData_Fluid_9.bgeo.gz"] {
        let bgeo = dir.path().join(name);
        let first = json(&["detect", s(&csv), "--radius", "0.05", "--output", s(&bgeo)]);
        assert_eq!(first["boundary"], 2407);
        let v = json(&["detect", s(&bgeo), "--radius", "0.05"]);
        assert_eq!(v["n"], 6859, "{name}");
        assert_eq!(v["dim"], 3, "{name}");
        assert_eq!(v["boundary"], 2407, "{name}");
    }
}

// ---------------------------------------------------------------------------------------------
// PySPH: the shared SPHysics dam break, as PySPH's example loads it, at h = 1.3 dx.

#[test]
fn pysph_dam_break_gives_the_readme_count() {
    let Some(csv) = shared("particles3d/pysph_sphysics_case5_dambreak_initial_fluid_15827.csv")
    else {
        return;
    };
    let v = json(&["detect", s(&csv), "--smoothing-length", "0.0253"]);
    assert_eq!(v["n"], 15827);
    assert_eq!(v["boundary"], 4931);
}

// PySPH's own .hdf5 (fixtures/pysph, written by PySPH's 2D dam break): read as it is, the
// walls from its `boundary` array, the labels equal those of the same particles as PySPH's
// loader exported them (`<array>_loaded.csv`).

fn pysph_fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/pysph")
        .join(name)
}

#[test]
fn pysph_hdf5_with_its_wall_array_labels_as_pysphs_loader_output() {
    let hdf5 = pysph_fixture("dam_break_2d_00010.hdf5");
    let fluid = pysph_fixture("fluid_loaded.csv");
    let walls = pysph_fixture("boundary_loaded.csv");
    let dir = tempfile::tempdir().unwrap();
    let from_hdf5 = dir.path().join("hdf5.csv");
    let from_loader = dir.path().join("loader.csv");
    let v = json(&[
        "detect",
        s(&hdf5),
        "--smoothing-length",
        "0.13",
        "--wall-array",
        "boundary",
        "--output",
        s(&from_hdf5),
    ]);
    let expected = json(&[
        "detect",
        s(&fluid),
        "--dim",
        "2",
        "--smoothing-length",
        "0.13",
        "--walls",
        s(&walls),
        "--output",
        s(&from_loader),
    ]);
    assert_eq!(v["dim"], 2);
    assert_eq!(v["n"], csv_rows(&fluid).len());
    assert_eq!(v["walls"], csv_rows(&walls).len());
    assert_eq!(v["boundary"], expected["boundary"]);
    let labels = column(&from_hdf5, "boundary");
    assert_eq!(labels, column(&from_loader, "boundary"));
    // PySPH's .npz of the same run (written without h5py) gives the same labels.
    let npz = pysph_fixture("dam_break_2d_00010.npz");
    let from_npz = dir.path().join("npz.csv");
    let w = json(&[
        "detect",
        s(&npz),
        "--smoothing-length",
        "0.13",
        "--wall-array",
        "boundary",
        "--output",
        s(&from_npz),
    ]);
    assert_eq!(
        (w["n"].clone(), w["walls"].clone()),
        (v["n"].clone(), v["walls"].clone())
    );
    assert_eq!(column(&from_npz, "boundary"), labels);
    // The walls matter: the tank floor is not free surface with them.
    let alone = json(&["detect", s(&hdf5), "--smoothing-length", "0.13"]);
    assert!(
        alone["boundary"].as_u64() > v["boundary"].as_u64(),
        "{alone} {v}"
    );
    // PySPH's properties are written back beside the labels.
    assert_eq!(column(&from_hdf5, "gid"), column(&fluid, "gid"));

    // A directory of frames is written as .vtu (PySPH's formats are read only).
    let out = dir.path().join("labelled");
    let v = json(&[
        "detect",
        s(&hdf5),
        "--smoothing-length",
        "0.13",
        "--wall-array",
        "boundary",
        "--output-dir",
        s(&out),
    ]);
    assert_eq!(v["frames"][0]["boundary"], expected["boundary"]);
    assert_eq!(v["domain"]["wall_arrays"][0], "boundary");
    assert!(out.join("dam_break_2d_00010.vtu").is_file());

    // Refused before any work: writing PySPH's format, and an array the file lacks.
    let o = boundary(&[
        "detect",
        s(&hdf5),
        "--smoothing-length",
        "0.13",
        "--output",
        s(&dir.path().join("out.hdf5")),
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("out.hdf5"), "{}", stderr(&o));
    let o = boundary(&[
        "detect",
        s(&hdf5),
        "--smoothing-length",
        "0.13",
        "--wall-array",
        "solid",
    ]);
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(
        e.contains("dam_break_2d_00010.hdf5") && e.contains("\"solid\""),
        "{e}"
    );
    // --array labels another particle array of the file: its `boundary` array alone, as the
    // loader exported it; an array the file lacks is refused, naming it.
    let walls_out = dir.path().join("walls.csv");
    let v = json(&[
        "detect",
        s(&hdf5),
        "--smoothing-length",
        "0.13",
        "--array",
        "boundary",
        "--output",
        s(&walls_out),
    ]);
    let expected = json(&[
        "detect",
        s(&walls),
        "--dim",
        "2",
        "--smoothing-length",
        "0.13",
        "--output",
        s(&from_loader),
    ]);
    assert_eq!(v["n"], csv_rows(&walls).len());
    assert_eq!(v["boundary"], expected["boundary"]);
    assert_eq!(
        column(&walls_out, "boundary"),
        column(&from_loader, "boundary")
    );
    let o = boundary(&[
        "detect",
        s(&hdf5),
        "--smoothing-length",
        "0.13",
        "--array",
        "solid",
    ]);
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(
        e.contains("dam_break_2d_00010.hdf5") && e.contains("\"solid\""),
        "{e}"
    );
    // A PySPH file of several arrays as --walls would be its fluid: refused, naming the way.
    let o = boundary(&[
        "detect",
        s(&hdf5),
        "--smoothing-length",
        "0.13",
        "--walls",
        s(&hdf5),
    ]);
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(
        e.contains("--wall-array") && e.contains("boundary (532)"),
        "{e}"
    );
}
