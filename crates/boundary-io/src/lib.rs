//! Particle files: read positions from CSV, XYZ, PLY and legacy VTK, write them back with
//! per-particle columns such as the `boundary` label. The only crate of the workspace (with the
//! CLI and xtask) that touches particle files.
//!
//! | format | read | write |
//! |---|---|---|
//! | CSV (`.csv`) | header naming `x,y[,z]` (also `Pos.x [m]`, `Points:0`, `position_x`, `px`), `,` `;` or tab separated; or headerless numbers | `x,y[,z],<columns>` |
//! | XYZ (`.xyz`, `.txt`, `.dat`) | whitespace-separated numbers per line; the chemistry header (count line + comment line, element symbol first) is recognised | `# x y [z] <columns>` then rows |
//! | PLY (`.ply`) | ascii, binary little and big endian (via `ply-rs-bw`); element `vertex`, properties `x, y[, z]` | ascii, columns as vertex properties |
//! | VTK legacy (`.vtk`) | `POINTS` of POLYDATA / UNSTRUCTURED_GRID / any dataset, ascii or binary (big endian) | ascii POLYDATA with `VERTICES` and `POINT_DATA` scalars |
//!
//! # Dimension
//! A file with two coordinates is a 2D set. A file with three is 3D unless
//! [`ReadOptions::dim`] is `Some(2)`: then the one axis whose coordinate is the same for every
//! particle is dropped (DualSPHysics' 2D runs live in the x–z plane at constant y; other tools
//! write z = 0); if several are constant, z goes first, then y; if none is, it is an error. A
//! 2D set is never padded with z = 0, except in VTK output, whose `POINTS` always have three
//! components.
//!
//! # Errors and robustness
//! Every error names the file, and the line (text formats) or the particle index (binary
//! formats). Non-finite coordinates are rejected. Readers never panic and never allocate from a
//! header's declared count before the data is there to back it.
//!
//! # Example
//! ```
//! use boundary_core::{AnyParticleSet, ParticleSet};
//! use boundary_io::{read_particles, write_particles, Column, ReadOptions};
//!
//! let dir = tempfile::tempdir().unwrap();
//! let path = dir.path().join("labels.csv");
//! let set = ParticleSet::from_rows(&[[0.0, 0.5], [1.0, 0.25]]).unwrap().to_any();
//! write_particles(&path, None, &set, &[("boundary", Column::Int(&[1, 0]))]).unwrap();
//! assert_eq!(std::fs::read_to_string(&path).unwrap(), "x,y,boundary\n0,0.5,1\n1,0.25,0\n");
//!
//! let back = read_particles(&path, &ReadOptions::default()).unwrap();
//! assert_eq!(back, set);
//! let labels = boundary_io::read_csv_column(&path, "boundary").unwrap();
//! assert_eq!(labels, vec![1.0, 0.0]);
//! ```

mod csv;
mod ply;
mod text;
mod vtk;
mod xyz;

use boundary_core::{AnyParticleSet, ParticleSet, Point};
use std::fmt;
use std::io::{BufWriter, Read, Write};
use std::path::Path;
use std::str::FromStr;
use thiserror::Error;

/// A particle file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Comma/semicolon/tab separated values with a header.
    Csv,
    /// Whitespace-separated numbers.
    Xyz,
    /// Stanford polygon format.
    Ply,
    /// Legacy VTK.
    Vtk,
}

impl Format {
    /// The format of `path` by its extension (case-insensitive): `csv`; `xyz`, `txt`, `dat`;
    /// `ply`; `vtk`.
    pub fn from_path(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "csv" => Some(Format::Csv),
            "xyz" | "txt" | "dat" => Some(Format::Xyz),
            "ply" => Some(Format::Ply),
            "vtk" => Some(Format::Vtk),
            _ => None,
        }
    }

    /// The format's short name.
    pub fn name(self) -> &'static str {
        match self {
            Format::Csv => "csv",
            Format::Xyz => "xyz",
            Format::Ply => "ply",
            Format::Vtk => "vtk",
        }
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Format {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "csv" => Ok(Format::Csv),
            "xyz" | "txt" | "dat" => Ok(Format::Xyz),
            "ply" => Ok(Format::Ply),
            "vtk" => Ok(Format::Vtk),
            _ => Err(format!("unknown format '{s}' (csv, xyz, ply, vtk)")),
        }
    }
}

/// How to read a particle file.
#[derive(Debug, Clone, Default)]
pub struct ReadOptions {
    /// `None`: from the file; `Some(2)` drops the constant axis of a 3D file; `Some(3)`.
    pub dim: Option<usize>,
    /// `None`: from the extension.
    pub format: Option<Format>,
}

