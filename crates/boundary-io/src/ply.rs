//! PLY through `ply-rs-bw`: ascii, binary little and big endian. The element `vertex` must have
//! scalar properties `x`, `y`, optionally `z`, of any numeric type; its other scalar properties
//! are kept as attributes when asked; other elements and list properties are skipped.
//!
//! `ply-rs-bw` caps its preallocation from declared counts and reports errors with the line (for
//! binary payloads: a running element counter, from which the vertex index is recovered). The
//! writer is hand-written: ascii PLY is a few header lines and one line per vertex, while the
//! crate's writer wants one owned property map per vertex.

use crate::error::{IoError, Location};
use crate::out::{self, Real, AXES};
use crate::{Attribute, AttributeValues, Column, Positions};
use boundary_core::AnyParticleSet;
use ply_rs_bw::parser::{ParseError, Parser, Reader};
use ply_rs_bw::ply::{Encoding, PropertyAccess, PropertyType, ScalarType};
use std::io::{BufRead, Write};

/// An element the reader does not need: every property is ignored (lists are still read
/// through, with the parser's capped preallocation).
struct Skip;

impl PropertyAccess for Skip {
    fn new() -> Self {
        Skip
    }
}

/// A vertex: its x, y, z, and its other scalar properties in header order (the parser sets
/// the properties of an element in the order the header declares them; every PLY scalar type
/// converts exactly to `f64`).
struct Vertex([f64; 3], Vec<f64>);

impl Vertex {
    fn set(&mut self, name: &str, value: f64) -> ply_rs_bw::ply::PropertyAccessResult {
        use ply_rs_bw::ply::PropertyAccessResult::Set;
        match name {
            "x" => self.0[0] = value,
            "y" => self.0[1] = value,
            "z" => self.0[2] = value,
            _ => self.1.push(value),
        }
        Set
    }
}

impl PropertyAccess for Vertex {
    fn new() -> Self {
        Vertex([0.0; 3], Vec::new())
    }
    fn set_char(&mut self, n: &str, v: i8) -> ply_rs_bw::ply::PropertyAccessResult {
        self.set(n, f64::from(v))
    }
    fn set_uchar(&mut self, n: &str, v: u8) -> ply_rs_bw::ply::PropertyAccessResult {
        self.set(n, f64::from(v))
    }
    fn set_short(&mut self, n: &str, v: i16) -> ply_rs_bw::ply::PropertyAccessResult {
        self.set(n, f64::from(v))
    }
    fn set_ushort(&mut self, n: &str, v: u16) -> ply_rs_bw::ply::PropertyAccessResult {
        self.set(n, f64::from(v))
    }
    fn set_int(&mut self, n: &str, v: i32) -> ply_rs_bw::ply::PropertyAccessResult {
        self.set(n, f64::from(v))
    }
    fn set_uint(&mut self, n: &str, v: u32) -> ply_rs_bw::ply::PropertyAccessResult {
        self.set(n, f64::from(v))
    }
    fn set_float(&mut self, n: &str, v: f32) -> ply_rs_bw::ply::PropertyAccessResult {
        self.set(n, f64::from(v))
    }
    fn set_double(&mut self, n: &str, v: f64) -> ply_rs_bw::ply::PropertyAccessResult {
        self.set(n, v)
    }
}

/// The parser's message as one lower-case line without its `Line N:` prefix, shortened.
fn flatten(e: &ParseError) -> String {
    let text = e.to_string();
    let text = match e.line() {
        Some(line) => text
            .strip_prefix(&format!("Line {line}: "))
            .unwrap_or(&text)
            .to_owned(),
        None => text,
    };
    let one_line: Vec<&str> = text.split_whitespace().collect();
    let mut message = crate::error::excerpt(&one_line.join(" "), 160);
    if let Some(first) = message.get(..1) {
        let lower = first.to_ascii_lowercase();
        message.replace_range(..1, &lower);
    }
    let message = message.trim_end_matches('.').to_owned();
    format!("malformed PLY: {message}")
}

