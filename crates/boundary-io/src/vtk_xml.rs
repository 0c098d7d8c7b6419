//! VTK XML: UnstructuredGrid (`.vtu`) and PolyData (`.vtp`), as written by VTK, ParaView,
//! SPHinXsys, pyevtk and meshio.
//!
//! Read: the `Points` of the first `Piece` and every `PointData` array, in the `ascii`,
//! `binary` (base64) and `appended` (raw or base64) data modes, uncompressed or with
//! `vtkZLibDataCompressor`, little or big endian, `header_type` `UInt32` (the default) or
//! `UInt64`. Cells are not read (particles are points). Hand-written on `quick-xml`: `vtkio`
//! 0.6 panics on ascii VTP and cannot read appended data.
//!
//! Appended raw data is not XML (arbitrary bytes after `_`), so the file is split at
//! `<AppendedData` first: the XML before it is parsed, the bytes after the `_` are addressed by
//! the arrays' `offset`s. Every size declared by a header is checked against the bytes present
//! before memory is reserved for it; a compressed block may not inflate beyond the size its
//! header declares.
//!
//! Written: the points (`Float64`), one vertex cell per particle (VTK_VERTEX cells in a `.vtu`,
//! `Verts` in a `.vtp`, so ParaView renders them without a glyph filter) and the columns as
//! `PointData`, base64 inline binary with a `UInt64` header. Columns named `name:0`, `name:1`, …
//! in a row (ParaView's names for the components of a vector) become one array `name` with
//! that many components, so a velocity read from a VTU file is written back as a vector.

use crate::error::{excerpt, IoError, Location};
use crate::{Attribute, AttributeValues, Column, Positions, MAX_PREALLOCATE};
use base64::engine::general_purpose::STANDARD;
use base64::Engine;
use boundary_core::AnyParticleSet;
use quick_xml::events::{BytesStart, Event};
use std::io::{BufRead, Read, Write};

/// Which XML dataset.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    /// `.vtu`
    UnstructuredGrid,
    /// `.vtp`
    PolyData,
}

impl Kind {
    fn tag(self) -> &'static str {
        match self {
            Kind::UnstructuredGrid => "UnstructuredGrid",
            Kind::PolyData => "PolyData",
        }
    }
}

/// The comment by which this crate marks a 2D set padded with z = 0.
const DIM2_MARKER: &str = "boundary-io dim=2";

/// A scalar type of a `DataArray`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    I64,
    U64,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Scalar> {
        Some(match name {
            "Int8" | "Char" => Scalar::I8,
            "UInt8" | "UChar" => Scalar::U8,
            "Int16" => Scalar::I16,
            "UInt16" => Scalar::U16,
            "Int32" => Scalar::I32,
            "UInt32" => Scalar::U32,
            "Int64" => Scalar::I64,
            "UInt64" => Scalar::U64,
            "Float32" => Scalar::F32,
            "Float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::I64 | Scalar::U64 | Scalar::F64 => 8,
        }
    }

    fn is_float(self) -> bool {
        matches!(self, Scalar::F32 | Scalar::F64)
    }
}

/// One `DataArray` as found in the XML, before its data is decoded.
#[derive(Debug)]
struct ArrayHeader {
    /// `Points`, or the array's `Name`.
    name: String,
    type_name: String,
    components: usize,
    format: String,
    offset: Option<usize>,
    /// Inline text (ascii numbers or base64), children such as `InformationKey` excluded.
    text: String,
    /// 1-based line of the `<DataArray` tag.
    line: usize,
}

/// Decoded values of an array.
enum Values {
    Int(Vec<i64>),
    Float(Vec<f64>),
}

/// What the XML says about the file.
struct Document {
    big_endian: bool,
    header64: bool,
    zlib: bool,
    points: Option<usize>,
    /// 1-based line of `<Piece`.
    piece_line: usize,
    point_arrays: Vec<ArrayHeader>,
    positions: Option<ArrayHeader>,
    /// The `Name` of the `<Points>` array, when it has one.
    points_name: Option<String>,
    appended_base64: bool,
    padded_2d: bool,
}