/// A per-particle output column.
#[derive(Debug, Clone, Copy)]
pub enum Column<'a> {
    /// Integers (labels, codes).
    Int(&'a [i64]),
    /// Reals (margins, scores).
    Float(&'a [f64]),
}

impl Column<'_> {
    fn len(&self) -> usize {
        match self {
            Column::Int(v) => v.len(),
            Column::Float(v) => v.len(),
        }
    }

    /// The value of particle `i` as text (integers without a decimal point, reals so that
    /// they read back to the same `f64`).
    fn text(&self, i: usize) -> String {
        match self {
            Column::Int(v) => v[i].to_string(),
            Column::Float(v) => v[i].to_string(),
        }
    }
}

/// A particle file that cannot be read or written.
#[derive(Debug, Error)]
pub enum IoError {
    /// The file cannot be opened, read or written.
    #[error("{file}: {source}")]
    Io {
        /// The file.
        file: String,
        /// The operating system's reason.
        source: std::io::Error,
    },
    /// The format cannot be told from the file name.
    #[error("{file}: unknown format (extension .csv, .xyz, .txt, .dat, .ply or .vtk, or give the format)")]
    UnknownFormat {
        /// The file.
        file: String,
    },
    /// Malformed text at a line (1-based).
    #[error("{file}:{line}: {message}")]
    Line {
        /// The file.
        file: String,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// Malformed content not tied to a line (binary data, missing sections).
    #[error("{file}: {message}")]
    Content {
        /// The file.
        file: String,
        /// What is wrong.
        message: String,
    },
    /// A non-finite coordinate in a binary file.
    #[error("{file}: particle {index}: coordinate {axis} is {value}")]
    NonFinite {
        /// The file.
        file: String,
        /// 0-based particle index.
        index: usize,
        /// Axis (0 = x).
        axis: usize,
        /// The value.
        value: f64,
    },
    /// The dimension asked for does not fit the file.
    #[error("{file}: {message}")]
    Dimension {
        /// The file.
        file: String,
        /// What is wrong.
        message: String,
    },
    /// An output column's length differs from the particle count.
    #[error("{file}: column '{column}' has {got} values for {expected} particles")]
    ColumnLength {
        /// The file.
        file: String,
        /// The column.
        column: String,
        /// Its length.
        got: usize,
        /// The particle count.
        expected: usize,
    },
}

/// Coordinates as read, before the dimension policy: `width` values per particle (2 or 3).
#[derive(Debug, Default)]
pub(crate) struct Raw {
    pub width: usize,
    pub coords: Vec<f64>,
}

/// Preallocation cap for counts declared in headers.
pub(crate) const MAX_PREALLOCATE: usize = 1 << 20;

fn io_error(file: &str) -> impl FnOnce(std::io::Error) -> IoError + '_ {
    move |source| IoError::Io {
        file: file.to_owned(),
        source,
    }
}

/// Reads the particles of `path`.
pub fn read_particles(path: &Path, options: &ReadOptions) -> Result<AnyParticleSet, IoError> {
    let name = path.display().to_string();
    let format = match options.format {
        Some(f) => f,
        None => {
            Format::from_path(path).ok_or_else(|| IoError::UnknownFormat { file: name.clone() })?
        }
    };
    let file = std::fs::File::open(path).map_err(io_error(&name))?;
    read_particles_from(file, &name, format, options)
}

/// Reads particles in `format` from `reader`; `name` names the source in errors.
pub fn read_particles_from(
    mut reader: impl Read,
    name: &str,
    format: Format,
    options: &ReadOptions,
) -> Result<AnyParticleSet, IoError> {
    if let Some(d) = options.dim {
        if d != 2 && d != 3 {
            return Err(IoError::Dimension {
                file: name.to_owned(),
                message: format!("dimension must be 2 or 3, got {d}"),
            });
        }
    }
    let mut bytes = Vec::new();
    reader.read_to_end(&mut bytes).map_err(io_error(name))?;
    let raw = match format {
        Format::Csv => csv::read(text::utf8(&bytes, name)?, name, options.dim)?,
        Format::Xyz => xyz::read(text::utf8(&bytes, name)?, name, options.dim)?,
        Format::Ply => ply::read(&bytes, name)?,
        Format::Vtk => vtk::read(&bytes, name)?,
    };
    finish(raw, name, options.dim)
}

