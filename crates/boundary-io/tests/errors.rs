//! Error messages: one line, lower-case start, no trailing period, naming the file and the line
//! (or item) where the problem is.
#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use boundary_io::{read_particles, Format, IoError, Location, ReadOptions};
use common::read_bytes;

/// Reads `bytes`, expects an error, checks the message's form and that it contains `needles`.
fn error(
    bytes: &[u8],
    name: &str,
    format: Format,
    dim: Option<usize>,
    needles: &[&str],
) -> IoError {
    let e = read_bytes(bytes, name, format, dim).unwrap_err();
    let message = e.to_string();
    assert!(!message.contains('\n'), "one line: {message}");
    assert!(
        message.starts_with(|c: char| c.is_lowercase()),
        "lower-case: {message}"
    );
    assert!(!message.ends_with('.'), "no period: {message}");
    assert!(message.contains(name), "names the file: {message}");
    for needle in needles {
        assert!(message.contains(needle), "{needle:?} not in: {message}");
    }
    e
}

#[test]
fn csv_bad_number_names_line_and_column() {
    let e = error(
        b"x,y\n0,0\n1,zz\n",
        "bad.csv",
        Format::Csv,
        None,
        &["line 3 column 2", "\"zz\""],
    );
    assert_eq!(e.location(), Some(Location::Cell { line: 3, column: 2 }));
    error(
        b"Pos.x [m];Pos.y [m]\n1;2\n3;;\n",
        "d.csv",
        Format::Csv,
        None,
        &["line 3 column 2", "Pos.y [m]"],
    );
}

#[test]
fn csv_rows_with_too_few_columns_are_errors_naming_the_line() {
    let e = error(
        b"x,y,z\n0,0,0\n\n1,2\n",
        "few.csv",
        Format::Csv,
        None,
        &["line 4", "too few columns"],
    );
    assert_eq!(e.location(), Some(Location::Line(4)));
    error(
        b"1\n2\n",
        "one.csv",
        Format::Csv,
        None,
        &["line 1", "too few columns"],
    );
    error(
        b"1,2\n3,4\n",
        "h.csv",
        Format::Csv,
        Some(3),
        &["line 1", "too few columns"],
    );
}

#[test]
fn csv_missing_header_column() {
    let e = error(
        b"x,vel\n0,0\n",
        "m.csv",
        Format::Csv,
        None,
        &["line 1", "missing position column y", "\"vel\""],
    );
    assert!(matches!(e, IoError::Parse { .. }));
    error(
        b"# c\n\nid;Vel.x\n1;2\n",
        "m2.csv",
        Format::Csv,
        None,
        &["line 3", "column x and y"],
    );
    error(
        b"Pos.x,px,y\n1,2,3\n",
        "a.csv",
        Format::Csv,
        None,
        &["line 1", "both name the x position"],
    );
}

#[test]
fn non_finite_coordinates_name_particle_and_line() {
    let e = error(
        b"x,y\n0,0\n# skip\n1,NaN\n",
        "n.csv",
        Format::Csv,
        None,
        &["particle 1", "line 4"],
    );
    assert!(
        matches!(
            e,
            IoError::NonFinite {
                index: 1,
                axis: 1,
                ..
            }
        ),
        "{e:?}"
    );
    error(
        b"1 2 3\n4 inf 6\n",
        "n.xyz",
        Format::Xyz,
        None,
        &["particle 1", "line 2"],
    );
    let ply = b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nend_header\n0 0\n1e39 0\n";
    // 1e39 overflows a PLY float to infinity.
    let e = error(ply, "n.ply", Format::Ply, None, &["particle 1", "line 8"]);
    assert!(
        matches!(
            e,
            IoError::NonFinite {
                index: 1,
                axis: 0,
                ..
            }
        ),
        "{e:?}"
    );
    let mut vtk =
        b"# vtk DataFile Version 3.0\nt\nBINARY\nDATASET POLYDATA\nPOINTS 2 double\n".to_vec();
    for v in [0.0, 0.0, 0.0, 1.0, f64::NEG_INFINITY, 0.0] {
        vtk.extend_from_slice(&f64::to_be_bytes(v));
    }
    error(&vtk, "n.vtk", Format::Vtk, None, &["particle 1", "point 1"]);
}

#[test]
fn non_utf8_text_is_an_error_with_its_line() {
    error(
        b"x,y\n0,0\n1,\xff\n",
        "u.csv",
        Format::Csv,
        None,
        &["line 3", "UTF-8"],
    );
    error(
        b"0 0\n\xc3\x28 1\n",
        "u.xyz",
        Format::Xyz,
        None,
        &["line 2", "UTF-8"],
    );
}

