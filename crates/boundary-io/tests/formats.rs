//! Round trips for every format, files shaped like those other tools write, every shared CSV,
//! and errors that name the file and the line.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_core::{AnyParticleSet, ParticleSet};
use boundary_io::{
    read_csv_column, read_particles, read_particles_from, write_particles, Column, Format, IoError,
    ReadOptions,
};
use proptest::prelude::*;
use std::path::{Path, PathBuf};

fn set2() -> AnyParticleSet {
    ParticleSet::from_rows(&[[0.1, -2.5], [1e-7, 3.0e5], [0.3333333333333333, 7.0]])
        .unwrap()
        .to_any()
}

fn set3() -> AnyParticleSet {
    ParticleSet::from_rows(&[[0.1, -2.5, 1.0], [1e6 + 0.01, 2.0, -0.0], [0.2, 0.7, 1e-12]])
        .unwrap()
        .to_any()
}

fn read(path: &Path, dim: Option<usize>) -> Result<AnyParticleSet, IoError> {
    read_particles(path, &ReadOptions { dim, format: None })
}

#[test]
fn every_format_round_trips_2d_and_3d_with_columns() {
    let dir = tempfile::tempdir().unwrap();
    let labels = [1i64, 0, 1];
    let margin = [0.25, -1.5e-9, 3.0];
    for ext in ["csv", "xyz", "ply", "vtk"] {
        for (d, set) in [(2, set2()), (3, set3())] {
            let path = dir.path().join(format!("p{d}.{ext}"));
            let cols = [
                ("boundary", Column::Int(&labels)),
                ("margin", Column::Float(&margin)),
            ];
            write_particles(&path, None, &set, &cols).unwrap();
            // VTK stores three components: a 2D set reads back with --dim 2.
            let dim = (ext == "vtk" && d == 2).then_some(2);
            let back = read(&path, dim).unwrap();
            assert_eq!(back, set, "{ext} {d}D");
            if ext == "csv" {
                assert_eq!(
                    read_csv_column(&path, "boundary").unwrap(),
                    vec![1.0, 0.0, 1.0]
                );
                assert_eq!(read_csv_column(&path, "MARGIN").unwrap(), margin.to_vec());
            }
        }
    }
}

#[test]
fn vtk_output_carries_the_boundary_attribute() {
    let mut out = Vec::new();
    boundary_io::write_particles_to(
        &mut out,
        Format::Vtk,
        &set3(),
        &[("boundary", Column::Int(&[1, 0, 1]))],
    )
    .unwrap();
    let text = String::from_utf8(out).unwrap();
    assert!(
        text.contains("POINT_DATA 3\nSCALARS boundary int 1\nLOOKUP_TABLE default\n1\n0\n1\n"),
        "{text}"
    );
    assert!(text.contains("VERTICES 3 6"));
}

#[test]
fn dualsphysics_semicolon_csv_in_the_xz_plane() {
    let text = "Pos.x [m];Pos.y [m];Pos.z [m];Idp;Vel.x [m/s];Vel.y [m/s];Vel.z [m/s];Rhop [kg/m^3];Type\n\
                0.1;0.0;0.2;0;0.0;0.0;0.0;1000.0;Fluid\n\
                0.12;0.0;0.2;1;0.0;0.0;0.0;1000.0;Fluid\n\
                0.1;0.0;0.22;2;0.0;0.0;0.0;1000.0;Fluid\n";
    let opts = ReadOptions {
        dim: Some(2),
        format: None,
    };
    let set = read_particles_from(text.as_bytes(), "dsph.csv", Format::Csv, &opts).unwrap();
    let expect = ParticleSet::from_rows(&[[0.1, 0.2], [0.12, 0.2], [0.1, 0.22]])
        .unwrap()
        .to_any();
    assert_eq!(set, expect, "the constant y axis is dropped");
    let three = read_particles_from(
        text.as_bytes(),
        "dsph.csv",
        Format::Csv,
        &ReadOptions::default(),
    )
    .unwrap();
    assert_eq!(three.dim(), 3);
}

#[test]
fn paraview_points_columns_and_headerless_csv() {
    let text = "\"Points:0\",\"Points:1\",\"Points:2\",\"id\"\n1,2,3,0\n4,5,6,1\n";
    let set = read_particles_from(
        text.as_bytes(),
        "pv.csv",
        Format::Csv,
        &ReadOptions::default(),
    )
    .unwrap();
    assert_eq!(
        set,
        ParticleSet::from_rows(&[[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]])
            .unwrap()
            .to_any()
    );
    let bare = "1,2\n3,4\n";
    let set = read_particles_from(
        bare.as_bytes(),
        "bare.csv",
        Format::Csv,
        &ReadOptions::default(),
    )
    .unwrap();
    assert_eq!(set.dim(), 2);
}

