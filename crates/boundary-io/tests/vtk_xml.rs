//! VTK XML (`.vtu`, `.vtp`) and legacy VTK point data: files written by VTK 9.5 itself (`data/make_vtk_xml.py`, every
//! data mode: ascii, inline base64, appended raw and base64, zlib, big endian, `UInt32` and
//! `UInt64` headers) read to the known positions and point data; our writer round-trips
//! positions bit for bit and every attribute; damaged files give errors naming the file and
//! the array, never a panic or a huge allocation.
#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use boundary_core::{AnyParticleSet, ParticleSet};
use boundary_io::{
    read_particle_file, read_particle_file_from, write_particles, write_particles_to,
    AttributeValues, Column, Format, IoError, ParticleFile, ReadOptions,
};
use common::{same_bits, set2, set3};
use std::path::PathBuf;

fn data(file: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(file)
}

/// Written by VTK 9.5 (`data/make_vtk_xml.py`), legacy ones included (version 5.1: OFFSETS
/// and CONNECTIVITY sections, point data as FIELD arrays).
const VTK_FILES: [&str; 11] = [
    "poly_legacy_ascii.vtk",
    "grid_legacy_binary.vtk",
    "grid_ascii.vtu",
    "grid_binary.vtu",
    "grid_appended_raw.vtu",
    "grid_appended_zlib.vtu",
    "grid_binary_zlib_be.vtu",
    "poly_ascii.vtp",
    "poly_binary_zlib.vtp",
    "poly_appended_base64.vtp",
    "poly_appended_raw_be.vtp",
];

fn attribute<'a>(file: &'a ParticleFile, name: &str) -> &'a AttributeValues {
    &file
        .attributes
        .iter()
        .find(|a| a.name == name)
        .unwrap_or_else(|| panic!("no attribute {name}: {:?}", file.attributes))
        .values
}

fn floats(v: &AttributeValues) -> Vec<f64> {
    match v {
        AttributeValues::Float(v) => v.clone(),
        AttributeValues::Int(v) => panic!("integers {v:?} where reals were expected"),
    }
}

#[test]
fn files_written_by_vtk_read_to_the_known_values() {
    for file in VTK_FILES {
        let f = read_particle_file(&data(file), &ReadOptions::default()).unwrap();
        assert_eq!(f.set.dim(), 3, "{file}");
        assert_eq!(f.set.len(), 12, "{file}");
        for i in 0..12 {
            let expected = [
                0.5 * (i % 3) as f64,
                0.25 * ((i / 3) % 2) as f64,
                0.125 * (i / 6) as f64,
            ];
            assert_eq!(f.set.coords(i), &expected, "{file} point {i}");
        }
        let names: Vec<&str> = f.attributes.iter().map(|a| a.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "velocity:0",
                "velocity:1",
                "velocity:2",
                "density",
                "id",
                "type"
            ],
            "{file}"
        );
        assert!(f.skipped.is_empty(), "{file}: {:?}", f.skipped);
        let index: Vec<f64> = (0..12).map(f64::from).collect();
        assert_eq!(floats(attribute(&f, "velocity:0")), index, "{file}");
        let minus: Vec<f64> = index.iter().map(|v| -v).collect();
        assert_eq!(floats(attribute(&f, "velocity:1")), minus, "{file}");
        let half: Vec<f64> = index.iter().map(|v| 0.5 * v).collect();
        assert_eq!(floats(attribute(&f, "velocity:2")), half, "{file}");
        let density: Vec<f64> = index.iter().map(|v| 1000.0 + v / 8.0).collect();
        assert_eq!(floats(attribute(&f, "density")), density, "{file}");
        assert_eq!(
            attribute(&f, "id"),
            &AttributeValues::Int((100..112).collect()),
            "{file}"
        );
        assert_eq!(
            attribute(&f, "type"),
            &AttributeValues::Int((0..12).map(|i| i % 2).collect()),
            "{file}"
        );
    }
}

