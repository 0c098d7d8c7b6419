//! Houdini's classic binary geometry, BGEO version 5 (`.bgeo`, gzip-compressed `.bgeo.gz`), as
//! partio writes it for SPlisHSPlasH and other particle tools. Written from the format's public
//! description (the layout partio documents in its reader and writer); big endian throughout:
//!
//! ```text
//! "Bgeo" 'V' version:i32(=5) nPoints nPrims nPointGroups nPrimGroups
//!        nPointAttrib nVertexAttrib nPrimAttrib nDetailAttrib          (i32 each)
//! nPointAttrib × { nameLen:u16 name size:u16 type:i32 defaults }
//!     type 0 float, 1 int, 5 vector: `size` 4-byte defaults;
//!     type 4 indexed string: count:i32, count × { len:u16 bytes }
//! nPoints × { x y z w: f32, then per attribute `size` 4-byte words }
//! primitives, detail attributes (not read)
//! ```
//!
//! Read: the positions (w dropped) and every point attribute (float and vector as reals,
//! int as integers, indexed strings as their integer index; a vector of `k` components as
//! `name:0` … `name:k-1`). A file starting with the gzip magic is inflated first. The new
//! (Houdini 12+) BGEO and Blosc-compressed `.bgeo.sc` are not read: an error says so.
//!
//! Written: BGEO 5 with no primitive, positions and reals as 32-bit floats (the format has no
//! doubles: writing rounds them), integer columns as `int` (an error when a value does not fit
//! 32 bits), bytes as `int`, columns `name:0..k` as one vector; a 2D set gets z = 0.

use crate::error::{excerpt, IoError, Location};
use crate::{Attribute, AttributeValues, Column, Positions};
use boundary_core::AnyParticleSet;
use std::io::{BufRead, Read, Write};

const MAGIC: &[u8; 4] = b"Bgeo";
/// The magic of the new (Houdini 12+) binary JSON geometry.
const NEW_MAGIC: &[u8; 4] = b"\x7fNSJ";

/// A cursor over the bytes with big-endian reads; `None` at the end.
struct Bytes<'a> {
    data: &'a [u8],
    pos: usize,
}

impl<'a> Bytes<'a> {
    fn take(&mut self, n: usize) -> Option<&'a [u8]> {
        let end = self.pos.checked_add(n)?;
        let out = self.data.get(self.pos..end)?;
        self.pos = end;
        Some(out)
    }
    fn u16(&mut self) -> Option<u16> {
        self.take(2).map(|b| u16::from_be_bytes([b[0], b[1]]))
    }
    fn i32(&mut self) -> Option<i32> {
        self.take(4)
            .map(|b| i32::from_be_bytes([b[0], b[1], b[2], b[3]]))
    }
}

/// A point attribute's definition.
struct Definition {
    name: String,
    size: usize,
    /// Houdini type: 0 float, 1 int, 4 indexed string, 5 vector.
    kind: i32,
}

