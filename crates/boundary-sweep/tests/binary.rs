//! The `boundary-sweep` binary end to end on the smallest scale set: its options, the files it
//! writes, and the peak memory its counting allocator measures.

use std::path::Path;
use std::process::Command;

fn sweep(out: &Path, extra: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_boundary-sweep"))
        .current_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("../.."))
        .args(["--scenes", "scale_ball3d_10k", "--methods", "exact,marrone"])
        .args(["--no-single-thread", "--threads", "2", "--out"])
        .arg(out)
        .args(extra)
        .output()
        .expect("the sweep binary runs")
}

#[test]
fn the_scale_tier_writes_its_csv_section_and_plot_with_peak_memory() {
    let dir = tempfile::tempdir().unwrap();
    let out = sweep(dir.path(), &["--scale-max", "10000", "--scale-runs", "2"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = std::fs::read_to_string(dir.path().join("scale.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 3, "{csv}");
    let header: Vec<&str> = lines[0].split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    for line in &lines[1..] {
        let fields: Vec<&str> = line.split(',').collect();
        assert_eq!(fields[col("scene")], "scale_ball3d_10k");
        assert_eq!(fields[col("runs")], "2");
        let n: f64 = fields[col("n")].parse().unwrap();
        let peak: f64 = fields[col("peak_bytes")].parse().unwrap();
        // The binary's allocator counts: at least the labels, one byte per particle.
        assert!(peak >= n, "{line}");
    }
    let report = std::fs::read_to_string(dir.path().join("report.md")).unwrap();
    assert!(report.contains("## Scale tier"));
    assert!(dir.path().join("scale_3d.png").is_file());
    assert!(!dir.path().join("scale_2d.png").exists());
}

#[test]
fn quick_skips_the_scale_tier_and_bad_scale_options_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = sweep(dir.path(), &["--quick"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(dir.path().join("report.md").is_file());
    assert!(!dir.path().join("scale.csv").exists());
    for bad in [["--scale-budget", "0"], ["--scale-runs", "0"]] {
        let out = sweep(dir.path(), &bad);
        assert!(!out.status.success());
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("--scale-budget must be a positive"), "{err}");
    }
}
