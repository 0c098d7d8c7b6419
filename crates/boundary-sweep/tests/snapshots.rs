//! Classification snapshots: for every scene of the manifest and every registered method at its
//! default parameters, the confusion counts against `exact` and a fingerprint of the label
//! vector. Any change of any label fails here until the new snapshot is reviewed
//! (`cargo insta review`, or `INSTA_UPDATE=always` and a look at the diff). Certified methods
//! must also have no false negative on any scene. A scene with a domain (walls, solids,
//! periodic axes, phases) is classified in it by every method, `exact` included; with phases
//! the interface counts are kept too.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary::{detector_by_name, methods, Confusion, DetectError, Domain, Labels, Radius};
use boundary_scenes::{fixtures_dir, Manifest, SharedData};
use std::fmt::Write;

#[test]
fn labels_of_every_method_on_every_scene() {
    let manifest = Manifest::load(&fixtures_dir().join("scenes.toml")).unwrap();
    // A missing data folder fails here unless BOUNDARY_ALLOW_MISSING_DATA=1 (then each
    // skipped scene is printed on stderr by the helper).
    let data = SharedData::from_env();
    for entry in &manifest.scene {
        // A scene with a domain is always one of our fixtures: a failure to load it fails.
        let (set, domain) = if entry.has_domain() {
            let (set, domain) = entry
                .load_in_domain(&fixtures_dir(), data.dir())
                .unwrap_or_else(|e| panic!("{}: {e}", entry.name));
            (set, Some(domain))
        } else {
            let Some(set) = data.scene(entry, &fixtures_dir()).unwrap() else {
                continue;
            };
            (set, None)
        };
        let r = Radius::new(entry.radius).unwrap();
        let classify = |name: &str| -> Result<(Labels, Option<Labels>), DetectError> {
            let detector = detector_by_name(name).unwrap();
            match &domain {
                None => detector.detect(&set, r).map(|d| (d.labels, None)),
                Some(domain) => detector
                    .detect_in(&set, domain, r)
                    .map(|d| (d.detection.labels, d.interface)),
            }
        };
        let (truth, truth_interface) = classify("exact").unwrap();
        let mut text = format!(
            "{} particles, {}D, r = {}\n",
            set.len(),
            set.dim(),
            entry.radius
        );
        if let Some(d) = &domain {
            writeln!(text, "{}", describe(d)).unwrap();
        }
        for name in methods() {
            let detector = detector_by_name(name).unwrap();
            let (labels, interface) = match classify(name) {
                Ok(d) => d,
                // A scene with per-particle radii: methods without support say so.
                Err(DetectError::PerParticleRadii { .. }) if set.radii().is_some() => {
                    writeln!(text, "{name:<8} unsupported: per-particle radii").unwrap();
                    continue;
                }
                // A solid region the method has no rule for: it says so.
                Err(DetectError::UnsupportedOption { option, .. })
                    if domain.as_ref().is_some_and(|d| !d.solids().is_empty()) =>
                {
                    writeln!(text, "{name:<8} unsupported: {option}").unwrap();
                    continue;
                }
                Err(e) => panic!("{}: {name}: {e}", entry.name),
            };
            let c = Confusion::from_labels(labels.as_slice(), truth.as_slice()).unwrap();
            // Certified methods promise Rec = 1 on every scene, fixtures and hard cases included.
            assert!(
                !detector.certified() || c.fn_ == 0,
                "{}: certified method {name} has {} false negatives",
                entry.name,
                c.fn_
            );
            writeln!(
                text,
                "{name:<8} {}: boundary {:>6}  TP {:>6} TN {:>6} FP {:>6} FN {:>6}  labels {:016x}",
                detector.describe(),
                labels.boundary_count(),
                c.tp,
                c.tn,
                c.fp,
                c.fn_,
                labels.fingerprint()
            )
            .unwrap();
            if let (Some(i), Some(t)) = (&interface, &truth_interface) {
                let c = Confusion::from_labels(i.as_slice(), t.as_slice()).unwrap();
                writeln!(
                    text,
                    "{:<8} interface {:>6}  TP {:>6} TN {:>6} FP {:>6} FN {:>6}  labels {:016x}",
                    "",
                    i.boundary_count(),
                    c.tp,
                    c.tn,
                    c.fp,
                    c.fn_,
                    i.fingerprint()
                )
                .unwrap();
            }
        }
        insta::assert_snapshot!(entry.name.clone(), text);
    }
}

/// The domain in one line: wall count, solids, periodic axes, phase counts.
fn describe(domain: &Domain) -> String {
    let mut parts = Vec::new();
    if let Some(w) = domain.walls() {
        parts.push(format!("{} wall particles", w.len()));
    }
    for h in domain.solids().half_spaces() {
        parts.push(format!("solid {h}"));
    }
    for p in domain.periodic() {
        parts.push(format!("periodic {p}"));
    }
    if let Some(phases) = domain.phases() {
        let mut kinds: Vec<u32> = phases.to_vec();
        kinds.sort_unstable();
        kinds.dedup();
        let counts: Vec<String> = kinds
            .iter()
            .map(|k| format!("{}x phase {k}", phases.iter().filter(|&&p| p == *k).count()))
            .collect();
        parts.push(counts.join(", "));
    }
    format!("domain: {}", parts.join("; "))
}
