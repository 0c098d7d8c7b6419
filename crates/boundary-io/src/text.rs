//! Line-oriented reading of text formats, and the naming conventions of position columns shared
//! by the CSV header and the XYZ comment header.

use crate::error::{excerpt, IoError, Location};
use std::io::BufRead;

/// Reads a text file line by line, counting lines (1-based) and checking UTF-8 per line, so that
/// a non-UTF-8 byte is reported with its line and nothing is decoded twice.
pub(crate) struct TextLines<R> {
    reader: R,
    buf: Vec<u8>,
    line: usize,
    /// Bytes consumed so far.
    offset: u64,
}

impl<R: BufRead> TextLines<R> {
    pub(crate) fn new(reader: R) -> Self {
        TextLines {
            reader,
            buf: Vec::new(),
            line: 0,
            offset: 0,
        }
    }

    /// The byte offset of the next line: the bytes of the lines read so far.
    pub(crate) fn offset(&self) -> u64 {
        self.offset
    }

    /// The next line without its `\n` / `\r\n` terminator, with its 1-based number; `None` at
    /// the end of the input. A UTF-8 byte-order mark at the start of the file is dropped.
    pub(crate) fn next_line(&mut self, file: &str) -> Result<Option<(usize, &str)>, IoError> {
        self.buf.clear();
        let n = self
            .reader
            .read_until(b'\n', &mut self.buf)
            .map_err(|e| IoError::read(file, e))?;
        if n == 0 {
            return Ok(None);
        }
        self.offset += n as u64;
        self.line += 1;
        line_text(&self.buf, self.line, file).map(|text| Some((self.line, text)))
    }
}

/// The text of line number `line` (1-based) from its bytes: without its `\n` / `\r\n`
/// terminator, and on line 1 without a UTF-8 byte-order mark. Errors: invalid UTF-8, naming
/// the line.
pub(crate) fn line_text<'a>(bytes: &'a [u8], line: usize, file: &str) -> Result<&'a str, IoError> {
    let bytes = bytes.strip_suffix(b"\n").unwrap_or(bytes);
    let bytes = bytes.strip_suffix(b"\r").unwrap_or(bytes);
    let text = std::str::from_utf8(bytes).map_err(|e| {
        IoError::parse(
            file,
            Location::Line(line),
            format!(
                "invalid UTF-8 text (byte {} of the line)",
                e.valid_up_to() + 1
            ),
        )
    })?;
    Ok(if line == 1 {
        text.strip_prefix('\u{feff}').unwrap_or(text)
    } else {
        text
    })
}

/// Trims spaces and quotes around a field.
pub(crate) fn trim_field(field: &str) -> &str {
    field.trim_matches(|c: char| c.is_whitespace() || c == '"' || c == '\'')
}

/// Parses a decimal number (Rust's `f64` syntax: `1`, `-2.5e-3`, `inf`, `NaN`; finiteness is
/// checked by the caller, which knows the particle and the line).
pub(crate) fn parse_number(field: &str) -> Option<f64> {
    trim_field(field).parse::<f64>().ok()
}

/// Normalises a column name for matching: spaces and quotes trimmed, a unit suffix in brackets
/// or parentheses removed (`Pos.x [m]` → `pos.x`), lower-cased.
pub(crate) fn normalise_name(name: &str) -> String {
    let name = trim_field(name);
    let cut = name.find(['[', '(']).unwrap_or(name.len());
    trim_field(&name[..cut]).to_ascii_lowercase()
}

/// Prefixes that, followed by an optional separator (`.`, `_`, `:`, `-`, space) and an axis,
/// name a position column: `pos.x`, `Position_y`, `Points:2`, `coords.z`. Longest first, so
/// that `positions` is not read as `position` + `s`.
const POSITION_PREFIXES: [&str; 9] = [
    "coordinates",
    "positions",
    "position",
    "coords",
    "coord",
    "points",
    "point",
    "pos",
    "p",
];

/// The position axis (0, 1, 2) a column name denotes, with a priority: 0 for the bare names
/// `x`, `y`, `z`; 1 for prefixed names (`pos.x`, `Pos.x [m]`, `position_x`, `px`,
/// `Points:0`). An axis given by a digit (`Points:0`, ParaView's CSV export) needs a prefix
/// longer than `p` and a separator, so that `p0` (say, a pressure) is not a position.
pub(crate) fn position_axis(name: &str) -> Option<(usize, u8)> {
    let n = normalise_name(name);
    let letter = |s: &str| match s {
        "x" => Some(0),
        "y" => Some(1),
        "z" => Some(2),
        _ => None,
    };
    if let Some(axis) = letter(&n) {
        return Some((axis, 0));
    }
    for prefix in POSITION_PREFIXES {
        let Some(rest) = n.strip_prefix(prefix) else {
            continue;
        };
        let (separated, rest) = match rest.strip_prefix(['.', '_', ':', '-', ' ']) {
            Some(r) => (true, r),
            None => (false, rest),
        };
        if let Some(axis) = letter(rest) {
            return Some((axis, 1));
        }
        if separated && prefix != "p" {
            if let Some(axis) = match rest {
                "0" => Some(0),
                "1" => Some(1),
                "2" => Some(2),
                _ => None,
            } {
                return Some((axis, 1));
            }
        }
    }
    None
}

