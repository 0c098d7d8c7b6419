//! Legacy VTK (`.vtk`): the `POINTS` of a POLYDATA, UNSTRUCTURED_GRID or STRUCTURED_GRID
//! dataset, `float` or `double`, ascii or binary (big endian, as the legacy format prescribes),
//! and on request the `POINT_DATA` arrays after them (`read_point_data`).
//!
//! Hand-written rather than through `vtkio` 0.6: only `POINTS` is needed, and vtkio's legacy
//! parser (nom 3 `many_m_n!`) reserves a vector of the declared size before reading, so a
//! header declaring billions of points aborts the process; it also reports no line or point.
//! This reader checks a binary block's declared size against the bytes present before reading
//! it, and caps preallocation for ascii data.

use crate::error::{excerpt, IoError, Location};
use crate::out::{self, Real};
use crate::{Column, Positions, MAX_PREALLOCATE};
use boundary_core::AnyParticleSet;
use std::io::{BufRead, Write};

/// The title token by which this crate marks a 2D set padded with z = 0.
const DIM2_MARKER: &str = "dim=2";

/// A cursor over the whole file: text lines for the header, tokens or raw bytes for data.
struct Cursor<'a> {
    bytes: &'a [u8],
    pos: usize,
    /// 1-based line of `pos` (counted as the cursor moves, never over binary data twice).
    line: usize,
}

impl<'a> Cursor<'a> {
    fn advance(&mut self, n: usize) {
        let end = (self.pos + n).min(self.bytes.len());
        self.line += self.bytes[self.pos..end]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        self.pos = end;
    }

    /// The next line that is not blank (whitespace skipped first), without its terminator, and
    /// its line number; the cursor moves past its `\n`.
    fn next_text_line(&mut self) -> Option<(usize, &'a [u8])> {
        let rest = &self.bytes[self.pos..];
        let skip = rest
            .iter()
            .position(|b| !b.is_ascii_whitespace())
            .unwrap_or(rest.len());
        self.advance(skip);
        if self.pos == self.bytes.len() {
            return None;
        }
        let line = self.line;
        let rest = &self.bytes[self.pos..];
        let len = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
        let text = &rest[..len];
        self.advance((len + 1).min(rest.len()));
        Some((line, text.strip_suffix(b"\r").unwrap_or(text)))
    }

    /// The raw line at the cursor (may be empty), for the title.
    fn raw_line(&mut self) -> Option<&'a [u8]> {
        if self.pos == self.bytes.len() {
            return None;
        }
        let rest = &self.bytes[self.pos..];
        let len = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
        self.advance((len + 1).min(rest.len()));
        Some(&rest[..len])
    }

    /// The next whitespace-delimited token and its line.
    fn token(&mut self) -> Option<(usize, &'a [u8])> {
        let rest = &self.bytes[self.pos..];
        let skip = rest
            .iter()
            .position(|b| !b.is_ascii_whitespace())
            .unwrap_or(rest.len());
        self.advance(skip);
        let rest = &self.bytes[self.pos..];
        let len = rest
            .iter()
            .position(|b| b.is_ascii_whitespace())
            .unwrap_or(rest.len());
        if len == 0 {
            return None;
        }
        let line = self.line;
        self.pos += len;
        Some((line, &rest[..len]))
    }

    /// `n` raw bytes, or `None` if fewer remain (the cursor does not move then).
    fn take(&mut self, n: usize) -> Option<&'a [u8]> {
        let end = self.pos.checked_add(n)?;
        let data = self.bytes.get(self.pos..end)?;
        self.pos = end;
        Some(data)
    }

    fn remaining(&self) -> usize {
        self.bytes.len() - self.pos
    }
}

/// Text of a header token for messages.
fn show(bytes: &[u8]) -> String {
    excerpt(&String::from_utf8_lossy(bytes), 40)
}

