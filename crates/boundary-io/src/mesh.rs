//! Triangle meshes of solid regions: STL (ascii and binary), OBJ and PLY faces.
//!
//! The readers return the vertices and the triangles as indices into them; polygons with more
//! than three corners (OBJ, PLY) are split into a fan from their first corner, which is right
//! for the convex polygons exporters write. STL stores every triangle's corners by value:
//! corners with bit-identical coordinates (`-0` equal to `0`) are merged into one vertex, so
//! that a closed STL surface reads as a closed indexed mesh. Whether the mesh is closed and
//! oriented is checked by [`boundary_core::SolidMesh::new`], not here.
//!
//! OBJ is parsed by hand (the statements `v` and `f`; the others are skipped): a general OBJ
//! reader reports no line for a malformed statement, and a mesh needs only these two.

use crate::error::{IoError, Location};
use std::collections::HashMap;
use std::io::{BufRead, Read};

/// The triangles and vertices a reader returns.
pub(crate) type Mesh = (Vec<[f64; 3]>, Vec<[u32; 3]>);

/// Reads STL, ascii or binary. A file whose size is `84 + 50·n` for the triangle count `n`
/// its header declares is binary (binary files may also begin with `solid`); otherwise a file
/// beginning with `solid` is ascii.
pub(crate) fn read_stl(mut reader: impl Read, name: &str) -> Result<Mesh, IoError> {
    let mut bytes = Vec::new();
    reader
        .read_to_end(&mut bytes)
        .map_err(|e| IoError::read(name, e))?;
    if bytes.len() >= 84 {
        let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64;
        if 84 + 50 * count == bytes.len() as u64 {
            return stl_binary(&bytes, name);
        }
    }
    let head = bytes.iter().position(|b| !b.is_ascii_whitespace());
    if head.is_some_and(|k| bytes[k..].starts_with(b"solid")) {
        let text = std::str::from_utf8(&bytes).map_err(|e| {
            IoError::parse(
                name,
                Location::File,
                format!("ascii STL is not UTF-8 text (byte {})", e.valid_up_to()),
            )
        })?;
        return stl_ascii(text, name);
    }
    if bytes.len() >= 84 {
        let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]);
        return Err(IoError::parse(
            name,
            Location::File,
            format!(
                "binary STL declares {count} triangles ({} bytes) but has {} bytes, and it \
                 does not begin with 'solid' as ascii STL does",
                84 + 50 * u64::from(count),
                bytes.len()
            ),
        ));
    }
    Err(IoError::parse(
        name,
        Location::File,
        format!(
            "not an STL file: {} bytes, shorter than a binary header, and no 'solid'",
            bytes.len()
        ),
    ))
}

/// Merges corners with identical coordinates into indexed vertices.
#[derive(Default)]
struct Welder {
    vertices: Vec<[f64; 3]>,
    index: HashMap<[u64; 3], u32>,
}

impl Welder {
    fn vertex(&mut self, v: [f64; 3]) -> Option<u32> {
        // `+ 0.0` turns -0 into +0: equal coordinates, one vertex.
        let key = v.map(|c| (c + 0.0).to_bits());
        if let Some(&k) = self.index.get(&key) {
            return Some(k);
        }
        let k = u32::try_from(self.vertices.len()).ok()?;
        self.vertices.push(v);
        self.index.insert(key, k);
        Some(k)
    }
}

fn stl_binary(bytes: &[u8], name: &str) -> Result<Mesh, IoError> {
    let mut welder = Welder::default();
    let mut triangles = Vec::new();
    for (t, record) in bytes[84..].chunks_exact(50).enumerate() {
        let mut corner = [0u32; 3];
        for (c, slot) in corner.iter_mut().enumerate() {
            let mut v = [0.0f64; 3];
            for (axis, x) in v.iter_mut().enumerate() {
                let at = 12 + 12 * c + 4 * axis;
                let value = f32::from_le_bytes([
                    record[at],
                    record[at + 1],
                    record[at + 2],
                    record[at + 3],
                ]);
                if !value.is_finite() {
                    return Err(IoError::parse(
                        name,
                        Location::Item {
                            kind: "triangle",
                            index: t,
                        },
                        format!("corner {c} coordinate {axis} is not finite ({value})"),
                    ));
                }
                *x = f64::from(value);
            }
            *slot = welder.vertex(v).ok_or_else(|| too_many(name))?;
        }
        triangles.push(corner);
    }
    Ok((welder.vertices, triangles))
}

fn too_many(name: &str) -> IoError {
    IoError::parse(name, Location::File, "more than 2^32 vertices")
}

