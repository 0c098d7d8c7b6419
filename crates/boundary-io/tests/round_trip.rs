//! Write → read round trips for every format in 2D and 3D with extra columns. Positions come
//! back bit for bit (the writers print the shortest text that parses to the same `f64`); the
//! extra columns are checked by reading the written file independently of the crate's readers.
#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use boundary_core::AnyParticleSet;
use boundary_io::{
    read_csv_column, read_particles, write_particles, write_particles_to, Column, Format, IoError,
    ReadOptions,
};
use common::{read_bytes, same_bits, set2, set3};
use ply_rs_bw::parser::Parser;
use ply_rs_bw::ply::{DefaultElement, Property};

const LABELS: [i64; 5] = [1, 0, 1, -7, 1 << 40];
const MARGIN: [f64; 5] = [0.25, -1.5e-9, 3.0, 1e300, 1.0 / 7.0];

fn columns() -> [(&'static str, Column<'static>); 2] {
    [
        ("boundary", Column::Int(&LABELS)),
        ("margin", Column::Float(&MARGIN)),
    ]
}

fn sets() -> [(usize, AnyParticleSet); 2] {
    [(2, set2()), (3, set3())]
}

#[test]
fn every_format_round_trips_positions_exactly_through_files() {
    let dir = tempfile::tempdir().unwrap();
    for ext in ["csv", "xyz", "txt", "ply", "vtk", "vtu", "vtp"] {
        for (d, set) in sets() {
            let path = dir.path().join(format!("p{d}.{ext}"));
            write_particles(&path, None, &set, &columns()).unwrap();
            // No dim given: the file's own dimension (VTK marks its z = 0 padding of 2D sets).
            let back = read_particles(&path, &ReadOptions::default()).unwrap();
            assert!(same_bits(&back, &set), "{ext} {d}D: {back:?}");
            // Asking for the dimension the file has changes nothing.
            let back = read_particles(
                &path,
                &ReadOptions {
                    dim: Some(d),
                    format: None,
                },
            )
            .unwrap();
            assert!(same_bits(&back, &set), "{ext} {d}D with dim");
        }
    }
}

#[test]
fn format_argument_overrides_the_extension() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("particles.out");
    write_particles(&path, Some(Format::Ply), &set3(), &[]).unwrap();
    assert!(std::fs::read_to_string(&path).unwrap().starts_with("ply\n"));
    let back = read_particles(
        &path,
        &ReadOptions {
            dim: None,
            format: Some(Format::Ply),
        },
    )
    .unwrap();
    assert!(same_bits(&back, &set3()));
}

#[test]
fn non_finite_reals_go_to_csv_and_xyz_only() {
    let set = set3();
    let margin = [0.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 1.0];
    let cols = [("margin", Column::Float(&margin))];
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.csv");
    write_particles(&path, None, &set, &cols).unwrap();
    let back = read_csv_column(&path, "margin").unwrap();
    assert!(back[1].is_nan() && back[2] == f64::INFINITY && back[3] == f64::NEG_INFINITY);
    let mut out = Vec::new();
    write_particles_to(&mut out, Format::Xyz, &set, &cols).unwrap();
    for format in [Format::Ply, Format::Vtk] {
        let path = dir.path().join(format!("m.{format}"));
        let e = write_particles(&path, None, &set, &cols).unwrap_err();
        let message = e.to_string();
        assert!(
            message.contains("margin") && message.contains("particle 1"),
            "{message}"
        );
        assert!(message.contains(&*path.display().to_string()), "{message}");
        assert!(
            !path.exists(),
            "nothing is written when the columns are refused"
        );
    }
}

#[test]
fn csv_columns_read_back() {
    let dir = tempfile::tempdir().unwrap();
    for (d, set) in sets() {
        let path = dir.path().join(format!("c{d}.csv"));
        write_particles(&path, None, &set, &columns()).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let header = if d == 2 { "x,y" } else { "x,y,z" };
        assert_eq!(
            text.lines().next(),
            Some(&*format!("{header},boundary,margin"))
        );
        let labels: Vec<f64> = LABELS.iter().map(|&v| v as f64).collect();
        assert_eq!(read_csv_column(&path, "boundary").unwrap(), labels);
        assert_eq!(read_csv_column(&path, " MARGIN ").unwrap(), MARGIN.to_vec());
        // Integers are written as integers.
        assert!(text.contains(",1099511627776,"), "{text}");
    }
}

/// The whitespace-separated fields of the data lines of an XYZ file.
fn xyz_rows(text: &str) -> Vec<Vec<&str>> {
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.split_whitespace().collect())
        .collect()
}

