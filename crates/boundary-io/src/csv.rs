//! CSV: a header naming the position columns, or headerless numbers (crate docs, "Reading").

use crate::error::{excerpt, IoError, Location};
use crate::out::{self, Real, AXES};
use crate::text::{
    find_near_miss, line_text, normalise_name, position_axis, select_position_columns, trim_field,
    TextLines,
};
use crate::{Column, LineIndex, NearMiss, Positions, ReadOptions};
use boundary_core::AnyParticleSet;
use std::io::{BufRead, Read, Seek, SeekFrom, Write};
use std::ops::Range;
use std::path::Path;

/// The separator of a header or first row: the most frequent of `;`, tab and `,` (ties in that
/// order); `,` when none occurs (a single column).
fn detect_separator(line: &str) -> char {
    let mut best = (0, ',');
    for sep in [';', '\t', ','] {
        let count = line.matches(sep).count();
        if count > best.0 {
            best = (count, sep);
        }
    }
    best.1
}

/// The fields of a line, without the empty field a trailing separator leaves.
fn fields(line: &str, sep: char) -> impl Iterator<Item = &str> {
    let line = line.trim_end();
    line.strip_suffix(sep).unwrap_or(line).split(sep)
}

/// A field as a number; with `;` as separator a decimal comma is accepted.
fn number_of(field: &str, sep: char) -> Option<f64> {
    let f = trim_field(field);
    f.parse::<f64>()
        .ok()
        .or_else(|| (sep == ';' && f.contains(',')).then(|| f.replace(',', ".").parse().ok())?)
}

/// The first line that is neither blank nor a `#` comment, with the separator (from a
/// `sep=X` line if there is one) and the byte offset where that line starts.
fn first_line<R: BufRead>(
    lines: &mut TextLines<R>,
    name: &str,
) -> Result<Option<(usize, String, char, u64)>, IoError> {
    let mut forced = None;
    loop {
        let at = lines.offset();
        let Some((number, line)) = lines.next_line(name)? else {
            return Ok(None);
        };
        let t = line.trim();
        if t.is_empty() || t.starts_with('#') {
            continue;
        }
        if let Some(rest) = t
            .get(..4)
            .filter(|p| forced.is_none() && p.eq_ignore_ascii_case("sep="))
            .and_then(|_| t.get(4..))
        {
            if let Some(sep) = rest.chars().next() {
                forced = Some(sep);
                continue;
            }
        }
        let sep = forced.unwrap_or_else(|| detect_separator(t));
        return Ok(Some((number, line.to_owned(), sep, at)));
    }
}

/// Whether a line (as [`crate::text::line_text`] gives it) holds a row: not blank, not a `#`
/// comment.
fn is_row(line: &str) -> bool {
    let t = line.trim_start();
    !t.is_empty() && !t.starts_with('#')
}

/// How the rows of a file are read, from its header or (headerless) its first row.
#[derive(Debug, Clone)]
struct RowLayout {
    sep: char,
    headerless: bool,
    /// Position k of the particle's row for each field index < `needed`, or usize::MAX.
    slot: Vec<usize>,
    /// The names of the position columns used in messages.
    labels: Vec<String>,
    stride: usize,
    /// Fields a row needs (up to the last position column).
    needed: usize,
    /// The most values a row may hold: the header's columns (headerless: the first row's).
    width: usize,
}

