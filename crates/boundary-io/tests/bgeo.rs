//! BGEO (Houdini classic, version 5, as partio writes it): a file built byte by byte from the
//! format's description (independent of our writer) reads to its values; our writer
//! round-trips through plain and gzip files; damaged headers give errors naming the file and
//! the byte, without allocating for the declared counts.
#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use boundary_io::{
    read_particle_file, read_particle_file_from, write_particles, AttributeValues, Column, Format,
    ReadOptions,
};
use common::set3;

fn string(out: &mut Vec<u8>, s: &str) {
    out.extend_from_slice(&(s.len() as u16).to_be_bytes());
    out.extend_from_slice(s.as_bytes());
}

/// Two points with a vector `v`, an int `id` and an indexed string `kind`, built from the
/// layout: header, attribute definitions, then x y z w and the attribute words per point.
fn hand_made(points: i32) -> Vec<u8> {
    let mut b = b"BgeoV".to_vec();
    for h in [5, points, 0, 0, 0, 3, 0, 0, 0] {
        b.extend_from_slice(&i32::to_be_bytes(h));
    }
    string(&mut b, "v");
    b.extend_from_slice(&3u16.to_be_bytes());
    b.extend_from_slice(&5i32.to_be_bytes());
    b.extend_from_slice(&[0; 12]);
    string(&mut b, "id");
    b.extend_from_slice(&1u16.to_be_bytes());
    b.extend_from_slice(&1i32.to_be_bytes());
    b.extend_from_slice(&[0; 4]);
    string(&mut b, "kind");
    b.extend_from_slice(&1u16.to_be_bytes());
    b.extend_from_slice(&4i32.to_be_bytes());
    b.extend_from_slice(&2i32.to_be_bytes());
    string(&mut b, "water");
    string(&mut b, "foam");
    for (p, v, id, kind) in [
        ([0.5f32, 1.0, -2.0], [1.0f32, 2.0, 3.0], 7i32, 1i32),
        ([1.5, 0.25, 4.0], [-1.0, 0.0, 0.5], 9, 0),
    ] {
        for x in p.iter().chain(&[1.0]).chain(&v) {
            b.extend_from_slice(&x.to_be_bytes());
        }
        b.extend_from_slice(&id.to_be_bytes());
        b.extend_from_slice(&kind.to_be_bytes());
    }
    b.extend_from_slice(&[0x00, 0xff]);
    b
}

fn read(bytes: &[u8]) -> Result<boundary_io::ParticleFile, boundary_io::IoError> {
    read_particle_file_from(bytes, "p.bgeo", Format::Bgeo, &ReadOptions::default())
}

#[test]
fn a_file_built_from_the_format_description_reads_to_its_values() {
    let f = read(&hand_made(2)).unwrap();
    assert_eq!(f.set.dim(), 3);
    assert_eq!(f.set.coords(0), &[0.5, 1.0, -2.0]);
    assert_eq!(f.set.coords(1), &[1.5, 0.25, 4.0]);
    let got: Vec<(&str, &AttributeValues)> = f
        .attributes
        .iter()
        .map(|a| (a.name.as_str(), &a.values))
        .collect();
    assert_eq!(
        got,
        [
            ("v:0", &AttributeValues::Float(vec![1.0, -1.0])),
            ("v:1", &AttributeValues::Float(vec![2.0, 0.0])),
            ("v:2", &AttributeValues::Float(vec![3.0, 0.5])),
            ("id", &AttributeValues::Int(vec![7, 9])),
            ("kind", &AttributeValues::Int(vec![1, 0])),
        ]
    );
}

#[test]
fn written_files_round_trip_plain_and_gzip() {
    let dir = tempfile::tempdir().unwrap();
    let set = set3();
    let labels = [1i64, 0, 1, -7, 1 << 30];
    let margin = [0.25, -1.5e-9, 3.0, 1e30, 1.0 / 7.0];
    let v = [[1.0, 2.0, 3.0, 4.0, 5.0], [0.0; 5], [-1.0; 5]];
    let columns = [
        ("boundary", Column::Int(&labels)),
        ("margin", Column::Float(&margin)),
        ("v:0", Column::Float(&v[0])),
        ("v:1", Column::Float(&v[1])),
        ("v:2", Column::Float(&v[2])),
    ];
    for file in ["p.bgeo", "p.bgeo.gz"] {
        let path = dir.path().join(file);
        write_particles(&path, None, &set, &columns).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(
            bytes.starts_with(&[0x1f, 0x8b]),
            file.ends_with(".gz"),
            "{file}"
        );
        let back = read_particle_file(&path, &ReadOptions::default()).unwrap();
        // BGEO holds 32-bit floats: positions and reals come back rounded to f32.
        for i in 0..set.len() {
            let expected: Vec<f64> = set.coords(i).iter().map(|&x| f64::from(x as f32)).collect();
            assert_eq!(back.set.coords(i), expected.as_slice(), "{file} point {i}");
        }
        assert_eq!(
            back.attributes[0].values,
            AttributeValues::Int(labels.to_vec())
        );
        assert_eq!(
            back.attributes[1].values,
            AttributeValues::Float(margin.iter().map(|&x| f64::from(x as f32)).collect())
        );
        let names: Vec<&str> = back.attributes.iter().map(|a| a.name.as_str()).collect();
        assert_eq!(names, ["boundary", "margin", "v:0", "v:1", "v:2"]);
        assert_eq!(
            back.attributes[4].values,
            AttributeValues::Float(v[2].to_vec())
        );
    }
    // An integer beyond 32 bits is an error naming the column and the particle.
    let big = [0, 0, 0, 0, 1i64 << 40];
    let e = write_particles(
        &dir.path().join("q.bgeo"),
        None,
        &set,
        &[("id", Column::Int(&big))],
    )
    .unwrap_err();
    assert!(
        e.to_string().contains("\"id\"") && e.to_string().contains("particle 4"),
        "{e}"
    );
    // So is a coordinate beyond the 32-bit float range.
    let far = boundary_core::ParticleSet::from_rows(&[[0.0, 1e300]])
        .unwrap()
        .to_any();
    let e = write_particles(&dir.path().join("r.bgeo"), None, &far, &[]).unwrap_err();
    assert!(e.to_string().contains("particle 0"), "{e}");
}

#[test]
fn damaged_files_name_the_file_and_the_byte() {
    let good = hand_made(2);
    // Cut anywhere: an error (never a panic) naming the file.
    for cut in 0..good.len() - 2 {
        let e = read(&good[..cut]).unwrap_err();
        assert!(e.to_string().contains("p.bgeo"), "{e}");
    }
    // A header declaring a billion points: rejected by the size check, nothing reserved.
    let e = read(&hand_made(1_000_000_000)).unwrap_err();
    assert!(e.to_string().contains("declares 1000000000 points"), "{e}");
    assert!(e.to_string().contains("byte"), "{e}");
    let e = read(&hand_made(-1)).unwrap_err();
    assert!(e.to_string().contains("negative point count"), "{e}");
    let mut new_style = good.clone();
    new_style[..4].copy_from_slice(b"\x7fNSJ");
    assert!(read(&new_style)
        .unwrap_err()
        .to_string()
        .contains("Houdini 12"));
    let mut v4 = good.clone();
    v4[8] = 4;
    assert!(read(&v4).unwrap_err().to_string().contains("version 4"));
    assert!(read(b"\x1f\x8b garbage")
        .unwrap_err()
        .to_string()
        .contains("gzip"));
}