#[test]
fn xyz_columns_follow_the_positions() {
    for (d, set) in sets() {
        let mut out = Vec::new();
        write_particles_to(&mut out, Format::Xyz, &set, &columns()).unwrap();
        let text = String::from_utf8(out).unwrap();
        let header = if d == 2 { "# x y" } else { "# x y z" };
        assert_eq!(
            text.lines().next(),
            Some(&*format!("{header} boundary margin"))
        );
        let rows = xyz_rows(&text);
        assert_eq!(rows.len(), set.len());
        for (i, row) in rows.iter().enumerate() {
            assert_eq!(row.len(), d + 2);
            assert_eq!(row[d].parse::<i64>().unwrap(), LABELS[i]);
            assert_eq!(row[d + 1].parse::<f64>().unwrap(), MARGIN[i]);
        }
    }
}

#[test]
fn ply_columns_are_vertex_properties() {
    for (d, set) in sets() {
        let mut out = Vec::new();
        write_particles_to(&mut out, Format::Ply, &set, &columns()).unwrap();
        let text = String::from_utf8(out.clone()).unwrap();
        // 1 << 40 does not fit a PLY int: that column is written as double.
        assert!(
            text.contains("property double boundary\nproperty double margin\n"),
            "{text}"
        );
        let ply = Parser::<DefaultElement>::new()
            .read_ply(&mut out.as_slice())
            .unwrap();
        let vertices = &ply.payload["vertex"];
        assert_eq!(vertices.len(), set.len());
        for (i, v) in vertices.iter().enumerate() {
            assert_eq!(v["boundary"], Property::Double(LABELS[i] as f64));
            assert_eq!(v["margin"], Property::Double(MARGIN[i]));
            assert_eq!(v.contains_key("z"), d == 3);
        }
        // Small integers are written as PLY int.
        let mut out = Vec::new();
        let small = [0i64, 1, 0, 1, -1];
        write_particles_to(
            &mut out,
            Format::Ply,
            &set,
            &[("boundary", Column::Int(&small))],
        )
        .unwrap();
        let ply = Parser::<DefaultElement>::new()
            .read_ply(&mut out.as_slice())
            .unwrap();
        for (i, v) in ply.payload["vertex"].iter().enumerate() {
            assert_eq!(v["boundary"], Property::Int(small[i] as i32));
        }
    }
}

/// The values of the SCALARS block `name` of a legacy VTK ascii file.
fn vtk_scalars<'a>(text: &'a str, name: &str, n: usize) -> (&'a str, Vec<&'a str>) {
    let start = text.find(&format!("SCALARS {name} ")).unwrap();
    let mut lines = text[start..].lines();
    let ty = lines.next().unwrap().split_whitespace().nth(2).unwrap();
    assert_eq!(lines.next(), Some("LOOKUP_TABLE default"));
    (ty, lines.take(n).collect())
}

#[test]
fn vtk_has_vertices_and_point_data_scalars() {
    for (d, set) in sets() {
        let mut out = Vec::new();
        let small = [0i64, 1, 0, 1, -1];
        let cols = [
            ("boundary", Column::Int(&small)),
            ("margin", Column::Float(&MARGIN)),
        ];
        write_particles_to(&mut out, Format::Vtk, &set, &cols).unwrap();
        let text = String::from_utf8(out).unwrap();
        let n = set.len();
        assert!(text.contains(&format!("POINTS {n} double\n")));
        assert!(text.contains(&format!("VERTICES {n} {}\n1 0\n1 1\n", 2 * n)));
        assert!(text.contains(&format!("POINT_DATA {n}\n")));
        let (ty, values) = vtk_scalars(&text, "boundary", n);
        assert_eq!(ty, "int");
        assert_eq!(values, ["0", "1", "0", "1", "-1"]);
        let (ty, values) = vtk_scalars(&text, "margin", n);
        assert_eq!(ty, "double");
        let parsed: Vec<f64> = values.iter().map(|v| v.parse().unwrap()).collect();
        assert_eq!(parsed, MARGIN);
        // A 2D set is written with z = 0 and read back as 3D only when asked to.
        if d == 2 {
            let back = read_bytes(text.as_bytes(), "t.vtk", Format::Vtk, Some(3)).unwrap();
            assert_eq!(back.dim(), 3);
            assert!((0..n).all(|i| back.coords(i)[2] == 0.0));
            assert_eq!(&back.coords(1)[..2], set.coords(1));
        }
    }
}