/// Size in bytes of a legacy VTK data type, `None` if unknown.
fn type_size(name: &[u8]) -> Option<usize> {
    let name = name.to_ascii_lowercase();
    Some(match name.as_slice() {
        b"bit" => 0,
        b"char" | b"unsigned_char" => 1,
        b"short" | b"unsigned_short" => 2,
        b"int" | b"unsigned_int" | b"float" | b"vtkidtype" => 4,
        b"long" | b"unsigned_long" | b"double" | b"vtktypeint64" | b"vtktypeuint64" => 8,
        _ => return None,
    })
}

pub(crate) fn read<R: BufRead>(
    mut reader: R,
    name: &str,
    with_attributes: bool,
) -> Result<Positions, IoError> {
    let mut bytes = Vec::new();
    reader
        .read_to_end(&mut bytes)
        .map_err(|e| IoError::read(name, e))?;
    let mut c = Cursor {
        bytes: &bytes,
        pos: 0,
        line: 1,
    };
    let err = |at: Location, message: String| IoError::parse(name, at, message);
    let version = c.raw_line().unwrap_or_default();
    if !version
        .get(..5)
        .is_some_and(|v| v.eq_ignore_ascii_case(b"# vtk"))
    {
        return Err(err(
            Location::Line(1),
            "not a legacy VTK file: the first line must start with \"# vtk DataFile\"".into(),
        ));
    }
    let title = c.raw_line().unwrap_or_default();
    let padded_2d = String::from_utf8_lossy(title)
        .split_whitespace()
        .any(|t| t == DIM2_MARKER);
    let (line, encoding) = c.next_text_line().ok_or_else(|| {
        err(
            Location::File,
            "truncated VTK header: no ASCII or BINARY line".into(),
        )
    })?;
    let binary = match encoding.trim_ascii().to_ascii_uppercase().as_slice() {
        b"ASCII" => false,
        b"BINARY" => true,
        other => {
            return Err(err(
                Location::Line(line),
                format!("expected ASCII or BINARY, found {:?}", show(other)),
            ))
        }
    };
    let (line, dataset) = c.next_text_line().ok_or_else(|| {
        err(
            Location::File,
            "truncated VTK header: no DATASET line".into(),
        )
    })?;
    let mut words = dataset
        .split(|b| b.is_ascii_whitespace())
        .filter(|w| !w.is_empty());
    let keyword = words.next().unwrap_or_default();
    let kind = words.next().unwrap_or_default().to_ascii_uppercase();
    if !keyword.eq_ignore_ascii_case(b"DATASET") {
        return Err(err(
            Location::Line(line),
            format!("expected DATASET, found {:?}", show(keyword)),
        ));
    }
    if !matches!(
        kind.as_slice(),
        b"POLYDATA" | b"UNSTRUCTURED_GRID" | b"STRUCTURED_GRID"
    ) {
        return Err(err(
            Location::Line(line),
            format!(
                "unsupported dataset {:?} (POLYDATA, UNSTRUCTURED_GRID or STRUCTURED_GRID hold POINTS)",
                show(&kind)
            ),
        ));
    }
    // Sections before POINTS: FIELD data (skipped), DIMENSIONS of a structured grid.
    loop {
        let (line, text) = c
            .next_text_line()
            .ok_or_else(|| err(Location::File, "no POINTS section".into()))?;
        let mut words = text
            .split(|b| b.is_ascii_whitespace())
            .filter(|w| !w.is_empty());
        let keyword = words.next().unwrap_or_default().to_ascii_uppercase();
        match keyword.as_slice() {
            b"POINTS" => {
                let count = words.next().unwrap_or_default();
                let count: usize = std::str::from_utf8(count)
                    .ok()
                    .and_then(|s| s.parse().ok())
                    .ok_or_else(|| {
                        err(
                            Location::Line(line),
                            format!("invalid POINTS count {:?}", show(count)),
                        )
                    })?;
                let ty = words.next().unwrap_or_default().to_ascii_lowercase();
                let size = match ty.as_slice() {
                    b"float" => 4,
                    b"double" => 8,
                    other => {
                        return Err(err(
                            Location::Line(line),
                            format!(
                                "unsupported POINTS type {:?}: float or double expected",
                                show(other)
                            ),
                        ))
                    }
                };
                let coords = if binary {
                    read_binary_points(&mut c, name, line, count, size)?
                } else {
                    read_ascii_points(&mut c, name, line, count)?
                };
                let n = coords.len() / 3;
                let mut positions = Positions {
                    coords,
                    stride: 3,
                    padded_2d,
                    ..Default::default()
                };
                if with_attributes {
                    // The file's points are read; damage after them costs the attributes only.
                    if let Err(e) = read_point_data(&mut c, binary, n, &mut positions.attributes) {
                        positions.skipped.push(format!("POINT_DATA not read: {e}"));
                    }
                }
                return Ok(positions);
            }
            b"FIELD" => skip_field(&mut c, name, line, words.nth(1), binary)?,
            b"DIMENSIONS" => {}
            other => {
                return Err(err(
                    Location::Line(line),
                    format!("expected POINTS, found {:?}", show(other)),
                ))
            }
        }
    }
}