pub(crate) fn read<R: BufRead>(
    mut reader: R,
    name: &str,
    with_attributes: bool,
) -> Result<Positions, IoError> {
    let mut raw = Vec::new();
    reader
        .read_to_end(&mut raw)
        .map_err(|e| IoError::read(name, e))?;
    let data = if raw.starts_with(&[0x1f, 0x8b]) {
        let mut out = Vec::new();
        flate2::read::MultiGzDecoder::new(raw.as_slice())
            .read_to_end(&mut out)
            .map_err(|e| IoError::parse(name, Location::File, format!("invalid gzip data: {e}")))?;
        out
    } else {
        raw
    };
    let at_byte = |pos: usize| Location::Item {
        kind: "byte",
        index: pos,
    };
    let err = |pos: usize, message: String| IoError::parse(name, at_byte(pos), message);
    let mut b = Bytes {
        data: &data,
        pos: 0,
    };
    let truncated = |b: &Bytes<'_>, what: &str| err(b.pos, format!("truncated BGEO: {what}"));
    let magic = b.take(4).ok_or_else(|| truncated(&b, "no header"))?;
    if magic == NEW_MAGIC {
        return Err(err(
            0,
            "new-style (Houdini 12+) BGEO is not supported; write classic BGEO (.bhclassic) \
             or another format"
                .into(),
        ));
    }
    if magic != MAGIC {
        return Err(err(
            0,
            "not a BGEO file: the magic number is not \"Bgeo\"".into(),
        ));
    }
    if b.take(1) != Some(b"V") {
        return Err(err(
            4,
            "not a BGEO file: no 'V' after the magic number".into(),
        ));
    }
    let mut header = [0i32; 9];
    for h in &mut header {
        *h = b.i32().ok_or_else(|| truncated(&b, "header"))?;
    }
    let [version, points, _prims, _, _, point_attributes, ..] = header;
    if version != 5 {
        return Err(err(
            5,
            format!("BGEO version {version}, only version 5 is read"),
        ));
    }
    let count = |v: i32, what: &str| {
        usize::try_from(v).map_err(|_| err(9, format!("negative {what} count {v}")))
    };
    let n = count(points, "point")?;
    let attribute_count = count(point_attributes, "point attribute")?;
    let mut definitions = Vec::new();
    for k in 0..attribute_count {
        let start = b.pos;
        let len = b
            .u16()
            .ok_or_else(|| truncated(&b, "attribute definition"))?;
        let attribute = b
            .take(usize::from(len))
            .ok_or_else(|| truncated(&b, "attribute name"))?;
        let attribute = String::from_utf8_lossy(attribute).into_owned();
        let size = usize::from(b.u16().ok_or_else(|| truncated(&b, "attribute size"))?);
        let kind = b.i32().ok_or_else(|| truncated(&b, "attribute type"))?;
        match kind {
            0 | 1 | 5 => {
                b.take(4 * size)
                    .ok_or_else(|| truncated(&b, "attribute defaults"))?;
            }
            4 => {
                let strings = b.i32().ok_or_else(|| truncated(&b, "string count"))?;
                let strings = usize::try_from(strings)
                    .map_err(|_| err(b.pos - 4, format!("negative string count {strings}")))?;
                for _ in 0..strings {
                    let len = b.u16().ok_or_else(|| truncated(&b, "string table"))?;
                    b.take(usize::from(len))
                        .ok_or_else(|| truncated(&b, "string table"))?;
                }
            }
            other => {
                return Err(err(
                    start,
                    format!(
                        "point attribute {k} ({:?}) has type {other}, which is not read \
                         (float 0, int 1, indexed string 4, vector 5)",
                        excerpt(&attribute, 40)
                    ),
                ))
            }
        }
        definitions.push(Definition {
            name: attribute,
            size,
            kind,
        });
    }
    let words: usize = 4 + definitions.iter().map(|d| d.size).sum::<usize>();
    let first = b.pos;
    let body = n
        .checked_mul(4 * words)
        .and_then(|len| b.take(len))
        .ok_or_else(|| {
            err(
                first,
                format!(
                    "the header declares {n} points of {} bytes but only {} bytes follow",
                    4 * words,
                    data.len() - first
                ),
            )
        })?;
    let word = |i: usize, k: usize| {
        let at = 4 * (i * words + k);
        [body[at], body[at + 1], body[at + 2], body[at + 3]]
    };
    let mut coords = Vec::with_capacity(3 * n);
    for i in 0..n {
        for axis in 0..3 {
            let value = f64::from(f32::from_be_bytes(word(i, axis)));
            if !value.is_finite() {
                return Err(IoError::non_finite_point(name, i, axis, value));
            }
            coords.push(value);
        }
    }
    let mut attributes = Vec::new();
    let mut skipped = Vec::new();
    if with_attributes {
        let mut offset = 4;
        for d in &definitions {
            let base = crate::attribute_name(&d.name, attributes.len());
            for k in 0..d.size {
                let column = if d.size == 1 {
                    base.clone()
                } else {
                    format!("{base}:{k}")
                };
                if let Some(why) = crate::attribute_conflict(&column, &attributes) {
                    skipped.push(format!("point attribute {:?}: {why}", excerpt(&d.name, 40)));
                    continue;
                }
                let values = if matches!(d.kind, 1 | 4) {
                    AttributeValues::Int(
                        (0..n)
                            .map(|i| i64::from(i32::from_be_bytes(word(i, offset + k))))
                            .collect(),
                    )
                } else {
                    AttributeValues::Float(
                        (0..n)
                            .map(|i| f64::from(f32::from_be_bytes(word(i, offset + k))))
                            .collect(),
                    )
                };
                attributes.push(Attribute {
                    name: column,
                    values,
                });
            }
            offset += d.size;
        }
    }
    Ok(Positions {
        coords,
        stride: 3,
        attributes,
        skipped,
        ..Default::default()
    })
}