impl RowLayout {
    /// The layout of the first line (number `number`) and the near-miss column beside two
    /// position columns, if any. `dim` chooses the columns of a headerless file only.
    fn new(
        number: usize,
        first: &str,
        sep: char,
        dim: Option<usize>,
        name: &str,
    ) -> Result<(RowLayout, Option<NearMiss>), IoError> {
        let first_fields: Vec<&str> = fields(first, sep).collect();
        let headerless = first_fields.iter().all(|f| number_of(f, sep).is_some());
        // Column index of each position axis, and the names used in messages.
        let (columns, labels): (Vec<usize>, Vec<String>) = if headerless {
            let count = first_fields.len();
            let stride = match dim {
                Some(d) => d,
                None if count >= 3 => 3,
                None => 2,
            };
            if count < stride {
                return Err(IoError::parse(
                    name,
                    Location::Line(number),
                    format!(
                        "too few columns in a headerless file: {count}, need {stride} coordinates"
                    ),
                ));
            }
            (
                (0..stride).collect(),
                AXES[..stride].iter().map(|s| (*s).to_owned()).collect(),
            )
        } else {
            let columns = select_position_columns(first_fields.iter().copied())
                .map_err(|m| IoError::parse(name, Location::Line(number), m))?;
            let labels = columns
                .iter()
                .map(|&c| excerpt(trim_field(first_fields[c]), 40))
                .collect();
            (columns, labels)
        };
        let stride = columns.len();
        // Two position columns and a third that looks like the missing axis misspelt (`x,y,zz`).
        let near_miss = if headerless || stride != 2 {
            None
        } else {
            let missing = (0..3)
                .find(|&a| {
                    columns
                        .iter()
                        .all(|&c| position_axis(first_fields[c]).map(|p| p.0) != Some(a))
                })
                .unwrap_or(2);
            find_near_miss(first_fields.iter().copied(), missing, &columns).map(|c| NearMiss {
                at: Location::Cell {
                    line: number,
                    column: c + 1,
                },
                vertex_property: false,
                name: excerpt(trim_field(first_fields[c]), 40),
                axis: missing,
            })
        };
        let needed = columns.iter().copied().max().unwrap_or(0) + 1;
        let mut slot = vec![usize::MAX; needed];
        for (k, &c) in columns.iter().enumerate() {
            slot[c] = k;
        }
        let layout = RowLayout {
            sep,
            headerless,
            slot,
            labels,
            stride,
            needed,
            width: first_fields.len(),
        };
        Ok((layout, near_miss))
    }

    /// Parses the row on line `line_number`, particle `index` of the file, appending its
    /// `stride` coordinates to `coords`.
    ///
    /// Policy: a row may not have more values than the header has columns (or, headerless,
    /// than the first row has values): such a row is misaligned data, not something to
    /// silently cut. One trailing separator is not a value (see `fields`).
    fn parse_row(
        &self,
        name: &str,
        line_number: usize,
        line: &str,
        index: usize,
        coords: &mut Vec<f64>,
    ) -> Result<(), IoError> {
        let sep = self.sep;
        let count = fields(line, sep).count();
        if count > self.width {
            let width_source = if self.headerless {
                "the first row has"
            } else {
                "the header names"
            };
            return Err(IoError::parse(
                name,
                Location::Line(line_number),
                format!(
                    "too many values: {count}, {width_source} {} columns",
                    self.width
                ),
            ));
        }
        let mut row = [0.0f64; 3];
        let mut seen = 0;
        for (c, field) in fields(line, sep).enumerate().take(self.needed) {
            seen = c + 1;
            let k = self.slot[c];
            if k == usize::MAX {
                continue;
            }
            let at = Location::Cell {
                line: line_number,
                column: c + 1,
            };
            let value = number_of(field, sep).ok_or_else(|| {
                IoError::parse(
                    name,
                    at,
                    format!(
                        "invalid number {:?} for {}",
                        excerpt(trim_field(field), 40),
                        self.labels[k]
                    ),
                )
            })?;
            if !value.is_finite() {
                return Err(IoError::NonFinite {
                    file: name.to_owned(),
                    at,
                    index,
                    axis: k,
                    value,
                });
            }
            row[k] = value;
        }
        if seen < self.needed {
            return Err(IoError::parse(
                name,
                Location::Line(line_number),
                format!("too few columns: {seen}, need {}", self.needed),
            ));
        }
        coords.extend_from_slice(&row[..self.stride]);
        Ok(())
    }
}