#[test]
fn dim_2_drops_the_constant_axis_of_a_vtk_file() {
    // z is not constant in the fixture: dim = 2 is an error naming the file.
    let e = read_particle_file(
        &data("poly_ascii.vtp"),
        &ReadOptions {
            dim: Some(2),
            format: None,
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("poly_ascii.vtp"), "{e}");
}

fn columns_with_vector() -> (Vec<i64>, Vec<f64>, [Vec<f64>; 3], Vec<u8>) {
    let labels = vec![1, 0, 1, -7, 1 << 40];
    let margin = vec![0.25, -1.5e-9, f64::NAN, 1e300, 1.0 / 7.0];
    let normal = [
        vec![1.0, 0.0, -0.5, 0.1, 0.0],
        vec![0.0, 1.0, 0.5, 0.2, 0.0],
        vec![0.0, 0.0, 0.0, 0.3, 1.0],
    ];
    let bytes = vec![0, 1, 2, 254, 255];
    (labels, margin, normal, bytes)
}

#[test]
fn written_files_round_trip_positions_and_every_column() {
    let dir = tempfile::tempdir().unwrap();
    let (labels, margin, normal, bytes) = columns_with_vector();
    let columns = [
        ("boundary", Column::Int(&labels)),
        ("margin", Column::Float(&margin)),
        ("normal:0", Column::Float(&normal[0])),
        ("normal:1", Column::Float(&normal[1])),
        ("normal:2", Column::Float(&normal[2])),
        ("red", Column::Byte(&bytes)),
    ];
    for ext in ["vtu", "vtp"] {
        for (d, set) in [(2, set2()), (3, set3())] {
            let path = dir.path().join(format!("p{d}.{ext}"));
            write_particles(&path, None, &set, &columns).unwrap();
            let back = read_particle_file(&path, &ReadOptions::default()).unwrap();
            assert!(same_bits(&back.set, &set), "{ext} {d}D: {:?}", back.set);
            let names: Vec<&str> = back.attributes.iter().map(|a| a.name.as_str()).collect();
            assert_eq!(
                names,
                ["boundary", "margin", "normal:0", "normal:1", "normal:2", "red"]
            );
            assert_eq!(
                attribute(&back, "boundary"),
                &AttributeValues::Int(labels.clone())
            );
            let m = floats(attribute(&back, "margin"));
            assert!(m[2].is_nan());
            assert_eq!(
                m.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                margin.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
            );
            for (k, component) in normal.iter().enumerate() {
                assert_eq!(floats(attribute(&back, &format!("normal:{k}"))), *component);
            }
            assert_eq!(
                attribute(&back, "red"),
                &AttributeValues::Int(bytes.iter().map(|&b| i64::from(b)).collect())
            );
            // The vector is one array of three components, as ParaView expects.
            let text = std::fs::read_to_string(&path).unwrap();
            assert!(
                text.contains("Name=\"normal\" NumberOfComponents=\"3\""),
                "{text}"
            );
            assert!(text.contains("<PointData Scalars=\"boundary\">"), "{text}");
        }
    }
}

#[test]
fn attributes_read_from_vtk_are_written_back_next_to_new_columns() {
    let f = read_particle_file(&data("grid_appended_zlib.vtu"), &ReadOptions::default()).unwrap();
    let flags: Vec<i64> = (0..12).map(|i| i64::from(i < 4)).collect();
    let mut columns = vec![("boundary", Column::Int(&flags))];
    columns.extend(f.columns(&["boundary"]));
    let mut out = Vec::new();
    write_particles_to(&mut out, Format::Vtp, &f.set, &columns).unwrap();
    let back = read_particle_file_from(
        out.as_slice(),
        "out.vtp",
        Format::Vtp,
        &ReadOptions::default(),
    )
    .unwrap();
    assert_eq!(back.set, f.set);
    assert_eq!(back.attributes[0].values, AttributeValues::Int(flags));
    assert_eq!(&back.attributes[1..], &f.attributes[..]);
    let text = String::from_utf8(out).unwrap();
    assert!(
        text.contains("Name=\"velocity\" NumberOfComponents=\"3\""),
        "{text}"
    );
}

#[test]
fn an_empty_set_is_written_and_refused_on_reading() {
    let set = AnyParticleSet::from(ParticleSet::<3>::new(Vec::new()).unwrap());
    let mut out = Vec::new();
    write_particles_to(&mut out, Format::Vtu, &set, &[("b", Column::Int(&[]))]).unwrap();
    let e = read_particle_file_from(
        out.as_slice(),
        "e.vtu",
        Format::Vtu,
        &ReadOptions::default(),
    )
    .unwrap_err();
    assert!(
        matches!(e, IoError::NoParticles { dim: Some(3), .. }),
        "{e}"
    );
    assert_eq!(
        e.to_string(),
        "no particles in e.vtu: its <Piece> has NumberOfPoints=\"0\""
    );
}

fn read_text(text: &str, format: Format) -> Result<ParticleFile, IoError> {
    read_particle_file_from(text.as_bytes(), "bad.vtu", format, &ReadOptions::default())
}

fn expect_error(text: &str, format: Format, needles: &[&str]) {
    let e = read_text(text, format).unwrap_err();
    let message = e.to_string();
    assert!(message.contains("bad.vtu"), "{message}");
    for needle in needles {
        assert!(message.contains(needle), "{needle:?} not in {message}");
    }
}

fn ascii_vtu(points_attr: &str, points: &str, extra: &str) -> String {
    format!(
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\">\n<UnstructuredGrid>\n\
         <Piece NumberOfPoints=\"2\" NumberOfCells=\"0\">\n<PointData>{extra}</PointData>\n\
         <Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" {points_attr}>\n{points}\n</DataArray>\n</Points>\n\
         </Piece>\n</UnstructuredGrid>\n</VTKFile>\n"
    )
}

#[test]
fn malformed_files_name_the_file_the_array_and_the_line() {
    let good = ascii_vtu("format=\"ascii\"", "0 0 0 1 2 3", "");
    assert_eq!(read_text(&good, Format::Vtu).unwrap().set.len(), 2);
    // A PolyData file is not a .vtu.
    expect_error(
        &good,
        Format::Vtp,
        &["UnstructuredGrid", "PolyData", "line 1"],
    );
    // Too few and too many values, a bad number.
    expect_error(
        &ascii_vtu("format=\"ascii\"", "0 0 0 1 2", ""),
        Format::Vtu,
        &["\"Points\"", "5 values where 6", "line 6"],
    );
    expect_error(
        &ascii_vtu("format=\"ascii\"", "0 0 0 1 2 3 4", ""),
        Format::Vtu,
        &["7 values where 6"],
    );
    expect_error(
        &ascii_vtu("format=\"ascii\"", "0 0 0 1 x 3", ""),
        Format::Vtu,
        &["invalid number \"x\""],
    );
    // NaN coordinates are rejected with the particle.
    expect_error(
        &ascii_vtu("format=\"ascii\"", "0 0 0 1 NaN 3", ""),
        Format::Vtu,
        &["particle 1", "coordinate 1"],
    );
    // A point array with the wrong count.
    expect_error(
        &ascii_vtu(
            "format=\"ascii\"",
            "0 0 0 1 2 3",
            "<DataArray type=\"Int32\" Name=\"id\" format=\"ascii\">1 2 3</DataArray>",
        ),
        Format::Vtu,
        &["\"id\"", "3 values where 2"],
    );
    // Base64 whose header declares more bytes than the array holds.
    let mut block = (1u32 << 30).to_le_bytes().to_vec();
    block.extend_from_slice(&[0; 48]);
    use base64::Engine;
    let b64 = base64::engine::general_purpose::STANDARD.encode(&block);
    expect_error(
        &ascii_vtu("format=\"binary\"", &b64, ""),
        Format::Vtu,
        &["header declares 1073741824 bytes, the array needs 48"],
    );
    // Invalid base64.
    expect_error(
        &ascii_vtu("format=\"binary\"", "@@@@", ""),
        Format::Vtu,
        &["invalid base64"],
    );
    // Not XML, no Points, not a VTKFile, an unknown compressor.
    expect_error(
        "<VTKFile type=\"UnstructuredGrid\"><Unstr",
        Format::Vtu,
        &["malformed XML"],
    );
    expect_error(
        "<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid><Piece NumberOfPoints=\"1\"></Piece></UnstructuredGrid></VTKFile>",
        Format::Vtu,
        &["no <Points>"],
    );
    expect_error("<vtk/>", Format::Vtu, &["root element is <vtk>"]);
    expect_error(
        "<VTKFile type=\"UnstructuredGrid\" compressor=\"vtkLZ4DataCompressor\"/>",
        Format::Vtu,
        &["vtkLZ4DataCompressor"],
    );
}

#[test]
fn huge_declared_counts_fail_before_allocating() {
    // 10^15 points declared, a few bytes present: the size check fails, nothing is reserved.
    let text = "<VTKFile type=\"PolyData\" header_type=\"UInt64\" byte_order=\"LittleEndian\">\
        <PolyData><Piece NumberOfPoints=\"1000000000000000\"><Points>\
        <DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"appended\" offset=\"0\"/>\
        </Points></Piece></PolyData><AppendedData encoding=\"raw\">_\u{1}\u{0}\u{0}\u{0}\u{0}\u{0}\u{0}\u{0}xyz</AppendedData></VTKFile>";
    let e = read_text(text, Format::Vtp).unwrap_err();
    assert!(
        e.to_string().contains("the array needs 12000000000000000"),
        "{e}"
    );
    let ascii = ascii_vtu("format=\"ascii\"", "0 0 0", "")
        .replace("NumberOfPoints=\"2\"", "NumberOfPoints=\"99999999999999\"");
    let e = read_text(&ascii, Format::Vtu).unwrap_err();
    assert!(e.to_string().contains("3 values where"), "{e}");
}

#[test]
fn truncated_vtk_files_are_errors_at_every_cut() {
    for file in [
        "grid_appended_raw.vtu",
        "grid_appended_zlib.vtu",
        "poly_binary_zlib.vtp",
    ] {
        let bytes = std::fs::read(data(file)).unwrap();
        let format = Format::from_path(&data(file)).unwrap();
        // Cutting inside the first appended array (velocity, over 100 bytes in both files) is
        // always an error; no cut panics. (Cuts in the cells' arrays are not: cells are not
        // read.)
        let appended = bytes
            .windows(13)
            .position(|w| w == b"<AppendedData")
            .map(|tag| tag + bytes[tag..].iter().position(|&b| b == b'_').unwrap());
        for cut in 0..bytes.len() {
            let r =
                read_particle_file_from(&bytes[..cut], "cut.vtu", format, &ReadOptions::default());
            if let Err(e) = &r {
                assert!(e.to_string().contains("cut.vtu"), "{e}");
            }
            if appended.is_some_and(|a| (a + 1..a + 100).contains(&cut)) {
                assert!(r.is_err(), "{file} cut at {cut} of {}", bytes.len());
            }
        }
    }
}

#[test]
fn a_lying_compression_header_is_an_error() {
    // Flip the declared uncompressed block size of the first array (UInt64 header at offset 8).
    let mut bytes = std::fs::read(data("grid_appended_zlib.vtu")).unwrap();
    let tag = bytes
        .windows(13)
        .position(|w| w == b"<AppendedData")
        .unwrap();
    let start = tag + bytes[tag..].iter().position(|&b| b == b'_').unwrap() + 1;
    bytes[start + 8] = bytes[start + 8].wrapping_add(1);
    let e = read_particle_file_from(
        bytes.as_slice(),
        "z.vtu",
        Format::Vtu,
        &ReadOptions::default(),
    )
    .unwrap_err();
    assert!(e.to_string().contains("z.vtu"), "{e}");
    assert!(e.to_string().contains("velocity"), "{e}");
}
