//! Legacy VTK: the `POINTS` section of any dataset, ascii or binary (big endian, as the format
//! prescribes).
//!
//! Hand-written rather than through `vtkio`: only `POINTS` is needed, the reader must never
//! panic on real files (vtkio 0.6's legacy parser can), and it must not allocate from the
//! declared count before the bytes are there.

use crate::{Column, IoError, Raw, MAX_PREALLOCATE};
use boundary_core::AnyParticleSet;
use std::io::Write;

/// Splits the next whitespace-delimited token off `bytes[*pos..]`.
fn token<'a>(bytes: &'a [u8], pos: &mut usize) -> Option<&'a [u8]> {
    while *pos < bytes.len() && bytes[*pos].is_ascii_whitespace() {
        *pos += 1;
    }
    let start = *pos;
    while *pos < bytes.len() && !bytes[*pos].is_ascii_whitespace() {
        *pos += 1;
    }
    (start < *pos).then(|| &bytes[start..*pos])
}

/// Position just after the end of the line containing `pos`.
fn next_line(bytes: &[u8], pos: usize) -> usize {
    bytes[pos..]
        .iter()
        .position(|&b| b == b'\n')
        .map_or(bytes.len(), |k| pos + k + 1)
}

pub(crate) fn read(bytes: &[u8], name: &str) -> Result<Raw, IoError> {
    let content = |message: String| IoError::Content {
        file: name.to_owned(),
        message,
    };
    if !bytes.starts_with(b"# vtk DataFile") {
        return Err(content(
            "not a legacy VTK file (no '# vtk DataFile' line)".into(),
        ));
    }
    // Line 2 is a free title, line 3 the encoding.
    let title_start = next_line(bytes, 0);
    let encoding_start = next_line(bytes, title_start);
    let mut pos = encoding_start;
    let encoding = token(bytes, &mut pos)
        .unwrap_or_default()
        .to_ascii_uppercase();
    let binary = match encoding.as_slice() {
        b"ASCII" => false,
        b"BINARY" => true,
        other => {
            return Err(content(format!(
                "line 3: expected ASCII or BINARY, got '{}'",
                String::from_utf8_lossy(other)
            )))
        }
    };
    // Find the POINTS keyword (sections before it, like DATASET, are skipped).
    loop {
        match token(bytes, &mut pos) {
            Some(t) if t.eq_ignore_ascii_case(b"POINTS") => break,
            Some(_) => {}
            None => return Err(content("no POINTS section".into())),
        }
    }
    let count_text = token(bytes, &mut pos).unwrap_or_default();
    let count: usize = std::str::from_utf8(count_text)
        .ok()
        .and_then(|s| s.parse().ok())
        .ok_or_else(|| {
            content(format!(
                "POINTS: bad count '{}'",
                String::from_utf8_lossy(count_text)
            ))
        })?;
    let ty = token(bytes, &mut pos)
        .unwrap_or_default()
        .to_ascii_lowercase();
    let size = match ty.as_slice() {
        b"float" => 4,
        b"double" => 8,
        other => {
            return Err(content(format!(
                "POINTS of type '{}' (float or double supported)",
                String::from_utf8_lossy(other)
            )))
        }
    };
    let values = count
        .checked_mul(3)
        .ok_or_else(|| content(format!("POINTS count {count} too large")))?;
    let mut coords = Vec::with_capacity(values.min(MAX_PREALLOCATE));
    if binary {
        let start = next_line(bytes, pos);
        let need = values
            .checked_mul(size)
            .ok_or_else(|| content(format!("POINTS count {count} too large")))?;
        let data = bytes
            .get(start..start.saturating_add(need))
            .ok_or_else(|| {
                content(format!(
                    "POINTS declares {count} points ({need} bytes) but only {} bytes follow",
                    bytes.len().saturating_sub(start)
                ))
            })?;
        for chunk in data.chunks_exact(size) {
            coords.push(if size == 4 {
                f64::from(f32::from_be_bytes([chunk[0], chunk[1], chunk[2], chunk[3]]))
            } else {
                let mut b = [0u8; 8];
                b.copy_from_slice(chunk);
                f64::from_be_bytes(b)
            });
        }
    } else {
        for k in 0..values {
            let t = token(bytes, &mut pos).ok_or_else(|| {
                content(format!(
                    "POINTS declares {count} points but the data ends after {}",
                    k / 3
                ))
            })?;
            let v: f64 = std::str::from_utf8(t)
                .ok()
                .and_then(|s| s.parse().ok())
                .ok_or_else(|| {
                    content(format!(
                        "point {}: '{}' is not a number",
                        k / 3,
                        String::from_utf8_lossy(t)
                    ))
                })?;
            coords.push(v);
        }
    }
    Ok(Raw { width: 3, coords })
}

pub(crate) fn write(
    out: &mut dyn Write,
    set: &AnyParticleSet,
    columns: &[(&str, Column<'_>)],
) -> std::io::Result<()> {
    let n = set.len();
    writeln!(
        out,
        "# vtk DataFile Version 3.0\nparticles written by boundary-io\nASCII\nDATASET POLYDATA"
    )?;
    writeln!(out, "POINTS {n} double")?;
    for i in 0..n {
        let c = set.coords(i);
        // VTK points always have three components: a 2D set gets z = 0 here only.
        let z = c.get(2).copied().unwrap_or(0.0);
        writeln!(out, "{} {} {}", c[0], c[1], z)?;
    }
    writeln!(out, "VERTICES {n} {}", 2 * n)?;
    for i in 0..n {
        writeln!(out, "1 {i}")?;
    }
    if !columns.is_empty() {
        writeln!(out, "POINT_DATA {n}")?;
        for (name, column) in columns {
            let ty = match column {
                Column::Int(_) => "int",
                Column::Float(_) => "double",
            };
            writeln!(out, "SCALARS {name} {ty} 1\nLOOKUP_TABLE default")?;
            for i in 0..n {
                writeln!(out, "{}", column.text(i))?;
            }
        }
    }
    Ok(())
}