#[test]
fn splashsurf_style_binary_ply_little_and_big_endian() {
    let points = [[0.5f32, 1.25, -2.0], [3.0, 0.0, 1e-3]];
    for (format, be) in [("binary_little_endian", false), ("binary_big_endian", true)] {
        let mut bytes = format!(
            "ply\nformat {format} 1.0\ncomment splashsurf\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nproperty float density\nend_header\n"
        )
        .into_bytes();
        for p in &points {
            for v in p.iter().chain(std::iter::once(&1000.0f32)) {
                bytes.extend(if be { v.to_be_bytes() } else { v.to_le_bytes() });
            }
        }
        let set =
            read_particles_from(&bytes[..], "s.ply", Format::Ply, &ReadOptions::default()).unwrap();
        let expect: Vec<[f64; 3]> = points.iter().map(|p| p.map(f64::from)).collect();
        assert_eq!(
            set,
            ParticleSet::from_rows(&expect).unwrap().to_any(),
            "{format}"
        );
        // Truncated data is an error naming the file, not a panic.
        let cut = &bytes[..bytes.len() - 5];
        let err =
            read_particles_from(cut, "s.ply", Format::Ply, &ReadOptions::default()).unwrap_err();
        assert!(err.to_string().starts_with("s.ply:"), "{err}");
    }
}

#[test]
fn splishsplash_style_binary_vtk_unstructured_grid() {
    let mut bytes = b"# vtk DataFile Version 4.1\nSPlisHSPlasH particle data\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 2 float\n".to_vec();
    for v in [1.0f32, 2.0, 3.0, -4.0, 5.5, 6.0] {
        bytes.extend(v.to_be_bytes());
    }
    bytes.extend(b"\nCELLS 2 4\n");
    let set =
        read_particles_from(&bytes[..], "sph.vtk", Format::Vtk, &ReadOptions::default()).unwrap();
    assert_eq!(
        set,
        ParticleSet::from_rows(&[[1.0, 2.0, 3.0], [-4.0, 5.5, 6.0]])
            .unwrap()
            .to_any()
    );
    // A count larger than the data: an error, and no huge allocation.
    let lie = b"# vtk DataFile Version 3.0\nx\nBINARY\nDATASET POLYDATA\nPOINTS 99999999999 float\n\0\0\0\0".to_vec();
    let err =
        read_particles_from(&lie[..], "lie.vtk", Format::Vtk, &ReadOptions::default()).unwrap_err();
    assert!(
        err.to_string().contains("lie.vtk") && err.to_string().contains("99999999999"),
        "{err}"
    );
}

#[test]
fn chemistry_xyz_with_count_and_comment_lines() {
    let text = "3\nwater droplet\nO 0.0 0.0 0.1\nH 0.75 0.0 -0.5\nH -0.75 0.0 -0.5\n";
    let set = read_particles_from(
        text.as_bytes(),
        "w.xyz",
        Format::Xyz,
        &ReadOptions::default(),
    )
    .unwrap();
    assert_eq!(set.len(), 3);
    assert_eq!(set.coords(1), &[0.75, 0.0, -0.5]);
    let short = "4\ncomment\n0 0 0\n";
    let err = read_particles_from(
        short.as_bytes(),
        "s.xyz",
        Format::Xyz,
        &ReadOptions::default(),
    )
    .unwrap_err();
    assert!(err.to_string().contains("declares 4"), "{err}");
    // Plain two-column data with --dim 2 and a 3-column file read as 2D by --dim 2 keeps x, y.
    let plain = "# x y\n0 1\n2 3\n";
    let set = read_particles_from(
        plain.as_bytes(),
        "p.dat",
        Format::Xyz,
        &ReadOptions::default(),
    )
    .unwrap();
    assert_eq!(set.dim(), 2);
}

fn shared_dir() -> PathBuf {
    std::env::var_os("BOUNDARY_DATA_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data"))
}