fn read_binary_points(
    c: &mut Cursor<'_>,
    name: &str,
    line: usize,
    count: usize,
    size: usize,
) -> Result<Vec<f64>, IoError> {
    let need = count.checked_mul(3 * size);
    let data = need.and_then(|n| c.take(n)).ok_or_else(|| {
        IoError::parse(
            name,
            Location::Line(line),
            format!(
                "the POINTS line declares {count} points ({} bytes) but only {} bytes follow",
                need.map_or_else(|| "too many".to_owned(), |n| n.to_string()),
                c.remaining()
            ),
        )
    })?;
    let mut coords = Vec::with_capacity(3 * count);
    for (k, chunk) in data.chunks_exact(size).enumerate() {
        let value = match *chunk {
            [a, b, c, d] => f64::from(f32::from_be_bytes([a, b, c, d])),
            [a, b, c, d, e, f, g, h] => f64::from_be_bytes([a, b, c, d, e, f, g, h]),
            _ => unreachable!("chunks are 4 or 8 bytes"),
        };
        if !value.is_finite() {
            return Err(IoError::non_finite_point(name, k / 3, k % 3, value));
        }
        coords.push(value);
    }
    Ok(coords)
}

fn read_ascii_points(
    c: &mut Cursor<'_>,
    name: &str,
    line: usize,
    count: usize,
) -> Result<Vec<f64>, IoError> {
    let values = count.saturating_mul(3);
    // Each value takes at least two bytes ("0 "): no more can be there.
    let mut coords = Vec::with_capacity(values.min(c.remaining() / 2).min(MAX_PREALLOCATE));
    for k in 0..values {
        let (at_line, token) = c.token().ok_or_else(|| {
            IoError::parse(
                name,
                Location::Line(line),
                format!(
                    "the POINTS line declares {count} points but the data ends after {} values",
                    k
                ),
            )
        })?;
        let at = Location::Line(at_line);
        let value: f64 = std::str::from_utf8(token)
            .ok()
            .and_then(|s| s.parse().ok())
            .ok_or_else(|| {
                IoError::parse(
                    name,
                    at,
                    format!(
                        "invalid number {:?} in POINTS (point {})",
                        show(token),
                        k / 3
                    ),
                )
            })?;
        if !value.is_finite() {
            return Err(IoError::NonFinite {
                file: name.to_owned(),
                at,
                index: k / 3,
                axis: k % 3,
                value,
            });
        }
        coords.push(value);
    }
    Ok(coords)
}

