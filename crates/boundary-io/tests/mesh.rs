//! Triangle-mesh readers: the same cube written by the tests as ascii and binary STL, OBJ and
//! ascii and binary PLY reads back as the same triangles; malformed files give errors naming
//! the file and the line or item, never a panic.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use boundary_io::{read_mesh, read_mesh_from, MeshFormat};
use std::path::{Path, PathBuf};

/// The cube [0, 1]^3 with its six faces as quads, outward.
fn cube_quads() -> (Vec<[f64; 3]>, Vec<[u32; 4]>) {
    let v: Vec<[f64; 3]> = (0..8)
        .map(|k| {
            [
                (k & 1) as f64,
                ((k >> 1) & 1) as f64 * 0.5,
                ((k >> 2) & 1) as f64 - 0.25,
            ]
        })
        .collect();
    let q = vec![
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    (v, q)
}

fn cube_triangles() -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let (v, q) = cube_quads();
    let t = q
        .iter()
        .flat_map(|f| [[f[0], f[1], f[2]], [f[0], f[2], f[3]]])
        .collect();
    (v, t)
}

/// The triangles as corner coordinates, rotated so that the smallest corner comes first
/// (orientation kept), then sorted: equal for equal oriented surfaces whatever the indexing.
fn canonical(v: &[[f64; 3]], t: &[[u32; 3]]) -> Vec<[[f64; 3]; 3]> {
    let mut out: Vec<[[f64; 3]; 3]> = t
        .iter()
        .map(|tri| {
            let c = tri.map(|i| v[i as usize]);
            let k = (0..3)
                .min_by(|&a, &b| c[a].partial_cmp(&c[b]).unwrap())
                .unwrap();
            [c[k], c[(k + 1) % 3], c[(k + 2) % 3]]
        })
        .collect();
    out.sort_by(|a, b| a.partial_cmp(b).unwrap());
    out
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

fn stl_ascii(v: &[[f64; 3]], t: &[[u32; 3]]) -> String {
    let mut s = String::from("solid cube\n");
    for tri in t {
        s.push_str("  facet normal 0 0 0\n    outer loop\n");
        for &i in tri {
            let p = v[i as usize];
            s.push_str(&format!("      vertex {} {} {}\n", p[0], p[1], p[2]));
        }
        s.push_str("    endloop\n  endfacet\n");
    }
    s.push_str("endsolid cube\n");
    s
}

fn stl_binary(v: &[[f64; 3]], t: &[[u32; 3]], header: &[u8]) -> Vec<u8> {
    let mut b = vec![0u8; 80];
    b[..header.len()].copy_from_slice(header);
    b.extend((t.len() as u32).to_le_bytes());
    for tri in t {
        b.extend([0u8; 12]);
        for &i in tri {
            for c in v[i as usize] {
                b.extend((c as f32).to_le_bytes());
            }
        }
        b.extend([0u8; 2]);
    }
    b
}

#[test]
fn stl_ascii_and_binary_read_as_the_cube() {
    let dir = tempfile::tempdir().unwrap();
    let (v, t) = cube_triangles();
    let want = canonical(&v, &t);
    let ascii = write(dir.path(), "cube.stl", stl_ascii(&v, &t).as_bytes());
    let (rv, rt) = read_mesh(&ascii).unwrap();
    assert_eq!(rv.len(), 8, "shared corners are merged");
    assert_eq!(canonical(&rv, &rt), want);
    // A binary file whose header begins with "solid", as some exporters write.
    let binary = write(
        dir.path(),
        "cube_bin.STL",
        &stl_binary(&v, &t, b"solid but binary"),
    );
    let (rv, rt) = read_mesh(&binary).unwrap();
    assert_eq!(rv.len(), 8);
    assert_eq!(canonical(&rv, &rt), want);
}

#[test]
fn obj_quads_slashes_and_negative_indices_read_as_the_cube() {
    let (v, q) = cube_quads();
    let (tv, tt) = cube_triangles();
    let mut s = String::from("# a cube\no cube\n");
    for p in &v {
        s.push_str(&format!("v {} {} {}  # corner\n", p[0], p[1], p[2]));
    }
    s.push_str("vn 0 0 1\nvt 0 0\n\n");
    for (k, f) in q.iter().enumerate() {
        let corner = |i: u32| match k % 3 {
            0 => format!("{}", i + 1),
            1 => format!("{}/1/1", i + 1),
            _ => format!("{}//1", i as i64 - 8),
        };
        s.push_str(&format!(
            "f {} {} {} {}\n",
            corner(f[0]),
            corner(f[1]),
            corner(f[2]),
            corner(f[3])
        ));
    }
    let (rv, rt) = read_mesh_from(s.as_bytes(), "cube.obj", MeshFormat::Obj).unwrap();
    assert_eq!(rv, v);
    assert_eq!(rt, tt);
    assert_eq!(canonical(&rv, &rt), canonical(&tv, &tt));
}

fn ply_ascii(v: &[[f64; 3]], q: &[[u32; 4]]) -> String {
    let mut s = format!(
        "ply\nformat ascii 1.0\ncomment a cube\nelement vertex {}\nproperty double x\n\
         property double y\nproperty double z\nproperty uchar red\nelement face {}\n\
         property list uchar int vertex_indices\nend_header\n",
        v.len(),
        q.len()
    );
    for p in v {
        s.push_str(&format!("{} {} {} 7\n", p[0], p[1], p[2]));
    }
    for f in q {
        s.push_str(&format!("4 {} {} {} {}\n", f[0], f[1], f[2], f[3]));
    }
    s
}

#[test]
fn ply_ascii_and_binary_faces_read_as_the_cube() {
    let dir = tempfile::tempdir().unwrap();
    let (v, q) = cube_quads();
    let (tv, tt) = cube_triangles();
    let ascii = write(dir.path(), "cube.ply", ply_ascii(&v, &q).as_bytes());
    let (rv, rt) = read_mesh(&ascii).unwrap();
    assert_eq!(rv, v);
    assert_eq!(rt, tt);
    // Binary little endian, faces first, float vertices, uint indices.
    let mut b = format!(
        "ply\nformat binary_little_endian 1.0\nelement face {}\n\
         property list uchar uint vertex_index\nelement vertex {}\nproperty float x\n\
         property float y\nproperty float z\nend_header\n",
        q.len(),
        v.len()
    )
    .into_bytes();
    for f in &q {
        b.push(4);
        for i in f {
            b.extend(i.to_le_bytes());
        }
    }
    for p in &v {
        for c in p {
            b.extend((*c as f32).to_le_bytes());
        }
    }
    let binary = write(dir.path(), "cube_bin.ply", &b);
    let (rv, rt) = read_mesh(&binary).unwrap();
    assert_eq!(canonical(&rv, &rt), canonical(&tv, &tt));
}

fn error(name: &str, bytes: &[u8]) -> String {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), name, bytes);
    let e = read_mesh(&path).unwrap_err().to_string();
    assert!(e.contains(name), "the error names the file: {e}");
    e
}