pub(crate) fn read<R: BufRead>(
    mut reader: R,
    name: &str,
    expected: Kind,
    with_attributes: bool,
) -> Result<Positions, IoError> {
    let mut bytes = Vec::new();
    reader
        .read_to_end(&mut bytes)
        .map_err(|e| IoError::read(name, e))?;
    let appended_at = find(&bytes, b"<AppendedData");
    let xml_bytes = &bytes[..appended_at.unwrap_or(bytes.len())];
    let xml = std::str::from_utf8(xml_bytes).map_err(|e| {
        IoError::parse(
            name,
            Location::Line(line_of(xml_bytes, e.valid_up_to())),
            "invalid UTF-8 in the XML part of the file",
        )
    })?;
    let mut doc = parse_xml(xml, name, expected)?;
    // The appended block: after `<AppendedData encoding="...">`, whitespace, then `_`.
    let appended: &[u8] = match appended_at {
        None => &[],
        Some(start) => {
            let tag_end = find(&bytes[start..], b">")
                .map(|k| start + k)
                .ok_or_else(|| {
                    IoError::parse(
                        name,
                        Location::Line(line_of(&bytes, start)),
                        "unclosed <AppendedData> tag",
                    )
                })?;
            let tag = String::from_utf8_lossy(&bytes[start..tag_end]);
            doc.appended_base64 = tag.contains("\"base64\"") || tag.contains("'base64'");
            let rest = &bytes[tag_end + 1..];
            let skip = rest
                .iter()
                .position(|b| !b.is_ascii_whitespace())
                .unwrap_or(rest.len());
            if rest.get(skip) != Some(&b'_') {
                return Err(IoError::parse(
                    name,
                    Location::Line(line_of(&bytes, tag_end)),
                    "<AppendedData> must start with '_'",
                ));
            }
            &rest[skip + 1..]
        }
    };
    let n = doc.points.unwrap_or(0);
    let positions = doc.positions.take().ok_or_else(|| {
        IoError::parse(
            name,
            Location::Line(doc.piece_line),
            "no <Points> DataArray in the first <Piece>",
        )
    })?;
    if positions.components != 3 {
        return Err(IoError::parse(
            name,
            Location::Line(positions.line),
            format!(
                "<Points> must have 3 components, found {}",
                positions.components
            ),
        ));
    }
    let coords = match decode(&doc, &positions, n, appended, name)? {
        Values::Float(v) => v,
        Values::Int(v) => v.into_iter().map(|x| x as f64).collect(),
    };
    if let Some(k) = coords.iter().position(|v| !v.is_finite()) {
        return Err(IoError::non_finite_point(name, k / 3, k % 3, coords[k]));
    }
    let mut attributes: Vec<Attribute> = Vec::new();
    let mut skipped = Vec::new();
    let arrays = std::mem::take(&mut doc.point_arrays);
    for array in arrays.into_iter().filter(|_| with_attributes) {
        if Scalar::parse(&array.type_name).is_none() {
            skipped.push(format!(
                "point array {:?}: type {} is not numeric",
                array.name, array.type_name
            ));
            continue;
        }
        let values = decode(&doc, &array, n, appended, name)?;
        let base = crate::attribute_name(&array.name, attributes.len());
        let names: Vec<String> = if array.components == 1 {
            vec![base]
        } else {
            (0..array.components)
                .map(|k| format!("{base}:{k}"))
                .collect()
        };
        if let Some(why) = names
            .iter()
            .find_map(|c| crate::attribute_conflict(c, &attributes))
        {
            skipped.push(format!("point array {:?}: {why}", array.name));
            continue;
        }
        let comps = array.components;
        for (k, column) in names.into_iter().enumerate() {
            let values = match &values {
                Values::Int(v) => {
                    AttributeValues::Int(v.iter().skip(k).step_by(comps).copied().collect())
                }
                Values::Float(v) => {
                    AttributeValues::Float(v.iter().skip(k).step_by(comps).copied().collect())
                }
            };
            attributes.push(Attribute {
                name: column,
                values,
            });
        }
    }
    Ok(Positions {
        coords,
        stride: 3,
        padded_2d: doc.padded_2d,
        attributes,
        skipped,
        names: vec![doc
            .points_name
            .map_or_else(|| "Points".to_owned(), |n| excerpt(n.trim(), 40))],
        ..Default::default()
    })
}

fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}

/// 1-based line of byte `pos`.
fn line_of(bytes: &[u8], pos: usize) -> usize {
    1 + bytes[..pos.min(bytes.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
}

fn attr(e: &BytesStart<'_>, key: &str) -> Option<String> {
    e.attributes()
        .flatten()
        .find(|a| a.key.as_ref() == key)
        // Control characters would break one-line error messages.
        .map(|a| a.value.trim().replace(char::is_control, " "))
}

/// State of the walk over the XML.
struct Walk<'n> {
    name: &'n str,
    expected: Kind,
    doc: Document,
    /// Local names of the open elements.
    stack: Vec<String>,
    /// The `DataArray` being read.
    current: Option<ArrayHeader>,
    pieces: usize,
    seen_root: bool,
}

impl Walk<'_> {
    fn err(&self, line: usize, message: String) -> IoError {
        IoError::parse(self.name, Location::Line(line), message)
    }

    /// A start tag (`empty`: a self-closing one, which gets no end event).
    fn open(&mut self, e: &BytesStart<'_>, empty: bool, line: usize) -> Result<(), IoError> {
        let tag = e.local_name().as_ref().to_owned();
        if !self.seen_root {
            self.root(e, &tag, line)?;
        } else if tag == "Piece" && self.stack.len() == 2 {
            self.pieces += 1;
            if self.pieces > 1 {
                return Err(self.err(line, "files with several <Piece>s are not supported".into()));
            }
            self.doc.piece_line = line;
            let count = attr(e, "NumberOfPoints").unwrap_or_default();
            self.doc.points = Some(count.parse().map_err(|_| {
                self.err(
                    line,
                    format!("invalid NumberOfPoints {:?}", excerpt(&count, 40)),
                )
            })?);
        } else if tag == "DataArray"
            && self.stack.len() == 4
            && self.stack[2] == "Piece"
            && (self.stack[3] == "PointData" || self.stack[3] == "Points")
        {
            let components = match attr(e, "NumberOfComponents") {
                None => 1,
                Some(c) => c.parse().ok().filter(|&c| c >= 1).ok_or_else(|| {
                    self.err(
                        line,
                        format!("invalid NumberOfComponents {:?}", excerpt(&c, 40)),
                    )
                })?,
            };
            let offset = match attr(e, "offset") {
                None => None,
                Some(o) => Some(o.parse().map_err(|_| {
                    self.err(line, format!("invalid offset {:?}", excerpt(&o, 40)))
                })?),
            };
            if self.stack[3] == "Points" {
                self.doc.points_name = attr(e, "Name").filter(|n| !n.trim().is_empty());
            }
            self.current = Some(ArrayHeader {
                name: if self.stack[3] == "Points" {
                    "Points".to_owned()
                } else {
                    attr(e, "Name").unwrap_or_default()
                },
                type_name: attr(e, "type").unwrap_or_default(),
                components,
                format: attr(e, "format").unwrap_or_else(|| "ascii".to_owned()),
                offset,
                text: String::new(),
                line,
            });
        }
        if empty {
            if self.stack.len() == 4 {
                self.finish()?;
            }
        } else {
            self.stack.push(tag);
        }
        Ok(())
    }

    /// The `VTKFile` element.
    fn root(&mut self, e: &BytesStart<'_>, tag: &str, line: usize) -> Result<(), IoError> {
        if tag != "VTKFile" {
            return Err(self.err(
                line,
                format!(
                    "not a VTK XML file: the root element is <{}>, expected <VTKFile>",
                    excerpt(tag, 40)
                ),
            ));
        }
        self.seen_root = true;
        let ty = attr(e, "type").unwrap_or_default();
        if ty != self.expected.tag() {
            return Err(self.err(
                line,
                format!(
                    "VTKFile type {:?} where {:?} was expected (.vtu holds UnstructuredGrid, \
                     .vtp PolyData)",
                    excerpt(&ty, 40),
                    self.expected.tag()
                ),
            ));
        }
        self.doc.big_endian = match attr(e, "byte_order").as_deref() {
            None | Some("LittleEndian") => false,
            Some("BigEndian") => true,
            Some(other) => {
                return Err(self.err(line, format!("unknown byte_order {:?}", excerpt(other, 40))))
            }
        };
        self.doc.header64 = match attr(e, "header_type").as_deref() {
            None | Some("UInt32") => false,
            Some("UInt64") => true,
            Some(other) => {
                return Err(self.err(
                    line,
                    format!(
                        "unknown header_type {:?} (UInt32 or UInt64)",
                        excerpt(other, 40)
                    ),
                ))
            }
        };
        self.doc.zlib = match attr(e, "compressor").as_deref() {
            None | Some("") => false,
            Some("vtkZLibDataCompressor") => true,
            Some(other) => {
                return Err(self.err(
                    line,
                    format!(
                        "unsupported compressor {:?} (only vtkZLibDataCompressor)",
                        excerpt(other, 40)
                    ),
                ))
            }
        };
        Ok(())
    }

    /// Files the array being read under `Points` or `PointData`.
    fn finish(&mut self) -> Result<(), IoError> {
        let Some(array) = self.current.take() else {
            return Ok(());
        };
        if self.stack.get(3).map(String::as_str) == Some("Points") {
            if self.doc.positions.is_some() {
                return Err(self.err(array.line, "several DataArrays in <Points>".into()));
            }
            self.doc.positions = Some(array);
        } else {
            self.doc.point_arrays.push(array);
        }
        Ok(())
    }
}

