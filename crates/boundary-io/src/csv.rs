//! CSV: a header naming the position columns, or headerless numbers (crate docs, "Reading").

use crate::error::{excerpt, IoError, Location};
use crate::out::{self, Real, AXES};
use crate::text::{
    find_near_miss, normalise_name, position_axis, select_position_columns, trim_field, TextLines,
};
use crate::{Column, LineIndex, NearMiss, Positions};
use boundary_core::AnyParticleSet;
use std::io::{BufRead, Write};

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
fn number(field: &str, sep: char) -> Option<f64> {
    let f = trim_field(field);
    f.parse::<f64>()
        .ok()
        .or_else(|| (sep == ';' && f.contains(',')).then(|| f.replace(',', ".").parse().ok())?)
}

/// The first line that is neither blank nor a `#` comment, with the separator (from a
/// `sep=X` line if there is one).
fn first_line<R: BufRead>(
    lines: &mut TextLines<R>,
    name: &str,
) -> Result<Option<(usize, String, char)>, IoError> {
    let mut forced = None;
    while let Some((number, line)) = lines.next_line(name)? {
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
        return Ok(Some((number, line.to_owned(), sep)));
    }
    Ok(None)
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
    let Some((first_number, first, sep)) = first_line(&mut lines, name)? else {
        return Err(IoError::NoParticles {
            file: name.to_owned(),
            dim: None,
            detail: "the file holds no header and no data row (empty file)".to_owned(),
        });
    };
    let first_fields: Vec<&str> = fields(&first, sep).collect();
    let headerless = first_fields.iter().all(|f| number(f, sep).is_some());
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
                Location::Line(first_number),
                format!("too few columns in a headerless file: {count}, need {stride} coordinates"),
            ));
        }
        (
            (0..stride).collect(),
            AXES[..stride].iter().map(|s| (*s).to_owned()).collect(),
        )
    } else {
        let columns = select_position_columns(first_fields.iter().copied())
            .map_err(|m| IoError::parse(name, Location::Line(first_number), m))?;
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
                line: first_number,
                column: c + 1,
            },
            vertex_property: false,
            name: excerpt(trim_field(first_fields[c]), 40),
            axis: missing,
        })
    };
    // The other named columns, kept as attributes while all their values are numbers.
    let mut extra: Vec<ExtraColumn> = if with_attributes && !headerless {
        first_fields
            .iter()
            .enumerate()
            .filter(|(c, _)| !columns.contains(c))
            .map(|(c, f)| ExtraColumn::new(c, f))
            .collect()
    } else {
        Vec::new()
    };
    let needed = columns.iter().copied().max().unwrap_or(0) + 1;
    // Position k of the particle's row for each field index < needed, or usize::MAX.
    let mut slot = vec![usize::MAX; needed];
    for (k, &c) in columns.iter().enumerate() {
        slot[c] = k;
    }
    let mut coords = Vec::new();
    let mut line_index = LineIndex::default();
    let mut row = [0.0f64; 3];
    let mut index = 0usize;
    // Policy: a row may not have more values than the header has columns (or, headerless,
    // than the first row has values): such a row is misaligned data, not something to
    // silently cut. One trailing separator is not a value (see `fields`).
    let width = first_fields.len();
    let width_source = if headerless {
        "the first row has"
    } else {
        "the header names"
    };
    let mut parse_row = |line_number: usize, line: &str, coords: &mut Vec<f64>| {
        let count = fields(line, sep).count();
        if count > width {
            return Err(IoError::parse(
                name,
                Location::Line(line_number),
                format!("too many values: {count}, {width_source} {width} columns"),
            ));
        }
        let mut seen = 0;
        for (c, field) in fields(line, sep).enumerate().take(needed) {
            seen = c + 1;
            let k = slot[c];
            if k == usize::MAX {
                continue;
            }
            let at = Location::Cell {
                line: line_number,
                column: c + 1,
            };
            let value = number(field, sep).ok_or_else(|| {
                IoError::parse(
                    name,
                    at,
                    format!(
                        "invalid number {:?} for {}",
                        excerpt(trim_field(field), 40),
                        labels[k]
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
        if seen < needed {
            return Err(IoError::parse(
                name,
                Location::Line(line_number),
                format!("too few columns: {seen}, need {needed}"),
            ));
        }
        coords.extend_from_slice(&row[..stride]);
        line_index.push(line_number);
        index += 1;
        if !extra.is_empty() {
            let all: Vec<&str> = fields(line, sep).collect();
            for column in &mut extra {
                column.push(all.get(column.index).copied(), sep, line_number);
            }
        }
        Ok(())
    };
    if headerless {
        parse_row(first_number, &first, &mut coords)?;
    }
    while let Some((line_number, line)) = lines.next_line(name)? {
        let t = line.trim_start();
        if t.is_empty() || t.starts_with('#') {
            continue;
        }
        parse_row(line_number, line, &mut coords)?;
    }
    let mut attributes = Vec::new();
    let mut skipped = Vec::new();
    for column in extra {
        column.finish(&mut attributes, &mut skipped);
    }
    let empty = (!headerless).then(|| {
        format!(
            "the header on line {first_number} ({}) is followed by no data row",
            excerpt(&labels.join(", "), 80)
        )
    });
    Ok(Positions {
        coords,
        stride,
        attributes,
        skipped,
        names: if headerless { Vec::new() } else { labels },
        near_miss,
        empty,
        lines: line_index,
        ..Default::default()
    })
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
        match number(field, sep) {
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
    let Some((header_number, header, sep)) = first_line(&mut lines, name)? else {
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
        let value = number(field, sep).ok_or_else(|| {
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
        assert_eq!(number(" 0,5 ", ';'), Some(0.5));
        assert_eq!(number("0,5", ','), None);
        assert_eq!(number("\"-1e-3\"", ','), Some(-1e-3));
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

    #[test]
    fn trailing_separator_and_excel_sep_line() {
        let text = "sep=;\nx;y;\n1,5;2;\n";
        let p = read(text.as_bytes(), "t.csv", None, false).unwrap();
        assert_eq!((p.stride, p.coords), (2, vec![1.5, 2.0]));
    }
}