/// Names that, after an axis letter, still name a position (`zpos`, `z_coord`): the words of
/// [`POSITION_PREFIXES`] and their other forms.
const POSITION_WORDS: [&str; 9] = [
    "coordinates",
    "coordinate",
    "coords",
    "coord",
    "positions",
    "position",
    "pos",
    "points",
    "point",
];

/// Whether the column `name` is a *near miss* of the position axis `axis` (0, 1, 2 for `x`,
/// `y`, `z`): a name that is not a position name itself ([`position_axis`] is `None`) but one
/// a typo or a tool's decoration away from the axis letter, so that a file naming x and y
/// and, say, `zz` would otherwise be read as 2D without a word.
///
/// Precisely: the name is normalised as for matching ([`normalise_name`]: spaces and quotes
/// trimmed, a unit suffix in brackets or parentheses dropped, lower-cased), optionally loses
/// one position prefix (`pos`, `position`, `coords`, `points`, `p`, …, see
/// [`POSITION_PREFIXES`]), and what remains is kept letters only; that is then
///
/// - the axis letter more than once, with or without other characters: `zz`, `zzz`, `z z`;
/// - the axis letter once with other characters that are no letters (digits, `_`, `.`, `:`,
///   `-`, spaces, brackets inside the name): `z_`, `_z`, `z1`, `z0`, `z.`, `Pos.z_`;
/// - the axis letter followed by a position word (`pos`, `position`, `coord`, `coordinate`,
///   `point`, plural forms): `zpos`, `z_coord`, `Z-Position`.
///
/// Differences of case, surrounding spaces or quotes and a unit suffix are *not* near misses:
/// `Z`, `␣z`, `"z"` and `z [m]` name the axis and are read as it.
pub(crate) fn near_miss(name: &str, axis: usize) -> bool {
    if position_axis(name).is_some() {
        return false;
    }
    let letter = ['x', 'y', 'z'][axis];
    let n = normalise_name(name);
    std::iter::once(n.as_str())
        .chain(POSITION_PREFIXES.iter().filter_map(|p| n.strip_prefix(p)))
        .any(|rest| {
            let letters: String = rest.chars().filter(|c| c.is_alphabetic()).collect();
            let Some(after) = letters.strip_prefix(letter) else {
                return false;
            };
            after.chars().all(|c| c == letter) || POSITION_WORDS.contains(&after)
        })
}

/// The first of `names` that is a near miss of axis `axis` ([`near_miss`]), skipping the
/// columns in `taken`: its 0-based index.
pub(crate) fn find_near_miss<'a>(
    names: impl IntoIterator<Item = &'a str>,
    axis: usize,
    taken: &[usize],
) -> Option<usize> {
    names
        .into_iter()
        .enumerate()
        .find(|(c, name)| !taken.contains(c) && near_miss(name, axis))
        .map(|(c, _)| c)
}