/// Walks the XML: `VTKFile` → dataset → first `Piece` → `PointData` / `Points` arrays.
fn parse_xml(xml: &str, name: &str, expected: Kind) -> Result<Document, IoError> {
    let mut reader = quick_xml::Reader::from_str(xml);
    let mut walk = Walk {
        name,
        expected,
        doc: Document {
            big_endian: false,
            header64: false,
            zlib: false,
            points: None,
            piece_line: 1,
            point_arrays: Vec::new(),
            positions: None,
            points_name: None,
            appended_base64: false,
            padded_2d: false,
        },
        stack: Vec::new(),
        current: None,
        pieces: 0,
        seen_root: false,
    };
    loop {
        let pos = usize::try_from(reader.buffer_position()).unwrap_or(usize::MAX);
        let line = || line_of(xml.as_bytes(), pos);
        match reader.read_event() {
            Ok(Event::Eof) => break,
            Ok(Event::Comment(c)) => {
                if c.contains(DIM2_MARKER) {
                    walk.doc.padded_2d = true;
                }
            }
            Ok(Event::Start(e)) => walk.open(&e, false, line())?,
            Ok(Event::Empty(e)) => walk.open(&e, true, line())?,
            Ok(Event::Text(t)) => {
                if walk.stack.len() == 5 {
                    if let Some(a) = walk.current.as_mut() {
                        a.text.push_str(&t);
                    }
                }
            }
            Ok(Event::End(_)) => {
                walk.stack.pop();
                if walk.stack.len() == 4 {
                    walk.finish()?;
                }
            }
            Ok(_) => {}
            // The XML part ends where the appended data starts, so unclosed elements at the end
            // are not an error (quick-xml does not report them); anything else is.
            Err(e) => {
                return Err(IoError::parse(
                    name,
                    Location::Line(line()),
                    format!(
                        "malformed XML: {}",
                        excerpt(
                            &e.to_string()
                                .split_whitespace()
                                .collect::<Vec<_>>()
                                .join(" "),
                            120
                        )
                    ),
                ))
            }
        }
    }
    if !walk.seen_root {
        return Err(IoError::parse(
            name,
            Location::File,
            "not a VTK XML file: no <VTKFile> element",
        ));
    }
    if walk.doc.points.is_none() {
        return Err(IoError::parse(
            name,
            Location::File,
            format!("no <Piece> in the <{}>", expected.tag()),
        ));
    }
    Ok(walk.doc)
}