/// Reads the positions. `dim` chooses the columns of a headerless file only; the dimension
/// policy is applied by the caller.
pub(crate) fn read<R: BufRead>(
    reader: R,
    name: &str,
    dim: Option<usize>,
    with_attributes: bool,
) -> Result<Positions, IoError> {
    let mut lines = TextLines::new(reader);
    let Some((first_number, first, sep, _)) = first_line(&mut lines, name)? else {
        return Err(no_header(name));
    };
    let (layout, near_miss) = RowLayout::new(first_number, &first, sep, dim, name)?;
    let headerless = layout.headerless;
    let columns: Vec<usize> = (0..layout.needed)
        .filter(|&c| layout.slot[c] != usize::MAX)
        .collect();
    // The other named columns, kept as attributes while all their values are numbers.
    let mut extra: Vec<ExtraColumn> = if with_attributes && !headerless {
        fields(&first, sep)
            .enumerate()
            .filter(|(c, _)| !columns.contains(c))
            .map(|(c, f)| ExtraColumn::new(c, f))
            .collect()
    } else {
        Vec::new()
    };
    let mut coords = Vec::new();
    let mut line_index = LineIndex::default();
    let mut index = 0usize;
    let mut parse_row = |line_number: usize, line: &str, coords: &mut Vec<f64>| {
        layout.parse_row(name, line_number, line, index, coords)?;
        line_index.push(line_number);
        index += 1;
        if !extra.is_empty() {
            let all: Vec<&str> = fields(line, sep).collect();
            for column in &mut extra {
                column.push(all.get(column.index).copied(), sep, line_number);
            }
        }
        Ok::<(), IoError>(())
    };
    if headerless {
        parse_row(first_number, &first, &mut coords)?;
    }
    while let Some((line_number, line)) = lines.next_line(name)? {
        if !is_row(line) {
            continue;
        }
        parse_row(line_number, line, &mut coords)?;
    }
    let mut attributes = Vec::new();
    let mut skipped = Vec::new();
    for column in extra {
        column.finish(&mut attributes, &mut skipped);
    }
    let empty = (!headerless).then(|| no_rows_detail(first_number, &layout.labels));
    Ok(Positions {
        coords,
        stride: layout.stride,
        attributes,
        skipped,
        names: if headerless {
            Vec::new()
        } else {
            layout.labels.clone()
        },
        near_miss,
        empty,
        lines: line_index,
        ..Default::default()
    })
}

/// The error of a file without a header or a data row.
fn no_header(name: &str) -> IoError {
    IoError::NoParticles {
        file: name.to_owned(),
        dim: None,
        detail: "the file holds no header and no data row (empty file)".to_owned(),
    }
}

/// Why a file with a header on line `line` holds no particle.
fn no_rows_detail(line: usize, labels: &[String]) -> String {
    format!(
        "the header on line {line} ({}) is followed by no data row",
        excerpt(&labels.join(", "), 80)
    )
}

/// The header of a CSV file that several processes read in parts, each its own byte range
/// ([`read_csv_header`]): what every part needs to parse its rows as [`crate::read_particles`]
/// parses them (separator, position columns, row width, where the rows start).
///
/// A part's rows are the lines that *start* in its byte range ([`CsvHeader::read_chunk`]), so
/// any split of [`CsvHeader::data_bytes`] into ranges reads every row once. Lines are numbered
/// by counting: each part counts the newlines and rows of its chunk, an exclusive prefix sum of
/// the counts over the parts before it gives its first line and first particle, and
/// [`CsvChunk::parse`] then names lines and particles as a whole-file read does.
/// [`CsvHeader::finish`] applies the dimension policy with facts about the whole file.
///
/// ```
/// use boundary_io::{read_csv_header, ReadOptions};
///
/// let dir = tempfile::tempdir().expect("temporary directory");
/// let path = dir.path().join("p.csv");
/// std::fs::write(&path, "x,y\n0,0\n# comment\n1,0\r\n2,5\n")?;
/// let header = read_csv_header(&path, &ReadOptions::default())?;
/// // Two parts, split in the middle of the rows.
/// let (a, b) = (header.part(0, 2), header.part(1, 2));
/// let first = header.read_chunk(&path, a)?;
/// let second = header.read_chunk(&path, b)?;
/// assert_eq!(first.rows() + second.rows(), 3);
/// // The second part starts after the first part's lines and rows.
/// let mut coords = first.parse(&header, header.first_data_line(), 0)?;
/// coords.extend(second.parse(
///     &header,
///     header.first_data_line() + first.newlines(),
///     first.rows(),
/// )?);
/// assert_eq!(coords, [0.0, 0.0, 1.0, 0.0, 2.0, 5.0]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct CsvHeader {
    name: String,
    layout: RowLayout,
    near_miss: Option<NearMiss>,
    /// The line of the header (headerless: of the first row).
    first_number: usize,
    /// Byte offset and line number of the first line after the header (headerless: of the
    /// first row).
    data_start: u64,
    data_line: usize,
    file_len: u64,
    dim: Option<usize>,
}

