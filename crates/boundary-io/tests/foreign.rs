//! Small inline files shaped like those other tools write: DualSPHysics' semicolon CSV with
//! units, ParaView's `Points:0` CSV, splashsurf-style binary PLY, SPlisHSPlasH-style binary
//! legacy VTK, chemistry-style XYZ with count and comment lines.
#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use boundary_io::Format;
use common::read_bytes;

/// DualSPHysics' CSV export (PartVTK -SaveCsv) style: `;` separated, units in brackets, a
/// trailing separator, extra columns of other types.
const DUALSPHYSICS_2D: &str = "\
Pos.x [m];Pos.y [m];Pos.z [m];Idp;Vel.x [m/s];Vel.y [m/s];Vel.z [m/s];Rhop [kg/m^3];Type;
0.1;0.0;0.2;0;0.0;0.0;-0.1;1000.0;Fluid;
0.12;0.0;0.2;1;0.0;0.0;0.0;1000.3;Fluid;
0.1;0.0;0.22;2;0.5;0.0;0.0;999.8;Fluid;
";

#[test]
fn dualsphysics_semicolon_csv_in_the_xz_plane() {
    let bytes = DUALSPHYSICS_2D.as_bytes();
    // As a file it is 3D (y = 0 everywhere is still a coordinate).
    let set = read_bytes(bytes, "Part_0000.csv", Format::Csv, None).unwrap();
    assert_eq!((set.dim(), set.len()), (3, 3));
    assert_eq!(set.coords(2), &[0.1, 0.0, 0.22]);
    // dim = 2 drops the constant y: the x–z plane.
    let set = read_bytes(bytes, "Part_0000.csv", Format::Csv, Some(2)).unwrap();
    assert_eq!((set.dim(), set.len()), (2, 3));
    assert_eq!(set.coords(0), &[0.1, 0.2]);
    assert_eq!(set.coords(1), &[0.12, 0.2]);
    assert_eq!(set.coords(2), &[0.1, 0.22]);
}

#[test]
fn dualsphysics_3d_csv_with_comment_preamble() {
    let text = "# DualSPHysics PartVTK output\n\
                Pos.x [m];Pos.y [m];Pos.z [m];Idp;Vel.x [m/s]\n\
                0.03;0.03;0.03;0;0\n0.05;0.03;0.03;1;0\n\n0.03;0.05;0.04;2;0\n";
    let set = read_bytes(text.as_bytes(), "fluid.csv", Format::Csv, Some(3)).unwrap();
    assert_eq!((set.dim(), set.len()), (3, 3));
    assert_eq!(set.coords(2), &[0.03, 0.05, 0.04]);
}

#[test]
fn paraview_points_columns_with_quotes() {
    let text =
        "\"density\",\"Points:0\",\"Points:1\",\"Points:2\"\n1000,0.5,0.25,0.125\n998,1,2,3\n";
    let set = read_bytes(text.as_bytes(), "pv.csv", Format::Csv, None).unwrap();
    assert_eq!(set.dim(), 3);
    assert_eq!(set.coords(0), &[0.5, 0.25, 0.125]);
}

#[test]
fn tab_separated_with_columns_in_any_order() {
    let text = "id\ty\tx\n0\t2.5\t1.5\n1\t-1\t4\n";
    let set = read_bytes(text.as_bytes(), "t.csv", Format::Csv, None).unwrap();
    assert_eq!(set.dim(), 2);
    assert_eq!(set.coords(0), &[1.5, 2.5]);
    assert_eq!(set.coords(1), &[4.0, -1.0]);
}

#[test]
fn headerless_csv_takes_leading_columns_by_dim() {
    let text = "1,2,3,4\n5,6,7,8\n";
    let three = read_bytes(text.as_bytes(), "h.csv", Format::Csv, None).unwrap();
    assert_eq!(three.coords(1), &[5.0, 6.0, 7.0]);
    let two = read_bytes(text.as_bytes(), "h.csv", Format::Csv, Some(2)).unwrap();
    assert_eq!(two.coords(1), &[5.0, 6.0]);
    let text = "1,2\n5,6\n";
    let two = read_bytes(text.as_bytes(), "h.csv", Format::Csv, None).unwrap();
    assert_eq!((two.dim(), two.coords(1)), (2, &[5.0, 6.0][..]));
}