/// Base64 text that may hold several independently padded streams (VTK encodes a compressed
/// array's header apart from its blocks), decoded on demand.
struct Base64Stream<'a> {
    text: &'a [u8],
    pos: usize,
    out: Vec<u8>,
}

impl Base64Stream<'_> {
    /// Decodes until at least `need` bytes are out, or the text ends (then fewer are).
    fn fill(&mut self, need: usize) -> Result<(), String> {
        while self.out.len() < need && self.pos < self.text.len() {
            let rest = &self.text[self.pos..];
            // Whole 4-character groups, up to and including the first group with padding.
            let want = (need - self.out.len()).div_ceil(3).saturating_mul(4).max(4);
            let mut end = want.min(rest.len()) / 4 * 4;
            if let Some(pad) = rest[..end].iter().position(|&b| b == b'=') {
                end = (pad / 4 + 1) * 4;
            }
            if end == 0 {
                return Err(format!(
                    "truncated base64 data ({} characters left over)",
                    rest.len()
                ));
            }
            STANDARD
                .decode_vec(&rest[..end], &mut self.out)
                .map_err(|e| format!("invalid base64 data: {e}"))?;
            self.pos += end;
        }
        Ok(())
    }
}

/// The bytes an array's data is read from.
enum Source<'a> {
    Raw(&'a [u8]),
    Base64(Base64Stream<'a>),
}

impl Source<'_> {
    /// `len` bytes from byte `start`, or a message saying how many there are.
    fn get(&mut self, start: usize, len: usize) -> Result<&[u8], String> {
        let end = start
            .checked_add(len)
            .ok_or_else(|| "declared size overflows".to_owned())?;
        match self {
            Source::Raw(bytes) => bytes.get(start..end).ok_or_else(|| {
                format!(
                    "needs bytes {start}..{end} but only {} are present",
                    bytes.len()
                )
            }),
            Source::Base64(s) => {
                s.fill(end)?;
                s.out.get(start..end).ok_or_else(|| {
                    format!(
                        "needs bytes {start}..{end} but the base64 data holds {}",
                        s.out.len()
                    )
                })
            }
        }
    }
}

fn read_uint(bytes: &[u8], big: bool) -> u64 {
    let mut v = 0u64;
    if big {
        for &b in bytes {
            v = (v << 8) | u64::from(b);
        }
    } else {
        for &b in bytes.iter().rev() {
            v = (v << 8) | u64::from(b);
        }
    }
    v
}

/// The values of `array`: `n` tuples of `array.components`.
fn decode(
    doc: &Document,
    array: &ArrayHeader,
    n: usize,
    appended: &[u8],
    name: &str,
) -> Result<Values, IoError> {
    let fail = |message: String| {
        IoError::parse(
            name,
            Location::Line(array.line),
            format!("DataArray {:?}: {message}", excerpt(&array.name, 40)),
        )
    };
    let scalar = Scalar::parse(&array.type_name).ok_or_else(|| {
        fail(format!(
            "unsupported type {:?}",
            excerpt(&array.type_name, 20)
        ))
    })?;
    let count = n
        .checked_mul(array.components)
        .ok_or_else(|| fail("too many values".into()))?;
    match array.format.as_str() {
        "ascii" => decode_ascii(&array.text, scalar, count).map_err(fail),
        "binary" => {
            let compact: Vec<u8> = array
                .text
                .bytes()
                .filter(|b| !b.is_ascii_whitespace())
                .collect();
            let mut source = Source::Base64(Base64Stream {
                text: &compact,
                pos: 0,
                out: Vec::new(),
            });
            decode_binary(doc, &mut source, scalar, count).map_err(fail)
        }
        "appended" => {
            let offset = array
                .offset
                .ok_or_else(|| fail("format=\"appended\" without an offset".into()))?;
            let rest = appended.get(offset..).ok_or_else(|| {
                fail(format!(
                    "offset {offset} is past the end of the appended data ({} bytes)",
                    appended.len()
                ))
            })?;
            let mut source = if doc.appended_base64 {
                Source::Base64(Base64Stream {
                    text: rest,
                    pos: 0,
                    out: Vec::new(),
                })
            } else {
                Source::Raw(rest)
            };
            decode_binary(doc, &mut source, scalar, count)
                .map_err(|m| fail(format!("at appended offset {offset}: {m}")))
        }
        other => Err(fail(format!(
            "unknown format {:?} (ascii, binary or appended)",
            excerpt(other, 20)
        ))),
    }
}