/// Values of a data section: `count` numbers of `ty`, big-endian in binary files.
fn read_values(
    c: &mut Cursor<'_>,
    binary: bool,
    ty: &[u8],
    count: usize,
) -> Result<crate::AttributeValues, String> {
    use crate::AttributeValues;
    let ty = ty.to_ascii_lowercase();
    let size = type_size(&ty).ok_or_else(|| format!("unknown data type {:?}", show(&ty)))?;
    let float = matches!(ty.as_slice(), b"float" | b"double");
    if binary {
        if size == 0 {
            return Err("bit arrays are not supported".into());
        }
        let bytes = count
            .checked_mul(size)
            .and_then(|b| c.take(b))
            .ok_or_else(|| format!("{count} values declared, fewer bytes present"))?;
        let word = |chunk: &[u8]| {
            let mut w = [0u8; 8];
            w[8 - chunk.len()..].copy_from_slice(chunk);
            u64::from_be_bytes(w)
        };
        let signed = !ty.starts_with(b"unsigned") && ty.as_slice() != b"vtktypeuint64";
        Ok(if float {
            AttributeValues::Float(
                bytes
                    .chunks_exact(size)
                    .map(|ch| match *ch {
                        [a, b, c, d] => f64::from(f32::from_be_bytes([a, b, c, d])),
                        _ => f64::from_bits(word(ch)),
                    })
                    .collect(),
            )
        } else {
            let bits = 8 * size as u32;
            AttributeValues::Int(
                bytes
                    .chunks_exact(size)
                    .map(|ch| sign_extend(word(ch), bits, signed))
                    .collect(),
            )
        })
    } else {
        let cap = count.min(c.remaining() / 2).min(MAX_PREALLOCATE);
        let mut ints: Option<Vec<i64>> = (!float).then(|| Vec::with_capacity(cap));
        let mut reals = Vec::with_capacity(cap);
        for k in 0..count {
            let (line, token) = c
                .token()
                .ok_or_else(|| format!("{count} values declared, the data ends after {k}"))?;
            let text = std::str::from_utf8(token).unwrap_or("");
            if let Some(v) = ints.as_mut() {
                match text.parse::<i64>() {
                    Ok(x) => v.push(x),
                    Err(_) => ints = None,
                }
            }
            reals.push(
                text.parse::<f64>()
                    .map_err(|_| format!("invalid number {:?} on line {line}", show(token)))?,
            );
        }
        Ok(match ints {
            Some(v) => AttributeValues::Int(v),
            None => AttributeValues::Float(reals),
        })
    }
}