#[test]
fn truncated_binary_ply_names_the_vertex() {
    let mut ply = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n".to_vec();
    for v in [1.0f32, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0] {
        ply.extend_from_slice(&v.to_le_bytes());
    }
    let e = error(
        &ply,
        "t.ply",
        Format::Ply,
        None,
        &["vertex 2", "end of file"],
    );
    assert_eq!(
        e.location(),
        Some(Location::Item {
            kind: "vertex",
            index: 2
        })
    );
}

#[test]
fn declared_counts_larger_than_the_data_are_errors_not_allocations() {
    // PLY ascii: 5 vertices declared, 2 present.
    let ply = b"ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nend_header\n0 0\n1 1\n";
    error(ply, "c.ply", Format::Ply, None, &["end of file"]);
    // PLY binary with an absurd count: an error, not an allocation of the declared size.
    let ply = b"ply\nformat binary_big_endian 1.0\nelement vertex 18446744073709551615\nproperty double x\nproperty double y\nend_header\n\0\0";
    error(ply, "huge.ply", Format::Ply, None, &["vertex 0"]);
    // VTK binary and ascii.
    let vtk = b"# vtk DataFile Version 3.0\nt\nBINARY\nDATASET POLYDATA\nPOINTS 4000000000 float\n\0\0\0\0";
    error(
        vtk,
        "c.vtk",
        Format::Vtk,
        None,
        &["line 5", "4000000000 points", "4 bytes follow"],
    );
    let vtk = b"# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 1000000000000 float\n1 2 3\n";
    error(
        vtk,
        "c.vtk",
        Format::Vtk,
        None,
        &["line 5", "ends after 3 values"],
    );
    // XYZ count line.
    error(
        b"4\ncomment\n1 2 3\n",
        "c.xyz",
        Format::Xyz,
        None,
        &["line 1", "declared 4 particles", "holds 1"],
    );
}

#[test]
fn unknown_extension_names_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("particles.pdb");
    std::fs::write(&path, "x,y\n0,0\n").unwrap();
    let e = read_particles(&path, &ReadOptions::default()).unwrap_err();
    assert!(matches!(e, IoError::UnknownFormat { .. }));
    let message = e.to_string();
    assert!(
        message.contains("particles.pdb") && message.starts_with("unknown"),
        "{message}"
    );
    // Given a format, the extension does not matter.
    let set = read_particles(
        &path,
        &ReadOptions {
            dim: None,
            format: Some(Format::Csv),
        },
    )
    .unwrap();
    assert_eq!(set.len(), 1);
    // A missing file names itself.
    let missing = dir.path().join("missing.csv");
    let message = read_particles(&missing, &ReadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        message.starts_with("cannot read") && message.contains("missing.csv"),
        "{message}"
    );
}

#[test]
fn impossible_dimension_requests_are_dimension_errors() {
    let e = error(
        b"x,y,z\n0,1,2\n1,2,3\n",
        "free.csv",
        Format::Csv,
        Some(2),
        &["none of x, y, z is constant"],
    );
    assert!(matches!(e, IoError::Dimension { .. }));
    error(
        b"x,y\n0,1\n",
        "flat.csv",
        Format::Csv,
        Some(3),
        &["dim = 3 requested"],
    );
    error(
        b"0 1\n",
        "flat.xyz",
        Format::Xyz,
        Some(3),
        &["dim = 3 requested"],
    );
    error(
        b"x,y\n0,1\n",
        "d.csv",
        Format::Csv,
        Some(4),
        &["must be 2 or 3, got 4"],
    );
}

#[test]
fn malformed_headers_are_errors_naming_what_is_wrong() {
    error(b"", "e.csv", Format::Csv, None, &["empty file"]);
    error(
        b"\n# only comments\n",
        "e.xyz",
        Format::Xyz,
        None,
        &["empty file"],
    );
    error(
        b"ply\nformat ascii 1.0\nelement face 0\nend_header\n",
        "f.ply",
        Format::Ply,
        None,
        &["no element \"vertex\""],
    );
    error(b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float z\nend_header\n0 0\n", "f.ply", Format::Ply, None, &["lacks property y"]);
    error(b"ply\nformat ascii 1.0\nelement stuff 5\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n", "s.ply", Format::Ply, None, &["no properties"]);
    error(b"not ply\n", "n.ply", Format::Ply, None, &["malformed PLY"]);
    error(
        b"x y z\n",
        "n.vtk",
        Format::Vtk,
        None,
        &["line 1", "not a legacy VTK file"],
    );
    error(
        b"# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\n",
        "s.vtk",
        Format::Vtk,
        None,
        &["line 4", "unsupported dataset"],
    );
    error(
        b"# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 1 int\n1 2 3\n",
        "s.vtk",
        Format::Vtk,
        None,
        &["line 5", "float or double"],
    );
    error(
        b"# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 1 float\n1 2 x\n",
        "s.vtk",
        Format::Vtk,
        None,
        &["line 6", "invalid number \"x\""],
    );
}
