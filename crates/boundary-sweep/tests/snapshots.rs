//! Classification snapshots: for every scene of the manifest and every registered method at its
//! default parameters, the confusion counts against `exact` and a fingerprint of the label
//! vector. Any change of any label fails here until the new snapshot is reviewed
//! (`cargo insta review`, or `INSTA_UPDATE=always` and a look at the diff). Certified methods
//! must also have no false negative on any scene.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary::{detector_by_name, methods, Confusion, DetectError, Radius};
use boundary_scenes::{fixtures_dir, Manifest, SharedData};
use std::fmt::Write;

#[test]
fn labels_of_every_method_on_every_scene() {
    let manifest = Manifest::load(&fixtures_dir().join("scenes.toml")).unwrap();
    // A missing data folder fails here unless BOUNDARY_ALLOW_MISSING_DATA=1 (then each
    // skipped scene is printed on stderr by the helper).
    let data = SharedData::from_env();
    for entry in &manifest.scene {
        let Some(set) = data.scene(entry, &fixtures_dir()).unwrap() else {
            continue;
        };
        let r = Radius::new(entry.radius).unwrap();
        let truth = detector_by_name("exact").unwrap().detect(&set, r).unwrap();
        let mut text = format!(
            "{} particles, {}D, r = {}\n",
            set.len(),
            set.dim(),
            entry.radius
        );
        for name in methods() {
            let detector = detector_by_name(name).unwrap();
            let labels = match detector.detect(&set, r) {
                Ok(d) => d.labels,
                // A scene with per-particle radii: methods without support say so.
                Err(DetectError::PerParticleRadii { .. }) if set.radii().is_some() => {
                    writeln!(text, "{name:<8} unsupported: per-particle radii").unwrap();
                    continue;
                }
                Err(e) => panic!("{}: {name}: {e}", entry.name),
            };
            let c = Confusion::from_labels(labels.as_slice(), truth.labels.as_slice()).unwrap();
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
                detector.params(),
                labels.boundary_count(),
                c.tp,
                c.tn,
                c.fp,
                c.fn_,
                labels.fingerprint()
            )
            .unwrap();
        }
        insta::assert_snapshot!(entry.name.clone(), text);
    }
}
