//! PLY through `ply-rs-bw` (ascii, binary little and big endian): element `vertex` with
//! properties `x, y[, z]` of any numeric type.

use crate::{Column, IoError, Raw, AXES};
use boundary_core::AnyParticleSet;
use ply_rs_bw::parser::Parser;
use ply_rs_bw::ply::{DefaultElement, Property};
use std::io::Write;

fn scalar(p: &Property) -> Option<f64> {
    Some(match *p {
        Property::Char(v) => f64::from(v),
        Property::UChar(v) => f64::from(v),
        Property::Short(v) => f64::from(v),
        Property::UShort(v) => f64::from(v),
        Property::Int(v) => f64::from(v),
        Property::UInt(v) => f64::from(v),
        Property::Float(v) => f64::from(v),
        Property::Double(v) => v,
        _ => return None,
    })
}

pub(crate) fn read(bytes: &[u8], name: &str) -> Result<Raw, IoError> {
    let content = |message: String| IoError::Content {
        file: name.to_owned(),
        message,
    };
    // The parser is a third-party crate: a panic inside it must not reach the user.
    let parsed = std::panic::catch_unwind(|| {
        let mut source = bytes;
        Parser::<DefaultElement>::new().read_ply(&mut source)
    })
    .map_err(|_| content("malformed PLY (the parser gave up)".into()))?
    .map_err(|e| content(format!("malformed PLY: {e}")))?;
    let vertices = parsed
        .payload
        .get("vertex")
        .ok_or_else(|| content("no element 'vertex'".into()))?;
    let declared = parsed
        .header
        .elements
        .get("vertex")
        .map(|e| e.properties.keys().cloned().collect::<Vec<String>>())
        .unwrap_or_default();
    let has = |p: &str| declared.iter().any(|k| k == p);
    let width = match (has("x"), has("y"), has("z")) {
        (true, true, true) => 3,
        (true, true, false) => 2,
        _ => {
            return Err(content(format!(
                "element 'vertex' has no x and y properties (found: {})",
                declared.join(", ")
            )))
        }
    };
    let mut coords = Vec::with_capacity(vertices.len() * width);
    for (i, v) in vertices.iter().enumerate() {
        for axis in AXES.iter().take(width) {
            let value = v.get(*axis).and_then(scalar).ok_or_else(|| {
                content(format!(
                    "vertex {i}: property {axis} missing or not a scalar"
                ))
            })?;
            coords.push(value);
        }
    }
    Ok(Raw { width, coords })
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
    for (name, column) in columns {
        let ty = match column {
            Column::Int(_) => "int",
            Column::Float(_) => "double",
        };
        writeln!(out, "property {ty} {name}")?;
    }
    writeln!(out, "end_header")?;
    for i in 0..set.len() {
        let mut fields: Vec<String> = set.coords(i).iter().map(|v| v.to_string()).collect();
        fields.extend(columns.iter().map(|(_, c)| c.text(i)));
        writeln!(out, "{}", fields.join(" "))?;
    }
    Ok(())
}
