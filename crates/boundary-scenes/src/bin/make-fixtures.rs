//! Regenerates `fixtures/` (the generated scenes as CSV) and `fixtures/scenes.toml` (those
//! scenes plus the public ones). Run by `cargo xtask fixtures`; deterministic.

use boundary_io::{write_particles, Column, Format};
use boundary_scenes::mesh::{sample_obj, MESH_SCENES};
use boundary_scenes::{
    all_scenes, data_dir, fixtures_dir, Manifest, Origin, SceneEntry, SHARED_SCENES,
};

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), String> {
    let dir = fixtures_dir();
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let mut manifest = Manifest::default();
    for scene in all_scenes() {
        let file = format!("{}.csv", scene.name);
        let path = dir.join(&file);
        // Per-particle radii (factors of `radius`) and phases go in columns the manifest names.
        let phases: Option<Vec<i64>> = scene
            .domain
            .phases()
            .map(|p| p.iter().map(|&k| i64::from(k)).collect());
        let mut columns = Vec::new();
        if let Some(r) = scene.set.radii() {
            columns.push(("radius", Column::Float(r)));
        }
        if let Some(p) = &phases {
            columns.push(("phase", Column::Int(p)));
        }
        write_particles(&path, Some(Format::Csv), &scene.set, &columns)
            .map_err(|e| e.to_string())?;
        eprintln!("{}: {} particles", path.display(), scene.set.len());
        // Wall particles in a file of their own beside the scene's.
        let walls = match scene.domain.walls() {
            Some(w) => {
                let file = format!("{}_walls.csv", scene.name);
                let path = dir.join(&file);
                write_particles(&path, Some(Format::Csv), w, &[]).map_err(|e| e.to_string())?;
                eprintln!("{}: {} wall particles", path.display(), w.len());
                Some(file)
            }
            None => None,
        };
        manifest.scene.push(SceneEntry {
            name: scene.name,
            origin: Origin::Fixture,
            dim: scene.set.dim(),
            file,
            radius: scene.radius,
            n: scene.set.len(),
            radius_attribute: scene.set.radii().map(|_| "radius".to_owned()),
            walls,
            solids: scene
                .domain
                .solids()
                .half_spaces()
                .iter()
                .map(ToString::to_string)
                .collect(),
            periodic: scene
                .domain
                .periodic()
                .iter()
                .map(ToString::to_string)
                .collect(),
            phase_attribute: phases.as_ref().map(|_| "phase".to_owned()),
            expected_boundary: None,
            generator: Some(scene.generator.to_owned()),
            params: Some(scene.params),
            provenance: None,
        });
    }
    for &(name, dim, file, radius, n, expected, provenance) in SHARED_SCENES {
        manifest.scene.push(SceneEntry {
            name: name.to_owned(),
            origin: Origin::Shared,
            dim,
            file: file.to_owned(),
            radius,
            n,
            radius_attribute: None,
            walls: None,
            solids: Vec::new(),
            periodic: Vec::new(),
            phase_attribute: None,
            expected_boundary: Some(expected),
            generator: None,
            params: None,
            provenance: Some(provenance.to_owned()),
        });
    }
    for &(name, file, radius, params) in MESH_SCENES {
        // The count is part of the manifest, so the mesh must be there to make it.
        let mesh = data_dir().join(file);
        let set = sample_obj(&mesh, params)
            .map_err(|e| format!("{e} (the mesh scenes need the data directory)"))?;
        eprintln!("{}: {} particles sampled", mesh.display(), set.len());
        manifest.scene.push(SceneEntry {
            name: name.to_owned(),
            origin: Origin::Mesh,
            dim: 3,
            file: file.to_owned(),
            radius,
            n: set.len(),
            radius_attribute: None,
            walls: None,
            solids: Vec::new(),
            periodic: Vec::new(),
            phase_attribute: None,
            expected_boundary: None,
            generator: Some("mesh_volume_sample".to_owned()),
            params: Some(params.to_owned()),
            provenance: Some("../shared/data/README.md (meshes)".to_owned()),
        });
    }
    let path = dir.join("scenes.toml");
    std::fs::write(&path, manifest.to_toml()).map_err(|e| format!("{}: {e}", path.display()))?;
    eprintln!("{}: {} scenes", path.display(), manifest.scene.len());
    Ok(())
}
