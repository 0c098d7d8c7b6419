//! Inputs that cannot be misread: a near-miss third coordinate (`x,y,zz`) is an error naming
//! the column and the fix, every read says which columns it used (`PositionColumns`), and a
//! file of no particle is an error naming the file.
#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_io::{
    read_particle_file_from, read_positions, Format, IoError, Location, ParticleFile,
    PositionColumns, ReadOptions,
};

fn read(
    bytes: &[u8],
    name: &str,
    format: Format,
    dim: Option<usize>,
) -> Result<ParticleFile, IoError> {
    read_particle_file_from(bytes, name, format, &ReadOptions { dim, format: None })
}

fn names(file: &ParticleFile) -> Vec<&str> {
    file.position_columns
        .names
        .iter()
        .map(String::as_str)
        .collect()
}

const ROWS: &str = "0,0,0\n1,0,0\n0,1,2\n";

#[test]
fn a_near_miss_third_coordinate_is_an_error_naming_the_column_and_the_fix() {
    for (third, shown) in [
        ("zz", "zz"),
        ("z_", "z_"),
        ("z1", "z1"),
        ("ZZ", "ZZ"),
        (" zz ", "zz"),
        ("\"z_\"", "z_"),
        ("zpos", "zpos"),
        ("z.", "z."),
    ] {
        let text = format!("x,y,{third}\n{ROWS}");
        let e = read(text.as_bytes(), "typo.csv", Format::Csv, None).unwrap_err();
        assert!(
            matches!(e, IoError::NearMissColumn { axis: 'z', .. }),
            "{third}: {e}"
        );
        assert_eq!(e.location(), Some(Location::Cell { line: 1, column: 3 }));
        assert_eq!(
            e.to_string(),
            format!(
                "column {shown:?} in typo.csv line 1 column 3 looks like a misspelt z, and \
                 without a z the file would be read as 2D from x, y: rename it to z, or pass \
                 --dim 2 (Python: dim=2) to read it as 2D on purpose"
            )
        );
        // Asking for 3D does not hide it either.
        let e = read(text.as_bytes(), "typo.csv", Format::Csv, Some(3)).unwrap_err();
        assert!(matches!(e, IoError::NearMissColumn { .. }), "{e}");
        // 2D on purpose: x and y, the other column an attribute like any other.
        let file = read(text.as_bytes(), "typo.csv", Format::Csv, Some(2)).unwrap();
        assert_eq!((file.set.dim(), file.set.len()), (2, 3));
        assert_eq!(names(&file), ["x", "y"]);
        assert_eq!(file.position_columns.to_string(), "x, y");
    }
    // The DualSPHysics 2D layout x, z: a misspelt y is caught the same way.
    let e = read(b"Pos.x,Pos.yy,Pos.z\n0,0,0\n", "d.csv", Format::Csv, None).unwrap_err();
    assert!(
        e.to_string().starts_with(
            "column \"Pos.yy\" in d.csv line 1 column 2 looks like a misspelt y, and without a \
             y the file would be read as 2D from Pos.x, Pos.z"
        ),
        "{e}"
    );
}

#[test]
fn case_spaces_quotes_and_units_name_the_axis_and_are_read_as_it() {
    for (header, shown) in [
        ("x,y,Z", ["x", "y", "Z"]),
        (" x , y , z ", ["x", "y", "z"]),
        ("\"x\",\"y\",\"z\"", ["x", "y", "z"]),
        ("X [m],Y [m],Z [m]", ["X [m]", "Y [m]", "Z [m]"]),
    ] {
        let text = format!("{header}\n{ROWS}");
        let file = read(text.as_bytes(), "ok.csv", Format::Csv, None).unwrap();
        assert_eq!(file.set.dim(), 3, "{header}");
        assert_eq!(names(&file), shown, "{header}");
    }
    // Other columns that merely contain a z are no near misses: the file is 2D.
    let file = read(b"x,y,vz,zone,size\n0,0,1,2,3\n", "v.csv", Format::Csv, None).unwrap();
    assert_eq!(file.set.dim(), 2);
}

#[test]
fn near_misses_in_xyz_names_and_ply_properties_are_errors_too() {
    let e = read(b"# x y zz\n0 0 0\n1 1 1\n", "n.xyz", Format::Xyz, None).unwrap_err();
    assert!(matches!(e, IoError::NearMissColumn { .. }), "{e}");
    assert!(e.to_string().contains("n.xyz line 1 column 3"), "{e}");
    let file = read(b"# x y zz\n0 0 0\n1 1 1\n", "n.xyz", Format::Xyz, Some(2)).unwrap();
    assert_eq!((file.set.dim(), names(&file)), (2, vec!["x", "y"]));

    let ply = b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float Z\nend_header\n0 0 0\n1 1 1\n";
    let e = read(ply, "p.ply", Format::Ply, None).unwrap_err();
    assert!(
        e.to_string().starts_with(
            "vertex property \"Z\" in p.ply looks like a misspelt z, and without a z the file \
             would be read as 2D from x, y: rename it to z"
        ),
        "{e}"
    );
    assert_eq!(
        read(ply, "p.ply", Format::Ply, Some(2)).unwrap().set.dim(),
        2
    );
}