pub(crate) fn read<R: BufRead>(
    reader: R,
    name: &str,
    with_attributes: bool,
) -> Result<Positions, IoError> {
    let mut reader = Reader::new(reader);
    let header = Parser::<Skip>::new()
        .read_header(&mut reader)
        .map_err(|e| {
            let at = e.line().map_or(Location::File, Location::Line);
            IoError::parse(name, at, flatten(&e))
        })?;
    let Some(vertex) = header.elements.get("vertex") else {
        return Err(IoError::parse(
            name,
            Location::File,
            "malformed PLY: no element \"vertex\"",
        ));
    };
    let mut stride = 0;
    for (axis, label) in AXES.iter().enumerate() {
        match vertex.properties.get(*label).map(|p| &p.data_type) {
            Some(PropertyType::Scalar(_)) if stride == axis => stride += 1,
            Some(PropertyType::Scalar(_)) => {}
            Some(PropertyType::List(..)) => {
                return Err(IoError::parse(
                    name,
                    Location::File,
                    format!("malformed PLY: vertex property {label} is a list, not a number"),
                ))
            }
            None => {}
        }
    }
    if stride < 2 {
        let found: Vec<&str> = vertex.properties.keys().map(String::as_str).collect();
        return Err(IoError::parse(
            name,
            Location::File,
            format!(
                "the PLY vertex element lacks property {} (it has: {})",
                if stride == 0 { "x" } else { "y" },
                crate::error::excerpt(&found.join(", "), 160)
            ),
        ));
    }
    // x and y without z, and a property that looks like a misspelt z: in PLY the names are
    // exact, so `Z` or `pos_z` are misses too.
    let near_miss = if stride == 2 {
        vertex
            .properties
            .keys()
            .find(|key| {
                key.as_str() != "z"
                    && (crate::text::near_miss(key, 2)
                        || crate::text::position_axis(key).map(|p| p.0) == Some(2))
            })
            .map(|key| crate::NearMiss {
                at: Location::File,
                vertex_property: true,
                name: crate::error::excerpt(key, 40),
                axis: 2,
            })
    } else {
        None
    };
    let binary = header.encoding != Encoding::Ascii;
    // Elements before `vertex` are read through and dropped.
    for (key, element) in &header.elements {
        if key == "vertex" {
            break;
        }
        if element.properties.is_empty() && element.count > 0 {
            // Nothing to read per element: a huge count would spin without consuming input.
            return Err(IoError::parse(
                name,
                Location::File,
                format!(
                    "malformed PLY: element {:?} declares {} items but no properties",
                    crate::error::excerpt(key, 40),
                    element.count
                ),
            ));
        }
        Parser::<Skip>::new()
            .read_payload_for_element(&mut reader, element, &header)
            .map_err(|e| {
                let at = match (binary, e.line()) {
                    (false, Some(line)) => Location::Line(line),
                    _ => Location::File,
                };
                IoError::parse(name, at, flatten(&e))
            })?;
    }
    // The line of the first vertex (ascii), or the parser's element counter (binary).
    let first = reader.line().max(1);
    let locate = |i: usize| {
        if binary {
            Location::Item {
                kind: "vertex",
                index: i,
            }
        } else {
            Location::Line(first + i)
        }
    };
    let vertices = Parser::<Vertex>::new()
        .read_payload_for_element(&mut reader, vertex, &header)
        .map_err(|e| {
            let at = e
                .line()
                .map_or(Location::File, |line| locate(line.saturating_sub(first)));
            IoError::parse(name, at, flatten(&e))
        })?;
    let mut coords = Vec::with_capacity(vertices.len() * stride);
    for (index, v) in vertices.iter().enumerate() {
        for (axis, &value) in v.0[..stride].iter().enumerate() {
            if !value.is_finite() {
                return Err(IoError::NonFinite {
                    file: name.to_owned(),
                    at: locate(index),
                    index,
                    axis,
                    value,
                });
            }
        }
        coords.extend_from_slice(&v.0[..stride]);
    }
    let mut attributes = Vec::new();
    let mut skipped = Vec::new();
    if with_attributes {
        // The other scalar vertex properties, in header order (the order `Vertex` saw them).
        let others: Vec<(&String, bool)> = vertex
            .properties
            .iter()
            .filter(|(key, _)| !AXES.contains(&key.as_str()))
            .filter_map(|(key, p)| match &p.data_type {
                PropertyType::Scalar(t) => {
                    Some((key, !matches!(t, ScalarType::Float | ScalarType::Double)))
                }
                PropertyType::List(..) => {
                    skipped.push(format!(
                        "vertex property {:?}: a list",
                        crate::error::excerpt(key, 40)
                    ));
                    None
                }
            })
            .collect();
        if vertices.iter().all(|v| v.1.len() == others.len()) {
            for (k, (key, integer)) in others.iter().enumerate() {
                let attribute = crate::attribute_name(key, k);
                if let Some(why) = crate::attribute_conflict(&attribute, &attributes) {
                    skipped.push(format!(
                        "vertex property {:?}: {why}",
                        crate::error::excerpt(key, 40)
                    ));
                    continue;
                }
                let values = vertices.iter().map(|v| v.1[k]);
                let values = if *integer {
                    // Every PLY integer type fits i64 exactly.
                    AttributeValues::Int(values.map(|x| x as i64).collect())
                } else {
                    AttributeValues::Float(values.collect())
                };
                attributes.push(Attribute {
                    name: attribute,
                    values,
                });
            }
        }
    }
    Ok(Positions {
        coords,
        stride,
        attributes,
        skipped,
        names: AXES[..stride].iter().map(|a| (*a).to_owned()).collect(),
        near_miss,
        empty: Some("its header declares element vertex 0".to_owned()),
        ..Default::default()
    })
}