/// Reads the header of the CSV file at `path` (everything up to its first row), for a read
/// of its rows in parts ([`CsvHeader`]). `options.format` is not consulted: the file is read
/// as CSV. Errors: as [`crate::read_particles`] for the lines read, and an empty file.
pub fn read_csv_header(path: &Path, options: &ReadOptions) -> Result<CsvHeader, IoError> {
    let name = path.display().to_string();
    crate::check_dim(&name, options.dim)?;
    let file = std::fs::File::open(path).map_err(|e| IoError::read(&name, e))?;
    let file_len = file.metadata().map_err(|e| IoError::read(&name, e))?.len();
    let mut lines = TextLines::new(std::io::BufReader::new(file));
    let Some((first_number, first, sep, at)) = first_line(&mut lines, &name)? else {
        return Err(no_header(&name));
    };
    let (layout, near_miss) = RowLayout::new(first_number, &first, sep, options.dim, &name)?;
    let (data_start, data_line) = if layout.headerless {
        (at, first_number)
    } else {
        (lines.offset(), first_number + 1)
    };
    Ok(CsvHeader {
        name,
        layout,
        near_miss,
        first_number,
        data_start,
        data_line,
        file_len,
        dim: options.dim,
    })
}

impl CsvHeader {
    /// The bytes of the file that hold its rows: from the first line after the header
    /// (headerless: the first row) to the end of the file.
    pub fn data_bytes(&self) -> Range<u64> {
        self.data_start..self.file_len.max(self.data_start)
    }

    /// Part `part` of `parts` nearly equal byte ranges of [`CsvHeader::data_bytes`].
    pub fn part(&self, part: usize, parts: usize) -> Range<u64> {
        let Range { start, end } = self.data_bytes();
        let len = u128::from(end - start);
        let parts = parts.max(1) as u128;
        let at = |k: u128| start + (len * k.min(parts) / parts) as u64;
        at(part as u128)..at(part as u128 + 1)
    }

    /// The line number of the first line after the header (headerless: of the first row):
    /// the first line of a chunk that starts at the start of [`CsvHeader::data_bytes`].
    pub fn first_data_line(&self) -> usize {
        self.data_line
    }

    /// The values per row read (2 or 3), before the dimension policy.
    pub fn stride(&self) -> usize {
        self.layout.stride
    }

    /// The lines of the file at `path` that start in the byte range `range` (clamped to
    /// [`CsvHeader::data_bytes`]), the last of them read to its end even past the range. A
    /// line starts at the start of the rows or after a `\n`.
    pub fn read_chunk(&self, path: &Path, range: Range<u64>) -> Result<CsvChunk, IoError> {
        let name = &self.name;
        let data = self.data_bytes();
        let (start, end) = (range.start.max(data.start), range.end.min(data.end));
        if start >= end {
            return Ok(CsvChunk::default());
        }
        let mut file = std::fs::File::open(path).map_err(|e| IoError::read(name, e))?;
        // From the byte before the range, whose `\n` would make the range start a line start.
        let from = if start == data.start {
            start
        } else {
            start - 1
        };
        file.seek(SeekFrom::Start(from))
            .map_err(|e| IoError::read(name, e))?;
        let mut bytes = Vec::with_capacity((end - from) as usize + 1024);
        (&mut file)
            .take(end - from)
            .read_to_end(&mut bytes)
            .map_err(|e| IoError::read(name, e))?;
        let skip = if start == data.start {
            0
        } else {
            match bytes.iter().position(|&b| b == b'\n') {
                Some(i) => i + 1,
                None => return Ok(CsvChunk::default()),
            }
        };
        if from + skip as u64 >= end {
            return Ok(CsvChunk::default());
        }
        // The last line that starts in the range runs on to its newline or the end of file.
        if bytes.len() as u64 == end - from && bytes.last() != Some(&b'\n') {
            std::io::BufReader::new(file)
                .read_until(b'\n', &mut bytes)
                .map_err(|e| IoError::read(name, e))?;
        }
        bytes.drain(..skip);
        let (mut newlines, mut rows) = (0, 0);
        for line in lines_of(&bytes) {
            newlines += usize::from(line.last() == Some(&b'\n'));
            rows += usize::from(holds_row(line));
        }
        Ok(CsvChunk {
            bytes,
            newlines,
            rows,
        })
    }

