//! The one way tests load the public data of the shared data folder ([`crate::data_dir`]):
//! evidence that can fail.
//!
//! A test that reads shared data goes through [`SharedData`]. A missing or unreadable data
//! folder, or a scene in it that does not load, is an error naming the folder and the file,
//! so that a certification or snapshot test cannot pass by having checked nothing. Only when
//! `BOUNDARY_ALLOW_MISSING_DATA=1` is set (a checkout without the data) does a load failure
//! become a skip ([`Ok(None)`](Option::None)), printed on stderr with the reason.
//!
//! ```
//! use boundary_scenes::SharedData;
//!
//! // A folder that does not exist is an error unless missing data is allowed.
//! let strict = SharedData::new("/nonexistent/boundary-data", false);
//! assert!(strict.set::<2>("particles2d/any.csv").is_err());
//! let lenient = SharedData::new("/nonexistent/boundary-data", true);
//! assert_eq!(lenient.set::<2>("particles2d/any.csv"), Ok(None));
//! ```

use crate::manifest::Origin;
use crate::{data_dir, SceneEntry};
use boundary_core::{AnyParticleSet, ParticleSet, Point};
use boundary_core::{Dim, SupportedDim};
use boundary_io::{read_particles, ReadOptions};
use std::path::{Path, PathBuf};

/// Environment variable that turns a missing shared data folder (or scene) into a skip:
/// set to `1` to allow it. Any other value, or none, makes it a failure.
pub const ALLOW_MISSING_DATA_VAR: &str = "BOUNDARY_ALLOW_MISSING_DATA";

/// The shared data folder as the tests see it, with the policy for data that does not load.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SharedData {
    dir: PathBuf,
    allow_missing: bool,
}

impl SharedData {
    /// The folder of [`data_dir`] (`$BOUNDARY_DATA_DIR`, else `../shared/data`), with missing
    /// data allowed iff `BOUNDARY_ALLOW_MISSING_DATA=1`.
    pub fn from_env() -> Self {
        let allow = std::env::var_os(ALLOW_MISSING_DATA_VAR).is_some_and(|v| v == "1");
        Self::new(data_dir(), allow)
    }

    /// An explicit folder and policy (tests of the policy itself use this, never the
    /// process environment).
    pub fn new(dir: impl Into<PathBuf>, allow_missing: bool) -> Self {
        SharedData {
            dir: dir.into(),
            allow_missing,
        }
    }

    /// The folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Whether a load failure is a skip rather than an error.
    pub fn allows_missing(&self) -> bool {
        self.allow_missing
    }

    /// Checks that the folder exists and can be listed.
    pub fn check_dir(&self) -> Result<(), String> {
        std::fs::read_dir(&self.dir).map(drop).map_err(|e| {
            format!(
                "shared data folder {} is missing or unreadable ({e})",
                self.dir.display()
            )
        })
    }

    /// Applies the policy to the result of loading `what` (a file relative to the folder):
    /// `Ok(Some)` when loaded; when it failed, `Ok(None)` (and a line on stderr) if missing
    /// data is allowed, else an error naming the folder, the file and how to proceed.
    pub fn outcome<T>(&self, what: &str, loaded: Result<T, String>) -> Result<Option<T>, String> {
        let why = match self.check_dir().and(loaded) {
            Ok(value) => return Ok(Some(value)),
            Err(why) => why,
        };
        if self.allow_missing {
            // The skip must be visible: this is the one place tests print it.
            #[allow(clippy::print_stderr)]
            {
                eprintln!("skipped {what} ({ALLOW_MISSING_DATA_VAR}=1): {why}");
            }
            Ok(None)
        } else {
            Err(format!(
                "{what}: {why}; set {} to the shared data folder, or {ALLOW_MISSING_DATA_VAR}=1 \
                 to skip the tests that need it",
                crate::DATA_DIR_VAR
            ))
        }
    }

    /// Reads `file` (relative to the folder, as in [`crate::SHARED_SCENES`]) as a
    /// `D`-dimensional set.
    pub fn set<const D: usize>(&self, file: &str) -> Result<Option<ParticleSet<D>>, String>
    where
        Dim<D>: SupportedDim,
    {
        self.outcome(file, read_set::<D>(&self.dir.join(file)))
    }