#[test]
fn every_shared_csv_reads_with_its_dimension_and_count() {
    let mut seen = 0;
    for (sub, dim) in [("particles2d", 2), ("particles3d", 3)] {
        for entry in std::fs::read_dir(shared_dir().join(sub)).unwrap() {
            let path = entry.unwrap().path();
            let set = read(&path, None).unwrap();
            assert_eq!(set.dim(), dim, "{}", path.display());
            // Names ending in `_<count>.csv` state the particle count.
            let stem = path.file_stem().unwrap().to_str().unwrap();
            if let Some(count) = stem
                .rsplit('_')
                .next()
                .and_then(|c| c.parse::<usize>().ok())
            {
                if count > 100 {
                    assert_eq!(set.len(), count, "{}", path.display());
                }
            }
            seen += 1;
        }
    }
    assert!(seen >= 10);
}

/// The error for `text` read as `format` names the file and contains `needle`.
fn assert_error(text: &[u8], format: Format, dim: Option<usize>, needle: &str) {
    let err = read_particles_from(text, "bad.file", format, &ReadOptions { dim, format: None })
        .unwrap_err();
    let msg = err.to_string();
    assert!(msg.starts_with("bad.file"), "{msg}");
    assert!(msg.contains(needle), "expected '{needle}' in: {msg}");
    assert_eq!(msg.lines().count(), 1, "{msg}");
}

#[test]
fn errors_name_the_file_and_the_line() {
    assert_error(
        b"x,y\n0,0\n1,zz\n",
        Format::Csv,
        None,
        "bad.file:3: column 2 ('y'): 'zz'",
    );
    assert_error(
        b"x,y,z\n0,0,0\n1,2\n",
        Format::Csv,
        None,
        "bad.file:3: 2 columns",
    );
    assert_error(
        b"a,b\n0,0\n",
        Format::Csv,
        None,
        "bad.file:1: header has no x and y",
    );
    assert_error(b"x,y\n0,nan\n", Format::Csv, None, "bad.file:2:");
    assert_error(b"x,y\n0,inf\n", Format::Csv, None, "not finite");
    assert_error(b"", Format::Csv, None, "empty");
    assert_error(b"0 0 0\n1 1\n", Format::Xyz, None, "bad.file:2:");
    assert_error(b"x,y\n0,0\n", Format::Csv, Some(3), "3D was asked");
    assert_error(
        b"x,y,z\n0,0,0\n1,1,1\n",
        Format::Csv,
        Some(2),
        "no coordinate axis is constant",
    );
    assert_error(b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nend_header\n0 0\n", Format::Ply, None, "bad.file");
    assert_error(
        b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float a\nend_header\n0\n",
        Format::Ply,
        None,
        "no x and y",
    );
    assert_error(
        b"# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 2 float\n0 0 0\n1 1\n",
        Format::Vtk,
        None,
        "ends after 1",
    );
    assert_error(b"not vtk", Format::Vtk, None, "not a legacy VTK");
    assert_error(
        b"x,y\n\xff\xfe,0\n",
        Format::Csv,
        None,
        "bad.file:2: not UTF-8",
    );
    let err = read(Path::new("/nonexistent/dir/p.csv"), None).unwrap_err();
    assert!(err.to_string().contains("/nonexistent/dir/p.csv"), "{err}");
    let err = read(Path::new("particles.abc"), None).unwrap_err();
    assert!(
        err.to_string().contains("particles.abc: unknown format"),
        "{err}"
    );
    let err = write_particles(
        Path::new("x.csv"),
        None,
        &set2(),
        &[("b", Column::Int(&[1]))],
    )
    .unwrap_err();
    assert!(err.to_string().contains("'b' has 1 values for 3"), "{err}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]
    #[test]
    fn random_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..400), k in 0usize..4) {
        let format = [Format::Csv, Format::Xyz, Format::Ply, Format::Vtk][k];
        let _ = read_particles_from(&bytes[..], "fuzz", format, &ReadOptions::default());
    }

    #[test]
    fn mangled_valid_files_never_panic(cut in 0usize..200, flip in 0usize..200, k in 0usize..4) {
        let format = [Format::Csv, Format::Xyz, Format::Ply, Format::Vtk][k];
        let mut out = Vec::new();
        boundary_io::write_particles_to(&mut out, format, &set3(), &[("boundary", Column::Int(&[1, 0, 1]))]).unwrap();
        if flip < out.len() { out[flip] ^= 0x5a; }
        out.truncate(cut.min(out.len()));
        let _ = read_particles_from(&out[..], "fuzz", format, &ReadOptions::default());
    }
}