    /// Checks what needs the whole file, given the coordinates a part read (`stride` values
    /// per row), the rows of all parts (`total`) and, for each of the `stride` axes, whether
    /// it has one value over all rows of all parts (`constant`): the misspelt-axis check, the
    /// dimension policy (the axis dropped to make a file 2D is the one constant over the whole
    /// file) and a file of no row. Returns this part's set and the axis dropped, if one was.
    /// Every part gets the same error.
    pub fn finish(
        &self,
        coords: &[f64],
        total: usize,
        constant: &[bool],
    ) -> Result<(AnyParticleSet, Option<usize>), IoError> {
        let name = &self.name;
        if let Some(miss) = &self.near_miss {
            if self.dim != Some(2) {
                return Err(IoError::NearMissColumn {
                    file: name.to_owned(),
                    at: miss.at,
                    vertex_property: miss.vertex_property,
                    name: miss.name.clone(),
                    axis: ['x', 'y', 'z'][miss.axis],
                    kept: self.layout.labels.join(", "),
                });
            }
        }
        let stride = self.layout.stride;
        let (set, dropped) = crate::dimension_of(coords, stride, false, name, self.dim, |k| {
            constant.get(k).copied().unwrap_or(false)
        })?;
        if total == 0 {
            return Err(IoError::NoParticles {
                file: name.to_owned(),
                dim: Some(set.dim()),
                detail: if self.layout.headerless {
                    "the file has no data row".to_owned()
                } else {
                    no_rows_detail(self.first_number, &self.layout.labels)
                },
            });
        }
        Ok((set, dropped))
    }
}

/// Whether the bytes of a line hold a row, as [`is_row`] says of its text; a line that is
/// not text is a row (parsing it names the error).
fn holds_row(line: &[u8]) -> bool {
    match line
        .iter()
        .find(|&&b| !matches!(b, b' ' | b'\t' | b'\n' | b'\r' | 0x0b | 0x0c))
    {
        None => false,
        Some(b'#') => false,
        Some(&b) if b.is_ascii() => true,
        // Other white space is Unicode's: ask the text.
        Some(_) => std::str::from_utf8(line).map_or(true, is_row),
    }
}

/// The lines of `bytes`, each with its terminator; no empty line after a final `\n`.
fn lines_of(bytes: &[u8]) -> impl Iterator<Item = &[u8]> {
    bytes
        .split_inclusive(|&b| b == b'\n')
        .filter(|line| !line.is_empty())
}

/// The lines of a CSV file that start in one byte range ([`CsvHeader::read_chunk`]).
#[derive(Debug, Default)]
pub struct CsvChunk {
    bytes: Vec<u8>,
    newlines: usize,
    rows: usize,
}

impl CsvChunk {
    /// The `\n` in the chunk: the number of the line after it minus that of its first line.
    pub fn newlines(&self) -> usize {
        self.newlines
    }

    /// The rows in the chunk (lines neither blank nor `#` comments): its particles, if every
    /// row parses.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// The coordinates of the chunk's rows ([`CsvHeader::stride`] values each), its first line
    /// being line `first_line` of the file and its first row particle `first_index`: errors
    /// name the file's line and particle as [`crate::read_particles`] does.
    pub fn parse(
        &self,
        header: &CsvHeader,
        first_line: usize,
        first_index: usize,
    ) -> Result<Vec<f64>, IoError> {
        let name = &header.name;
        let mut coords = Vec::with_capacity(self.rows * header.layout.stride);
        let mut index = first_index;
        for (k, bytes) in lines_of(&self.bytes).enumerate() {
            let number = first_line + k;
            let line = line_text(bytes, number, name)?;
            if !is_row(line) {
                continue;
            }
            header
                .layout
                .parse_row(name, number, line, index, &mut coords)?;
            index += 1;
        }
        Ok(coords)
    }
}

