use boundary_core::CoreError;
use std::fmt;

/// Where in a file an error was found.
///
/// Lines and columns are 1-based (as an editor shows them); item indices (particles of a binary
/// file) are 0-based, as particle indices are everywhere else in the project.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Location {
    /// The file as a whole (an empty file, a dimension policy that cannot be met).
    File,
    /// A line of a text file or of a text header.
    Line(usize),
    /// A field of a delimited text file.
    Cell {
        /// 1-based line.
        line: usize,
        /// 1-based column (field) number.
        column: usize,
    },
    /// An item of binary data, such as `vertex 12` of a binary PLY file or `point 12` of a binary
    /// VTK file.
    Item {
        /// What the item is (`"vertex"`, `"point"`).
        kind: &'static str,
        /// 0-based index of the item.
        index: usize,
    },
}

impl fmt::Display for Location {
    /// Renders as a suffix of a file name: `""`, `" line 3"`, `" line 3 column 2"`, `" vertex 7"`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Location::File => Ok(()),
            Location::Line(line) => write!(f, " line {line}"),
            Location::Cell { line, column } => write!(f, " line {line} column {column}"),
            Location::Item { kind, index } => write!(f, " {kind} {index}"),
        }
    }
}

/// Errors of reading or writing particle files.
///
/// Every message is one line, starts lower-case, has no trailing period and names the file (for
/// [`crate::read_particles_from`] and [`crate::write_particles_to`], the name the caller gave, or
/// `<output>`), followed by the line, column or item where that is known.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum IoError {
    /// The operating system refused to open or read the file.
    #[error("cannot read {file}: {source}")]
    Read {
        /// The file.
        file: String,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The operating system refused to create or write the file.
    #[error("cannot write {file}: {source}")]
    Write {
        /// The file.
        file: String,
        /// The underlying error.
        source: std::io::Error,
    },
    /// No format was given and the file's extension names none.
    #[error(
        "unknown particle file format for {file}: expected extension .csv, .xyz, .txt, .ply, .vtk, .vtu, .vtp, .bgeo, .bgeo.gz, .hdf5 or .npz, \
         or name the format"
    )]
    UnknownFormat {
        /// The file.
        file: String,
    },
    /// The content does not follow the format.
    #[error("{message} in {file}{at}")]
    Parse {
        /// The file.
        file: String,
        /// Where.
        at: Location,
        /// What is wrong, lower-case, one line.
        message: String,
    },
    /// A coordinate is NaN or infinite.
    #[error("particle {index}: coordinate {axis} is not finite ({value}) in {file}{at}")]
    NonFinite {
        /// The file.
        file: String,
        /// Where the particle is written.
        at: Location,
        /// 0-based particle index in file order.
        index: usize,
        /// Axis in the file (0 = x, 1 = y, 2 = z).
        axis: usize,
        /// The value read.
        value: f64,
    },
    /// The requested dimension cannot be produced from the file's positions.
    #[error("{message} in {file}")]
    Dimension {
        /// The file.
        file: String,
        /// Why, lower-case, one line.
        message: String,
    },
    /// The file holds no particle: an empty file, a CSV header or an XYZ names line without a
    /// data row, a count of 0 (PLY `element vertex 0`, VTK `POINTS 0`). Particle sets may be
    /// empty, particle files may not: an empty file is almost always a failed export or the
    /// wrong file, and reading it as an empty set would report "0 of 0" as a result. A caller
    /// that takes empty frames (an emitter not started yet) can match this variant and use an
    /// empty set of `dim`.
    #[error("no particles in {file}: {detail}")]
    NoParticles {
        /// The file.
        file: String,
        /// The dimension its header declares (the columns named, the dimension policy
        /// applied), when it has a header.
        dim: Option<usize>,
        /// What the file holds instead, lower-case, one line.
        detail: String,
    },
    /// A header names two position axes and, beside them, a column that looks like the third
    /// misspelt (`x,y,zz`; see the crate docs, "Reading"): read as it is the set would silently
    /// be 2D. Not raised when 2D is asked for (`ReadOptions::dim` = 2): the file is then read
    /// as 2D from the two axes named.
    #[error(
        "{} {name:?} in {file}{at} looks like a misspelt {axis}, and without a {axis} the \
         file would be read as 2D from {kept}: rename it to {axis}, or pass --dim 2 (Python: \
         dim=2) to read it as 2D on purpose",
        if *.vertex_property { "vertex property" } else { "column" }
    )]
    NearMissColumn {
        /// The file.
        file: String,
        /// Where the column is named (the header line and the column's number).
        at: Location,
        /// Whether it is a PLY vertex property (else a column of a CSV header or of an XYZ
        /// names line).
        vertex_property: bool,
        /// The column's name as the file writes it (trimmed of spaces and quotes).
        name: String,
        /// The axis it looks like: `'x'`, `'y'` or `'z'`.
        axis: char,
        /// The names of the two position columns found, as `x, y`.
        kept: String,
    },
    /// A per-particle output column does not fit the set or the format.
    #[error("column {name:?}: {message} (writing {file})")]
    Column {
        /// The file being written.
        file: String,
        /// The column's name.
        name: String,
        /// What is wrong.
        message: String,
    },
    /// The positions were read but do not form a valid particle set (for instance more than
    /// `u32::MAX` particles).
    /// Writing a format that is only read (PySPH's `.hdf5` and `.npz`).
    #[error(
        "cannot write {file}: {format} files are read, not written; write .vtu (ParaView), \
         .csv or another format"
    )]
    ReadOnlyFormat {
        /// The destination.
        file: String,
        /// Its format.
        format: crate::Format,
    },
    #[error("invalid particle set in {file}: {source}")]
    Particles {
        /// The file.
        file: String,
        /// The core error.
        source: CoreError,
    },
}

impl IoError {
    pub(crate) fn parse(file: &str, at: Location, message: impl Into<String>) -> Self {
        IoError::Parse {
            file: file.to_owned(),
            at,
            message: message.into(),
        }
    }

    pub(crate) fn read(file: &str, source: std::io::Error) -> Self {
        IoError::Read {
            file: file.to_owned(),
            source,
        }
    }

    pub(crate) fn write(file: &str, source: std::io::Error) -> Self {
        IoError::Write {
            file: file.to_owned(),
            source,
        }
    }

    /// A non-finite coordinate of point `index` of a binary file (located by the point's
    /// index, as binary files have no lines).
    pub(crate) fn non_finite_point(file: &str, index: usize, axis: usize, value: f64) -> Self {
        IoError::NonFinite {
            file: file.to_owned(),
            at: Location::Item {
                kind: "point",
                index,
            },
            index,
            axis,
            value,
        }
    }

    pub(crate) fn dimension(file: &str, message: impl Into<String>) -> Self {
        IoError::Dimension {
            file: file.to_owned(),
            message: message.into(),
        }
    }

    /// The location inside the file, where the error has one.
    pub fn location(&self) -> Option<Location> {
        match self {
            IoError::Parse { at, .. }
            | IoError::NonFinite { at, .. }
            | IoError::NearMissColumn { at, .. } => Some(*at),
            _ => None,
        }
    }
}

/// Shortens a text quoted in an error message to at most `max` characters.
pub(crate) fn excerpt(text: &str, max: usize) -> String {
    if text.chars().count() <= max {
        text.to_owned()
    } else {
        let mut s: String = text.chars().take(max).collect();
        s.push('…');
        s
    }
}