/// Checks that every integer column fits BGEO's 32-bit `int` and every finite real its 32-bit
/// float (NaN and infinities are written as they are).
pub(crate) fn check(columns: &[(&str, Column<'_>)]) -> Result<(), (String, String)> {
    for (name, column) in columns {
        if let Column::Float(v) = column {
            if let Some((i, x)) = v
                .iter()
                .enumerate()
                .find(|(_, x)| x.is_finite() && x.abs() > f64::from(f32::MAX))
            {
                return Err((
                    (*name).to_owned(),
                    format!("value {x} of particle {i} does not fit BGEO's 32-bit float"),
                ));
            }
        }
        if let Column::Int(v) = column {
            if let Some((i, x)) = v
                .iter()
                .enumerate()
                .find(|(_, x)| i32::try_from(**x).is_err())
            {
                return Err((
                    (*name).to_owned(),
                    format!("value {x} of particle {i} does not fit BGEO's 32-bit int"),
                ));
            }
        }
    }
    Ok(())
}

/// Writes a Houdini length-prefixed string.
fn string(out: &mut dyn Write, s: &str) -> std::io::Result<()> {
    let bytes = &s.as_bytes()[..s.len().min(usize::from(u16::MAX))];
    out.write_all(&(bytes.len() as u16).to_be_bytes())?;
    out.write_all(bytes)
}

pub(crate) fn write(
    out: &mut dyn Write,
    set: &AnyParticleSet,
    columns: &[(&str, Column<'_>)],
) -> std::io::Result<()> {
    let groups = crate::vtk_xml::group_columns(columns);
    let n = set.len();
    out.write_all(MAGIC)?;
    out.write_all(b"V")?;
    let header = [5, n as i32, 0, 0, 0, groups.len() as i32, 0, 0, 0];
    for h in header {
        out.write_all(&i32::to_be_bytes(h))?;
    }
    for (name, members) in &groups {
        string(out, name)?;
        let kind: i32 = match (members[0], members.len()) {
            (Column::Float(_), 1) => 0,
            (Column::Float(_), _) => 5,
            _ => 1,
        };
        out.write_all(&(members.len() as u16).to_be_bytes())?;
        out.write_all(&kind.to_be_bytes())?;
        for _ in 0..members.len() {
            out.write_all(&0i32.to_be_bytes())?;
        }
    }
    for i in 0..n {
        let c = set.coords(i);
        for axis in 0..3 {
            let v = c.get(axis).copied().unwrap_or(0.0) as f32;
            out.write_all(&v.to_be_bytes())?;
        }
        out.write_all(&1.0f32.to_be_bytes())?;
        for (_, members) in &groups {
            for column in members {
                let word = match column {
                    Column::Float(v) => (v[i] as f32).to_be_bytes(),
                    // Checked to fit by `check`.
                    Column::Int(v) => (v[i] as i32).to_be_bytes(),
                    Column::Byte(v) => i32::from(v[i]).to_be_bytes(),
                };
                out.write_all(&word)?;
            }
        }
    }
    // The empty "extra" section that closes a classic geometry file.
    out.write_all(&[0x00, 0xff])
}
