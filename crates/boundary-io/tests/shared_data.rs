//! Every CSV of the shared data folder (`$BOUNDARY_DATA_DIR`, else `../shared/data` beside the
//! workspace) reads with its folder's dimension and, where the file name ends with the particle
//! count (`…_4416.csv`), that many particles; the others are checked against the count in the
//! data README (9600 for the DualSPHysics 3D dam break).
#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use boundary_io::{read_particles, ReadOptions};

/// The count a file name ends with (`name_4416.csv` → 4416), if it does.
fn count_in_name(stem: &str) -> Option<usize> {
    stem.rsplit_once('_')?.1.parse().ok()
}

#[test]
fn every_shared_csv_reads_with_its_dimension_and_count() {
    let mut checked = 0;
    for (folder, dim) in [("particles2d", 2), ("particles3d", 3)] {
        let dir = common::data_dir().join(folder);
        // The policy of `boundary_scenes::SharedData` (which this crate cannot depend on: the
        // scenes crate depends on it): a missing folder fails unless
        // BOUNDARY_ALLOW_MISSING_DATA=1, and then the skip is printed.
        let entries = match std::fs::read_dir(&dir) {
            Ok(entries) => entries,
            Err(e) if std::env::var_os("BOUNDARY_ALLOW_MISSING_DATA").is_some_and(|v| v == "1") => {
                eprintln!(
                    "skipped {} (BOUNDARY_ALLOW_MISSING_DATA=1): {e}",
                    dir.display()
                );
                return;
            }
            Err(e) => panic!(
                "cannot read {} ({e}); set BOUNDARY_DATA_DIR to the shared data folder, or \
                 BOUNDARY_ALLOW_MISSING_DATA=1 to skip the tests that need it",
                dir.display()
            ),
        };
        for entry in entries {
            let path = entry.unwrap().path();
            if path.extension().and_then(|e| e.to_str()) != Some("csv") {
                continue;
            }
            let stem = path.file_stem().unwrap().to_str().unwrap().to_owned();
            let expected = count_in_name(&stem).or(match stem.as_str() {
                // From the data README's table.
                "dualsphysics_dambreak3d_dp0.02_fluid" => Some(9600),
                _ => None,
            });
            let set = read_particles(&path, &ReadOptions::default()).unwrap();
            assert_eq!(set.dim(), dim, "{stem}");
            let expected = expected.unwrap_or_else(|| panic!("{stem}: no known count"));
            assert_eq!(set.len(), expected, "{stem}");
            // Asking for the folder's dimension gives the same set.
            let again = read_particles(
                &path,
                &ReadOptions {
                    dim: Some(dim),
                    format: None,
                },
            )
            .unwrap();
            assert_eq!(again, set, "{stem}");
            checked += 1;
        }
    }
    assert_eq!(checked, 11, "the data README lists 4 2D and 7 3D CSVs");
}
