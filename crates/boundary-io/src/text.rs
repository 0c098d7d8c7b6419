//! Helpers shared by the text formats.

use crate::IoError;

/// The bytes as UTF-8 text (a leading byte-order mark is skipped).
pub(crate) fn utf8<'a>(bytes: &'a [u8], name: &str) -> Result<&'a str, IoError> {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    std::str::from_utf8(bytes).map_err(|e| {
        let line = 1 + bytes[..e.valid_up_to()]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        IoError::Line {
            file: name.to_owned(),
            line,
            message: "not UTF-8 text (a binary file with a text extension?)".into(),
        }
    })
}

/// Parses a number field; the error says which column and what was found.
pub(crate) fn number(
    field: &str,
    name: &str,
    line: usize,
    column: usize,
    header: Option<&str>,
) -> Result<f64, IoError> {
    let field = field.trim().trim_matches('"');
    let value: f64 = field.parse().map_err(|_| IoError::Line {
        file: name.to_owned(),
        line,
        message: match header {
            Some(h) => format!("column {} ('{h}'): '{field}' is not a number", column + 1),
            None => format!("column {}: '{field}' is not a number", column + 1),
        },
    })?;
    if !value.is_finite() {
        return Err(IoError::Line {
            file: name.to_owned(),
            line,
            message: format!("column {}: coordinate '{field}' is not finite", column + 1),
        });
    }
    Ok(value)
}

/// Whether the line carries data (not blank, not a `#` comment).
pub(crate) fn is_data(line: &str) -> bool {
    let t = line.trim();
    !t.is_empty() && !t.starts_with('#')
}
