//! PySPH's own output: `fixtures/pysph/dam_break_2d_00010.hdf5` and `.npz`, written by PySPH's
//! 2D dam break, read to what PySPH's own loader (`pysph.solver.utils.load`) gives for each
//! particle array (`<array>_loaded.csv` beside them, written by `fixtures/pysph/make_pysph.py`):
//! the same particles in the same order, bit for bit, 2D, with `h`, `m`, `rho` and `gid`.
#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_io::{
    particle_arrays, read_particle_array, read_particle_file, read_particle_file_from,
    write_particles, AttributeValues, Format, IoError, ParticleFile, ReadOptions,
};
use std::path::PathBuf;

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/pysph")
        .join(name)
}

const HDF5: &str = "dam_break_2d_00010.hdf5";
const NPZ: &str = "dam_break_2d_00010.npz";

/// What PySPH's loader gave for `array`, read as 2D (its z is 0).
fn loaded(array: &str) -> ParticleFile {
    let options = ReadOptions {
        dim: Some(2),
        format: None,
    };
    read_particle_file(&fixture(&format!("{array}_loaded.csv")), &options).unwrap()
}

fn values(file: &ParticleFile, name: &str) -> Vec<f64> {
    let a = file
        .attributes
        .iter()
        .find(|a| a.name == name)
        .unwrap_or_else(|| panic!("no attribute {name}"));
    match &a.values {
        AttributeValues::Int(v) => v.iter().map(|&x| x as f64).collect(),
        AttributeValues::Float(v) => v.clone(),
    }
}

/// The particles, in order, and the attributes the loader exported are the same.
fn assert_same(read: &ParticleFile, expected: &ParticleFile) {
    assert_eq!(read.set.dim(), 2, "a 2D run reads as 2D");
    assert_eq!(read.set.len(), expected.set.len());
    for i in 0..read.set.len() {
        let (a, b) = (read.set.coords(i), expected.set.coords(i));
        assert!(
            a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits()),
            "particle {i}: {a:?} != {b:?}"
        );
    }
    for name in ["h", "m", "rho", "gid"] {
        assert_eq!(values(read, name), values(expected, name), "{name}");
    }
}

#[test]
fn hdf5_and_npz_read_as_pysphs_loader_does() {
    for name in [HDF5, NPZ] {
        reads_as_pysphs_loader_does(name);
    }
}

fn reads_as_pysphs_loader_does(name: &str) {
    let path = fixture(name);
    // Without a name: the array `fluid`.
    let fluid = read_particle_file(&path, &ReadOptions::default()).unwrap();
    assert_same(&fluid, &loaded("fluid"));
    assert_eq!(
        fluid.position_columns.to_string(),
        "x, y (z dropped: constant)"
    );
    // gid is PySPH's unsigned int: an integer attribute.
    let gid = fluid.attributes.iter().find(|a| a.name == "gid").unwrap();
    assert!(matches!(gid.values, AttributeValues::Int(_)));
    // Properties PySPH declares but does not output are not attributes.
    assert!(fluid.attributes.iter().all(|a| a.name != "au"));

    let walls = read_particle_array(&path, "boundary", &ReadOptions::default()).unwrap();
    assert_same(&walls, &loaded("boundary"));

    // In file order: HDF5 groups sort by name, the .npz keeps PySPH's order.
    let mut listed = particle_arrays(&path, &ReadOptions::default()).unwrap();
    listed.sort();
    let expected: Vec<(String, usize)> = ["boundary", "fluid"]
        .iter()
        .map(|a| (a.to_string(), loaded(a).set.len()))
        .collect();
    assert_eq!(listed, expected);
}

#[test]
fn dim_3_keeps_the_zero_z() {
    let options = ReadOptions {
        dim: Some(3),
        format: None,
    };
    for name in [HDF5, NPZ] {
        let file = read_particle_file(&fixture(name), &options).unwrap();
        assert_eq!(file.set.dim(), 3);
        assert!((0..file.set.len()).all(|i| file.set.coords(i)[2] == 0.0));
        assert_eq!(file.set.len(), loaded("fluid").set.len());
    }
}