/// Chooses the position columns among named columns: for each axis the column of best
/// priority (see [`position_axis`]); two columns of the same best priority for one axis are
/// ambiguous. At least two axes must be present; with exactly two (`x,y`, or `x,z` as in
/// DualSPHysics' 2D runs) the positions are 2D.
///
/// Returns the column indices in axis order (2 or 3 of them), or a message.
pub(crate) fn select_position_columns<'a>(
    names: impl IntoIterator<Item = &'a str>,
) -> Result<Vec<usize>, String> {
    let mut best: [Option<(u8, usize)>; 3] = [None; 3];
    let mut all = Vec::new();
    for (column, name) in names.into_iter().enumerate() {
        all.push(name);
        let Some((axis, priority)) = position_axis(name) else {
            continue;
        };
        match best[axis] {
            Some((p, other)) if p == priority => {
                return Err(format!(
                    "columns {} ({:?}) and {} ({:?}) both name the {} position",
                    other + 1,
                    trim_field(all[other]),
                    column + 1,
                    trim_field(name),
                    ["x", "y", "z"][axis]
                ));
            }
            Some((p, _)) if p < priority => {}
            _ => best[axis] = Some((priority, column)),
        }
    }
    let chosen: Vec<usize> = best.iter().flatten().map(|&(_, c)| c).collect();
    if chosen.len() < 2 {
        let missing: Vec<&str> = ["x", "y"]
            .into_iter()
            .zip(&best)
            .filter(|(_, b)| b.is_none())
            .map(|(a, _)| a)
            .collect();
        let listed: Vec<String> = all
            .iter()
            .map(|s| format!("{:?}", excerpt(trim_field(s), 40)))
            .collect();
        // A column that looks like a misspelt missing axis is named, with the fix.
        let hints: Vec<String> = ["x", "y"]
            .into_iter()
            .enumerate()
            .filter(|(axis, _)| best[*axis].is_none())
            .filter_map(|(axis, letter)| {
                let c = find_near_miss(all.iter().copied(), axis, &[])?;
                Some(format!(
                    "; column {} ({:?}) looks like a misspelt {letter}: rename it to {letter}",
                    c + 1,
                    excerpt(trim_field(all[c]), 40)
                ))
            })
            .collect();
        return Err(format!(
            "missing position column {} (need x and y, optionally z, also spelled like pos.x, \
             \"Pos.x [m]\", position_x or px); the header has {}{}",
            missing.join(" and "),
            excerpt(&listed.join(", "), 200),
            hints.concat()
        ));
    }
    Ok(chosen)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn position_names_of_common_tools() {
        for (name, axis, priority) in [
            ("x", 0, 0),
            (" \"Z\" ", 2, 0),
            ("Pos.x [m]", 0, 1),
            ("pos.y", 1, 1),
            ("position_z", 2, 1),
            ("Positions:1", 1, 1),
            ("px", 0, 1),
            ("Points:0", 0, 1),
            ("\"Points:2\"", 2, 1),
            ("coords.y", 1, 1),
            ("x (m)", 0, 1 - 1),
        ] {
            assert_eq!(position_axis(name), Some((axis, priority)), "{name}");
        }
        for name in [
            "vx",
            "Vel.x [m/s]",
            "p0",
            "idp",
            "Rhop",
            "pressure",
            "xx",
            "",
        ] {
            assert_eq!(position_axis(name), None, "{name}");
        }
    }

    #[test]
    fn bare_names_win_over_prefixed_ones() {
        assert_eq!(
            select_position_columns(["px", "x", "y", "py", "z"]),
            Ok(vec![1, 2, 4])
        );
        assert_eq!(select_position_columns(["x", "vx", "z"]), Ok(vec![0, 2]));
    }

    #[test]
    fn ambiguous_and_missing_columns_are_errors() {
        let e = select_position_columns(["pos.x", "px", "y"]).unwrap_err();
        assert!(
            e.contains("columns 1") && e.contains("both name the x"),
            "{e}"
        );
        let e = select_position_columns(["x", "vel"]).unwrap_err();
        assert!(e.starts_with("missing position column y"), "{e}");
    }

    #[test]
    fn near_misses_of_an_axis_are_typos_and_decorations_of_its_letter() {
        for name in [
            "zz",
            "zzz",
            "z z",
            "z_",
            "_z",
            "z1",
            "z0",
            "z.",
            "z-",
            " zz ",
            "ZZ",
            "Z_",
            "\"z_\"",
            "zz [m]",
            "Pos.zz",
            "position_z_",
            "pos.z1",
            "zpos",
            "z_coord",
            "Z-Position",
            "zcoordinates",
            "pzz",
        ] {
            assert!(near_miss(name, 2), "{name}");
        }
        // Positions themselves (case, spaces, quotes and units are no misses), and names
        // that are something else.
        for name in [
            "z", "Z", " z", "\"Z\"", "z [m]", "pos.z", "Points:2", "pz", "vz", "nz", "zeta",
            "size", "rho", "", "_", "12", "xz", "z_vel", "zone",
        ] {
            assert!(!near_miss(name, 2), "{name}");
        }
        assert!(near_miss("yy", 1) && !near_miss("yy", 2) && near_miss("x_", 0));
        assert_eq!(find_near_miss(["x", "y", "zz"], 2, &[0, 1]), Some(2));
        assert_eq!(find_near_miss(["x", "y", "vz"], 2, &[0, 1]), None);
    }

    #[test]
    fn a_missing_axis_with_a_near_miss_names_it() {
        let e = select_position_columns(["x", "yy"]).unwrap_err();
        assert!(
            e.contains("column 2 (\"yy\") looks like a misspelt y: rename it to y"),
            "{e}"
        );
    }

    #[test]
    fn normalise_strips_units_quotes_case() {
        assert_eq!(normalise_name(" 'Pos.X [m]' "), "pos.x");
        assert_eq!(normalise_name("Vel.z (m/s)"), "vel.z");
    }
}
