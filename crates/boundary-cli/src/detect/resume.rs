//! `detect --resume`: which frames a stopped run already did (their output and summary row
//! are there), and the temporary files a killed run left.

use super::frames::Output;
use super::DetectArgs;
use crate::error::CliError;
use std::path::{Path, PathBuf};

/// Whether `path` is a temporary file of an atomic write (`.frame_1.csv.tmp-<pid>-<n>`), left
/// by a run that was killed: never a frame.
pub(super) fn is_temp_file(path: &Path) -> bool {
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    temp_destination(&name).is_some()
}

/// The destination's name of a temporary file of an atomic write (`frame_1.csv` for
/// `.frame_1.csv.tmp-<pid>-<n>`), or `None` for any other name.
fn temp_destination(name: &str) -> Option<&str> {
    let rest = name.strip_prefix('.')?;
    let destination = &rest[..rest.rfind(boundary_io::TEMP_MARKER)?];
    (!destination.is_empty() && boundary_io::is_temp_name_for(name, destination))
        .then_some(destination)
}

/// `--resume`: for each frame, `Some(row)` when the run resumed did it (`row` its summary row
/// after the frame number, `None` without `--summary`), `None` when it is still to do. A frame
/// is done when its output exists (written atomically, so complete) and, with `--summary`, the
/// summary holds a row of it without an error. Removes the temporary files a killed run left
/// beside the outputs and the summary.
pub(super) fn resumable(
    args: &DetectArgs,
    paths: &[PathBuf],
    outputs: &[Output],
    header: &str,
) -> Result<Vec<Option<Option<String>>>, CliError> {
    if args.output_dir.is_none() && args.summary.is_none() {
        return Err(CliError::Usage(
            "--resume needs --output-dir or --summary (where the done frames are found)",
        ));
    }
    let output_of = |k: usize| match &outputs[k] {
        Ok(Some((p, _))) => Some(p.as_path()),
        _ => None,
    };
    remove_stale_temporaries(
        (0..paths.len())
            .filter_map(output_of)
            .chain(args.summary.as_deref()),
    );
    let previous = match &args.summary {
        Some(path) => Some(previous_rows(path, header)?),
        None => None,
    };
    let mut kept = Vec::with_capacity(paths.len());
    for (k, input) in paths.iter().enumerate() {
        let output = output_of(k);
        let output_text = output.map(|p| p.display().to_string()).unwrap_or_default();
        // An output that is the input itself says nothing about the frame being done.
        let output_done = match output {
            None => args.output_dir.is_none(),
            Some(out) => {
                std::fs::metadata(out).is_ok_and(|m| m.is_file()) && !same_file(out, input)
                    || previous.is_some() && same_file(out, input)
            }
        };
        let row = match &previous {
            None => Some(None),
            Some(rows) => rows
                .get(&input.display().to_string())
                .filter(|(output, _)| *output == output_text)
                .map(|(_, row)| Some(row.clone())),
        };
        kept.push(row.filter(|_| output_done));
    }
    Ok(kept)
}

/// Whether `a` and `b` name the same existing file.
fn same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}

/// Removes, beside each of `files`, the temporary files of its atomic writes (left by a run
/// that was killed); what cannot be removed stays, as it is never taken for an output.
fn remove_stale_temporaries<'a>(files: impl Iterator<Item = &'a Path>) {
    let mut by_dir: std::collections::HashMap<PathBuf, Vec<String>> =
        std::collections::HashMap::new();
    for file in files {
        let dir = match file.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
            _ => PathBuf::from("."),
        };
        if let Some(name) = file.file_name() {
            by_dir
                .entry(dir)
                .or_default()
                .push(name.to_string_lossy().into_owned());
        }
    }
    for (dir, names) in by_dir {
        let names: std::collections::HashSet<String> = names.into_iter().collect();
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        for entry in entries.flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            if temp_destination(&name).is_some_and(|d| names.contains(d)) {
                let _ = std::fs::remove_file(entry.path());
            }
        }
    }
}

/// The rows of the summary a stopped run wrote, by input: its output and the row after the
/// frame number. Rows with an error are left out (their frames are done again). No summary
/// yet: no rows.
fn previous_rows(
    path: &Path,
    header: &str,
) -> Result<std::collections::HashMap<String, (String, String)>, CliError> {
    let text = match std::fs::read_to_string(path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Default::default()),
        Err(e) => {
            return Err(CliError::Resume {
                path: path.to_path_buf(),
                problem: format!("cannot read it: {e}"),
            })
        }
    };
    let mut lines = text.lines();
    if lines.next().is_some_and(|first| first != header) {
        return Err(CliError::Resume {
            path: path.to_path_buf(),
            problem: format!(
                "its columns are not those this run writes ({header}): resume with the options \
                 of the run that wrote it, or remove it to start over"
            ),
        });
    }
    let columns = header.split(',').count();
    let mut rows = std::collections::HashMap::new();
    for line in lines {
        let Some(fields) = split_csv_line(line).filter(|f| f.len() == columns) else {
            continue;
        };
        // Column 3 is `n`, empty on a row with an error.
        if fields[3].is_empty() {
            continue;
        }
        if let Some((_, row)) = line.split_once(',') {
            rows.insert(fields[1].clone(), (fields[2].clone(), row.to_owned()));
        }
    }
    Ok(rows)
}

/// The fields of one CSV line as [`csv_field`] writes them; `None` when the quotes do not
/// close.
fn split_csv_line(line: &str) -> Option<Vec<String>> {
    let mut fields = Vec::new();
    let mut field = String::new();
    let mut chars = line.chars().peekable();
    let mut quoted = false;
    while let Some(c) = chars.next() {
        match (quoted, c) {
            (false, ',') => fields.push(std::mem::take(&mut field)),
            (false, '"') if field.is_empty() => quoted = true,
            (true, '"') if chars.peek() == Some(&'"') => {
                chars.next();
                field.push('"');
            }
            (true, '"') => quoted = false,
            (_, c) => field.push(c),
        }
    }
    if quoted {
        return None;
    }
    fields.push(field);
    Some(fields)
}

#[cfg(test)]
mod tests {
    use super::{split_csv_line, temp_destination};

    #[test]
    fn temporary_files_are_told_from_frames() {
        assert_eq!(temp_destination(".f_1.csv.tmp-12-0"), Some("f_1.csv"));
        assert_eq!(
            temp_destination(".a.tmp-b.csv.tmp-1-2"),
            Some("a.tmp-b.csv")
        );
        assert_eq!(temp_destination("f_1.csv"), None);
        assert_eq!(temp_destination(".hidden.csv"), None);
        assert_eq!(temp_destination(".tmp-1-2"), None);
        assert_eq!(temp_destination("é.tmp-1-2"), None);
        assert_eq!(temp_destination(".f.csv.tmp-1-2x"), None);
    }

    #[test]
    fn summary_lines_split_as_they_were_quoted() {
        assert_eq!(
            split_csv_line(r#"0,"a,b.csv",out/"x".csv,,"say ""hi""""#),
            Some(vec![
                "0".to_owned(),
                "a,b.csv".to_owned(),
                "out/\"x\".csv".to_owned(),
                String::new(),
                "say \"hi\"".to_owned()
            ])
        );
        assert_eq!(split_csv_line(r#"0,"open"#), None);
        assert_eq!(split_csv_line(""), Some(vec![String::new()]));
    }
}
