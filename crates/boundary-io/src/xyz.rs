//! XYZ: whitespace-separated numbers, one particle per line (crate docs, "Reading").

use crate::error::{excerpt, IoError, Location};
use crate::out::{self, Real, AXES};
use crate::text::{
    find_near_miss, parse_number, position_axis, select_position_columns, TextLines,
};
use crate::{Column, NearMiss, Positions, MAX_PREALLOCATE};
use boundary_core::AnyParticleSet;
use std::io::{BufRead, Write};

/// How the columns of the data lines are chosen.
enum Layout {
    /// Not yet known: the first data line decides (2 values: x y; 3 or more: x y z).
    Unknown,
    /// Named by a `# x y [z] …` comment: these column indices, in axis order.
    Named(Vec<usize>),
    /// The first `stride` columns.
    Leading(usize),
}

pub(crate) fn read<R: BufRead>(reader: R, name: &str) -> Result<Positions, IoError> {
    let mut lines = TextLines::new(reader);
    let mut layout = Layout::Unknown;
    // `(line of the count, count)` for the count + comment header.
    let mut declared: Option<(usize, usize)> = None;
    let mut coords = Vec::new();
    let mut index = 0usize;
    let mut first = true;
    // The names of a `# x y [z] …` line, its line, and a column there that looks like a
    // misspelt third axis.
    let mut column_names = Vec::new();
    let mut names_line = None;
    let mut near_miss = None;
    while let Some((line_number, line)) = lines.next_line(name)? {
        let t = line.trim();
        if first && !t.is_empty() {
            first = false;
            if let Ok(count) = t.parse::<usize>() {
                if t.bytes().all(|b| b.is_ascii_digit()) {
                    declared = Some((line_number, count));
                    coords.reserve(count.saturating_mul(3).min(MAX_PREALLOCATE));
                    // The next line is a free comment, whatever it holds.
                    lines.next_line(name)?;
                    continue;
                }
            }
        }
        if t.is_empty() {
            continue;
        }
        if let Some(comment) = t.strip_prefix('#') {
            if index == 0 && matches!(layout, Layout::Unknown) {
                let names: Vec<&str> = comment.split_whitespace().collect();
                let named = |axis| {
                    names
                        .iter()
                        .any(|n| position_axis(n).map(|a| a.0) == Some(axis))
                };
                if named(0) && named(1) {
                    let columns = select_position_columns(names.iter().copied())
                        .map_err(|m| IoError::parse(name, Location::Line(line_number), m))?;
                    if columns.len() == 2 {
                        let missing = (0..3)
                            .find(|&a| {
                                columns
                                    .iter()
                                    .all(|&c| position_axis(names[c]).map(|p| p.0) != Some(a))
                            })
                            .unwrap_or(2);
                        near_miss =
                            find_near_miss(names.iter().copied(), missing, &columns).map(|c| {
                                NearMiss {
                                    at: Location::Cell {
                                        line: line_number,
                                        column: c + 1,
                                    },
                                    vertex_property: false,
                                    name: excerpt(names[c], 40),
                                    axis: missing,
                                }
                            });
                    }
                    column_names = columns.iter().map(|&c| excerpt(names[c], 40)).collect();
                    names_line = Some(line_number);
                    layout = Layout::Named(columns);
                }
            }
            continue;
        }
        if let Some((_, count)) = declared {
            if index == count {
                // Later lines (further frames of a trajectory) are not read.
                break;
            }
        }
        let mut tokens: Vec<&str> = t.split_whitespace().collect();
        // A leading element symbol in the chemistry convention (`H 0.0 1.0 2.0`).
        if declared.is_some()
            && tokens.first().is_some_and(|s| {
                s.starts_with(|c: char| c.is_ascii_alphabetic()) && parse_number(s).is_none()
            })
        {
            tokens.remove(0);
        }
        if matches!(layout, Layout::Unknown) {
            layout = match tokens.len() {
                0 | 1 => {
                    return Err(IoError::parse(
                        name,
                        Location::Line(line_number),
                        format!("too few columns: {}, need 2 or 3 coordinates", tokens.len()),
                    ))
                }
                2 => Layout::Leading(2),
                _ => Layout::Leading(3),
            };
        }
        let columns: &[usize] = match &layout {
            Layout::Named(c) => c,
            Layout::Leading(2) => &[0, 1],
            _ => &[0, 1, 2],
        };
        let needed = columns.iter().copied().max().unwrap_or(0) + 1;
        if tokens.len() < needed {
            return Err(IoError::parse(
                name,
                Location::Line(line_number),
                format!("too few columns: {}, need {needed}", tokens.len()),
            ));
        }
        for (axis, &c) in columns.iter().enumerate() {
            let at = Location::Cell {
                line: line_number,
                column: c + 1,
            };
            let value = parse_number(tokens[c]).ok_or_else(|| {
                IoError::parse(
                    name,
                    at,
                    format!(
                        "invalid number {:?} for {}",
                        excerpt(tokens[c], 40),
                        AXES[axis]
                    ),
                )
            })?;
            if !value.is_finite() {
                return Err(IoError::NonFinite {
                    file: name.to_owned(),
                    at,
                    index,
                    axis,
                    value,
                });
            }
            coords.push(value);
        }
        index += 1;
    }
    if let Some((line, count)) = declared {
        if index < count {
            return Err(IoError::parse(
                name,
                Location::Line(line),
                format!("declared {count} particles but the file holds {index}"),
            ));
        }
    }
    let stride = match layout {
        Layout::Named(c) => c.len(),
        Layout::Leading(s) => s,
        Layout::Unknown if declared.is_some() => 3,
        Layout::Unknown => {
            return Err(IoError::NoParticles {
                file: name.to_owned(),
                dim: None,
                detail: "the file holds no particle line (empty file)".to_owned(),
            })
        }
    };
    let empty = match (declared, names_line) {
        (Some((line, count)), _) => {
            format!("its count line (line {line}) declares {count} particles")
        }
        (None, Some(line)) => {
            format!(
                "the names line {line} (# {}) is followed by no particle line",
                column_names.join(" ")
            )
        }
        (None, None) => "the file holds no particle line".to_owned(),
    };
    Ok(Positions {
        coords,
        stride,
        padded_2d: false,
        names: column_names,
        near_miss,
        empty: Some(empty),
        ..Default::default()
    })
}