#[test]
fn malformed_meshes_are_named_by_file_and_line_or_item() {
    let (v, t) = cube_triangles();
    let (qv, q) = cube_quads();
    // STL ascii: a bad coordinate on line 4, a facet of two corners, an unknown keyword.
    let mut s = stl_ascii(&v, &t);
    s = s.replacen("vertex 0 0 -0.25", "vertex 0 zero -0.25", 1);
    let e = error("bad.stl", s.as_bytes());
    assert!(e.contains("line 4") && e.contains("\"zero\""), "{e}");
    let two = "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid\n";
    let e = error("two.stl", two.as_bytes());
    assert!(e.contains("line 2") && e.contains("2 vertices"), "{e}");
    let e = error("kw.stl", b"solid x\nfacet normal 0 0 1\nbanana\n");
    assert!(e.contains("line 3") && e.contains("banana"), "{e}");
    let e = error("open.stl", b"solid x\nfacet normal 0 0 1\nouter loop\n");
    assert!(e.contains("line 2") && e.contains("endfacet"), "{e}");
    // STL binary: truncated, and a NaN in triangle 3.
    let mut b = stl_binary(&v, &t, b"binary");
    b.truncate(b.len() - 10);
    let e = error("short.stl", &b);
    assert!(e.contains("declares 12 triangles"), "{e}");
    let mut b = stl_binary(&v, &t, b"binary");
    let at = 84 + 3 * 50 + 12 + 4;
    b[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    let e = error("nan.stl", &b);
    assert!(e.contains("triangle 3") && e.contains("not finite"), "{e}");
    assert!(error("tiny.stl", b"abc").contains("not an STL file"));
    // OBJ: an index beyond the vertices read so far, a bad number, a degenerate face.
    let e = error("bad.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
    assert!(
        e.contains("line 4") && e.contains("out of range (3 vertices"),
        "{e}"
    );
    let e = error("num.obj", b"v 0 0 0\nv 1 0 nan\n");
    assert!(e.contains("line 2") && e.contains("coordinate 2"), "{e}");
    let e = error("two.obj", b"v 0 0 0\nv 1 0 0\n\nf 1 2\n");
    assert!(
        e.contains("line 4") && e.contains("at least 3 corners"),
        "{e}"
    );
    let e = error("zero.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
    assert!(e.contains("line 4"), "{e}");
    assert!(error("empty.obj", b"v 0 0 0\n").contains("no triangle"));
    // PLY: an index out of range on the face's line, no faces, a bad header.
    let bad = ply_ascii(&qv, &q).replacen("4 0 2 3 1", "4 0 2 3 9", 1);
    let e = error("bad.ply", bad.as_bytes());
    // 11 header lines, 8 vertex lines: the first face is line 20.
    assert!(
        e.contains("line 20") && e.contains("index 9 out of range"),
        "{e}"
    );
    let e = error(
        "nofaces.ply",
        b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n",
    );
    assert!(e.contains("face"), "{e}");
    let e = error(
        "hdr.ply",
        b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n",
    );
    assert!(!e.is_empty());
    // An unknown extension and a missing file.
    let dir = tempfile::tempdir().unwrap();
    let e = read_mesh(&dir.path().join("m.off"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("m.off") && e.contains(".stl"), "{e}");
    let e = read_mesh(&dir.path().join("none.stl"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("none.stl"), "{e}");
}

#[test]
fn arbitrary_bytes_never_panic() {
    // Deterministic pseudo-random inputs, and every prefix of valid files.
    let (v, t) = cube_triangles();
    let (qv, q) = cube_quads();
    let valid: Vec<(MeshFormat, Vec<u8>)> = vec![
        (MeshFormat::Stl, stl_ascii(&v, &t).into_bytes()),
        (MeshFormat::Stl, stl_binary(&v, &t, b"x")),
        (MeshFormat::Ply, ply_ascii(&qv, &q).into_bytes()),
        (
            MeshFormat::Obj,
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf -1 -2 -3\n".to_vec(),
        ),
    ];
    for (format, bytes) in &valid {
        for cut in (0..bytes.len()).step_by(7) {
            let _ = read_mesh_from(&bytes[..cut], "prefix", *format);
        }
    }
    let mut state = 0x9e3779b97f4a7c15u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    for _ in 0..300 {
        let len = (next() % 300) as usize;
        let mut bytes: Vec<u8> = (0..len).map(|_| next() as u8).collect();
        if next() % 2 == 0 {
            let prefix: &[u8] = match next() % 3 {
                0 => b"solid ",
                1 => b"ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n",
                _ => b"v 1 2 3\nf ",
            };
            bytes.splice(0..0, prefix.iter().copied());
        }
        for format in [MeshFormat::Stl, MeshFormat::Obj, MeshFormat::Ply] {
            let _ = read_mesh_from(&bytes[..], "random", format);
        }
    }
}