/// Walks the sections after `POINTS` (cells, `CELL_DATA`, `METADATA` are skipped) and keeps
/// the arrays of `POINT_DATA`: `SCALARS`, `VECTORS`, `NORMALS`, `TENSORS`,
/// `TEXTURE_COORDINATES`, `COLOR_SCALARS` and `FIELD` arrays; a `k`-component array becomes
/// `name:0` … `name:k-1`. Stops quietly at an unknown keyword.
fn read_point_data(
    c: &mut Cursor<'_>,
    binary: bool,
    points: usize,
    out: &mut Vec<crate::Attribute>,
) -> Result<(), String> {
    let number = |w: Option<&&[u8]>| -> Result<usize, String> {
        w.and_then(|w| std::str::from_utf8(w).ok()?.parse().ok())
            .ok_or_else(|| "invalid count".to_owned())
    };
    // Elements of the current data block, and whether it is POINT_DATA.
    let mut tuples = 0usize;
    let mut is_point = false;
    while let Some((line, text)) = c.next_text_line() {
        let words: Vec<&[u8]> = text
            .split(|b| b.is_ascii_whitespace())
            .filter(|w| !w.is_empty())
            .collect();
        let keyword = words
            .first()
            .map(|w| w.to_ascii_uppercase())
            .unwrap_or_default();
        let at = |m: String| format!("{m} (line {line})");
        // (name, type, components) of an array to read in the current block.
        let array: Option<(&[u8], Vec<u8>, usize)> = match keyword.as_slice() {
            b"VERTICES" | b"LINES" | b"POLYGONS" | b"TRIANGLE_STRIPS" | b"CELLS" => {
                let n = number(words.get(1)).map_err(at)?;
                let size = number(words.get(2)).map_err(at)?;
                // VTK 5.1 legacy: OFFSETS and CONNECTIVITY subsections with their own type.
                let save = (c.pos, c.line);
                match c.next_text_line() {
                    Some((_, sub)) if sub.to_ascii_uppercase().starts_with(b"OFFSETS") => {
                        let ty = sub.split(|b| b.is_ascii_whitespace()).nth(1).unwrap_or(b"");
                        read_values(c, binary, ty, n).map_err(at)?;
                        let (_, sub) = c.next_text_line().ok_or("truncated cells")?;
                        let ty = sub.split(|b| b.is_ascii_whitespace()).nth(1).unwrap_or(b"");
                        read_values(c, binary, ty, size).map_err(at)?;
                    }
                    _ => {
                        (c.pos, c.line) = save;
                        read_values(c, binary, b"int", size).map_err(at)?;
                    }
                }
                None
            }
            b"CELL_TYPES" => {
                read_values(c, binary, b"int", number(words.get(1)).map_err(at)?).map_err(at)?;
                None
            }
            b"POINT_DATA" | b"CELL_DATA" => {
                tuples = number(words.get(1)).map_err(at)?;
                is_point = keyword.as_slice() == b"POINT_DATA";
                if is_point && tuples != points {
                    return Err(at(format!("POINT_DATA {tuples} for {points} points")));
                }
                None
            }
            b"METADATA" => {
                // Ends at the first blank line.
                while let Some(rest) = c.raw_line() {
                    if rest.trim_ascii().is_empty() {
                        break;
                    }
                }
                None
            }
            b"SCALARS" => {
                let comps = match words.get(3) {
                    Some(_) => number(words.get(3)).map_err(at)?,
                    None => 1,
                };
                // An optional LOOKUP_TABLE line.
                let save = (c.pos, c.line);
                match c.next_text_line() {
                    Some((_, l)) if l.to_ascii_uppercase().starts_with(b"LOOKUP_TABLE") => {}
                    _ => (c.pos, c.line) = save,
                }
                Some((
                    words.get(1).copied().unwrap_or(b""),
                    words.get(2).copied().unwrap_or(b"").to_vec(),
                    comps,
                ))
            }
            b"VECTORS" | b"NORMALS" => Some((
                words.get(1).copied().unwrap_or(b""),
                words.get(2).copied().unwrap_or(b"").to_vec(),
                3,
            )),
            b"TENSORS" => Some((
                words.get(1).copied().unwrap_or(b""),
                words.get(2).copied().unwrap_or(b"").to_vec(),
                9,
            )),
            b"TEXTURE_COORDINATES" => Some((
                words.get(1).copied().unwrap_or(b""),
                words.get(3).copied().unwrap_or(b"").to_vec(),
                number(words.get(2)).map_err(at)?,
            )),
            b"COLOR_SCALARS" => Some((
                words.get(1).copied().unwrap_or(b""),
                if binary {
                    b"unsigned_char".to_vec()
                } else {
                    b"float".to_vec()
                },
                number(words.get(2)).map_err(at)?,
            )),
            b"LOOKUP_TABLE" => {
                let size = number(words.get(2)).map_err(at)?;
                let ty: &[u8] = if binary { b"unsigned_char" } else { b"float" };
                read_values(c, binary, ty, size.saturating_mul(4)).map_err(at)?;
                None
            }
            b"FIELD" => {
                let arrays = number(words.get(2)).map_err(at)?;
                for _ in 0..arrays {
                    let (line, header) = c.next_text_line().ok_or("truncated FIELD")?;
                    let w: Vec<&[u8]> = header
                        .split(|b| b.is_ascii_whitespace())
                        .filter(|w| !w.is_empty())
                        .collect();
                    let comps = number(w.get(1)).map_err(|m| format!("{m} (line {line})"))?;
                    let count = number(w.get(2)).map_err(|m| format!("{m} (line {line})"))?;
                    let ty = w.get(3).copied().unwrap_or(b"");
                    let values = read_values(c, binary, ty, comps.saturating_mul(count))
                        .map_err(|m| format!("{m} (line {line})"))?;
                    if is_point && count == points {
                        push_components(out, w.first().copied().unwrap_or(b""), comps, values);
                    }
                }
                None
            }
            _ => return Ok(()),
        };
        if let Some((array_name, ty, comps)) = array {
            let values = read_values(c, binary, &ty, tuples.saturating_mul(comps)).map_err(at)?;
            if is_point {
                push_components(out, array_name, comps, values);
            }
        }
    }
    Ok(())
}