/// A binary PLY file of `set` with `double` coordinates and an extra `uchar` property.
fn binary_ply(set: &AnyParticleSet, big_endian: bool) -> Vec<u8> {
    let endian = if big_endian { "big" } else { "little" };
    let mut bytes = format!(
        "ply\nformat binary_{endian}_endian 1.0\nelement vertex {}\n",
        set.len()
    )
    .into_bytes();
    for axis in &["x", "y", "z"][..set.dim()] {
        bytes.extend_from_slice(format!("property double {axis}\n").as_bytes());
    }
    bytes.extend_from_slice(b"property uchar label\nend_header\n");
    for i in 0..set.len() {
        for &v in set.coords(i) {
            bytes.extend_from_slice(&if big_endian {
                v.to_be_bytes()
            } else {
                v.to_le_bytes()
            });
        }
        bytes.push(i as u8);
    }
    bytes
}

#[test]
fn binary_ply_doubles_read_exactly_in_both_endiannesses() {
    for (_, set) in sets() {
        for big in [false, true] {
            let back = read_bytes(&binary_ply(&set, big), "b.ply", Format::Ply, None).unwrap();
            assert!(same_bits(&back, &set), "big endian {big}");
        }
    }
}

/// An empty set is written (a header, a count of 0), but a file of no particle is refused on
/// reading, with the dimension the header declares, so that a caller that takes empty frames
/// can still build the empty set.
#[test]
fn empty_sets_are_written_and_refused_on_reading_with_their_dimension() {
    for (d, set) in sets() {
        let empty = match set {
            AnyParticleSet::D2(_) => boundary_core::ParticleSet::<2>::new(vec![])
                .unwrap()
                .to_any(),
            AnyParticleSet::D3(_) => boundary_core::ParticleSet::<3>::new(vec![])
                .unwrap()
                .to_any(),
        };
        for format in [
            Format::Csv,
            Format::Xyz,
            Format::Ply,
            Format::Vtk,
            Format::Vtu,
            Format::Vtp,
            Format::Bgeo,
        ] {
            let mut out = Vec::new();
            write_particles_to(&mut out, format, &empty, &[("b", Column::Int(&[]))]).unwrap();
            let e = read_bytes(&out, "e", format, Some(d)).unwrap_err();
            let IoError::NoParticles { file, dim, .. } = &e else {
                panic!("{format}: {e}");
            };
            assert_eq!((file.as_str(), *dim), ("e", Some(d)), "{format}: {e}");
            assert!(e.to_string().starts_with("no particles in e: "), "{e}");
        }
    }
}

#[test]
fn byte_columns_are_uchar_in_ply_and_unsigned_char_in_vtk() {
    let red = [0u8, 255, 7, 128, 1];
    for (_, set) in sets() {
        let cols = [("red", Column::Byte(&red))];
        let mut ply = Vec::new();
        write_particles_to(&mut ply, Format::Ply, &set, &cols).unwrap();
        let parsed = Parser::<DefaultElement>::new()
            .read_ply(&mut ply.as_slice())
            .unwrap();
        for (i, v) in parsed.payload["vertex"].iter().enumerate() {
            assert_eq!(v["red"], Property::UChar(red[i]));
        }
        let mut vtk = Vec::new();
        write_particles_to(&mut vtk, Format::Vtk, &set, &cols).unwrap();
        let text = String::from_utf8(vtk).unwrap();
        let (ty, values) = vtk_scalars(&text, "red", set.len());
        assert_eq!(ty, "unsigned_char");
        assert_eq!(values, ["0", "255", "7", "128", "1"]);
        // The readers still read the positions back.
        let back = read_bytes(text.as_bytes(), "b.vtk", Format::Vtk, Some(set.dim())).unwrap();
        assert!(same_bits(&back, &set));
        let back = read_bytes(&ply, "b.ply", Format::Ply, None).unwrap();
        assert!(same_bits(&back, &set));
        let mut csv = Vec::new();
        write_particles_to(&mut csv, Format::Csv, &set, &cols).unwrap();
        assert!(String::from_utf8(csv).unwrap().contains(",255\n"));
    }
}