fn decode_ascii(text: &str, scalar: Scalar, count: usize) -> Result<Values, String> {
    Ok(if scalar.is_float() {
        Values::Float(parse_tokens(text, count, "number")?)
    } else {
        Values::Int(parse_tokens(text, count, "integer")?)
    })
}

/// Exactly `count` whitespace-separated values of type `T` (`what` names them in errors).
fn parse_tokens<T: std::str::FromStr>(
    text: &str,
    count: usize,
    what: &str,
) -> Result<Vec<T>, String> {
    let mismatch = |found: usize| format!("{found} values where {count} were declared");
    let mut v = Vec::with_capacity(count.min(MAX_PREALLOCATE));
    for (k, t) in text.split_ascii_whitespace().enumerate() {
        if k >= count {
            return Err(mismatch(text.split_ascii_whitespace().count()));
        }
        v.push(
            t.parse::<T>()
                .map_err(|_| format!("invalid {what} {:?} (value {k})", excerpt(t, 30)))?,
        );
    }
    if v.len() != count {
        return Err(mismatch(v.len()));
    }
    Ok(v)
}

/// Header + data of a binary array (inline or appended), uncompressed or zlib blocks.
fn decode_binary(
    doc: &Document,
    source: &mut Source<'_>,
    scalar: Scalar,
    count: usize,
) -> Result<Values, String> {
    let h = if doc.header64 { 8 } else { 4 };
    let expected = count
        .checked_mul(scalar.size())
        .ok_or_else(|| "declared size overflows".to_owned())?;
    let as_usize = |v: u64| usize::try_from(v).map_err(|_| format!("size {v} too large"));
    let data: Vec<u8> = if doc.zlib {
        let head = source.get(0, 3 * h)?;
        let blocks = as_usize(read_uint(&head[..h], doc.big_endian))?;
        let block_size = as_usize(read_uint(&head[h..2 * h], doc.big_endian))?;
        let last_size = as_usize(read_uint(&head[2 * h..], doc.big_endian))?;
        let total = match blocks {
            0 => Some(0),
            b => (b - 1).checked_mul(block_size).and_then(|t| {
                t.checked_add(if last_size == 0 {
                    block_size
                } else {
                    last_size
                })
            }),
        };
        if total != Some(expected) {
            return Err(format!(
                "the compression header declares {} bytes, the array needs {expected}",
                total.map_or_else(|| "too many".to_owned(), |t| t.to_string())
            ));
        }
        let sizes_len = blocks
            .checked_mul(h)
            .ok_or_else(|| "declared size overflows".to_owned())?;
        let sizes: Vec<usize> = source
            .get(3 * h, sizes_len)?
            .chunks_exact(h)
            .map(|c| as_usize(read_uint(c, doc.big_endian)))
            .collect::<Result<_, _>>()?;
        let mut at = 3 * h + sizes_len;
        let mut data = Vec::with_capacity(expected.min(MAX_PREALLOCATE));
        for (b, &csize) in sizes.iter().enumerate() {
            let compressed = source.get(at, csize)?;
            at += csize;
            let want = if b + 1 == blocks && last_size != 0 {
                last_size
            } else {
                block_size
            };
            let before = data.len();
            // Inflate at most one byte more than declared, to detect a lying header.
            flate2::read::ZlibDecoder::new(compressed)
                .take(want as u64 + 1)
                .read_to_end(&mut data)
                .map_err(|e| format!("block {b}: zlib error: {e}"))?;
            if data.len() - before != want {
                return Err(format!(
                    "block {b} inflates to {} bytes, the header declares {want}",
                    data.len() - before
                ));
            }
        }
        data
    } else {
        let head = source.get(0, h)?;
        let declared = as_usize(read_uint(head, doc.big_endian))?;
        if declared != expected {
            return Err(format!(
                "the header declares {declared} bytes, the array needs {expected}"
            ));
        }
        source.get(h, expected)?.to_vec()
    };
    let big = doc.big_endian;
    let chunks = data.chunks_exact(scalar.size());
    let word = |c: &[u8]| -> [u8; 8] {
        let mut w = [0u8; 8];
        if big {
            for (k, &b) in c.iter().rev().enumerate() {
                w[k] = b;
            }
        } else {
            w[..c.len()].copy_from_slice(c);
        }
        w // little-endian bytes of the value, zero-extended
    };
    Ok(match scalar {
        Scalar::F32 => Values::Float(
            chunks
                .map(|c| {
                    let w = word(c);
                    f64::from(f32::from_le_bytes([w[0], w[1], w[2], w[3]]))
                })
                .collect(),
        ),
        Scalar::F64 => Values::Float(chunks.map(|c| f64::from_le_bytes(word(c))).collect()),
        Scalar::U64 => {
            let v: Vec<u64> = chunks.map(|c| u64::from_le_bytes(word(c))).collect();
            if v.iter().all(|&x| i64::try_from(x).is_ok()) {
                Values::Int(v.into_iter().map(|x| x as i64).collect())
            } else {
                Values::Float(v.into_iter().map(|x| x as f64).collect())
            }
        }
        _ => {
            let bits = 8 * scalar.size() as u32;
            let signed = matches!(scalar, Scalar::I8 | Scalar::I16 | Scalar::I32 | Scalar::I64);
            Values::Int(
                chunks
                    .map(|c| crate::vtk::sign_extend(u64::from_le_bytes(word(c)), bits, signed))
                    .collect(),
            )
        }
    })
}