/// Adds an array of `comps` interleaved components as attributes (`name` or `name:k`);
/// names that would clash are dropped.
fn push_components(
    out: &mut Vec<crate::Attribute>,
    name: &[u8],
    comps: usize,
    values: crate::AttributeValues,
) {
    use crate::AttributeValues;
    let base = crate::attribute_name(&String::from_utf8_lossy(name), out.len());
    for k in 0..comps {
        let column = if comps == 1 {
            base.clone()
        } else {
            format!("{base}:{k}")
        };
        if crate::attribute_conflict(&column, out).is_some() {
            continue;
        }
        let values = match &values {
            AttributeValues::Int(v) => {
                AttributeValues::Int(v.iter().skip(k).step_by(comps).copied().collect())
            }
            AttributeValues::Float(v) => {
                AttributeValues::Float(v.iter().skip(k).step_by(comps).copied().collect())
            }
        };
        out.push(crate::Attribute {
            name: column,
            values,
        });
    }
}

/// Skips a `FIELD name n` block: `n` arrays, each `name components tuples type` then data.
fn skip_field(
    c: &mut Cursor<'_>,
    name: &str,
    line: usize,
    arrays: Option<&[u8]>,
    binary: bool,
) -> Result<(), IoError> {
    let bad = |line: usize, message: String| IoError::parse(name, Location::Line(line), message);
    let arrays: usize = arrays
        .and_then(|a| std::str::from_utf8(a).ok()?.parse().ok())
        .ok_or_else(|| bad(line, "invalid FIELD line: expected FIELD name count".into()))?;
    for _ in 0..arrays {
        let (line, header) = c
            .next_text_line()
            .ok_or_else(|| bad(line, "truncated FIELD data".into()))?;
        let words: Vec<&[u8]> = header
            .split(|b| b.is_ascii_whitespace())
            .filter(|w| !w.is_empty())
            .collect();
        let number =
            |k: usize| -> Option<usize> { std::str::from_utf8(words.get(k)?).ok()?.parse().ok() };
        let (Some(components), Some(tuples), Some(size)) = (
            number(1),
            number(2),
            words.get(3).and_then(|t| type_size(t)),
        ) else {
            return Err(bad(
                line,
                "invalid FIELD array line: expected name components tuples type".into(),
            ));
        };
        let values = components
            .checked_mul(tuples)
            .ok_or_else(|| bad(line, "the FIELD array is too large".into()))?;
        if binary {
            let bytes = if size == 0 {
                values.div_ceil(8)
            } else {
                values
                    .checked_mul(size)
                    .ok_or_else(|| bad(line, "the FIELD array is too large".into()))?
            };
            c.take(bytes).ok_or_else(|| {
                bad(
                    line,
                    "a FIELD array declares more data than the file holds".into(),
                )
            })?;
        } else {
            for _ in 0..values {
                c.token().ok_or_else(|| {
                    bad(
                        line,
                        "a FIELD array declares more data than the file holds".into(),
                    )
                })?;
            }
        }
    }
    Ok(())
}