#[test]
fn a_missing_axis_with_a_near_miss_names_the_column_to_rename() {
    let e = read(b"x,yy\n0,0\n", "m.csv", Format::Csv, None).unwrap_err();
    assert!(
        e.to_string().contains(
            "missing position column y (need x and y, optionally z, also spelled like pos.x, \
             \"Pos.x [m]\", position_x or px); the header has \"x\", \"yy\"; column 2 (\"yy\") \
             looks like a misspelt y: rename it to y in m.csv line 1"
        ),
        "{e}"
    );
}

#[test]
fn every_format_says_which_columns_it_read() {
    let csv = read(
        b"Pos.x [m];Pos.y [m];Pos.z [m]\n0;0;0\n1;2;3\n",
        "d.csv",
        Format::Csv,
        None,
    )
    .unwrap();
    assert_eq!(
        csv.position_columns.to_string(),
        "Pos.x [m], Pos.y [m], Pos.z [m]"
    );
    let headerless = read(b"0,0,0\n1,2,3\n", "h.csv", Format::Csv, None).unwrap();
    assert_eq!(
        headerless.position_columns.names,
        ["column 1", "column 2", "column 3"]
    );
    assert_eq!(headerless.position_columns.to_string(), "columns 1, 2, 3");
    let xyz = read(b"0 0\n1 2\n", "p.xyz", Format::Xyz, None).unwrap();
    assert_eq!(xyz.position_columns.to_string(), "columns 1, 2");
    let named = read(b"# id x y\n7 0 0\n8 1 2\n", "n.xyz", Format::Xyz, None).unwrap();
    assert_eq!(named.position_columns.to_string(), "x, y");
    let ply = b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n";
    assert_eq!(
        read(ply, "p.ply", Format::Ply, None)
            .unwrap()
            .position_columns
            .to_string(),
        "x, y, z"
    );
    let vtk =
        b"# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 2 double\n0 0 0 1 2 0\n";
    let flat = read(vtk, "f.vtk", Format::Vtk, Some(2)).unwrap();
    assert_eq!(
        flat.position_columns,
        PositionColumns {
            names: vec!["POINTS".to_owned()],
            dropped: Some("z".to_owned()),
        }
    );
    assert_eq!(
        flat.position_columns.to_string(),
        "POINTS (z dropped: constant)"
    );
    let vtu = "<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid><Piece NumberOfPoints=\"1\">\
               <Points><DataArray type=\"Float64\" Name=\"Position\" NumberOfComponents=\"3\" \
               format=\"ascii\">0 0 0</DataArray></Points></Piece></UnstructuredGrid></VTKFile>";
    let vtu = read(vtu.as_bytes(), "s.vtu", Format::Vtu, None).unwrap();
    assert_eq!(vtu.position_columns.to_string(), "Position");
    // DualSPHysics' 2D runs: x, y, z with y constant, read as 2D.
    let dsph = read(b"x,y,z\n0,5,0\n1,5,2\n", "d2.csv", Format::Csv, Some(2)).unwrap();
    assert_eq!(
        dsph.position_columns.to_string(),
        "x, z (y dropped: constant)"
    );
    // read_positions: the same columns, no attribute parsed.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("a.csv");
    std::fs::write(&path, "x,y,p\n0,0,1\n1,1,2\n").unwrap();
    let file = read_positions(&path, &ReadOptions::default()).unwrap();
    assert_eq!((names(&file), file.attributes.len()), (vec!["x", "y"], 0));
}

#[test]
fn files_of_no_particle_are_errors_naming_the_file() {
    // (content, file name, format, dimension the header declares, message)
    type Case<'a> = (&'a [u8], &'a str, Format, Option<usize>, &'a str);
    let cases: [Case; 8] = [
        (
            b"x,y,z\n",
            "h.csv",
            Format::Csv,
            Some(3),
            "no particles in h.csv: the header on line 1 (x, y, z) is followed by no data row",
        ),
        (
            b"# exported\nx;y\n\n# nothing\n",
            "h2.csv",
            Format::Csv,
            Some(2),
            "no particles in h2.csv: the header on line 2 (x, y) is followed by no data row",
        ),
        (
            b"",
            "e.csv",
            Format::Csv,
            None,
            "no particles in e.csv: the file holds no header and no data row (empty file)",
        ),
        (
            b"\n\n",
            "e.xyz",
            Format::Xyz,
            None,
            "no particles in e.xyz: the file holds no particle line (empty file)",
        ),
        (
            b"0\ncomment\n",
            "c.xyz",
            Format::Xyz,
            Some(3),
            "no particles in c.xyz: its count line (line 1) declares 0 particles",
        ),
        (
            b"# x y\n",
            "n.xyz",
            Format::Xyz,
            Some(2),
            "no particles in n.xyz: the names line 1 (# x y) is followed by no particle line",
        ),
        (
            b"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nend_header\n",
            "v.ply",
            Format::Ply,
            Some(2),
            "no particles in v.ply: its header declares element vertex 0",
        ),
        (
            b"# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 0 double\n",
            "p.vtk",
            Format::Vtk,
            Some(3),
            "no particles in p.vtk: its POINTS section holds 0 points",
        ),
    ];
    for (bytes, name, format, dim, message) in cases {
        for attributes in [false, true] {
            let options = ReadOptions::default();
            let e = if attributes {
                read_particle_file_from(bytes, name, format, &options).map(|f| f.set)
            } else {
                boundary_io::read_particles_from(bytes, name, format, &options)
            }
            .unwrap_err();
            assert_eq!(e.to_string(), message);
            assert!(
                matches!(&e, IoError::NoParticles { dim: d, .. } if *d == dim),
                "{name}: {e:?}"
            );
        }
    }
}
