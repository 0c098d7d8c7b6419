//! Volumetric samples of closed triangle meshes (`../shared/data/meshes/*.obj`): the lattice
//! points of spacing `h` (plus seeded jitter) that lie inside the mesh. Generated at run time
//! (into the sweep's output folder), never committed.
//!
//! OBJ files are read with `tobj` (triangulated); the inside test is parry's point query on a
//! `TriMesh` built with `TriMeshFlags::ORIENTED`, which uses the pseudo-normals of the closest
//! feature and so answers "inside" for interior points (without the flag parry treats the mesh
//! as a surface and every interior point as outside). The meshes must be closed with outward
//! normals, as the ones in the data directory are.

use crate::generate::fill;
use boundary_core::{ParticleSet, Point};
use parry3d_f64::math::Vector;
use parry3d_f64::query::PointQuery;
use parry3d_f64::shape::{TriMesh, TriMeshFlags};
use rand::{rngs::StdRng, SeedableRng};
use std::path::Path;

/// The volumetric samples of the meshes of the data directory: name, mesh file (relative to
/// the data directory), resolution r, and the sampling parameters (`spacing`, `jitter` as a
/// fraction of the spacing, `seed`). r = 1.2 spacing, as the jittered-lattice benchmarks.
pub const MESH_SCENES: &[(&str, &str, f64, &str)] = &[
    (
        "bunny_small_volume",
        "meshes/bunny_small_closed_taichi_mpm.obj",
        0.03,
        "spacing=0.025, jitter=0.15, seed=11",
    ),
    (
        "stanford_bunny_volume",
        "meshes/stanford_bunny_closed_taichi_mpm.obj",
        3.6,
        "spacing=3, jitter=0.15, seed=12",
    ),
];

/// How to sample a mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshSampling {
    /// Lattice spacing, in the mesh's units.
    pub spacing: f64,
    /// Uniform jitter per axis, as a fraction of the spacing.
    pub jitter: f64,
    /// Seed of the jitter.
    pub seed: u64,
}

impl MeshSampling {
    /// Parses `spacing=H, jitter=J, seed=S` (any order; jitter and seed default to 0).
    pub fn parse(params: &str) -> Result<Self, String> {
        let mut out = MeshSampling {
            spacing: f64::NAN,
            jitter: 0.0,
            seed: 0,
        };
        for part in params.split(',').map(str::trim).filter(|p| !p.is_empty()) {
            let (key, value) = part
                .split_once('=')
                .ok_or_else(|| format!("expected key=value, got '{part}'"))?;
            let bad = |what: &str| format!("{}: {what}, got '{value}'", key.trim());
            match key.trim() {
                "spacing" => {
                    out.spacing = value
                        .trim()
                        .parse()
                        .ok()
                        .filter(|h: &f64| h.is_finite() && *h > 0.0)
                        .ok_or_else(|| bad("a positive number"))?;
                }
                "jitter" => {
                    out.jitter = value
                        .trim()
                        .parse()
                        .ok()
                        .filter(|j: &f64| (0.0..0.5).contains(j))
                        .ok_or_else(|| bad("a number in [0, 0.5)"))?;
                }
                "seed" => out.seed = value.trim().parse().map_err(|_| bad("an integer"))?,
                other => return Err(format!("unknown sampling parameter '{other}'")),
            }
        }
        if out.spacing.is_nan() {
            return Err("missing spacing=".into());
        }
        Ok(out)
    }
}

/// Reads a closed triangle mesh from an OBJ file (faces triangulated).
pub fn read_obj(path: &Path) -> Result<TriMesh, String> {
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    let (models, _materials) =
        tobj::load_obj(path, &options).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut vertices = Vec::new();
    let mut indices = Vec::new();
    for model in &models {
        let base = u32::try_from(vertices.len())
            .map_err(|_| format!("{}: too many vertices", path.display()))?;
        vertices.extend(
            model
                .mesh
                .positions
                .chunks_exact(3)
                .map(|p| Vector::new(p[0], p[1], p[2])),
        );
        indices.extend(
            model
                .mesh
                .indices
                .chunks_exact(3)
                .map(|t| [base + t[0], base + t[1], base + t[2]]),
        );
    }
    if vertices.iter().any(|v| !v.is_finite()) {
        return Err(format!("{}: non-finite vertex coordinates", path.display()));
    }
    TriMesh::with_flags(vertices, indices, TriMeshFlags::ORIENTED)
        .map_err(|e| format!("{}: not a usable triangle mesh: {e}", path.display()))
}

