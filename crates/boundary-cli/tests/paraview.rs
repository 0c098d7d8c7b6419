//! The ParaView filter (`examples/paraview/BoundaryParticles.py`) through
//! `examples/paraview/label.py`, run with ParaView's `pvpython`: its labels equal the command
//! line's on the DualSPHysics dam break with its walls (3D) and the still wedge (2D), frame by
//! frame on a time series, and a refused input is an error of the filter, never a crash of
//! ParaView. Without `pvpython` (`BOUNDARY_PVPYTHON` names another) the ParaView tests print
//! `SKIPPED` with the install command; `cargo xtask test` installs ParaView when it runs as
//! root.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn plugin() -> PathBuf {
    root().join("examples/paraview/BoundaryParticles.py")
}

/// ParaView's `pvpython`, or `None` after printing why the test is skipped.
fn pvpython() -> Option<PathBuf> {
    if std::env::var("BOUNDARY_PARAVIEW").is_ok_and(|v| v == "skip") {
        eprintln!("SKIPPED: BOUNDARY_PARAVIEW=skip is set");
        return None;
    }
    let name = std::env::var_os("BOUNDARY_PVPYTHON").unwrap_or_else(|| "pvpython".into());
    let name = PathBuf::from(name);
    let found = if name.components().count() > 1 {
        name.is_file().then_some(name.clone())
    } else {
        std::env::var_os("PATH").and_then(|paths| {
            std::env::split_paths(&paths)
                .map(|dir| dir.join(&name))
                .find(|p| p.is_file())
        })
    };
    if found.is_none() {
        eprintln!(
            "SKIPPED: ParaView's {} not found (BOUNDARY_PVPYTHON names another); install it \
             with `sudo apt-get install --no-install-recommends paraview python3-paraview` \
             (Debian, Ubuntu), or run `cargo xtask test` as root, which installs it",
            name.display()
        );
    }
    found
}

/// `pvpython examples/paraview/label.py ARGS` with the command line under test.
fn label(pvpython: &Path, args: &[&str]) -> Output {
    Command::new(pvpython)
        .arg(root().join("examples/paraview/label.py"))
        .args(args)
        .env("BOUNDARY_CLI", env!("CARGO_BIN_EXE_boundary"))
        .output()
        .unwrap()
}

fn boundary(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_boundary"))
        .args(args)
        .output()
        .unwrap()
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
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

/// The column `name` of a CSV with a header, as integers.
fn column(path: &Path, name: &str) -> Vec<i64> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let k = header
        .iter()
        .position(|c| *c == name)
        .unwrap_or_else(|| panic!("{}: no column {name} in {header:?}", path.display()));
    lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.split(',').nth(k).unwrap().trim().parse().unwrap())
        .collect()
}

/// The rows of `path` (a header, then one row per particle), without the header.
fn rows(path: &Path) -> usize {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .count()
}