/// A non-position column of the header, read as an attribute.
struct ExtraColumn {
    /// 0-based field index.
    index: usize,
    /// The header's name (trimmed of spaces and quotes).
    header: String,
    /// While every value is an integer.
    ints: Option<Vec<i64>>,
    floats: Vec<f64>,
    /// Why the column cannot be kept, once known.
    failed: Option<String>,
}

impl ExtraColumn {
    fn new(index: usize, header: &str) -> Self {
        ExtraColumn {
            index,
            header: trim_field(header).to_owned(),
            ints: Some(Vec::new()),
            floats: Vec::new(),
            failed: None,
        }
    }

    fn push(&mut self, field: Option<&str>, sep: char, line: usize) {
        if self.failed.is_some() {
            return;
        }
        let Some(field) = field else {
            self.failed = Some(format!("no value on line {line}"));
            return;
        };
        let text = trim_field(field);
        if let Some(ints) = self.ints.as_mut() {
            match text.parse::<i64>() {
                Ok(v) => ints.push(v),
                Err(_) => self.ints = None,
            }
        }
        match number_of(field, sep) {
            Some(v) => self.floats.push(v),
            None => {
                self.failed = Some(format!(
                    "{:?} on line {line} is not a number",
                    excerpt(text, 20)
                ))
            }
        }
    }

    fn finish(self, attributes: &mut Vec<crate::Attribute>, skipped: &mut Vec<String>) {
        let shown = excerpt(&self.header, 40);
        if let Some(why) = self.failed {
            skipped.push(format!("column {shown:?}: {why}"));
            return;
        }
        let name = crate::attribute_name(&self.header, self.index);
        if let Some(why) = crate::attribute_conflict(&name, attributes) {
            skipped.push(format!("column {shown:?}: {why}"));
            return;
        }
        let values = match self.ints {
            Some(ints) => crate::AttributeValues::Int(ints),
            None => crate::AttributeValues::Float(self.floats),
        };
        attributes.push(crate::Attribute { name, values });
    }
}

/// The values of the column named `column` of a CSV file with a header.
pub(crate) fn read_column<R: BufRead>(
    reader: R,
    name: &str,
    column: &str,
) -> Result<Vec<f64>, IoError> {
    let mut lines = TextLines::new(reader);
    let Some((header_number, header, sep, _)) = first_line(&mut lines, name)? else {
        return Err(IoError::parse(
            name,
            Location::File,
            "no header (empty file)",
        ));
    };
    let wanted = normalise_name(column);
    let index = fields(&header, sep)
        .position(|h| normalise_name(h) == wanted)
        .ok_or_else(|| {
            IoError::parse(
                name,
                Location::Line(header_number),
                format!("no column named {column:?} in the header"),
            )
        })?;
    let mut values = Vec::new();
    while let Some((line_number, line)) = lines.next_line(name)? {
        let t = line.trim_start();
        if t.is_empty() || t.starts_with('#') {
            continue;
        }
        let field = fields(line, sep).nth(index).ok_or_else(|| {
            IoError::parse(
                name,
                Location::Line(line_number),
                format!("too few columns: no value for {column:?}"),
            )
        })?;
        let value = number_of(field, sep).ok_or_else(|| {
            IoError::parse(
                name,
                Location::Cell {
                    line: line_number,
                    column: index + 1,
                },
                format!(
                    "invalid number {:?} for {column}",
                    excerpt(trim_field(field), 40)
                ),
            )
        })?;
        values.push(value);
    }
    Ok(values)
}