    /// Loads a scene of the manifest: a fixture is always loaded (its failure is an error
    /// whatever the policy); a shared scene or mesh sample goes through [`Self::outcome`].
    pub fn scene(
        &self,
        entry: &SceneEntry,
        fixtures_dir: &Path,
    ) -> Result<Option<AnyParticleSet>, String> {
        let loaded = entry.load(fixtures_dir, &self.dir);
        match entry.origin {
            Origin::Fixture => loaded.map(Some).map_err(|e| format!("{}: {e}", entry.name)),
            Origin::Shared | Origin::Mesh => self.outcome(&entry.file, loaded),
        }
    }

    /// The volumetric sample of the mesh `file` (relative to the folder) with the sampling
    /// `params` (see [`crate::mesh`]).
    pub fn mesh(&self, file: &str, params: &str) -> Result<Option<ParticleSet<3>>, String> {
        self.outcome(file, crate::mesh::sample_obj(&self.dir.join(file), params))
    }
}

/// Reads a particle file as a `D`-dimensional set.
pub(crate) fn read_set<const D: usize>(path: &Path) -> Result<ParticleSet<D>, String>
where
    Dim<D>: SupportedDim,
{
    let options = ReadOptions {
        dim: Some(D),
        ..Default::default()
    };
    let set = read_particles(path, &options).map_err(|e| e.to_string())?;
    let points = (0..set.len())
        .map(|i| Point::<D>::from_fn(|a, _| set.coords(i)[a]))
        .collect();
    ParticleSet::new(points).map_err(|e| format!("{}: {e}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn missing() -> PathBuf {
        std::env::temp_dir().join("boundary-scenes-no-such-data-folder")
    }

    #[test]
    fn a_missing_folder_is_an_error_naming_it_and_the_variables() {
        let data = SharedData::new(missing(), false);
        let err = data.set::<2>("particles2d/x.csv").unwrap_err();
        assert!(err.contains("boundary-scenes-no-such-data-folder"), "{err}");
        assert!(err.contains("particles2d/x.csv"), "{err}");
        assert!(err.contains(ALLOW_MISSING_DATA_VAR), "{err}");
        assert!(err.contains(crate::DATA_DIR_VAR), "{err}");
        assert!(data.check_dir().is_err());
        let err = data.mesh("meshes/m.obj", "spacing=1").unwrap_err();
        assert!(err.contains("meshes/m.obj"), "{err}");
    }

    #[test]
    fn a_missing_folder_is_a_skip_only_when_allowed() {
        let data = SharedData::new(missing(), true);
        assert_eq!(data.set::<3>("particles3d/x.csv"), Ok(None));
        assert_eq!(data.mesh("meshes/m.obj", "spacing=1"), Ok(None));
    }

    #[test]
    fn a_missing_file_in_an_existing_folder_is_an_error() {
        let dir = tempfile::tempdir().unwrap();
        let data = SharedData::new(dir.path(), false);
        assert!(data.check_dir().is_ok());
        let err = data.set::<2>("absent.csv").unwrap_err();
        assert!(err.contains("absent.csv"), "{err}");
        std::fs::write(dir.path().join("two.csv"), "x,y\n0,0\n1,0.5\n").unwrap();
        let set = data.set::<2>("two.csv").unwrap().unwrap();
        assert_eq!(set.len(), 2);
    }

    #[test]
    fn a_fixture_scene_is_never_skipped() {
        let entry = SceneEntry {
            name: "gone".into(),
            origin: Origin::Fixture,
            dim: 2,
            file: "gone.csv".into(),
            radius: 1.0,
            n: 1,
            radius_attribute: None,
            walls: None,
            solids: Vec::new(),
            periodic: Vec::new(),
            phase_attribute: None,
            expected_boundary: None,
            generator: None,
            params: None,
            provenance: None,
        };
        let lenient = SharedData::new(missing(), true);
        let err = lenient.scene(&entry, &missing()).unwrap_err();
        assert!(err.starts_with("gone:"), "{err}");
        let shared = SceneEntry {
            origin: Origin::Shared,
            ..entry
        };
        assert_eq!(lenient.scene(&shared, &missing()), Ok(None));
        assert!(SharedData::new(missing(), false)
            .scene(&shared, &missing())
            .is_err());
    }
}
