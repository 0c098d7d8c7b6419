//! `mpirun -np 2` and `-np 4` give the labels of the single-process run, byte for byte, on
//! every scene of `fixtures/scenes.toml` (our fixtures, `../shared/data`, the mesh samples).
//!
//! The single-process reference is computed here with the library (`detect` on the whole set)
//! and written with `boundary-io` exactly as `boundary detect --output` writes it; the MPI runs
//! write their gathered labels with the same writer, so the files must be identical.
//! Needs `mpirun` on PATH (this crate only builds where MPI is installed).

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use boundary::{detector_by_name, AnyParticleSet, Radius};
use boundary_io::{read_csv_column, write_particles, Column};
use boundary_scenes::{data_dir, fixtures_dir, Manifest, Origin, SceneEntry, SharedData};

const BIN: &str = env!("CARGO_BIN_EXE_boundary-mpi");

/// A run that takes longer than this has deadlocked (the longest scene takes seconds).
const DEADLINE: Duration = Duration::from_secs(180);

/// Runs `boundary-mpi ARGS` on `np` ranks; kills it past [`DEADLINE`].
fn mpirun(np: usize, args: &[&str]) -> Output {
    let mut child = Command::new("mpirun")
        .args(["--allow-run-as-root", "--oversubscribe", "-np"])
        .arg(np.to_string())
        .arg(BIN)
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("mpirun not found on PATH (install Open MPI: see docs/MPI.md)");
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > DEADLINE {
            child.kill().unwrap();
            panic!("mpirun -np {np} {args:?}: no result after {DEADLINE:?} (deadlock?)");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

fn ok(np: usize, args: &[&str]) -> String {
    let out = mpirun(np, args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(
        out.status.success(),
        "mpirun -np {np} {args:?} failed: {stderr}"
    );
    stderr
}

/// The file the driver reads for `entry`: its own file, or (mesh scenes, sampled at run
/// time) the sample written to CSV, which reads back to the same coordinates.
fn input_file(entry: &SceneEntry, set: &AnyParticleSet, dir: &Path) -> PathBuf {
    match entry.origin {
        Origin::Fixture | Origin::Shared => entry.path(&fixtures_dir(), &data_dir()),
        Origin::Mesh => {
            let path = dir.join(format!("{}.csv", entry.name));
            write_particles(&path, None, set, &[]).unwrap();
            path
        }
    }
}

/// Writes the single-process labels of `method` the way `boundary detect --output` does.
fn reference(set: &AnyParticleSet, r: f64, method: &str, path: &Path) {
    let detection = detector_by_name(method)
        .unwrap()
        .detect(set, Radius::new(r).unwrap())
        .unwrap();
    let flags: Vec<i64> = detection
        .labels
        .as_slice()
        .iter()
        .map(|&b| i64::from(b))
        .collect();
    write_particles(path, None, set, &[("boundary", Column::Int(&flags))]).unwrap();
}

/// Second methods, with the decomposition they run under, on a few scenes: a certified
/// approximation (`ia`, halo 2r), the other reference (`dilts`), an SPH baseline whose
/// halo is wider (`muller`, 4h) and the visibility method (`hpr`, halo 11.9r).
const SECOND: &[(&str, &str, &str)] = &[
    ("vortex2d_t4", "ia", "morton"),
    ("ball_bubble3d", "ia", "rcb"),
    ("sandim_vortex_050", "dilts", "morton"),
    ("duplicates3d", "dilts", "rcb"),
    ("dambreak9_r0.1", "muller", "rcb"),
    ("zalesak2d_rot45", "muller", "morton"),
    ("sheet_ligament_droplets3d", "hpr", "rcb"),
    ("far_offset3d", "marrone", "morton"),
];

#[test]
fn two_and_four_ranks_match_the_single_process_labels_on_every_scene() {
    let manifest = Manifest::load(&fixtures_dir().join("scenes.toml")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let data = SharedData::from_env();
    let mut skipped = 0;
    let mut runs = 0;
    for entry in &manifest.scene {
        // The MPI driver takes one uniform radius (`--radius`); scenes with per-particle radii
        // are not its input.
        if entry.radius_attribute.is_some() {
            continue;
        }
        // A missing data folder fails unless BOUNDARY_ALLOW_MISSING_DATA=1 (the helper prints
        // each skip).
        let Some(set) = data.scene(entry, &fixtures_dir()).unwrap() else {
            skipped += 1;
            continue;
        };
        let input = input_file(entry, &set, dir.path());
        let input = input.to_str().unwrap();
        let radius = entry.radius.to_string();
        let dim = entry.dim.to_string();
        let mut jobs: Vec<(&str, &str, Vec<usize>)> = vec![("exact", "rcb", vec![2, 4])];
        for &(scene, method, decomposition) in SECOND {
            if scene == entry.name {
                jobs.push((method, decomposition, vec![2, 4]));
            }
        }
        for (method, decomposition, ranks) in jobs {
            let expected = dir.path().join(format!("{}-{method}.csv", entry.name));
            reference(&set, entry.radius, method, &expected);
            let expected = std::fs::read(&expected).unwrap();
            for np in ranks {
                let out = dir.path().join(format!("{}-{method}-{np}.csv", entry.name));
                ok(
                    np,
                    &[
                        "detect",
                        input,
                        "--radius",
                        &radius,
                        "--dim",
                        &dim,
                        "--method",
                        method,
                        "--decomposition",
                        decomposition,
                        "--output",
                        out.to_str().unwrap(),
                    ],
                );
                let got = std::fs::read(&out).unwrap();
                assert!(
                    got == expected,
                    "{}: {method} on {np} ranks ({decomposition}) differs from one process",
                    entry.name
                );
                runs += 1;
            }
        }
    }
    assert!(skipped > 0 || runs >= 36, "only {runs} runs");
}

/// Per-rank files in, per-rank files and a gathered file out: the simulation's own
/// decomposition (here: particles dealt round-robin, so every rank's box spans the scene and
/// the strips are large) gives the same labels.
#[test]
fn per_rank_input_and_output_match_the_single_process_labels() {
    let manifest = Manifest::load(&fixtures_dir().join("scenes.toml")).unwrap();
    let entry = manifest
        .scene
        .iter()
        .find(|e| e.name == "ball_bubble3d")
        .unwrap();
    let set = entry.load(&fixtures_dir(), &data_dir()).unwrap();
    let AnyParticleSet::D3(points) = &set else {
        panic!("ball_bubble3d is 3D")
    };
    let dir = tempfile::tempdir().unwrap();
    let ranks = 3;
    for rank in 0..ranks {
        // Rank k holds particles k, k + 3, ... in reverse order (the driver sorts them).
        let mine: Vec<usize> = (rank..points.len()).step_by(ranks).rev().collect();
        let part =
            boundary::ParticleSet::new(mine.iter().map(|&i| points.positions()[i]).collect())
                .unwrap();
        let index: Vec<i64> = mine.iter().map(|&i| i as i64).collect();
        write_particles(
            &dir.path().join(format!("part_{rank}.csv")),
            None,
            &AnyParticleSet::from(part),
            &[("index", Column::Int(&index))],
        )
        .unwrap();
    }
    let expected = dir.path().join("expected.csv");
    reference(&set, entry.radius, "exact", &expected);
    let gathered = dir.path().join("gathered.csv");
    let pattern = dir.path().join("part_{rank}.csv");
    let out_pattern = dir.path().join("labels_{rank}.csv");
    ok(
        ranks,
        &[
            "detect",
            "--per-rank-input",
            pattern.to_str().unwrap(),
            "--radius",
            &entry.radius.to_string(),
            "--output",
            gathered.to_str().unwrap(),
            "--per-rank-output",
            out_pattern.to_str().unwrap(),
        ],
    );
    assert_eq!(
        std::fs::read(&gathered).unwrap(),
        std::fs::read(&expected).unwrap()
    );
    let truth = read_csv_column(&expected, "boundary").unwrap();
    let mut seen = 0;
    for rank in 0..ranks {
        let file = dir.path().join(format!("labels_{rank}.csv"));
        let index = read_csv_column(&file, "index").unwrap();
        let labels = read_csv_column(&file, "boundary").unwrap();
        assert!(
            index.windows(2).all(|w| w[0] < w[1]),
            "rank {rank}: ascending"
        );
        for (i, l) in index.iter().zip(&labels) {
            assert_eq!(truth[*i as usize], *l, "particle {i}");
            assert_eq!(*i as usize % ranks, rank);
        }
        seen += index.len();
    }
    assert_eq!(seen, set.len());
}

#[test]
fn errors_stop_every_rank_and_name_the_cause() {
    let dir = tempfile::tempdir().unwrap();
    // A missing input: rank 0 names the file, every rank exits.
    let missing = dir.path().join("missing.csv");
    let out = mpirun(2, &["detect", missing.to_str().unwrap(), "--radius", "1"]);
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("missing.csv"), "{stderr}");

    // An unknown method and a bad radius: one message, from rank 0.
    let input = fixtures_dir().join("tiny2d.csv");
    let input = input.to_str().unwrap();
    let out = mpirun(2, &["detect", input, "--radius", "1", "--method", "nope"]);
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(stderr.matches("nope").count(), 1, "{stderr}");
    let out = mpirun(2, &["detect", input, "--radius", "-1"]);
    assert!(!out.status.success());

    // A per-rank file with a duplicate global index.
    let set = AnyParticleSet::from(
        boundary::ParticleSet::<2>::from_rows(&[[0.0, 0.0], [1.0, 0.0]]).unwrap(),
    );
    for rank in 0..2 {
        write_particles(
            &dir.path().join(format!("p_{rank}.csv")),
            None,
            &set,
            &[("index", Column::Int(&[0, 1 + rank as i64]))],
        )
        .unwrap();
    }
    let pattern = dir.path().join("p_{rank}.csv");
    let gathered = dir.path().join("out.csv");
    let out = mpirun(
        2,
        &[
            "detect",
            "--per-rank-input",
            pattern.to_str().unwrap(),
            "--radius",
            "1",
            "--output",
            gathered.to_str().unwrap(),
        ],
    );
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("global index 0 is owned by two ranks"),
        "{stderr}"
    );

    // More ranks than particles: the empty ranks take part and the labels are right.
    let out_file = dir.path().join("tiny.csv");
    ok(
        4,
        &[
            "detect",
            input,
            "--radius",
            "1",
            "--output",
            out_file.to_str().unwrap(),
        ],
    );
    let tiny = boundary_io::read_particles(
        &fixtures_dir().join("tiny2d.csv"),
        &boundary_io::ReadOptions::default(),
    )
    .unwrap();
    let expected = dir.path().join("tiny-expected.csv");
    reference(&tiny, 1.0, "exact", &expected);
    assert_eq!(
        std::fs::read(&out_file).unwrap(),
        std::fs::read(&expected).unwrap()
    );
}

/// The parallel read of a CSV file: ranks read byte ranges that cut lines anywhere (CRLF
/// endings, a byte-order mark, a `sep=` line, comments and blank lines between rows, no
/// newline at the end), and the labels, the decomposition and the messages are those of a
/// whole-file read.
#[test]
fn the_parallel_csv_read_matches_the_whole_file_read() {
    let dir = tempfile::tempdir().unwrap();
    // A jittered 9 x 7 x 5 lattice, written by hand with every kind of line.
    let mut text = String::from("\u{feff}sep=;\r\n# a comment before the header\r\nid;x;y;z\r\n");
    let mut k = 0usize;
    for i in 0..9 {
        for j in 0..7 {
            for l in 0..5 {
                let jitter = 0.11 * ((k * 7919) % 13) as f64 / 13.0;
                text.push_str(&format!(
                    "{k};{};{};{}\r\n",
                    (i as f64 + jitter).to_string().replace('.', ","),
                    j,
                    l as f64 - jitter
                ));
                if k % 17 == 3 {
                    text.push_str("# comment between rows\r\n\r\n");
                }
                k += 1;
            }
        }
    }
    let text = text.trim_end().to_owned(); // no newline after the last row
    let input = dir.path().join("lattice.csv");
    std::fs::write(&input, &text).unwrap();
    let set = boundary_io::read_particles(&input, &boundary_io::ReadOptions::default()).unwrap();
    assert_eq!(set.len(), 9 * 7 * 5);
    let expected = dir.path().join("expected.csv");
    reference(&set, 1.2, "exact", &expected);
    let expected = std::fs::read(&expected).unwrap();
    let AnyParticleSet::D3(points) = &set else {
        panic!("3D")
    };
    let input = input.to_str().unwrap();
    for np in [1, 2, 3, 4] {
        for decomposition in ["rcb", "morton"] {
            let out = dir.path().join(format!("out-{np}-{decomposition}.csv"));
            let pattern = dir
                .path()
                .join(format!("own-{np}-{decomposition}-{{rank}}.csv"));
            ok(
                np,
                &[
                    "detect",
                    input,
                    "--radius",
                    "1.2",
                    "--decomposition",
                    decomposition,
                    "--output",
                    out.to_str().unwrap(),
                    "--per-rank-output",
                    pattern.to_str().unwrap(),
                ],
            );
            assert!(
                std::fs::read(&out).unwrap() == expected,
                "{np} ranks ({decomposition}): labels differ from one process"
            );
            // Each rank owns what the core's decomposition of the whole set gives it.
            let owner = match decomposition {
                "rcb" => boundary::implement::decompose::rcb_owners(points, np),
                _ => boundary::implement::decompose::morton_owners(points, np, 2.4),
            };
            for rank in 0..np {
                let file = dir
                    .path()
                    .join(format!("own-{np}-{decomposition}-{rank}.csv"));
                let got: Vec<usize> = read_csv_column(&file, "index")
                    .unwrap()
                    .iter()
                    .map(|&i| i as usize)
                    .collect();
                let want: Vec<usize> = (0..owner.len()).filter(|&i| owner[i] == rank).collect();
                assert_eq!(got, want, "{np} ranks ({decomposition}), rank {rank}");
            }
        }
    }

    // Fewer bytes of rows than ranks, and fewer particles: some ranks read nothing.
    let small = dir.path().join("small.csv");
    std::fs::write(&small, "x,y\n0,0\n1,0").unwrap();
    let small_set =
        boundary_io::read_particles(&small, &boundary_io::ReadOptions::default()).unwrap();
    let expected = dir.path().join("small-expected.csv");
    reference(&small_set, 1.0, "exact", &expected);
    for np in [3, 4] {
        let out = dir.path().join(format!("small-{np}.csv"));
        ok(
            np,
            &[
                "detect",
                small.to_str().unwrap(),
                "--radius",
                "1",
                "--output",
                out.to_str().unwrap(),
            ],
        );
        assert_eq!(
            std::fs::read(&out).unwrap(),
            std::fs::read(&expected).unwrap(),
            "{np} ranks"
        );
    }

    // `--dim 2` drops the axis constant over the whole file, whichever rank reads its rows.
    let flat = dir.path().join("flat.csv");
    let rows: String = (0..40)
        .map(|k| format!("{},7,{}\n", k % 8, k / 8))
        .collect();
    std::fs::write(&flat, format!("x,y,z\n{rows}")).unwrap();
    let options = boundary_io::ReadOptions {
        dim: Some(2),
        format: None,
    };
    let flat_set = boundary_io::read_particles(&flat, &options).unwrap();
    let expected = dir.path().join("flat-expected.csv");
    reference(&flat_set, 1.0, "exact", &expected);
    let out = dir.path().join("flat-3.csv");
    ok(
        3,
        &[
            "detect",
            flat.to_str().unwrap(),
            "--radius",
            "1",
            "--dim",
            "2",
            "--output",
            out.to_str().unwrap(),
        ],
    );
    assert_eq!(
        std::fs::read(&out).unwrap(),
        std::fs::read(&expected).unwrap()
    );
}

/// A bad row is reported once, by the rank that read it, with the line and particle a
/// whole-file read names, wherever the byte ranges fall; a later bad row is not reported.
#[test]
fn a_bad_row_is_named_by_its_line_from_any_rank() {
    let dir = tempfile::tempdir().unwrap();
    for bad in [3usize, 40, 77, 118] {
        let mut text = String::from("# header follows\r\nx,y\r\n");
        for k in 0..120 {
            match k {
                _ if k == bad => text.push_str(&format!("{k},1e400\r\n")),
                _ if k == bad + 1 => text.push_str(&format!("{k},oops\r\n")),
                _ => text.push_str(&format!("{k},0\r\n")),
            }
            if k % 10 == 0 {
                text.push_str("\r\n# a comment\r\n");
            }
        }
        let input = dir.path().join(format!("bad{bad}.csv"));
        std::fs::write(&input, &text).unwrap();
        let whole = boundary_io::read_particles(&input, &boundary_io::ReadOptions::default())
            .unwrap_err()
            .to_string();
        assert!(whole.contains(&format!("particle {bad}:")), "{whole}");
        for np in [1, 2, 3, 4] {
            let out = mpirun(np, &["detect", input.to_str().unwrap(), "--radius", "1"]);
            assert!(!out.status.success());
            let stderr = String::from_utf8_lossy(&out.stderr);
            assert_eq!(
                stderr.matches("error:").count(),
                1,
                "{np} ranks, row {bad}: {stderr}"
            );
            assert!(stderr.contains(&whole), "{np} ranks, row {bad}: {stderr}");
        }
    }
}

/// Formats without a parallel read are read by rank 0 and decomposed in parallel all the
/// same.
#[test]
fn formats_read_by_rank_0_give_the_same_labels() {
    let manifest = Manifest::load(&fixtures_dir().join("scenes.toml")).unwrap();
    let entry = manifest
        .scene
        .iter()
        .find(|e| e.name == "ball_bubble3d")
        .unwrap();
    let set = entry.load(&fixtures_dir(), &data_dir()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let expected = dir.path().join("expected.csv");
    reference(&set, entry.radius, "exact", &expected);
    for ext in ["vtu", "ply"] {
        let input = dir.path().join(format!("ball.{ext}"));
        write_particles(&input, None, &set, &[]).unwrap();
        let out = dir.path().join(format!("out-{ext}.csv"));
        ok(
            3,
            &[
                "detect",
                input.to_str().unwrap(),
                "--radius",
                &entry.radius.to_string(),
                "--output",
                out.to_str().unwrap(),
            ],
        );
        assert_eq!(
            std::fs::read(&out).unwrap(),
            std::fs::read(&expected).unwrap(),
            "{ext}"
        );
    }
}