/// A splashsurf-style binary little-endian PLY: float x, y, z, then an empty face element.
fn splashsurf_ply(points: &[[f32; 3]]) -> Vec<u8> {
    let mut bytes = format!(
        "ply\nformat binary_little_endian 1.0\ncomment created by splashsurf\nelement vertex {}\n\
         property float x\nproperty float y\nproperty float z\n\
         element face 0\nproperty list uchar uint vertex_indices\nend_header\n",
        points.len()
    )
    .into_bytes();
    for p in points {
        for v in p {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
    }
    bytes
}

#[test]
fn splashsurf_binary_little_endian_ply() {
    let points = [[0.5f32, -1.25, 2.0], [0.1, 0.2, 0.3], [1e-3, 7.0, -0.0]];
    let set = read_bytes(&splashsurf_ply(&points), "fluid.ply", Format::Ply, None).unwrap();
    assert_eq!((set.dim(), set.len()), (3, 3));
    for (i, p) in points.iter().enumerate() {
        let expected: Vec<f64> = p.iter().map(|&v| f64::from(v)).collect();
        assert_eq!(set.coords(i), &expected[..]);
    }
}

#[test]
fn ply_with_an_element_before_vertex_and_int_coordinates() {
    let text = "ply\nformat ascii 1.0\nelement camera 1\nproperty float fov\nproperty list uchar int ids\n\
                element vertex 2\nproperty int x\nproperty uchar y\nproperty float nx\nend_header\n\
                0.7 3 1 2 3\n-3 200 0.5\n4 0 0\n";
    let set = read_bytes(text.as_bytes(), "i.ply", Format::Ply, None).unwrap();
    assert_eq!(set.dim(), 2);
    assert_eq!(set.coords(0), &[-3.0, 200.0]);
    assert_eq!(set.coords(1), &[4.0, 0.0]);
}

/// A SPlisHSPlasH-style legacy VTK: BINARY UNSTRUCTURED_GRID with big-endian float POINTS,
/// vertex CELLS, CELL_TYPES and POINT_DATA.
fn splishsplash_vtk(points: &[[f32; 3]]) -> Vec<u8> {
    let n = points.len();
    let mut b = format!(
        "# vtk DataFile Version 4.1\nSPlisHSPlasH particle data (4.1)\nBINARY\n\
         DATASET UNSTRUCTURED_GRID\nPOINTS {n} float\n"
    )
    .into_bytes();
    for p in points {
        for v in p {
            b.extend_from_slice(&v.to_be_bytes());
        }
    }
    b.extend_from_slice(format!("\nCELLS {n} {}\n", 2 * n).as_bytes());
    for i in 0..n as i32 {
        b.extend_from_slice(&1i32.to_be_bytes());
        b.extend_from_slice(&i.to_be_bytes());
    }
    b.extend_from_slice(format!("\nCELL_TYPES {n}\n").as_bytes());
    for _ in 0..n {
        b.extend_from_slice(&1i32.to_be_bytes());
    }
    b.extend_from_slice(
        format!("\nPOINT_DATA {n}\nSCALARS id unsigned_int 1\nLOOKUP_TABLE id_table\n").as_bytes(),
    );
    for i in 0..n as u32 {
        b.extend_from_slice(&i.to_be_bytes());
    }
    b.push(b'\n');
    b
}

#[test]
fn splishsplash_binary_vtk_unstructured_grid() {
    let points = [[0.5f32, -1.25, 2.0], [0.1, 0.2, 0.3]];
    let bytes = splishsplash_vtk(&points);
    let set = read_bytes(&bytes, "ParticleData_Fluid_1.vtk", Format::Vtk, None).unwrap();
    assert_eq!((set.dim(), set.len()), (3, 2));
    assert_eq!(
        set.coords(1),
        &[f64::from(0.1f32), f64::from(0.2f32), f64::from(0.3f32)]
    );
    // A 2D run written by such a tool (z = 0) becomes 2D only when asked.
    let flat = [[0.5f32, -1.25, 0.0], [0.1, 0.2, 0.0]];
    let bytes = splishsplash_vtk(&flat);
    assert_eq!(
        read_bytes(&bytes, "f.vtk", Format::Vtk, None)
            .unwrap()
            .dim(),
        3
    );
    let set = read_bytes(&bytes, "f.vtk", Format::Vtk, Some(2)).unwrap();
    assert_eq!(set.coords(0), &[0.5, -1.25]);
}

#[test]
fn chemistry_xyz_with_count_comment_and_symbols() {
    let text = "3\nwater and a helium atom, energy=-76.4\nO 0.0 0.0 0.1173\nH 0.0 0.7572 -0.4692\n\
                He 5 5 5\n";
    let set = read_bytes(text.as_bytes(), "w.xyz", Format::Xyz, None).unwrap();
    assert_eq!((set.dim(), set.len()), (3, 3));
    assert_eq!(set.coords(1), &[0.0, 0.7572, -0.4692]);
    // Without symbols, and with a blank comment line.
    let text = "2\n\n1 2 3\n4 5 6\n";
    let set = read_bytes(text.as_bytes(), "p.xyz", Format::Xyz, None).unwrap();
    assert_eq!(set.coords(1), &[4.0, 5.0, 6.0]);
}

#[test]
fn plain_xyz_two_and_three_columns() {
    let set = read_bytes(b"1 2\n3 4\n", "p.xyz", Format::Xyz, None).unwrap();
    assert_eq!((set.dim(), set.coords(1)), (2, &[3.0, 4.0][..]));
    let set = read_bytes(
        b"# a comment\n1\t2 3 9 9\n\n3 4 5 9 9\n",
        "p.txt",
        Format::Xyz,
        None,
    )
    .unwrap();
    assert_eq!((set.dim(), set.coords(1)), (3, &[3.0, 4.0, 5.0][..]));
}
