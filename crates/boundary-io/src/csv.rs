//! CSV: a header naming the position columns, or headerless numbers.

use crate::text::{is_data, number};
use crate::{Column, IoError, Raw, AXES, MAX_PREALLOCATE};
use boundary_core::AnyParticleSet;
use std::io::Write;

/// The separator of a line: `;`, else `,`, else tab, else `,` (single column).
fn separator(line: &str) -> char {
    if line.contains(';') {
        ';'
    } else if line.contains(',') {
        ','
    } else if line.contains('\t') {
        '\t'
    } else {
        ','
    }
}

/// The axis a header names, if any: `x`, `Pos.x [m]`, `position_x`, `px`, `Points:0`, … .
pub(crate) fn axis_of(header: &str) -> Option<usize> {
    let mut h = header.trim().trim_matches('"').trim().to_ascii_lowercase();
    // Drop a unit suffix: `pos.x [m]`, `x (m)`.
    if let Some(k) = h.find(['[', '(']) {
        h.truncate(k);
    }
    let key: String = h
        .chars()
        .filter(|c| !matches!(c, '.' | '_' | ':' | ' ' | '-'))
        .collect();
    match key.as_str() {
        "x" | "posx" | "positionx" | "px" | "points0" | "coordx" | "coordsx" | "x0" => Some(0),
        "y" | "posy" | "positiony" | "py" | "points1" | "coordy" | "coordsy" | "x1" => Some(1),
        "z" | "posz" | "positionz" | "pz" | "points2" | "coordz" | "coordsz" | "x2" => Some(2),
        _ => None,
    }
}

/// The data lines with their 1-based numbers.
fn lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.lines()
        .enumerate()
        .map(|(k, l)| (k + 1, l.trim_end_matches('\r')))
        .filter(|(_, l)| is_data(l))
}

fn starts_with_number(line: &str, sep: char) -> bool {
    line.split(sep)
        .next()
        .map(|f| f.trim().trim_matches('"').parse::<f64>().is_ok())
        .unwrap_or(false)
}

pub(crate) fn read(text: &str, name: &str, dim: Option<usize>) -> Result<Raw, IoError> {
    let mut rows = lines(text).peekable();
    let Some(&(first_line, first)) = rows.peek() else {
        return Err(IoError::Content {
            file: name.to_owned(),
            message: "no data (empty file)".into(),
        });
    };
    let sep = separator(first);
    // Column index of each axis, and the header names for messages.
    let (columns, headers): (Vec<usize>, Vec<String>) = if starts_with_number(first, sep) {
        let count = first.split(sep).count();
        let width = dim.unwrap_or(if count >= 3 { 3 } else { 2 });
        if count < width {
            return Err(IoError::Line {
                file: name.to_owned(),
                line: first_line,
                message: format!("{count} columns, {width} coordinates needed"),
            });
        }
        ((0..width).collect(), Vec::new())
    } else {
        rows.next();
        let names: Vec<&str> = first.split(sep).collect();
        let mut found = [None; 3];
        for (c, h) in names.iter().enumerate() {
            if let Some(a) = axis_of(h) {
                found[a].get_or_insert(c);
            }
        }
        let width = match (found[0], found[1], found[2]) {
            (Some(_), Some(_), Some(_)) => 3,
            (Some(_), Some(_), None) => 2,
            _ => {
                return Err(IoError::Line {
                    file: name.to_owned(),
                    line: first_line,
                    message: format!(
                        "header has no x and y columns (found: {})",
                        names
                            .iter()
                            .map(|h| h.trim())
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                })
            }
        };
        let columns: Vec<usize> = found[..width].iter().map(|c| c.unwrap_or(0)).collect();
        let headers = columns
            .iter()
            .map(|&c| names[c].trim().to_owned())
            .collect();
        (columns, headers)
    };
    let width = columns.len();
    let needed = columns.iter().copied().max().unwrap_or(0) + 1;
    let mut coords = Vec::with_capacity((text.len() / 8).min(MAX_PREALLOCATE));
    let mut fields: Vec<&str> = Vec::new();
    for (line, row) in rows {
        fields.clear();
        fields.extend(row.split(sep));
        if fields.len() < needed {
            return Err(IoError::Line {
                file: name.to_owned(),
                line,
                message: format!("{} columns, at least {needed} expected", fields.len()),
            });
        }
        for (a, &c) in columns.iter().enumerate() {
            let header = headers.get(a).map(String::as_str).or(Some(AXES[a]));
            coords.push(number(fields[c], name, line, c, header)?);
        }
    }
    Ok(Raw { width, coords })
}

/// The values of the column named `column` (case-insensitive).
pub(crate) fn read_column(text: &str, name: &str, column: &str) -> Result<Vec<f64>, IoError> {
    let mut rows = lines(text);
    let Some((header_line, header)) = rows.next() else {
        return Err(IoError::Content {
            file: name.to_owned(),
            message: "no data (empty file)".into(),
        });
    };
    let sep = separator(header);
    let index = header
        .split(sep)
        .position(|h| h.trim().trim_matches('"').eq_ignore_ascii_case(column))
        .ok_or_else(|| IoError::Line {
            file: name.to_owned(),
            line: header_line,
            message: format!("no column named '{column}' in the header"),
        })?;
    rows.map(|(line, row)| {
        let field = row.split(sep).nth(index).ok_or_else(|| IoError::Line {
            file: name.to_owned(),
            line,
            message: format!("no value for column '{column}'"),
        })?;
        number(field, name, line, index, Some(column))
    })
    .collect()
}

pub(crate) fn write(
    out: &mut dyn Write,
    set: &AnyParticleSet,
    columns: &[(&str, Column<'_>)],
) -> std::io::Result<()> {
    let dim = set.dim();
    let mut header: Vec<&str> = AXES[..dim].to_vec();
    header.extend(columns.iter().map(|(n, _)| *n));
    writeln!(out, "{}", header.join(","))?;
    for i in 0..set.len() {
        let mut fields: Vec<String> = set.coords(i).iter().map(|v| v.to_string()).collect();
        fields.extend(columns.iter().map(|(_, c)| c.text(i)));
        writeln!(out, "{}", fields.join(","))?;
    }
    Ok(())
}