/// A run of columns written as one array: `name` with `components` (1 for a plain column).
struct Group<'c, 'a> {
    name: String,
    columns: Vec<&'c Column<'a>>,
}

/// Groups consecutive columns `base:0`, `base:1`, … of one kind into vectors.
fn groups<'c, 'a>(columns: &'c [(&str, Column<'a>)]) -> Vec<Group<'c, 'a>> {
    let mut out: Vec<Group<'c, 'a>> = Vec::new();
    let mut k = 0;
    while k < columns.len() {
        let (name, column) = &columns[k];
        if let Some(base) = name.strip_suffix(":0") {
            let mut members = vec![column];
            while let Some((next, c)) = columns.get(k + members.len()) {
                let same_kind = std::mem::discriminant(c) == std::mem::discriminant(column);
                if same_kind && *next == format!("{base}:{}", members.len()) {
                    members.push(c);
                } else {
                    break;
                }
            }
            if members.len() > 1 {
                k += members.len();
                out.push(Group {
                    name: base.to_owned(),
                    columns: members,
                });
                continue;
            }
        }
        out.push(Group {
            name: (*name).to_owned(),
            columns: vec![column],
        });
        k += 1;
    }
    out
}

/// Consecutive columns `base:0`, `base:1`, … of one kind as `(base, members)`; any other
/// column alone under its name. Shared with the BGEO writer (its vector attributes).
pub(crate) fn group_columns<'c, 'a>(
    columns: &'c [(&str, Column<'a>)],
) -> Vec<(String, Vec<&'c Column<'a>>)> {
    groups(columns)
        .into_iter()
        .map(|g| (g.name, g.columns))
        .collect()
}

/// Writes one inline base64 `DataArray` with a `UInt64` byte-count header.
fn write_array(
    out: &mut dyn Write,
    indent: &str,
    type_name: &str,
    name: Option<&str>,
    components: usize,
    data: &[u8],
) -> std::io::Result<()> {
    let mut block = Vec::with_capacity(8 + data.len());
    block.extend_from_slice(&(data.len() as u64).to_le_bytes());
    block.extend_from_slice(data);
    write!(out, "{indent}<DataArray type=\"{type_name}\"")?;
    if let Some(name) = name {
        write!(out, " Name=\"{}\"", quick_xml::escape::escape(name))?;
    }
    if components > 1 {
        write!(out, " NumberOfComponents=\"{components}\"")?;
    }
    writeln!(out, " format=\"binary\">")?;
    writeln!(out, "{indent}  {}", STANDARD.encode(&block))?;
    writeln!(out, "{indent}</DataArray>")
}