pub(crate) fn write(
    out: &mut dyn Write,
    set: &AnyParticleSet,
    columns: &[(&str, Column<'_>)],
) -> std::io::Result<()> {
    let n = set.len();
    writeln!(out, "# vtk DataFile Version 3.0")?;
    writeln!(out, "particles written by boundary-io dim={}", set.dim())?;
    writeln!(out, "ASCII\nDATASET POLYDATA\nPOINTS {n} double")?;
    for i in 0..n {
        let c = set.coords(i);
        // VTK points have three components: a 2D set gets z = 0 here, and `dim=2` in the title.
        let z = c.get(2).copied().unwrap_or(0.0);
        writeln!(out, "{} {} {}", Real(c[0]), Real(c[1]), Real(z))?;
    }
    writeln!(out, "VERTICES {n} {}", 2 * n)?;
    for i in 0..n {
        writeln!(out, "1 {i}")?;
    }
    if !columns.is_empty() {
        writeln!(out, "POINT_DATA {n}")?;
        for (name, column) in columns {
            let ty = out::binary_type(column);
            let vtk_type = if ty == "uchar" { "unsigned_char" } else { ty };
            writeln!(out, "SCALARS {name} {vtk_type} 1\nLOOKUP_TABLE default")?;
            for i in 0..n {
                out::typed_value(out, column, ty, i)?;
                writeln!(out)?;
            }
        }
    }
    Ok(())
}

/// An integer of `bits` bits read into the low bits of `raw`, as `i64`: sign-extended when
/// `signed` (two's complement), else taken as is (unsigned 64-bit values beyond `i64::MAX`
/// wrap; callers that care check first).
pub(crate) fn sign_extend(raw: u64, bits: u32, signed: bool) -> i64 {
    if signed && bits < 64 {
        let shift = 64 - bits;
        ((raw << shift) as i64) >> shift
    } else {
        raw as i64
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn field_block_before_points_is_skipped_in_binary() {
        let mut file = b"# vtk DataFile Version 3.0\nt\nBINARY\nDATASET POLYDATA\nFIELD FieldData 2\nTIME 1 1 double\n".to_vec();
        // The binary value starts with bytes that look like whitespace and "POINTS".
        file.extend_from_slice(b"\n POINTS");
        file.extend_from_slice(b"\nCYCLE 1 1 int\n");
        file.extend_from_slice(&7i32.to_be_bytes());
        file.extend_from_slice(b"\nPOINTS 1 double\n");
        for v in [1.5f64, -2.0, 0.25] {
            file.extend_from_slice(&v.to_be_bytes());
        }
        let p = read(file.as_slice(), "f.vtk", false).unwrap();
        assert_eq!(p.coords, vec![1.5, -2.0, 0.25]);
    }

    #[test]
    fn ascii_points_across_lines() {
        let file = "# vtk DataFile Version 2.0\ntitle\nASCII\n\nDATASET UNSTRUCTURED_GRID\nPOINTS 2 float\n1 2\n3 4 5 6\nCELLS 0 0\n";
        let p = read(file.as_bytes(), "a.vtk", false).unwrap();
        assert_eq!(p.coords, vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        assert!(!p.padded_2d);
    }

    #[test]
    fn point_data_is_read_and_damage_after_points_keeps_the_positions() {
        use crate::AttributeValues::{Float, Int};
        let file = "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 2 float\n0 0 0 1 1 1\nVERTICES 2 4\n1 0\n1 1\nPOINT_DATA 2\nSCALARS p double 1\nLOOKUP_TABLE default\n1.5 2\nVECTORS v float\n1 2 3 4 5 6\nSCALARS id int\n7 8\nCELL_DATA 2\nSCALARS c int 1\nLOOKUP_TABLE default\n0 0\n";
        let p = read(file.as_bytes(), "a.vtk", true).unwrap();
        let got: Vec<(&str, &crate::AttributeValues)> = p
            .attributes
            .iter()
            .map(|a| (a.name.as_str(), &a.values))
            .collect();
        assert_eq!(
            got,
            [
                ("p", &Float(vec![1.5, 2.0])),
                ("v:0", &Float(vec![1.0, 4.0])),
                ("v:1", &Float(vec![2.0, 5.0])),
                ("v:2", &Float(vec![3.0, 6.0])),
                ("id", &Int(vec![7, 8])),
            ]
        );
        assert!(p.skipped.is_empty(), "{:?}", p.skipped);
        // Cut inside the vectors: the positions survive, the loss is reported.
        let cut = &file[..file.find("4 5 6").unwrap()];
        let p = read(cut.as_bytes(), "a.vtk", true).unwrap();
        assert_eq!(p.coords.len(), 6);
        assert!(
            p.skipped[0].contains("POINT_DATA not read"),
            "{:?}",
            p.skipped
        );
        assert!(p.skipped[0].contains("line 14"), "{:?}", p.skipped);
    }

    #[test]
    fn ascii_error_names_the_line_of_the_token() {
        let file = "# vtk DataFile Version 2.0\ntitle\nASCII\nDATASET POLYDATA\nPOINTS 2 float\n1 2 3\n4 x 6\n";
        let e = read(file.as_bytes(), "a.vtk", false).unwrap_err();
        assert_eq!(e.location(), Some(Location::Line(7)), "{e}");
    }
}