/// Applies the dimension policy (crate docs) and builds the set.
fn finish(raw: Raw, name: &str, dim: Option<usize>) -> Result<AnyParticleSet, IoError> {
    let n = raw.coords.len() / raw.width.max(1);
    for (k, &v) in raw.coords.iter().enumerate() {
        if !v.is_finite() {
            return Err(IoError::NonFinite {
                file: name.to_owned(),
                index: k / raw.width,
                axis: k % raw.width,
                value: v,
            });
        }
    }
    match (raw.width, dim) {
        (2, Some(3)) => Err(IoError::Dimension {
            file: name.to_owned(),
            message: "the file has 2 coordinates per particle, but 3D was asked for".into(),
        }),
        (2, _) => Ok(build::<2>(&raw.coords, 2, [0, 1, 0])),
        (3, Some(2)) => {
            let constant = |axis: usize| {
                let first = raw.coords.get(axis).copied();
                (0..n).all(|i| Some(raw.coords[3 * i + axis]) == first)
            };
            let dropped = [2, 1, 0]
                .into_iter()
                .find(|&a| constant(a))
                .ok_or_else(|| IoError::Dimension {
                    file: name.to_owned(),
                    message: "2D was asked for, but no coordinate axis is constant over all \
                              particles"
                        .into(),
                })?;
            let kept: Vec<usize> = (0..3).filter(|&a| a != dropped).collect();
            Ok(build::<2>(&raw.coords, 3, [kept[0], kept[1], 0]))
        }
        (3, _) => Ok(build::<3>(&raw.coords, 3, [0, 1, 2])),
        (w, _) => Err(IoError::Content {
            file: name.to_owned(),
            message: format!("{w} coordinates per particle"),
        }),
    }
}

fn build<const D: usize>(coords: &[f64], width: usize, axes: [usize; 3]) -> AnyParticleSet {
    let points: Vec<Point<D>> = coords
        .chunks_exact(width)
        .map(|row| Point::<D>::from_fn(|a, _| row[axes[a]]))
        .collect();
    // Finite coordinates were checked by `finish`.
    ParticleSet::new(points)
        .expect("coordinates checked finite")
        .to_any()
}

/// Reads the numeric column `column` (by header name, case-insensitive) of a CSV file, e.g. the
/// `boundary` labels written by `boundary detect`.
pub fn read_csv_column(path: &Path, column: &str) -> Result<Vec<f64>, IoError> {
    let name = path.display().to_string();
    let bytes = std::fs::read(path).map_err(io_error(&name))?;
    csv::read_column(text::utf8(&bytes, &name)?, &name, column)
}

/// Writes the particles of `set` and extra `columns` to `path` (format from `format` or the
/// extension).
pub fn write_particles(
    path: &Path,
    format: Option<Format>,
    set: &AnyParticleSet,
    columns: &[(&str, Column<'_>)],
) -> Result<(), IoError> {
    let name = path.display().to_string();
    let format = match format {
        Some(f) => f,
        None => {
            Format::from_path(path).ok_or_else(|| IoError::UnknownFormat { file: name.clone() })?
        }
    };
    check_columns(&name, set, columns)?;
    let file = std::fs::File::create(path).map_err(io_error(&name))?;
    let mut out = BufWriter::new(file);
    write_body(&mut out, format, set, columns).map_err(io_error(&name))?;
    out.flush().map_err(io_error(&name))
}

/// Writes particles in `format` to `writer`.
pub fn write_particles_to(
    mut writer: impl Write,
    format: Format,
    set: &AnyParticleSet,
    columns: &[(&str, Column<'_>)],
) -> Result<(), IoError> {
    check_columns("<output>", set, columns)?;
    write_body(&mut writer, format, set, columns).map_err(io_error("<output>"))
}

fn check_columns(
    name: &str,
    set: &AnyParticleSet,
    columns: &[(&str, Column<'_>)],
) -> Result<(), IoError> {
    for (column, values) in columns {
        if values.len() != set.len() {
            return Err(IoError::ColumnLength {
                file: name.to_owned(),
                column: (*column).to_owned(),
                got: values.len(),
                expected: set.len(),
            });
        }
    }
    Ok(())
}

fn write_body(
    out: &mut dyn Write,
    format: Format,
    set: &AnyParticleSet,
    columns: &[(&str, Column<'_>)],
) -> std::io::Result<()> {
    match format {
        Format::Csv => csv::write(out, set, columns),
        Format::Xyz => xyz::write(out, set, columns),
        Format::Ply => ply::write(out, set, columns),
        Format::Vtk => vtk::write(out, set, columns),
    }
}

/// Axis names for headers.
pub(crate) const AXES: [&str; 3] = ["x", "y", "z"];