pub(crate) fn write(
    out: &mut dyn Write,
    set: &AnyParticleSet,
    columns: &[(&str, Column<'_>)],
) -> std::io::Result<()> {
    write!(out, "# {}", AXES[..set.dim()].join(" "))?;
    for (name, _) in columns {
        write!(out, " {name}")?;
    }
    writeln!(out)?;
    for i in 0..set.len() {
        for (k, v) in set.coords(i).iter().enumerate() {
            if k > 0 {
                write!(out, " ")?;
            }
            write!(out, "{}", Real(*v))?;
        }
        for (_, column) in columns {
            write!(out, " ")?;
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
    fn count_header_with_zero_particles_is_an_empty_3d_file() {
        let p = read("0\ncomment\n".as_bytes(), "e.xyz").unwrap();
        assert_eq!((p.stride, p.coords.len()), (3, 0));
    }

    #[test]
    fn named_comment_picks_columns() {
        let p = read("# id x y\n7 1 2\n8 3 4\n".as_bytes(), "n.xyz").unwrap();
        assert_eq!((p.stride, p.coords), (2, vec![1.0, 2.0, 3.0, 4.0]));
    }

    #[test]
    fn later_frames_are_not_read() {
        let text = "2\nframe 0\nH 0 0 0\nH 1 0 0\n2\nframe 1\nH 5 5 5\nH 6 5 5\n";
        let p = read(text.as_bytes(), "t.xyz").unwrap();
        assert_eq!(p.coords, vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0]);
    }
}