/// The lattice points inside `mesh`: spacing `h` over its bounding box, offset by `h/2` from
/// the box's corner (so that no lattice point starts on an axis-aligned face), then jittered.
/// The inside test is made on the unjittered point.
pub fn sample_volume(mesh: &TriMesh, sampling: &MeshSampling) -> Result<ParticleSet<3>, String> {
    let aabb = mesh.local_aabb();
    let h = sampling.spacing;
    let lo = [aabb.mins.x, aabb.mins.y, aabb.mins.z].map(|c| c + 0.5 * h);
    let hi = [aabb.maxs.x, aabb.maxs.y, aabb.maxs.z];
    let cells: f64 = (0..3)
        .map(|a| ((hi[a] - lo[a]) / h).max(0.0) + 1.0)
        .product();
    if cells > 5e7 {
        return Err(format!(
            "spacing {h} makes {cells:.0} lattice points in the mesh's box: too many"
        ));
    }
    let mut rng = StdRng::seed_from_u64(sampling.seed);
    let points = fill(lo, hi, h, sampling.jitter, &mut rng, |p: &Point<3>| {
        mesh.contains_local_point(Vector::new(p.x, p.y, p.z))
    });
    ParticleSet::new(points).map_err(|e| e.to_string())
}

/// [`read_obj`] then [`sample_volume`] with the parameters text of the manifest.
pub fn sample_obj(path: &Path, params: &str) -> Result<ParticleSet<3>, String> {
    let sampling = MeshSampling::parse(params).map_err(|e| format!("{}: {e}", path.display()))?;
    sample_volume(&read_obj(path)?, &sampling)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    /// A closed cube `[0, 1]^3` with outward normals, as OBJ text (or inward if `flip`).
    fn cube_obj(flip: bool) -> String {
        let mut text = String::new();
        for k in 0..8 {
            text += &format!("v {} {} {}\n", k & 1, (k >> 1) & 1, (k >> 2) & 1);
        }
        // Outward counter-clockwise quads, 1-based.
        let quads = [
            [1, 3, 4, 2],
            [5, 6, 8, 7],
            [1, 2, 6, 5],
            [3, 7, 8, 4],
            [1, 5, 7, 3],
            [2, 4, 8, 6],
        ];
        for q in quads {
            let q = if flip { [q[3], q[2], q[1], q[0]] } else { q };
            text += &format!("f {} {} {} {}\n", q[0], q[1], q[2], q[3]);
        }
        text
    }

    #[test]
    fn a_cube_is_filled_exactly() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cube.obj");
        std::fs::write(&path, cube_obj(false)).unwrap();
        // Lattice at 0.125, 0.375, 0.625, 0.875 per axis: 64 points, all inside.
        let set = sample_obj(&path, "spacing=0.25").unwrap();
        assert_eq!(set.len(), 64);
        assert!(set
            .positions()
            .iter()
            .all(|p| p.iter().all(|&c| (0.0..=1.0).contains(&c))));
        // Jitter keeps the count (the test is on the unjittered points) and is seeded.
        let a = sample_obj(&path, "spacing=0.25, jitter=0.2, seed=3").unwrap();
        let b = sample_obj(&path, "seed=3, jitter=0.2, spacing=0.25").unwrap();
        assert_eq!(a.len(), 64);
        assert_eq!(a.positions(), b.positions());
        assert_ne!(a.positions(), set.positions());
    }

    #[test]
    fn bad_input_is_an_error_naming_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("missing.obj");
        assert!(sample_obj(&missing, "spacing=1")
            .unwrap_err()
            .contains("missing.obj"));
        let empty = dir.path().join("empty.obj");
        std::fs::write(&empty, "# nothing\n").unwrap();
        assert!(sample_obj(&empty, "spacing=1")
            .unwrap_err()
            .contains("empty.obj"));
        let cube = dir.path().join("cube.obj");
        std::fs::write(&cube, cube_obj(false)).unwrap();
        for bad in [
            "",
            "spacing=0",
            "spacing=-1",
            "spacing=1, jitter=0.7",
            "h=1",
        ] {
            assert!(sample_obj(&cube, bad).is_err(), "{bad}");
        }
        assert!(sample_obj(&cube, "spacing=1e-4")
            .unwrap_err()
            .contains("too many"));
    }

    #[test]
    fn the_data_meshes_are_closed_and_sampled_inside() {
        let data = crate::SharedData::from_env();
        for &(name, file, _, params) in MESH_SCENES {
            let Some(set) = data.mesh(file, params).unwrap() else {
                continue;
            };
            let mesh = read_obj(&data.dir().join(file)).unwrap();
            // A closed mesh fills a good part of its box; an open or inverted one would leave
            // nothing inside.
            let aabb = mesh.local_aabb();
            let h = MeshSampling::parse(params).unwrap().spacing;
            let box_points = (0..3)
                .map(|a| ((aabb.maxs[a] - aabb.mins[a]) / h).floor())
                .product::<f64>();
            let fill = set.len() as f64 / box_points;
            eprintln!("{name}: {} particles, fill {fill:.2}", set.len());
            assert!((0.2..0.9).contains(&fill), "{name}: fill {fill}");
        }
    }
}