pub(crate) fn write(
    out: &mut dyn Write,
    set: &AnyParticleSet,
    columns: &[(&str, Column<'_>)],
) -> std::io::Result<()> {
    let dim = set.dim();
    write!(out, "{}", AXES[..dim].join(","))?;
    for (name, _) in columns {
        write!(out, ",{name}")?;
    }
    writeln!(out)?;
    for i in 0..set.len() {
        for (k, v) in set.coords(i).iter().enumerate() {
            if k > 0 {
                write!(out, ",")?;
            }
            write!(out, "{}", Real(*v))?;
        }
        for (_, column) in columns {
            write!(out, ",")?;
            out::value(out, column, i)?;
        }
        writeln!(out)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::read_csv_header;

    #[test]
    fn separator_is_the_most_frequent() {
        assert_eq!(detect_separator("x,y,z"), ',');
        assert_eq!(detect_separator("Pos.x [m];Pos.y [m];Pos.z [m]"), ';');
        assert_eq!(detect_separator("x\ty\tz"), '\t');
        assert_eq!(detect_separator("a,b;c"), ';');
        assert_eq!(detect_separator("x"), ',');
    }

    #[test]
    fn decimal_comma_only_with_semicolons() {
        assert_eq!(number_of(" 0,5 ", ';'), Some(0.5));
        assert_eq!(number_of("0,5", ','), None);
        assert_eq!(number_of("\"-1e-3\"", ','), Some(-1e-3));
    }

    #[test]
    fn multibyte_text_at_the_sep_prefix_is_not_sliced() {
        // Found by the fuzz test: byte 4 inside a two-byte character.
        let e = read("|U\u{212}i\n".as_bytes(), "m.csv", None, false).unwrap_err();
        assert!(e.to_string().contains("missing position column"), "{e}");
        assert!(read("sep\u{212}\n".as_bytes(), "m.csv", None, false).is_err());
    }

    #[test]
    fn other_columns_are_read_as_attributes_when_asked() {
        use crate::AttributeValues::{Float, Int};
        let text = "idp;x;y;Vel.x [m/s];Type;px\n1;0,5;2;0,25;fluid;9\n2;1;3;-1;wall;8\n";
        let p = read(text.as_bytes(), "dsph.csv", None, true).unwrap();
        assert_eq!((p.stride, &p.coords), (2, &vec![0.5, 2.0, 1.0, 3.0]));
        let got: Vec<(&str, &crate::AttributeValues)> = p
            .attributes
            .iter()
            .map(|a| (a.name.as_str(), &a.values))
            .collect();
        assert_eq!(
            got,
            [
                ("idp", &Int(vec![1, 2])),
                ("Vel.x_[m/s]", &Float(vec![0.25, -1.0])),
            ]
        );
        // A text column and a name that would read back as a position are skipped, with why.
        assert_eq!(p.skipped.len(), 2, "{:?}", p.skipped);
        assert!(p.skipped[0].contains("\"Type\"") && p.skipped[0].contains("line 2"));
        assert!(p.skipped[1].contains("position"), "{:?}", p.skipped);
        // Without the flag nothing but the positions is parsed.
        let p = read(text.as_bytes(), "dsph.csv", None, false).unwrap();
        assert!(p.attributes.is_empty() && p.skipped.is_empty());
        // A short row drops the column, not the file.
        let p = read("x,y,a\n1,2,3\n4,5\n".as_bytes(), "s.csv", None, true).unwrap();
        assert!(p.attributes.is_empty());
        assert!(
            p.skipped[0].contains("no value on line 3"),
            "{:?}",
            p.skipped
        );
    }

    #[test]
    fn each_particle_keeps_the_line_it_was_read_from() {
        let text = "sep=;\n# comment\nx;y;h\n\n0;0;1\n# skipped\n1;0;2\n\n2;0;3\n";
        let p = read(text.as_bytes(), "l.csv", None, true).unwrap();
        let lines: Vec<Option<usize>> = (0..4).map(|i| p.lines.line(i)).collect();
        assert_eq!(lines, [Some(5), Some(7), Some(9), None]);
        assert_eq!(p.coords, [0.0, 0.0, 1.0, 0.0, 2.0, 0.0]);
        // Headerless: the first data line is particle 0.
        let text = "\n0,0\n1,1\n";
        let p = read(text.as_bytes(), "h.csv", None, false).unwrap();
        assert_eq!((p.lines.line(0), p.lines.line(1)), (Some(2), Some(3)));
    }

    #[test]
    fn rows_longer_than_the_header_are_errors_naming_the_line() {
        for attributes in [false, true] {
            let e = read("x,y\n1,2\n3,4,5\n".as_bytes(), "w.csv", None, attributes)
                .unwrap_err()
                .to_string();
            assert!(e.contains("w.csv") && e.contains("line 3"), "{e}");
            assert!(
                e.contains("too many values: 3") && e.contains("header names 2"),
                "{e}"
            );
        }
        // Headerless: the first row sets the width.
        let e = read("1,2,3\n4,5,6,7\n".as_bytes(), "h.csv", None, false)
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 2") && e.contains("first row has 3"), "{e}");
        // One trailing separator is not a value; a row as wide as the header is fine.
        let p = read("x,y,z\n1,2,3,\n4,5,6\n".as_bytes(), "t.csv", None, false).unwrap();
        assert_eq!(p.coords, vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
    }

    /// Reads `text` as a file in `parts` byte ranges, each part numbered by the counts of the
    /// parts before it (the exclusive prefix sum a parallel reader computes), and applies the
    /// whole-file checks: the set, or the first part's error.
    fn read_in_parts(
        path: &Path,
        options: &ReadOptions,
        parts: usize,
    ) -> Result<(AnyParticleSet, Option<usize>), String> {
        let header = read_csv_header(path, options).map_err(|e| e.to_string())?;
        let chunks: Vec<CsvChunk> = (0..parts)
            .map(|k| header.read_chunk(path, header.part(k, parts)))
            .collect::<Result<_, _>>()
            .map_err(|e| e.to_string())?;
        let (mut line, mut index) = (header.first_data_line(), 0);
        let mut coords = Vec::new();
        for chunk in &chunks {
            coords.extend(
                chunk
                    .parse(&header, line, index)
                    .map_err(|e| e.to_string())?,
            );
            line += chunk.newlines();
            index += chunk.rows();
        }
        let stride = header.stride();
        let constant: Vec<bool> = (0..stride)
            .map(|k| {
                let mut v = coords.iter().skip(k).step_by(stride);
                let first = v.next().copied();
                v.all(|&x| Some(x) == first)
            })
            .collect();
        header
            .finish(&coords, index, &constant)
            .map_err(|e| e.to_string())
    }

    /// Every split of the rows into parts, with ranges cutting lines anywhere (CRLF pairs
    /// and multi-byte characters included), reads what the whole-file read reads, and fails
    /// with its message (the same line and particle) where it fails.
    #[test]
    fn reading_in_byte_ranges_matches_the_whole_file_read() {
        let dir = tempfile::tempdir().unwrap();
        let texts = [
            "x,y,z\n0,0,0\n1,0,0\n2,1,0.5\n",
            "\u{feff}# made by hand\r\nx;y;z\r\n0,5;1;2\r\n\r\n# mid comment é\r\n3;4;5\r\n6;7;8",
            "sep=;\nx;y\n1;2\n  # indented comment\n3;4\n\n5;6\n",
            "\u{feff}1 , 2 , 3\n4,5,6\n# c\n7,8,9\n",
            "x,y,z\n1,2,0\n3,4,0\n5,6,0\n",
            "x,y,h\n0,0,1\n",
            "x,y\n# only a comment\n\n",
            "x,y\n1,2\n3,oops\n5,6\n",
            "x,y\n1,2\n3,4,5\n",
            "x,y\n1,2\n\n3,inf\n",
            "x,y,zz\n1,2,3\n",
            "x,y,z\n1,2,3\n\u{ff}\n",
            "",
        ];
        let mut texts: Vec<Vec<u8>> = texts.iter().map(|t| t.as_bytes().to_vec()).collect();
        texts.push(b"x,y\n1,2\n\xff\xfe\n3,4\n".to_vec());
        for (t, text) in texts.iter().enumerate() {
            let path = dir.path().join(format!("t{t}.csv"));
            std::fs::write(&path, text).unwrap();
            for dim in [None, Some(2), Some(3)] {
                let options = ReadOptions { dim, format: None };
                let whole = crate::read_positions(&path, &options)
                    .map(|f| (f.set, f.position_columns.dropped.is_some()))
                    .map_err(|e| e.to_string());
                for parts in 1..=text.len() + 2 {
                    let got = read_in_parts(&path, &options, parts)
                        .map(|(set, dropped)| (set, dropped.is_some()));
                    assert_eq!(got, whole, "text {t}, dim {dim:?}, {parts} parts");
                }
            }
        }
    }

    #[test]
    fn trailing_separator_and_excel_sep_line() {
        let text = "sep=;\nx;y;\n1,5;2;\n";
        let p = read(text.as_bytes(), "t.csv", None, false).unwrap();
        assert_eq!((p.stride, p.coords), (2, vec![1.5, 2.0]));
    }
}
