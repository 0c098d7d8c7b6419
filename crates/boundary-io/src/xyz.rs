//! XYZ: whitespace-separated numbers, one particle per line.

use crate::text::{is_data, number};
use crate::{Column, IoError, Raw, AXES, MAX_PREALLOCATE};
use boundary_core::AnyParticleSet;
use std::io::Write;

pub(crate) fn read(text: &str, name: &str, dim: Option<usize>) -> Result<Raw, IoError> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(k, l)| (k + 1, l.trim_end_matches('\r')))
        .peekable();
    // The chemistry convention: a count line, a free comment line, then `Symbol x y z` rows.
    let mut declared = None;
    if let Some(&(_, first)) = lines.peek() {
        let tokens: Vec<&str> = first.split_whitespace().collect();
        if let [count] = tokens.as_slice() {
            if let Ok(count) = count.parse::<usize>() {
                declared = Some(count);
                lines.next();
                lines.next();
            }
        }
    }
    // A comment line naming the columns (`# x y [z] …`, as our writer puts first) says whether
    // there is a z column; otherwise three or more values per line mean 3D.
    let named = text
        .lines()
        .take_while(|l| !is_data(l))
        .filter_map(|l| l.trim().strip_prefix('#'))
        .map(|l| {
            l.split_whitespace()
                .filter_map(crate::csv::axis_of)
                .collect::<Vec<_>>()
        })
        .find(|axes| axes.contains(&0) && axes.contains(&1));
    let mut width = dim.or_else(|| named.map(|axes| if axes.contains(&2) { 3 } else { 2 }));
    let mut coords = Vec::with_capacity((text.len() / 8).min(MAX_PREALLOCATE));
    let mut rows = 0usize;
    for (line, row) in lines.filter(|(_, l)| is_data(l)) {
        let mut tokens: Vec<&str> = row.split_whitespace().collect();
        // A leading element symbol (chemistry XYZ) is skipped.
        if declared.is_some() && tokens.first().is_some_and(|t| t.parse::<f64>().is_err()) {
            tokens.remove(0);
        }
        let w = *width.get_or_insert(if tokens.len() >= 3 { 3 } else { 2 });
        if tokens.len() < w {
            return Err(IoError::Line {
                file: name.to_owned(),
                line,
                message: format!("{} values, {w} coordinates expected", tokens.len()),
            });
        }
        for (c, t) in tokens[..w].iter().enumerate() {
            coords.push(number(t, name, line, c, Some(AXES[c]))?);
        }
        rows += 1;
    }
    if let Some(count) = declared {
        if count != rows {
            return Err(IoError::Content {
                file: name.to_owned(),
                message: format!("the first line declares {count} particles, {rows} found"),
            });
        }
    }
    match width {
        Some(width) => Ok(Raw { width, coords }),
        None => Err(IoError::Content {
            file: name.to_owned(),
            message: "no data (empty file)".into(),
        }),
    }
}

pub(crate) fn write(
    out: &mut dyn Write,
    set: &AnyParticleSet,
    columns: &[(&str, Column<'_>)],
) -> std::io::Result<()> {
    let mut header: Vec<&str> = AXES[..set.dim()].to_vec();
    header.extend(columns.iter().map(|(n, _)| *n));
    writeln!(out, "# {}", header.join(" "))?;
    for i in 0..set.len() {
        let mut fields: Vec<String> = set.coords(i).iter().map(|v| v.to_string()).collect();
        fields.extend(columns.iter().map(|(_, c)| c.text(i)));
        writeln!(out, "{}", fields.join(" "))?;
    }
    Ok(())
}