#[test]
fn errors_name_the_file_and_the_array() {
    let path = fixture(HDF5);
    let e = read_particle_array(&path, "solid", &ReadOptions::default()).unwrap_err();
    let text = e.to_string();
    for needle in [HDF5, "\"solid\"", "fluid (231 particles)", "boundary"] {
        assert!(text.contains(needle), "{needle}: {text}");
    }
    // Only PySPH files hold named arrays.
    let csv = fixture("fluid_loaded.csv");
    let e = read_particle_array(&csv, "fluid", &ReadOptions::default()).unwrap_err();
    assert!(e.to_string().contains("fluid_loaded.csv"), "{e}");

    // Damaged files: an error naming the file, never a panic.
    let bytes = std::fs::read(&path).unwrap();
    for cut in [0, 8, 100, 1000, bytes.len() / 2] {
        let e = read_particle_file_from(
            &bytes[..cut],
            "cut.hdf5",
            Format::Hdf5,
            &ReadOptions::default(),
        )
        .unwrap_err();
        assert!(e.to_string().contains("cut.hdf5"), "{cut}: {e}");
        assert!(!e.to_string().contains('\n'), "one line: {e}");
    }
    let mut flipped = bytes.clone();
    for k in (0..flipped.len()).step_by(97) {
        flipped[k] ^= 0x5a;
    }
    // Whatever it reads to, it returns.
    let _ = read_particle_file_from(
        flipped.as_slice(),
        "flipped.hdf5",
        Format::Hdf5,
        &ReadOptions::default(),
    );
    for format in [Format::Hdf5, Format::Npz] {
        let name = format!("text.{format}");
        let e = read_particle_file_from(&b"x,y\n0,1\n"[..], &name, format, &ReadOptions::default())
            .unwrap_err();
        assert!(e.to_string().contains(&name), "{e}");
    }
}

#[test]
fn damaged_npz_files_are_errors_naming_the_file() {
    let path = fixture(NPZ);
    let e = read_particle_array(&path, "solid", &ReadOptions::default()).unwrap_err();
    assert!(
        e.to_string().contains(NPZ) && e.to_string().contains("fluid (231"),
        "{e}"
    );
    let bytes = std::fs::read(&path).unwrap();
    for cut in [0, 30, 1000, bytes.len() / 2, bytes.len() - 30] {
        let e = read_particle_file_from(
            &bytes[..cut],
            "cut.npz",
            Format::Npz,
            &ReadOptions::default(),
        )
        .unwrap_err();
        assert!(e.to_string().contains("cut.npz"), "{cut}: {e}");
        assert!(!e.to_string().contains('\n'), "one line: {e}");
    }
    // The pickle itself damaged, inside a valid archive: errors, never a panic.
    let mut archive = zip::ZipArchive::new(std::io::Cursor::new(&bytes)).unwrap();
    let mut entries = Vec::new();
    for name in ["version.npy", "particles.npy", "solver_data.npy"] {
        let mut data = Vec::new();
        std::io::Read::read_to_end(&mut archive.by_name(name).unwrap(), &mut data).unwrap();
        entries.push((name, data));
    }
    let pickle = entries[1].1.clone();
    for k in (130..pickle.len()).step_by(pickle.len() / 40) {
        for damage in [0u8, 0xff, b'.', b'h'] {
            let mut bad = pickle.clone();
            bad[k] = damage;
            entries[1].1 = bad;
            let mut out = std::io::Cursor::new(Vec::new());
            let mut w = zip::ZipWriter::new(&mut out);
            for (name, data) in &entries {
                w.start_file(*name, zip::write::SimpleFileOptions::default())
                    .unwrap();
                std::io::Write::write_all(&mut w, data).unwrap();
            }
            w.finish().unwrap();
            // Whatever it reads to, it returns.
            let _ = read_particle_file_from(
                out.get_ref().as_slice(),
                "damaged.npz",
                Format::Npz,
                &ReadOptions::default(),
            );
        }
    }
}

#[test]
fn pysph_formats_are_read_only() {
    let file = read_particle_file(&fixture(HDF5), &ReadOptions::default()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    for name in ["out.hdf5", "out.npz"] {
        let out = dir.path().join(name);
        let e = write_particles(&out, None, &file.set, &[]).unwrap_err();
        assert!(matches!(e, IoError::ReadOnlyFormat { .. }), "{e}");
        assert!(
            e.to_string().contains(name) && e.to_string().contains(".vtu"),
            "{e}"
        );
        assert!(!out.exists());
    }
}