/// `name` as a PLY property name, which the PLY grammar of readers (ours included) takes as
/// an identifier: letters, digits, `_` and `-`, not starting with a digit or `-`. Any other
/// character becomes `_` (a vector's `v:0` is written `v_0`), and a name that would start
/// with a digit or `-` gets a `_` before it.
pub(crate) fn property_name(name: &str) -> String {
    let mut out: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if out.starts_with(|c: char| c.is_ascii_digit() || c == '-') {
        out.insert(0, '_');
    }
    out
}

pub(crate) fn write(
    out: &mut dyn Write,
    set: &AnyParticleSet,
    columns: &[(&str, Column<'_>)],
) -> std::io::Result<()> {
    writeln!(out, "ply\nformat ascii 1.0\ncomment written by boundary-io")?;
    writeln!(out, "element vertex {}", set.len())?;
    for axis in &AXES[..set.dim()] {
        writeln!(out, "property double {axis}")?;
    }
    let types: Vec<&str> = columns.iter().map(|(_, c)| out::binary_type(c)).collect();
    for ((name, _), ty) in columns.iter().zip(&types) {
        writeln!(out, "property {ty} {}", property_name(name))?;
    }
    writeln!(out, "end_header")?;
    for i in 0..set.len() {
        for (k, v) in set.coords(i).iter().enumerate() {
            if k > 0 {
                write!(out, " ")?;
            }
            write!(out, "{}", Real(*v))?;
        }
        for ((_, column), ty) in columns.iter().zip(&types) {
            write!(out, " ")?;
            out::typed_value(out, column, ty, i)?;
        }
        writeln!(out)?;
    }
    Ok(())
}

/// A face: the corners of its list property `vertex_indices` (or `vertex_index`), as `i64`
/// so that every PLY integer type converts exactly and a negative index is caught.
struct Face(Option<Vec<i64>>);

impl Face {
    fn set(&mut self, name: &str, value: Vec<i64>) -> ply_rs_bw::ply::PropertyAccessResult {
        if name == "vertex_indices" || name == "vertex_index" {
            self.0 = Some(value);
        }
        ply_rs_bw::ply::PropertyAccessResult::Set
    }
}

impl PropertyAccess for Face {
    fn new() -> Self {
        Face(None)
    }
    fn set_list_char(&mut self, n: &str, v: Vec<i8>) -> ply_rs_bw::ply::PropertyAccessResult {
        self.set(n, v.into_iter().map(i64::from).collect())
    }
    fn set_list_uchar(&mut self, n: &str, v: Vec<u8>) -> ply_rs_bw::ply::PropertyAccessResult {
        self.set(n, v.into_iter().map(i64::from).collect())
    }
    fn set_list_short(&mut self, n: &str, v: Vec<i16>) -> ply_rs_bw::ply::PropertyAccessResult {
        self.set(n, v.into_iter().map(i64::from).collect())
    }
    fn set_list_ushort(&mut self, n: &str, v: Vec<u16>) -> ply_rs_bw::ply::PropertyAccessResult {
        self.set(n, v.into_iter().map(i64::from).collect())
    }
    fn set_list_int(&mut self, n: &str, v: Vec<i32>) -> ply_rs_bw::ply::PropertyAccessResult {
        self.set(n, v.into_iter().map(i64::from).collect())
    }
    fn set_list_uint(&mut self, n: &str, v: Vec<u32>) -> ply_rs_bw::ply::PropertyAccessResult {
        self.set(n, v.into_iter().map(i64::from).collect())
    }
}

/// Reads a triangle mesh: the `x, y, z` of the element `vertex` and the list property
/// `vertex_indices` (or `vertex_index`) of the element `face`, in any order and encoding;
/// other elements and properties are skipped. Polygons are split into fans.
pub(crate) fn read_mesh<R: BufRead>(reader: R, name: &str) -> Result<crate::mesh::Mesh, IoError> {
    let mut reader = Reader::new(reader);
    let header = Parser::<Skip>::new()
        .read_header(&mut reader)
        .map_err(|e| {
            let at = e.line().map_or(Location::File, Location::Line);
            IoError::parse(name, at, flatten(&e))
        })?;
    let binary = header.encoding != Encoding::Ascii;
    for (key, label) in [("vertex", "x"), ("vertex", "y"), ("vertex", "z")] {
        let ok = header.elements.get(key).is_some_and(|e| {
            matches!(
                e.properties.get(label).map(|p| &p.data_type),
                Some(PropertyType::Scalar(_))
            )
        });
        if !ok {
            return Err(IoError::parse(
                name,
                Location::File,
                format!("a PLY mesh needs the scalar vertex property {label}"),
            ));
        }
    }
    let has_faces = header.elements.get("face").is_some_and(|e| {
        ["vertex_indices", "vertex_index"].iter().any(|k| {
            matches!(
                e.properties.get(*k).map(|p| &p.data_type),
                Some(PropertyType::List(..))
            )
        })
    });
    if !has_faces {
        return Err(IoError::parse(
            name,
            Location::File,
            "a PLY mesh needs the element face with a list property vertex_indices",
        ));
    }
    let mut vertices: Vec<[f64; 3]> = Vec::new();
    let mut faces: Vec<Face> = Vec::new();
    let mut face_start = None;
    for (key, element) in &header.elements {
        if element.properties.is_empty() && element.count > 0 {
            return Err(IoError::parse(
                name,
                Location::File,
                format!(
                    "malformed PLY: element {:?} declares {} items but no properties",
                    crate::error::excerpt(key, 40),
                    element.count
                ),
            ));
        }
        let first = reader.line().max(1);
        let kind: &'static str = if key == "face" { "face" } else { "vertex" };
        let locate = move |line: Option<usize>| match (binary, line) {
            (false, Some(line)) => Location::Line(line),
            (true, Some(line)) => Location::Item {
                kind,
                index: line.saturating_sub(first),
            },
            (_, None) => Location::File,
        };
        match key.as_str() {
            "vertex" => {
                let read = Parser::<Vertex>::new()
                    .read_payload_for_element(&mut reader, element, &header)
                    .map_err(|e| IoError::parse(name, locate(e.line()), flatten(&e)))?;
                for (index, v) in read.iter().enumerate() {
                    if let Some(axis) = v.0.iter().position(|c| !c.is_finite()) {
                        return Err(IoError::NonFinite {
                            file: name.to_owned(),
                            at: if binary {
                                Location::Item {
                                    kind: "vertex",
                                    index,
                                }
                            } else {
                                Location::Line(first + index)
                            },
                            index,
                            axis,
                            value: v.0[axis],
                        });
                    }
                }
                vertices = read.into_iter().map(|v| v.0).collect();
            }
            "face" => {
                face_start = Some(first);
                faces = Parser::<Face>::new()
                    .read_payload_for_element(&mut reader, element, &header)
                    .map_err(|e| IoError::parse(name, locate(e.line()), flatten(&e)))?;
            }
            _ => {
                Parser::<Skip>::new()
                    .read_payload_for_element(&mut reader, element, &header)
                    .map_err(|e| IoError::parse(name, locate(e.line()), flatten(&e)))?;
            }
        }
    }
    let first = face_start.unwrap_or(1);
    let n = vertices.len();
    let mut triangles = Vec::new();
    for (index, face) in faces.iter().enumerate() {
        let at = if binary {
            Location::Item {
                kind: "face",
                index,
            }
        } else {
            Location::Line(first + index)
        };
        let corners = face.0.as_deref().unwrap_or(&[]);
        let mut checked = Vec::with_capacity(corners.len());
        for &i in corners {
            if i < 0 || i as u64 >= n as u64 || i > i64::from(u32::MAX) {
                return Err(IoError::parse(
                    name,
                    at,
                    format!("face {index}: vertex index {i} out of range ({n} vertices)"),
                ));
            }
            checked.push(i as u32);
        }
        crate::mesh::fan(&checked, &mut triangles)
            .map_err(|m| IoError::parse(name, at, format!("face {index}: {m}")))?;
    }
    Ok((vertices, triangles))
}