fn stl_ascii(text: &str, name: &str) -> Result<Mesh, IoError> {
    let mut welder = Welder::default();
    let mut triangles = Vec::new();
    // Corners of the facet being read, with the line of its `facet`.
    let mut corners: Vec<u32> = Vec::new();
    let mut facet_line: Option<usize> = None;
    for (k, line) in text.lines().enumerate() {
        let at = Location::Line(k + 1);
        let mut words = line.split_whitespace();
        let Some(word) = words.next() else { continue };
        match word.to_ascii_lowercase().as_str() {
            "solid" | "endsolid" | "outer" | "endloop" => {}
            "facet" => {
                if facet_line.is_some() {
                    return Err(IoError::parse(name, at, "'facet' before 'endfacet'"));
                }
                facet_line = Some(k + 1);
                corners.clear();
            }
            "vertex" => {
                if facet_line.is_none() {
                    return Err(IoError::parse(name, at, "'vertex' outside a facet"));
                }
                let mut v = [0.0f64; 3];
                for (axis, x) in v.iter_mut().enumerate() {
                    let field = words.next().ok_or_else(|| {
                        IoError::parse(name, at, "a vertex needs three coordinates")
                    })?;
                    *x = field
                        .parse::<f64>()
                        .ok()
                        .filter(|x| x.is_finite())
                        .ok_or_else(|| {
                            IoError::parse(
                                name,
                                at,
                                format!(
                                    "vertex coordinate {axis} is not a finite number: {:?}",
                                    crate::error::excerpt(field, 40)
                                ),
                            )
                        })?;
                }
                corners.push(welder.vertex(v).ok_or_else(|| too_many(name))?);
            }
            "endfacet" => {
                let Some(start) = facet_line.take() else {
                    return Err(IoError::parse(name, at, "'endfacet' without 'facet'"));
                };
                let [a, b, c] = corners[..] else {
                    return Err(IoError::parse(
                        name,
                        Location::Line(start),
                        format!("the facet has {} vertices, not 3", corners.len()),
                    ));
                };
                triangles.push([a, b, c]);
            }
            other => {
                return Err(IoError::parse(
                    name,
                    at,
                    format!(
                        "unknown ascii STL keyword {:?}",
                        crate::error::excerpt(other, 40)
                    ),
                ))
            }
        }
    }
    if let Some(start) = facet_line {
        return Err(IoError::parse(
            name,
            Location::Line(start),
            "the facet has no 'endfacet'",
        ));
    }
    Ok((welder.vertices, triangles))
}

/// Reads the `v` and `f` statements of an OBJ file (module docs). Face corners are `i`,
/// `i/t`, `i//n` or `i/t/n` with 1-based `i`, or negative `i` counted back from the last
/// vertex read so far.
pub(crate) fn read_obj(reader: impl BufRead, name: &str) -> Result<Mesh, IoError> {
    let mut vertices: Vec<[f64; 3]> = Vec::new();
    let mut triangles = Vec::new();
    for (k, line) in reader.lines().enumerate() {
        let at = Location::Line(k + 1);
        let line = line.map_err(|e| match e.kind() {
            std::io::ErrorKind::InvalidData => IoError::parse(name, at, "not UTF-8 text"),
            _ => IoError::read(name, e),
        })?;
        let line = line.split('#').next().unwrap_or("");
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let mut v = [0.0f64; 3];
                for (axis, x) in v.iter_mut().enumerate() {
                    let field = words.next().ok_or_else(|| {
                        IoError::parse(name, at, "a vertex needs three coordinates")
                    })?;
                    *x = field
                        .parse::<f64>()
                        .ok()
                        .filter(|x| x.is_finite())
                        .ok_or_else(|| {
                            IoError::parse(
                                name,
                                at,
                                format!(
                                    "vertex coordinate {axis} is not a finite number: {:?}",
                                    crate::error::excerpt(field, 40)
                                ),
                            )
                        })?;
                }
                vertices.push(v);
            }
            Some("f") => {
                let mut corners = Vec::new();
                for field in words {
                    let index = field.split('/').next().unwrap_or("");
                    let bad = |why: &str| {
                        IoError::parse(
                            name,
                            at,
                            format!("face corner {:?}: {why}", crate::error::excerpt(field, 40)),
                        )
                    };
                    let i: i64 = index.parse().map_err(|_| bad("not a vertex index"))?;
                    let n = vertices.len() as i64;
                    let zero_based = if i > 0 { i - 1 } else { n + i };
                    if i == 0 || zero_based < 0 || zero_based >= n {
                        return Err(bad(&format!(
                            "vertex index out of range ({n} vertices so far)"
                        )));
                    }
                    corners.push(u32::try_from(zero_based).map_err(|_| too_many(name))?);
                }
                fan(&corners, &mut triangles).map_err(|count| IoError::parse(name, at, count))?;
            }
            _ => {}
        }
    }
    Ok((vertices, triangles))
}

/// Splits the polygon `corners` into a fan of triangles from its first corner; an error
/// message for fewer than three corners.
pub(crate) fn fan(corners: &[u32], triangles: &mut Vec<[u32; 3]>) -> Result<(), String> {
    if corners.len() < 3 {
        return Err(format!(
            "a face needs at least 3 corners, this one has {}",
            corners.len()
        ));
    }
    for k in 1..corners.len() - 1 {
        triangles.push([corners[0], corners[k], corners[k + 1]]);
    }
    Ok(())
}