pub(crate) fn write(
    out: &mut dyn Write,
    set: &AnyParticleSet,
    columns: &[(&str, Column<'_>)],
    kind: Kind,
) -> std::io::Result<()> {
    let n = set.len();
    writeln!(out, "<?xml version=\"1.0\"?>")?;
    if set.dim() == 2 {
        // VTK points have three components: a 2D set gets z = 0 here, marked for the reader.
        writeln!(out, "<!-- {DIM2_MARKER} -->")?;
    }
    writeln!(
        out,
        "<VTKFile type=\"{}\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">",
        kind.tag()
    )?;
    writeln!(out, "  <{}>", kind.tag())?;
    match kind {
        Kind::UnstructuredGrid => writeln!(
            out,
            "    <Piece NumberOfPoints=\"{n}\" NumberOfCells=\"{n}\">"
        )?,
        Kind::PolyData => writeln!(
            out,
            "    <Piece NumberOfPoints=\"{n}\" NumberOfVerts=\"{n}\" NumberOfLines=\"0\" \
             NumberOfStrips=\"0\" NumberOfPolys=\"0\">"
        )?,
    }
    let groups = groups(columns);
    match groups.first() {
        Some(g) if g.columns.len() == 1 => writeln!(
            out,
            "      <PointData Scalars=\"{}\">",
            quick_xml::escape::escape(g.name.as_str())
        )?,
        _ => writeln!(out, "      <PointData>")?,
    }
    for group in &groups {
        let comps = group.columns.len();
        let mut data = Vec::new();
        let type_name = match group.columns[0] {
            Column::Byte(_) => "UInt8",
            Column::Int(_) => {
                let fits = group.columns.iter().all(|c| match c {
                    Column::Int(v) => v.iter().all(|&x| i32::try_from(x).is_ok()),
                    _ => false,
                });
                if fits {
                    "Int32"
                } else {
                    "Int64"
                }
            }
            Column::Float(_) => "Float64",
        };
        for i in 0..n {
            for c in &group.columns {
                match (c, type_name) {
                    (Column::Byte(v), _) => data.push(v[i]),
                    (Column::Int(v), "Int32") => {
                        data.extend_from_slice(&(v[i] as i32).to_le_bytes());
                    }
                    (Column::Int(v), _) => data.extend_from_slice(&v[i].to_le_bytes()),
                    (Column::Float(v), _) => data.extend_from_slice(&v[i].to_le_bytes()),
                }
            }
        }
        write_array(out, "        ", type_name, Some(&group.name), comps, &data)?;
    }
    writeln!(out, "      </PointData>")?;
    writeln!(out, "      <Points>")?;
    let mut data = Vec::with_capacity(24 * n);
    for i in 0..n {
        let c = set.coords(i);
        for axis in 0..3 {
            data.extend_from_slice(&c.get(axis).copied().unwrap_or(0.0).to_le_bytes());
        }
    }
    write_array(out, "        ", "Float64", Some("Points"), 3, &data)?;
    writeln!(out, "      </Points>")?;
    let connectivity: Vec<u8> = (0..n as i64).flat_map(i64::to_le_bytes).collect();
    let offsets: Vec<u8> = (1..=n as i64).flat_map(i64::to_le_bytes).collect();
    let (open, close) = match kind {
        Kind::UnstructuredGrid => ("<Cells>", "</Cells>"),
        Kind::PolyData => ("<Verts>", "</Verts>"),
    };
    writeln!(out, "      {open}")?;
    write_array(
        out,
        "        ",
        "Int64",
        Some("connectivity"),
        1,
        &connectivity,
    )?;
    write_array(out, "        ", "Int64", Some("offsets"), 1, &offsets)?;
    if kind == Kind::UnstructuredGrid {
        // VTK_VERTEX = 1.
        write_array(out, "        ", "UInt8", Some("types"), 1, &vec![1u8; n])?;
    }
    writeln!(out, "      {close}")?;
    writeln!(out, "    </Piece>\n  </{}>\n</VTKFile>", kind.tag())
}
