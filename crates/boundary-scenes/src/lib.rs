//! The scenes of the comparison sweep and the tests: generated fixtures (`fixtures/`, made by
//! `cargo xtask fixtures`) and the public particle data of `../shared/data`, both listed in the
//! manifest `fixtures/scenes.toml`.
//!
//! Generated scenes use only what each needs: analytic velocity fields integrated with RK4
//! (Bell–Colella–Glaz single vortex, Zalesak's slotted disk, Enright's 3D deformation),
//! lattices with seeded jitter, and hard cases (exact ties, duplicates, far offsets, tiny sets).
//! The public data is never copied: the manifest names its files relative to the data
//! directory ([`data_dir`]).
//!
//! ```
//! use boundary_scenes::{Manifest, Origin};
//!
//! let manifest = Manifest::load(&boundary_scenes::fixtures_dir().join("scenes.toml")).unwrap();
//! assert!(manifest.scene.iter().any(|s| s.origin == Origin::Fixture && s.dim == 2));
//! ```

pub mod against;
pub mod brute;
pub mod certify;
mod generate;
mod manifest;
pub mod mesh;
mod shared;
pub mod solids;
pub mod tuning;

pub use generate::{
    all_scenes, block_in_tank, enright, enright_sequence, enright_sphere, fill,
    jittered_lattice_ball, jittered_lattice_disc, rk4, single_vortex, Scene,
};
pub use manifest::{
    load_scene, Manifest, Origin, SceneDomain, SceneEntry, SceneError, SHARED_SCENES,
};
pub use shared::{SharedData, ALLOW_MISSING_DATA_VAR};

use boundary_core::ParticleSet;
use boundary_core::{Dim, SupportedDim};
use std::path::{Path, PathBuf};

/// Environment variable naming the directory of the public particle data.
pub const DATA_DIR_VAR: &str = "BOUNDARY_DATA_DIR";

/// The directory of the public particle data: `$BOUNDARY_DATA_DIR` if set, else
/// `../shared/data` beside the workspace root.
pub fn data_dir() -> PathBuf {
    match std::env::var_os(DATA_DIR_VAR) {
        Some(dir) => PathBuf::from(dir),
        None => workspace_root().join("../shared/data"),
    }
}

/// The `fixtures/` directory of the workspace.
pub fn fixtures_dir() -> PathBuf {
    workspace_root().join("fixtures")
}

fn workspace_root() -> PathBuf {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    crate_dir
        .parent()
        .and_then(Path::parent)
        .unwrap_or(crate_dir)
        .to_path_buf()
}

/// Reads `file` (relative to [`data_dir`], as in [`SHARED_SCENES`]) as a `D`-dimensional set,
/// under the policy of [`SharedData::from_env`]: a missing folder or file is an error naming
/// them and the variables to set, or `Ok(None)` (a skip, said on stderr) when
/// `BOUNDARY_ALLOW_MISSING_DATA=1`.
pub fn shared_set<const D: usize>(file: &str) -> Result<Option<ParticleSet<D>>, String>
where
    Dim<D>: SupportedDim,
{
    SharedData::from_env().set::<D>(file)
}

/// An `n × n` square lattice of spacing `a`, x fastest.
pub fn square_lattice(n: usize, a: f64) -> Vec<[f64; 2]> {
    (0..n * n)
        .map(|k| [(k % n) as f64 * a, (k / n) as f64 * a])
        .collect()
}

/// An `n × n × n` cubic lattice of spacing `a`, x fastest.
pub fn cubic_lattice(n: usize, a: f64) -> Vec<[f64; 3]> {
    (0..n * n * n)
        .map(|k| {
            [
                (k % n) as f64 * a,
                ((k / n) % n) as f64 * a,
                (k / (n * n)) as f64 * a,
            ]
        })
        .collect()
}