/// The filter's labels of `fluid` with `walls` at smoothing length `h` equal the command
/// line's, row by row, and count `expected` boundary particles.
fn same_labels_as_the_cli(pvpython: &Path, fluid: &Path, walls: &Path, h: &str, expected: i64) {
    let dir = tempfile::tempdir().unwrap();
    let ours = dir.path().join("paraview.csv");
    let cli = dir.path().join("cli.csv");
    let out = label(
        pvpython,
        &[
            s(fluid),
            s(&ours),
            "--smoothing-length",
            h,
            "--walls",
            s(walls),
        ],
    );
    assert!(
        out.status.success(),
        "label.py failed ({}): {}{}",
        out.status,
        text(&out.stdout),
        text(&out.stderr)
    );
    let out = boundary(&[
        "detect",
        s(fluid),
        "--smoothing-length",
        h,
        "--walls",
        s(walls),
        "--output",
        s(&cli),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let (from_paraview, from_cli) = (column(&ours, "boundary"), column(&cli, "boundary"));
    assert_eq!(from_paraview.len(), rows(fluid), "one label per input row");
    let differ: Vec<usize> = (0..from_cli.len())
        .filter(|&i| from_paraview[i] != from_cli[i])
        .collect();
    assert!(
        differ.is_empty(),
        "{} rows differ from the CLI, the first at rows {:?}",
        differ.len(),
        &differ[..differ.len().min(10)]
    );
    assert_eq!(from_paraview.iter().sum::<i64>(), expected);
}

#[test]
fn paraview_labels_equal_the_cli_on_the_dualsphysics_dam_break_with_its_walls() {
    let (Some(fluid), Some(walls)) = (
        shared("walls/dualsphysics_dambreak3d_dp0.02_fluid.csv"),
        shared("walls/dualsphysics_dambreak3d_dp0.02_walls.csv"),
    ) else {
        return;
    };
    let Some(pvpython) = pvpython() else {
        return;
    };
    // h = 1.5 dp, DualSPHysics' 3D default; the data README's exact count with the walls.
    same_labels_as_the_cli(&pvpython, &fluid, &walls, "0.03", 1088);
}

#[test]
fn paraview_labels_equal_the_cli_on_a_2d_tank_with_its_walls() {
    let (Some(fluid), Some(walls)) = (
        shared("walls/dualsphysics_stillwedge2d_dp0.01_fluid.csv"),
        shared("walls/dualsphysics_stillwedge2d_dp0.01_walls.csv"),
    ) else {
        return;
    };
    let Some(pvpython) = pvpython() else {
        return;
    };
    // The CSV has no z: label.py reads it as 2D points and the filter drops the flat axis.
    same_labels_as_the_cli(&pvpython, &fluid, &walls, "0.015", 219);
}

#[test]
fn paraview_labels_a_time_series_frame_by_frame_as_it_animates() {
    let frames: Vec<Option<PathBuf>> = [1, 50, 100]
        .iter()
        .map(|k| shared(&format!("sequences/sandim_vortex_spin/frame_{k:03}.csv")))
        .collect();
    let Some(frames) = frames.into_iter().collect::<Option<Vec<PathBuf>>>() else {
        return;
    };
    let Some(pvpython) = pvpython() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let labelled = dir.path().join("labelled");
    let mut args: Vec<&str> = frames.iter().map(|f| s(f)).collect();
    args.extend([s(&labelled), "--radius", "0.022105"]);
    let out = label(&pvpython, &args);
    assert!(
        out.status.success(),
        "label.py failed ({}): {}{}",
        out.status,
        text(&out.stdout),
        text(&out.stderr)
    );
    let mut counts = Vec::new();
    for frame in &frames {
        let cli = dir.path().join("cli.csv");
        let out = boundary(&[
            "detect",
            s(frame),
            "--radius",
            "0.022105",
            "--output",
            s(&cli),
        ]);
        assert!(out.status.success(), "{}", text(&out.stderr));
        let ours = labelled.join(frame.file_name().unwrap());
        let (from_paraview, from_cli) = (column(&ours, "boundary"), column(&cli, "boundary"));
        assert_eq!(from_paraview, from_cli, "{}", frame.display());
        counts.push(from_cli.iter().sum::<i64>());
    }
    // The frames differ, so a filter that kept its first result would fail above; the data
    // README's exact counts of frames 1, 50 and 100.
    assert_eq!(counts, [202, 239, 437]);
}

#[test]
fn a_refused_input_is_an_error_of_the_filter_not_a_crash_of_paraview() {
    let Some(pvpython) = pvpython() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let out_csv = dir.path().join("out.csv");
    let fixture = root().join("fixtures/tank_dambreak2d_walls.csv");
    // A 2D scene stored with z = 0 is flat: the command line refuses it as 3D, and the
    // filter passes its message on, with the filter's setting that reads it as 2D.
    let flat = dir.path().join("flat.csv");
    let text_2d = std::fs::read_to_string(&fixture).unwrap();
    let mut lines = text_2d.lines();
    let mut flat_text = format!("{},z\n", lines.next().unwrap());
    for line in lines.filter(|l| !l.trim().is_empty()) {
        flat_text.push_str(&format!("{line},0\n"));
    }
    std::fs::write(&flat, flat_text).unwrap();
    let out = label(&pvpython, &[s(&flat), s(&out_csv), "--radius", "0.015"]);
    let stderr = text(&out.stderr) + &text(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("Boundary Particles: `boundary detect` failed (exit status 1)"),
        "{stderr}"
    );
    assert!(
        stderr.contains("the input: all 2400 particles have z = 0"),
        "{stderr}"
    );
    assert!(stderr.contains("the filter's Dimension: 2D"), "{stderr}");
    // As 2D it is labelled.
    let out = label(
        &pvpython,
        &[s(&flat), s(&out_csv), "--radius", "0.015", "--dim", "2"],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(column(&out_csv, "boundary").len(), 2400);
    // A smoothing length of zero is refused by the filter before the command line runs.
    let out = label(
        &pvpython,
        &[s(&fixture), s(&out_csv), "--smoothing-length", "0"],
    );
    let stderr = text(&out.stderr) + &text(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("set Value to the smoothing length"),
        "{stderr}"
    );
}

#[test]
fn the_plugin_offers_every_method_of_the_command_line() {
    let out = boundary(&["methods", "--json"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let listed: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let names: Vec<String> = listed
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["name"].as_str().unwrap().to_owned())
        .collect();
    let source = std::fs::read_to_string(plugin()).unwrap();
    let start = source.find("METHODS = (").unwrap();
    let end = start + source[start..].find(')').unwrap();
    let offered: Vec<String> = source[start..end]
        .lines()
        .skip(1)
        .map(|l| l.trim().trim_end_matches(',').trim_matches('"').to_owned())
        .filter(|l| !l.is_empty())
        .collect();
    assert_eq!(offered, names);
}

/// `label.py INPUT OUT ARGS` and `boundary detect INPUT ARGS --output` agree on `columns`
/// (the same flags mean the same in both); returns the filter's columns.
fn agree_with_the_cli(
    pvpython: &Path,
    input: &Path,
    args: &[&str],
    columns: &[&str],
) -> Vec<Vec<i64>> {
    let dir = tempfile::tempdir().unwrap();
    let ours = dir.path().join("paraview.csv");
    let cli = dir.path().join("cli.csv");
    let mut label_args = vec![s(input), s(&ours)];
    label_args.extend(args);
    let out = label(pvpython, &label_args);
    assert!(
        out.status.success(),
        "label.py failed ({}): {}{}",
        out.status,
        text(&out.stdout),
        text(&out.stderr)
    );
    let mut cli_args = vec!["detect", s(input)];
    cli_args.extend(args);
    cli_args.extend(["--output", s(&cli)]);
    let out = boundary(&cli_args);
    assert!(out.status.success(), "{}", text(&out.stderr));
    columns
        .iter()
        .map(|name| {
            let from_paraview = column(&ours, name);
            assert_eq!(from_paraview, column(&cli, name), "column {name}");
            from_paraview
        })
        .collect()
}

#[test]
fn a_wall_array_of_the_input_gives_the_labels_of_the_walls_given_apart() {
    let Some(pvpython) = pvpython() else {
        return;
    };
    // The bundled 2D tank, fluid and walls in one file with a `kind` array as DualSPHysics
    // writes its `Type`: 3 for the fluid, 0 for the walls (listed first).
    let fixtures = root().join("fixtures");
    let fluid = std::fs::read_to_string(fixtures.join("tank_dambreak2d_walls.csv")).unwrap();
    let walls = std::fs::read_to_string(fixtures.join("tank_dambreak2d_walls_walls.csv")).unwrap();
    let mut both = String::from("x,y,kind\n");
    let rows = |text: &str, kind: &str, both: &mut String| {
        for line in text.lines().skip(1).filter(|l| !l.trim().is_empty()) {
            both.push_str(&format!("{line},{kind}\n"));
        }
    };
    rows(&walls, "0", &mut both);
    rows(&fluid, "3", &mut both);
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("tank.csv");
    std::fs::write(&input, both).unwrap();
    let labels = agree_with_the_cli(
        &pvpython,
        &input,
        &["--radius", "0.015", "--wall-attribute", "kind=0"],
        &["boundary", "wall"],
    );
    let (boundary_column, wall) = (&labels[0], &labels[1]);
    let n_walls = walls
        .lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .count();
    assert_eq!(wall.iter().sum::<i64>(), n_walls as i64);
    assert!(boundary_column[..n_walls].iter().all(|&b| b == 0));
    // The count of the fixture with its walls in a file of their own (docs/USAGE.md).
    assert_eq!(boundary_column.iter().sum::<i64>(), 99);
}

#[test]
fn a_phase_array_adds_the_interface_labels_of_the_cli() {
    let Some(pvpython) = pvpython() else {
        return;
    };
    let fixtures = root().join("fixtures");
    let walls = fixtures.join("pool_droplet2d_phases_walls.csv");
    let labels = agree_with_the_cli(
        &pvpython,
        &fixtures.join("pool_droplet2d_phases.csv"),
        &[
            "--radius",
            "0.015",
            "--phase-attribute",
            "phase",
            "--walls",
            s(&walls),
        ],
        &["boundary", "interface"],
    );
    // Both kinds of label occur, so the comparison is not of two empty columns.
    assert!(labels[0].iter().sum::<i64>() > 0);
    assert!(labels[1].iter().sum::<i64>() > 0);
}