#[test]
fn attributes_round_trip_through_every_format_that_keeps_them() {
    use boundary_io::{read_particle_file, AttributeValues};
    let dir = tempfile::tempdir().unwrap();
    let flags = [1i64, 0, 1, -7, 3];
    let density = [1000.0, 999.5, 1e-9, -0.0, 1.0 / 3.0];
    let red = [0u8, 1, 2, 254, 255];
    let columns = [
        ("boundary", Column::Int(&flags)),
        ("Density", Column::Float(&density)),
        ("red", Column::Byte(&red)),
    ];
    for ext in ["csv", "ply", "vtk", "vtu", "vtp"] {
        for (d, set) in sets() {
            let path = dir.path().join(format!("a{d}.{ext}"));
            write_particles(&path, None, &set, &columns).unwrap();
            let file = read_particle_file(&path, &ReadOptions::default()).unwrap();
            assert!(same_bits(&file.set, &set), "{ext} {d}D");
            assert!(file.skipped.is_empty(), "{ext}: {:?}", file.skipped);
            let got: Vec<(&str, &AttributeValues)> = file
                .attributes
                .iter()
                .map(|a| (a.name.as_str(), &a.values))
                .collect();
            assert_eq!(
                got,
                [
                    ("boundary", &AttributeValues::Int(flags.to_vec())),
                    ("Density", &AttributeValues::Float(density.to_vec())),
                    (
                        "red",
                        &AttributeValues::Int(red.iter().map(|&b| i64::from(b)).collect())
                    ),
                ],
                "{ext} {d}D"
            );
        }
    }
}

#[test]
fn binary_ply_properties_are_kept_and_lists_skipped() {
    use boundary_io::{read_particle_file_from, AttributeValues};
    let mut ply = b"ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty uchar red\nproperty list uchar int idx\nproperty double rho\nend_header\n".to_vec();
    for (x, y, red, rho) in [(1.0f32, 2.0f32, 7u8, 0.5f64), (3.0, 4.0, 9, 1.5)] {
        ply.extend_from_slice(&x.to_le_bytes());
        ply.extend_from_slice(&y.to_le_bytes());
        ply.push(red);
        ply.push(1);
        ply.extend_from_slice(&5i32.to_le_bytes());
        ply.extend_from_slice(&rho.to_le_bytes());
    }
    let file = read_particle_file_from(
        ply.as_slice(),
        "b.ply",
        Format::Ply,
        &ReadOptions::default(),
    )
    .unwrap();
    assert_eq!(file.set.coords(1), &[3.0, 4.0]);
    assert_eq!(file.attributes.len(), 2);
    assert_eq!(file.attributes[0].values, AttributeValues::Int(vec![7, 9]));
    assert_eq!(
        file.attributes[1].values,
        AttributeValues::Float(vec![0.5, 1.5])
    );
    assert!(file.skipped[0].contains("\"idx\""), "{:?}", file.skipped);
}

/// PLY property names are identifiers: a vector's `name:k` columns and other characters are
/// written with `_`, so the file reads back (here and in any PLY reader); names that would
/// collide there are refused, naming both columns.
#[test]
fn ply_property_names_read_back() {
    use boundary_io::{read_particle_file, AttributeValues};
    let dir = tempfile::tempdir().unwrap();
    let (_, set) = sets()[1].clone();
    let n = set.len();
    let v0: Vec<f64> = (0..n).map(|i| i as f64 + 0.5).collect();
    let v1: Vec<f64> = (0..n).map(|i| -(i as f64)).collect();
    let ids: Vec<i64> = (0..n as i64).collect();
    let columns = [
        ("velocity:0", Column::Float(&v0)),
        ("velocity:1", Column::Float(&v1)),
        ("Pressure[Pa]", Column::Float(&v0)),
        ("2nd", Column::Int(&ids)),
    ];
    let path = dir.path().join("v.ply");
    write_particles(&path, None, &set, &columns).unwrap();
    let file = read_particle_file(&path, &ReadOptions::default()).unwrap();
    assert!(same_bits(&file.set, &set));
    let got: Vec<(&str, &AttributeValues)> = file
        .attributes
        .iter()
        .map(|a| (a.name.as_str(), &a.values))
        .collect();
    assert_eq!(
        got,
        [
            ("velocity_0", &AttributeValues::Float(v0.clone())),
            ("velocity_1", &AttributeValues::Float(v1.clone())),
            ("Pressure_Pa_", &AttributeValues::Float(v0.clone())),
            ("_2nd", &AttributeValues::Int(ids.clone())),
        ]
    );
    let clash = [("a:0", Column::Float(&v0)), ("a_0", Column::Float(&v0))];
    let e = write_particles(&dir.path().join("c.ply"), None, &set, &clash).unwrap_err();
    let text = e.to_string();
    assert!(text.contains("a:0") && text.contains("a_0"), "{text}");
    // Other formats keep the names as they are.
    let path = dir.path().join("v.csv");
    write_particles(&path, None, &set, &columns[..1]).unwrap();
    let file = read_particle_file(&path, &ReadOptions::default()).unwrap();
    assert_eq!(file.attributes[0].name, "velocity:0");
}
