//! Particle files: read positions from CSV, XYZ, PLY, legacy VTK, VTK XML (`.vtu`, `.vtp`),
//! Houdini BGEO and PySPH's output (`.hdf5`, `.npz`)
//! into an [`AnyParticleSet`], with the other point attributes where asked
//! ([`read_particle_file`]), and write them back with per-particle columns such as the
//! `boundary` label next to the attributes of the input.
//!
//! Architecture invariant: this is the only crate of the workspace that parses or writes
//! particle files; `boundary-core` and the detector crates know no file format.
//!
//! | format | extension | read | write |
//! |---|---|---|---|
//! | CSV | `.csv` | header naming the position columns, `,` `;` or tab separated; or headerless numbers | `x,y[,z],<columns>` |
//! | XYZ | `.xyz`, `.txt`, `.dat` | whitespace-separated numbers, one particle per line; optional count + comment lines | `# x y [z] <columns>` then rows |
//! | PLY | `.ply` | ascii, binary little and big endian; element `vertex`, properties `x, y[, z]` | ascii, columns as vertex properties |
//! | VTK legacy | `.vtk` | `POINTS` (float or double) of POLYDATA, UNSTRUCTURED_GRID or STRUCTURED_GRID, ascii or binary | ascii POLYDATA: `POINTS`, `VERTICES`, `POINT_DATA` scalars |
//! | BGEO | `.bgeo`, `.bgeo.gz` | Houdini classic BGEO 5 (partio, SPlisHSPlasH): points and point attributes, gzip detected by its magic | BGEO 5, 32-bit floats, gzip for `.gz` |
//! | VTK XML | `.vtu`, `.vtp` | `Points` and every numeric `PointData` array of the first `Piece`; ascii, base64 binary, appended raw or base64; zlib; either byte order; `UInt32`/`UInt64` headers | base64 binary: `Points`, a vertex cell per particle, `PointData` (vectors joined, see below) |
//! | PySPH | `.hdf5`, `.h5`, `.npz` | one particle array (`fluid` unless named, [`read_particle_array`]): `x`, `y`, `z` and every output property | no (an error) |
//!
//! # Reading
//!
//! **CSV.** The separator is `;`, tab or `,`, whichever occurs most often in the first
//! non-comment line (ties in that order), or the one an Excel-style `sep=;` first line names.
//! If that line has a field that is not a number it is a header, and the position columns are
//! found by name, case-insensitively, after trimming spaces and quotes and dropping a unit
//! suffix in brackets or parentheses: `x`, `y`, `z`; also `pos.x`, `Pos.x [m]` (DualSPHysics'
//! CSV export), `position_x`, `px`, `Points:0` (ParaView's CSV export), `coords.x`. A bare `x`
//! wins over a prefixed name; two columns of equal standing for one axis are an error. Other
//! columns are ignored (not even parsed). With exactly two position columns (`x,y`, or `x,z` as
//! in DualSPHysics' 2D runs) the file is 2D. A headerless file takes its first 2 or 3 columns as
//! positions: as many as [`ReadOptions::dim`] says, else 3 if the first row has at least 3
//! fields, else 2. Blank lines and lines starting with `#` are skipped; a trailing separator is
//! allowed; with `;` as separator a decimal comma (`0,5`) is accepted. A row with more values
//! than the header has columns (headerless: than the first row has) is an error naming the
//! line: it is misaligned data, which cutting it to the header would hide.
//!
//! **Columns that cannot be misread.** A header with two position axes and, beside them, a
//! column that looks like the third misspelt (`x,y,zz`, `x,y,z_`, `x,y,z1`, `Pos.x,Pos.y,Pos.zz`,
//! `x,y,zpos`; the precise rule is a *near miss*: the name, normalised as above and without a
//! position prefix, is the axis letter repeated, or with only non-letters around it, or
//! followed by a position word such as `pos` or `coord`) is an error,
//! [`IoError::NearMissColumn`], naming the file, the header line, the column and the fix:
//! rename it, or read the file as 2D on purpose with `dim = Some(2)`, which then takes the two
//! axes named. Case, spaces, quotes and a unit suffix are no near misses: `X,Y,Z` and
//! `x, y, z [m]` name the axes. The same holds for an XYZ `#` names line and for PLY
//! properties (where names are exact, so `Z` beside `x` and `y` is a near miss there). Every
//! read reports the coordinates it used ([`ParticleFile::position_columns`], "2D from x, y").
//!
//! **Files of no particle** are an error, [`IoError::NoParticles`], naming the file and what
//! it holds instead: an empty file, a CSV header or an XYZ names line with no data row after
//! it, a count of 0 (XYZ count line, PLY `element vertex 0`, VTK `POINTS 0`, VTK XML
//! `NumberOfPoints="0"`, BGEO). Particle *sets* may be empty (`boundary_core` allows it, and
//! the writers write them); a particle *file* with none is almost always a failed export or
//! the wrong file. The error carries the dimension the header declares, for a caller that
//! takes empty frames.
//!
//! **XYZ.** One particle per line, whitespace-separated numbers: 2 columns are x y, 3 or more
//! are x y z (further columns ignored). A comment line `# x y [z] …` before the data (what the
//! writer puts first) names the columns, found as in CSV, so a written 2D file with extra
//! columns reads back as 2D. The common `.xyz` header, a first line holding only a particle
//! count and a free comment line after it, is recognised: then exactly that many particle lines
//! are read (further lines, such as later frames of a trajectory, are ignored), a leading
//! element symbol (`H 0.0 1.0 2.0`) is skipped, and fewer lines than declared is an error.
//!
//! **PLY** (through `ply-rs-bw`): ascii and binary of both endiannesses. The element `vertex`
//! must have scalar properties `x` and `y`, optionally `z`, of any numeric type (converted
//! exactly to `f64`); other properties and elements are skipped.
//!
//! **VTK legacy** (hand-written; see the `vtk` module for why not `vtkio`): the `POINTS` of a
//! POLYDATA, UNSTRUCTURED_GRID or STRUCTURED_GRID dataset, `float` or `double`, ascii or binary
//! (big endian, as the format prescribes; splashsurf and SPlisHSPlasH write these). A `FIELD`
//! block before `POINTS` is skipped. Everything after `POINTS` is ignored by [`read_particles`];
//! [`read_particle_file`] also reads the `POINT_DATA` arrays (see "Attributes").
//!
//! **VTK XML** (hand-written on `quick-xml`; see the `vtk_xml` module for why not `vtkio`):
//! UnstructuredGrid (`.vtu`) and PolyData (`.vtp`) as VTK, ParaView and SPHinXsys write them.
//! Files with several `Piece`s are an error; cells are not read.
//!
//! **PySPH** (`.hdf5` through the pure-Rust `hdf5-pure`, no HDF5 library needed): the layout
//! PySPH's `HDFOutput` writes, `/particles/<array>/arrays/<property>`. A file holds several
//! particle arrays; [`read_particle_file`] reads `fluid`, or the file's only array, and
//! [`read_particle_array`] the one named (`boundary`, `solid`, … for walls);
//! [`particle_arrays`] lists them. PySPH keeps `z` = 0 in a 2D run: such a file reads as 2D
//! (`dim = 3` keeps the zeros). Properties declared but not output (no value) are left out; a
//! property of `k` values per particle becomes `name:0` … `name:k-1`. PySPH's `.npz` output
//! (written without h5py: a NumPy zip whose `particles` entry is a pickled dictionary of the
//! arrays, PySPH's output version 2) is read through `zip` and a small pickle stack machine
//! that builds no Python object. Neither format is written.
//!
//! **BGEO** (hand-written from the format's public description; see the `bgeo` module): the
//! classic binary geometry of Houdini, version 5, as partio writes it; the new Houdini 12+
//! format and Blosc `.bgeo.sc` are errors that say so. It stores 32-bit floats: a coordinate
//! or real beyond their range is an error on writing, others are rounded.
//!
//! **CSV in parts.** [`read_csv_header`] reads a CSV file's header once; each process then
//! reads the lines that start in its byte range ([`CsvHeader::read_chunk`]) and, numbered by
//! the counts of the parts before it, parses them as a whole-file read does
//! ([`CsvChunk::parse`]: the same values, the same errors with the same line and particle).
//! The MPI driver reads its input so.
//!
//! # Attributes
//!
//! [`read_particle_file`] also returns the input's other per-particle values as
//! [`Attribute`]s, so that a tool can write them back next to its own columns
//! ([`ParticleFile::columns`]) and the output opens in ParaView beside the simulation fields.
//! Formats that keep them: CSV (every other column of a header whose values are all numbers;
//! integers stay integers) and VTK XML (every numeric `PointData` array; a vector of `k`
//! components becomes `name:0` … `name:k-1`, ParaView's names for components), PLY (every other
//! scalar vertex property; integer types stay integers; list properties are skipped), BGEO
//! (every point attribute; indexed strings as their index) and legacy VTK (the `POINT_DATA`
//! arrays: `SCALARS`, `VECTORS`, `NORMALS`, `TENSORS`,
//! `TEXTURE_COORDINATES`, `COLOR_SCALARS`, `FIELD`, after cell sections of either the classic
//! or the 5.1 `OFFSETS`/`CONNECTIVITY` layout; a damaged section after `POINTS` loses the
//! attributes, reported in `skipped`, not the positions). PySPH files keep every property output (`h`, `m`, `rho`, `gid`, …).
//! XYZ keeps none yet. Names are made valid column names (a character a column name may
//! not hold becomes `_`); an attribute is skipped, with the reason in
//! [`ParticleFile::skipped`], when a value is not a number, when its name would read back as a
//! position (`px` beside `x`), or when it repeats a name. [`read_particles`] parses none of it.
//!
//! # Frames
//!
//! [`read_frame`] reads a file once into a [`Frame`]: the set, the attributes (when asked,
//! [`FrameParts`]), the coordinates used and the line of each particle ([`Frame::line`], CSV),
//! so that a tool that finds a bad value after reading (a radius, an id) names its line
//! without opening the file again.
//!
//! # Dimension
//!
//! A file with two coordinates per particle (CSV or XYZ with x and y only, PLY without `z`) is a
//! 2D set; asking for `dim = Some(3)` on it is an error. A file with three coordinates is a 3D
//! set, unless `dim = Some(2)`: then the **one** axis whose coordinate is the same (`==`) for
//! every particle is dropped (DualSPHysics' 2D runs live in the x–z plane at constant y; other
//! tools write z = 0); if several axes are constant, z is dropped first, then y, then x; if none
//! is, it is an error. A 3D file whose z is all zero is still read as 3D without `dim` (it is the
//! user's file), with one exception: VTK files written by this crate from a 2D set carry
//! `dim=2` in their title line (VTK XML: the comment `boundary-io dim=2`) and read back as 2D
//! when their z is all zero; so do PySPH files whose `z` is all zero (PySPH's 2D runs). Such a
//! flat 3D set is all boundary; the `boundary` command and the
//! bindings refuse it unless asked for 3D (`boundary_core::ParticleSet::flatness`).
//!
//! # Writing
//!
//! [`write_particles`] writes the positions and extra named [`Column`]s. Reals are written in
//! the shortest form that reads back to the same `f64` (Rust's `{}`, or `{:e}` for magnitudes
//! below 1e-5 or from 1e16 on), integers as integers. Column names must be non-empty printable
//! ASCII without spaces, quotes, `,`, `;` or `#`, unique, and must not name a position (`x`,
//! `Pos.x`, …); a column's length must equal the number of particles. In PLY and VTK an integer
//! column is written as `int` when every value fits 32 bits, as `double` otherwise (neither
//! format has a portable 64-bit integer). VTK points always have three components, so a 2D set
//! is written there with z = 0 (and the `dim=2` title marker above); it is the only place a 2D
//! set gets a z coordinate. NaN and infinite reals in a [`Column::Float`] are written as `NaN`
//! and `inf` in CSV and XYZ (Rust reads them back); PLY and VTK readers have no common text for
//! them, so writing one there is an error naming the column and the particle. VTK XML is
//! binary and writes every value exactly (NaN included); integer columns are `Int32` when every
//! value fits, `Int64` otherwise, and consecutive columns `name:0`, `name:1`, … of one kind are
//! written as one array `name` with that many components. PLY property names are identifiers
//! (letters, digits, `_`, `-`): other characters of a column name become `_` there (a
//! vector's `name:0` is the property `name_0`, read back as a scalar attribute of that name),
//! and a name starting with a digit or `-` gets a `_` before it; two columns that would get the
//! same property name are an error naming both.
//!
//! # Meshes
//!
//! [`read_mesh`] reads the closed triangle mesh of a solid region (STL ascii or binary, OBJ,
//! PLY with faces) into vertices and triangles for `boundary_core::SolidMesh::new`, which
//! checks that they bound a solid. Errors name the file and the line, triangle or face.
//!
//! # Errors and robustness
//!
//! Every [`IoError`] names the file, and the line and column (text formats and ascii PLY) or the
//! item index (binary formats) where that is known. NaN and infinite coordinates are rejected
//! with the particle index and its line. Non-UTF-8 text is an error, not a panic. Readers never
//! panic, and never reserve memory from a count declared in a header beyond a fixed cap
//! ([`MAX_PREALLOCATE`] values; for PLY, `ply-rs-bw`'s own cap of 65536 elements) before the
//! data backing it has been read: a binary VTK block is checked against the bytes present.
//!
//! Writes are atomic ([`write_atomic`]): the file is written beside its destination under a
//! hidden temporary name, synced, and renamed into place, so a reader (or a run resumed after a
//! crash) never finds a partial file, and a failed write (a full disk) leaves no file behind.
//!
//! # Example
//!
//! ```
//! use boundary_core::ParticleSet;
//! use boundary_io::{read_particles, write_particles, Column, ReadOptions};
//!
//! let dir = tempfile::tempdir().expect("temporary directory");
//! let path = dir.path().join("labels.csv");
//! let set = ParticleSet::from_rows(&[[0.0, 0.5], [1.0, 0.25]])?.to_any();
//! write_particles(&path, None, &set, &[("boundary", Column::Int(&[1, 0]))])?;
//! assert_eq!(std::fs::read_to_string(&path)?, "x,y,boundary\n0,0.5,1\n1,0.25,0\n");
//!
//! let back = read_particles(&path, &ReadOptions::default())?;
//! assert_eq!(back, set);
//! assert_eq!(boundary_io::read_csv_column(&path, "boundary")?, vec![1.0, 0.0]);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod atomic;
mod bgeo;
mod csv;
mod error;
mod frame;
mod mesh;
mod npz;
mod ply;
mod pysph;
mod text;
mod vtk;
mod vtk_xml;
mod xyz;

pub use atomic::{is_temp_name_for, write_atomic, TEMP_MARKER};
pub use csv::{read_csv_header, CsvChunk, CsvHeader};
pub use error::{IoError, Location};
pub use frame::{Frame, FrameParts, LineIndex};

use boundary_core::{AnyParticleSet, CoreError, ParticleSet, Point};
use boundary_core::{Dim, SupportedDim};
use std::fmt;
use std::io::{BufReader, BufWriter, Read, Write};
use std::path::Path;
use std::str::FromStr;

/// The most values a reader reserves memory for from a count declared in a file header before
/// the data is read; beyond it, vectors grow only as data actually arrives.
pub const MAX_PREALLOCATE: usize = 1 << 20;

/// A particle file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Comma, semicolon or tab separated values, with or without a header.
    Csv,
    /// Whitespace-separated numbers, one particle per line.
    Xyz,
    /// The Stanford polygon format (ascii or binary).
    Ply,
    /// Legacy VTK (ascii or binary).
    Vtk,
    /// VTK XML UnstructuredGrid (`.vtu`).
    Vtu,
    /// VTK XML PolyData (`.vtp`).
    Vtp,
    /// Houdini classic BGEO version 5 (`.bgeo`, gzip-compressed `.bgeo.gz`), as partio writes.
    Bgeo,
    /// PySPH's HDF5 output (`.hdf5`, `.h5`): read only.
    Hdf5,
    /// PySPH's NumPy output (`.npz`): read only.
    Npz,
}

impl Format {
    /// The format named by the extension of `path`, case-insensitive: `csv`; `xyz`, `txt`,
    /// `dat`; `ply`; `vtk`; `vtu`; `vtp`; `bgeo`, and `gz` after `.bgeo`; `hdf5`, `h5`; `npz`.
    pub fn from_path(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        if ext == "gz" {
            let inner = Path::new(path.file_stem()?).extension()?.to_str()?;
            return inner.eq_ignore_ascii_case("bgeo").then_some(Format::Bgeo);
        }
        match ext.as_str() {
            "csv" => Some(Format::Csv),
            "xyz" | "txt" | "dat" => Some(Format::Xyz),
            "ply" => Some(Format::Ply),
            "vtk" => Some(Format::Vtk),
            "vtu" => Some(Format::Vtu),
            "vtp" => Some(Format::Vtp),
            "bgeo" => Some(Format::Bgeo),
            "hdf5" | "h5" => Some(Format::Hdf5),
            "npz" => Some(Format::Npz),
            _ => None,
        }
    }

    /// Whether particle files of this format can be written (PySPH's are read only).
    pub fn can_write(self) -> bool {
        !matches!(self, Format::Hdf5 | Format::Npz)
    }

    /// The format's short name (and usual extension): `"csv"`, `"xyz"`, `"ply"`, `"vtk"`,
    /// `"vtu"`, `"vtp"`, `"bgeo"`, `"hdf5"`, `"npz"`.
    pub fn name(self) -> &'static str {
        match self {
            Format::Csv => "csv",
            Format::Xyz => "xyz",
            Format::Ply => "ply",
            Format::Vtk => "vtk",
            Format::Vtu => "vtu",
            Format::Vtp => "vtp",
            Format::Bgeo => "bgeo",
            Format::Hdf5 => "hdf5",
            Format::Npz => "npz",
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

    /// Parses a format name, case-insensitive: `csv`, `xyz` (also `txt`, `dat`), `ply`, `vtk`,
    /// `vtu`, `vtp`, `bgeo`, `hdf5` (also `h5`), `npz`.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "csv" => Ok(Format::Csv),
            "xyz" | "txt" | "dat" => Ok(Format::Xyz),
            "ply" => Ok(Format::Ply),
            "vtk" => Ok(Format::Vtk),
            "vtu" => Ok(Format::Vtu),
            "vtp" => Ok(Format::Vtp),
            "bgeo" => Ok(Format::Bgeo),
            "hdf5" | "h5" => Ok(Format::Hdf5),
            "npz" => Ok(Format::Npz),
            _ => Err(format!(
                "unknown format {s:?} (expected csv, xyz, ply, vtk, vtu, vtp, bgeo, hdf5 or npz)"
            )),
        }
    }
}

/// How to read a particle file.
#[derive(Debug, Clone, Default)]
pub struct ReadOptions {
    /// `None`: the file's own dimension; `Some(2)`: a 3D file loses its one constant axis;
    /// `Some(3)`: a 3D file is required. See the crate docs, "Dimension".
    pub dim: Option<usize>,
    /// `None`: from the extension (an error naming the file if it names no format).
    pub format: Option<Format>,
}

/// A per-particle output column.
#[derive(Debug, Clone, Copy)]
pub enum Column<'a> {
    /// Integers (labels, codes).
    Int(&'a [i64]),
    /// Reals (margins, scores).
    Float(&'a [f64]),
    /// Bytes, written as PLY `uchar` / VTK `unsigned_char` (colour components `red`, `green`,
    /// `blue`, which PLY viewers show as vertex colours); integers in text formats.
    Byte(&'a [u8]),
}

impl Column<'_> {
    /// Number of values.
    pub fn len(&self) -> usize {
        match self {
            Column::Int(v) => v.len(),
            Column::Float(v) => v.len(),
            Column::Byte(v) => v.len(),
        }
    }

    /// Whether the column holds no value.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// The values of a point attribute read from a file.
#[derive(Debug, Clone, PartialEq)]
pub enum AttributeValues {
    /// Integer data (any integer type of the file; unsigned 64-bit values beyond `i64` are
    /// read as reals).
    Int(Vec<i64>),
    /// Real data.
    Float(Vec<f64>),
}

/// A per-particle attribute of the input file other than the positions (velocity, pressure,
/// density, ids): one scalar per particle. A vector attribute of `k` components is read as `k`
/// attributes `name:0` … `name:k-1` (ParaView's names for components), which the VTK XML
/// writer joins again into one vector.
#[derive(Debug, Clone, PartialEq)]
pub struct Attribute {
    /// A valid column name (see the crate docs, "Writing").
    pub name: String,
    /// One value per particle, in file order.
    pub values: AttributeValues,
}

impl Attribute {
    /// The attribute as a column to write back.
    pub fn column(&self) -> Column<'_> {
        match &self.values {
            AttributeValues::Int(v) => Column::Int(v),
            AttributeValues::Float(v) => Column::Float(v),
        }
    }
}

/// A column name made from an attribute's name in a file: characters a column name may not
/// hold (see "Writing") become `_`; an empty name becomes `column<k>`.
pub(crate) fn attribute_name(name: &str, k: usize) -> String {
    let s: String = text::trim_field(name)
        .chars()
        .map(|c| {
            if c.is_ascii_graphic() && !",;#\"'".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() {
        format!("column{k}")
    } else {
        s
    }
}

/// Why an attribute named `name` cannot be kept beside `kept`: a name that reads as a position
/// (it would be taken for one when the output is read back), or a duplicate.
pub(crate) fn attribute_conflict(name: &str, kept: &[Attribute]) -> Option<&'static str> {
    if text::position_axis(name).is_some() {
        Some("its name reads as a position column")
    } else if kept.iter().any(|a| a.name.eq_ignore_ascii_case(name)) {
        Some("duplicate name")
    } else {
        None
    }
}

/// A particle file read with its attributes: what [`read_particle_file`] returns.
#[derive(Debug, Clone, PartialEq)]
pub struct ParticleFile {
    /// The positions, after the dimension policy.
    pub set: AnyParticleSet,
    /// Every other per-particle attribute the reader keeps, in file order.
    pub attributes: Vec<Attribute>,
    /// Attributes the file has but the reader could not keep, each with the reason (a
    /// non-numeric column, a name that would read as a position, a duplicate name).
    pub skipped: Vec<String>,
    /// The file's coordinates the positions were read from ("2D from x, y").
    pub position_columns: PositionColumns,
}

impl ParticleFile {
    /// The attributes as columns for [`write_particles`], leaving out those whose name equals
    /// (ignoring ASCII case) one in `except`: the columns the caller writes itself.
    pub fn columns<'a>(&'a self, except: &[&str]) -> Vec<(&'a str, Column<'a>)> {
        attribute_columns(&self.attributes, except)
    }
}

/// `attributes` as columns to write, less those named (ignoring ASCII case) in `except`.
pub(crate) fn attribute_columns<'a>(
    attributes: &'a [Attribute],
    except: &[&str],
) -> Vec<(&'a str, Column<'a>)> {
    attributes
        .iter()
        .filter(|a| !except.iter().any(|e| e.eq_ignore_ascii_case(&a.name)))
        .map(|a| (a.name.as_str(), a.column()))
        .collect()
}

/// Coordinates as a reader found them, before the dimension policy.
#[derive(Debug, Default)]
pub(crate) struct Positions {
    /// `stride` values per particle, in file order.
    pub coords: Vec<f64>,
    /// 2 or 3.
    pub stride: usize,
    /// The file says it holds a 2D set padded with z = 0 (VTK written by this crate).
    pub padded_2d: bool,
    /// Other point attributes, one value per particle each (formats that read them).
    pub attributes: Vec<Attribute>,
    /// Attributes not kept, with the reason.
    pub skipped: Vec<String>,
    /// The file's names of the `stride` coordinates read (a column per axis), or empty for a
    /// format whose positions are one vector array (named in [`read_any`]).
    pub names: Vec<String>,
    /// A column that looks like a misspelt third axis beside the two read
    /// ([`text::near_miss`]); an error unless 2D is asked for.
    pub near_miss: Option<NearMiss>,
    /// Why the file holds no particle, in the reader's words, when it holds none (for
    /// [`IoError::NoParticles`]; a generic reason by format otherwise).
    pub empty: Option<String>,
    /// The line of each particle, for readers that count lines (CSV).
    pub lines: LineIndex,
}

/// A column beside two position columns that looks like the misspelt third
/// ([`text::near_miss`]).
#[derive(Debug)]
pub(crate) struct NearMiss {
    /// Where it is named.
    pub at: Location,
    /// A PLY vertex property (else a column).
    pub vertex_property: bool,
    /// Its name as the file writes it (trimmed).
    pub name: String,
    /// The axis it would be (0, 1, 2).
    pub axis: usize,
}

/// Which coordinates of a file became the positions of its particle set
/// ([`ParticleFile::position_columns`]): what a tool shows ("2D from x, y") so that a misread
/// file is seen at once.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct PositionColumns {
    /// The file's names of the coordinates used, in axis order. Formats with a column per
    /// coordinate give one name per axis: the CSV header's names as written (`x`, `Pos.y [m]`,
    /// `Points:2`), the names of an XYZ `#` line, the PLY properties (`x`, `y`, `z`), and
    /// `column 1`, `column 2`, … for a headerless CSV or an XYZ file without names. Formats
    /// that store a position as one vector give its one name: `POINTS` (legacy VTK), the
    /// `Name` of the `<Points>` array or else `Points` (VTK XML), `P` (BGEO).
    pub names: Vec<String>,
    /// The coordinate the dimension policy dropped (a 3D file read as 2D: the constant one),
    /// by the file's name for it (`z`, `Pos.y [m]`; for a vector array, `x`, `y` or `z`);
    /// `None` when every coordinate read is used.
    pub dropped: Option<String>,
}

impl fmt::Display for PositionColumns {
    /// `x, y`; `columns 1, 2, 3`; `Points`; `Pos.x [m], Pos.z [m] (Pos.y [m] dropped:
    /// constant)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let numbers: Option<Vec<&str>> = self
            .names
            .iter()
            .map(|n| n.strip_prefix("column "))
            .collect();
        match numbers {
            Some(numbers) if numbers.len() > 1 => write!(f, "columns {}", numbers.join(", "))?,
            _ => f.write_str(&self.names.join(", "))?,
        }
        if let Some(dropped) = &self.dropped {
            write!(f, " ({dropped} dropped: constant)")?;
        }
        Ok(())
    }
}

/// A triangle-mesh file format (see [`read_mesh`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MeshFormat {
    /// STL, ascii or binary (`.stl`).
    Stl,
    /// Wavefront OBJ (`.obj`): its `v` and `f` statements.
    Obj,
    /// PLY with the elements `vertex` and `face` (`.ply`).
    Ply,
}

impl MeshFormat {
    /// The format named by the extension of `path`, case-insensitive: `stl`, `obj`, `ply`.
    pub fn from_path(path: &Path) -> Option<MeshFormat> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "stl" => Some(MeshFormat::Stl),
            "obj" => Some(MeshFormat::Obj),
            "ply" => Some(MeshFormat::Ply),
            _ => None,
        }
    }
}

/// The vertices and triangles (indices into the vertices) of a triangle mesh.
pub type TriangleMesh = (Vec<[f64; 3]>, Vec<[u32; 3]>);

/// Reads a triangle mesh, for a solid region (`boundary_core::SolidMesh::new` validates it):
/// STL (ascii or binary), OBJ or PLY, by the extension of `path`.
///
/// - **STL**: binary when the size is `84 + 50·n` for the count `n` in its header, else ascii
///   (`solid` … `facet` … `vertex x y z` … `endfacet` … `endsolid`). Corners with identical
///   coordinates become one vertex (STL stores each triangle's corners by value).
/// - **OBJ**: the `v x y z` and `f` statements (`f 1 2 3`, `f 1/1/1 2/2/2 3/3/3`, negative
///   indices relative to the last vertex); other statements are skipped.
/// - **PLY**: `x, y, z` of the element `vertex` and the list `vertex_indices` (or
///   `vertex_index`) of the element `face`, ascii or binary.
///
/// Polygons with more corners are split into a fan from their first corner. Errors name the
/// file and the line (text) or the triangle, vertex or face (binary). Nothing here checks that
/// the surface is closed; the core constructor does.
///
/// ```
/// let dir = tempfile::tempdir().expect("temporary directory");
/// let path = dir.path().join("tetra.obj");
/// std::fs::write(&path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")?;
/// let (vertices, triangles) = boundary_io::read_mesh(&path)?;
/// assert_eq!((vertices.len(), triangles.len()), (4, 4));
/// assert_eq!(triangles[0], [0, 2, 1]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn read_mesh(path: &Path) -> Result<TriangleMesh, IoError> {
    let name = path.display().to_string();
    let format = MeshFormat::from_path(path).ok_or_else(|| {
        IoError::parse(
            &name,
            Location::File,
            "unknown mesh format: expected extension .stl, .obj or .ply",
        )
    })?;
    let file = std::fs::File::open(path).map_err(|e| IoError::read(&name, e))?;
    read_mesh_from(file, &name, format)
}

/// [`read_mesh`] from a reader; `name` names the source in error messages.
pub fn read_mesh_from(
    reader: impl Read,
    name: &str,
    format: MeshFormat,
) -> Result<TriangleMesh, IoError> {
    let reader = BufReader::new(reader);
    let mesh = match format {
        MeshFormat::Stl => mesh::read_stl(reader, name)?,
        MeshFormat::Obj => mesh::read_obj(reader, name)?,
        MeshFormat::Ply => ply::read_mesh(reader, name)?,
    };
    if mesh.1.is_empty() {
        return Err(IoError::parse(
            name,
            Location::File,
            "the mesh has no triangle",
        ));
    }
    Ok(mesh)
}

/// Reads the particles of the file at `path`; the format is `options.format` or the one the
/// extension names. See the crate docs for the formats and the dimension policy.
pub fn read_particles(path: &Path, options: &ReadOptions) -> Result<AnyParticleSet, IoError> {
    let (file, name, format) = open_input(path, options)?;
    read_particles_from(file, &name, format, options)
}

/// The open file at `path`, its name for messages, and its format (`options.format`, else the
/// one the extension names).
fn open_input(
    path: &Path,
    options: &ReadOptions,
) -> Result<(std::fs::File, String, Format), IoError> {
    let name = path.display().to_string();
    let format = match options.format {
        Some(f) => f,
        None => {
            Format::from_path(path).ok_or_else(|| IoError::UnknownFormat { file: name.clone() })?
        }
    };
    let file = std::fs::File::open(path).map_err(|e| IoError::read(&name, e))?;
    Ok((file, name, format))
}

/// Reads particles in `format` from `reader`; `name` names the source in error messages.
/// `options.format` is ignored (the format is given).
pub fn read_particles_from(
    reader: impl Read,
    name: &str,
    format: Format,
    options: &ReadOptions,
) -> Result<AnyParticleSet, IoError> {
    read_any(reader, name, format, options, false, None).map(|(f, _)| f.set)
}

/// Reads the particles of the file at `path` with their other point attributes (see the crate
/// docs, "Attributes"); the format is `options.format` or the one the extension names.
pub fn read_particle_file(path: &Path, options: &ReadOptions) -> Result<ParticleFile, IoError> {
    let (file, name, format) = open_input(path, options)?;
    read_particle_file_from(file, &name, format, options)
}

/// [`read_particle_file`] from a reader; `name` names the source in error messages.
pub fn read_particle_file_from(
    reader: impl Read,
    name: &str,
    format: Format,
    options: &ReadOptions,
) -> Result<ParticleFile, IoError> {
    read_any(reader, name, format, options, true, None).map(|(f, _)| f)
}

/// Reads the particle array `array` (`"fluid"`, `"boundary"`, `"solid"`, …) of a PySPH file
/// (`.hdf5` or `.npz`) with its attributes, as [`read_particle_file`] reads the default one
/// (`fluid`, else the file's only array). Other formats hold no named arrays: asking one of
/// them for an array is an error.
pub fn read_particle_array(
    path: &Path,
    array: &str,
    options: &ReadOptions,
) -> Result<ParticleFile, IoError> {
    let (file, name, format) = open_input(path, options)?;
    if !matches!(format, Format::Hdf5 | Format::Npz) {
        return Err(not_an_array_format(&name, array, format));
    }
    read_any(file, &name, format, options, true, Some(array)).map(|(f, _)| f)
}

/// The error of asking a format without named particle arrays for one.
fn not_an_array_format(name: &str, array: &str, format: Format) -> IoError {
    IoError::parse(
        name,
        Location::File,
        format!(
            "particle array {array:?} asked for, but only PySPH files (.hdf5, .npz) hold named \
             particle arrays, not {format} files"
        ),
    )
}

/// The particle arrays of a PySPH file (`.hdf5` or `.npz`) with their particle counts, in
/// file order; for another format, the file's one set, named `""`.
pub fn particle_arrays(
    path: &Path,
    options: &ReadOptions,
) -> Result<Vec<(String, usize)>, IoError> {
    let (file, name, format) = open_input(path, options)?;
    match format {
        Format::Hdf5 | Format::Npz => {
            let arrays = pysph::read_arrays(BufReader::new(file), &name, format == Format::Npz)?;
            Ok(pysph::list(&arrays))
        }
        _ => {
            let set = read_particles_from(file, &name, format, options)?;
            Ok(vec![(String::new(), set.len())])
        }
    }
}

/// [`read_particle_file`] without the attributes: the particle set and the
/// [`ParticleFile::position_columns`] it was read from, with `attributes` and `skipped` empty
/// (nothing but the positions is parsed, as in [`read_particles`]).
pub fn read_positions(path: &Path, options: &ReadOptions) -> Result<ParticleFile, IoError> {
    let (file, name, format) = open_input(path, options)?;
    read_any(file, &name, format, options, false, None).map(|(f, _)| f)
}

/// Reads the file at `path` once into a [`Frame`]: the particles, with `parts` the other
/// point attributes too, and the line of each particle (CSV) for later messages. The format
/// is `options.format` or the one the extension names.
///
/// ```
/// use boundary_io::{read_frame, FrameParts, ReadOptions};
///
/// let dir = tempfile::tempdir().expect("temporary directory");
/// let path = dir.path().join("frame.csv");
/// std::fs::write(&path, "x,y,h\n0,0,1\n# a comment\n1,0,2\n")?;
/// let frame = read_frame(&path, &ReadOptions::default(), FrameParts::WithAttributes)?;
/// assert_eq!(frame.set.len(), 2);
/// assert_eq!(frame.attribute("H").map(|a| a.name.as_str()), Some("h"));
/// assert_eq!((frame.line(0), frame.line(1), frame.line(2)), (Some(2), Some(4), None));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn read_frame(path: &Path, options: &ReadOptions, parts: FrameParts) -> Result<Frame, IoError> {
    let (file, name, format) = open_input(path, options)?;
    let attributes = parts == FrameParts::WithAttributes;
    let (file, lines) = read_any(file, &name, format, options, attributes, None)?;
    Ok(Frame::new(path, file, lines))
}

/// [`read_frame`] of the particle array `array` (`"fluid"`, `"boundary"`, …) of a PySPH file
/// (`.hdf5` or `.npz`), as [`read_particle_array`] reads it. Other formats hold no named
/// arrays: asking one of them for an array is an error.
pub fn read_array_frame(
    path: &Path,
    array: &str,
    options: &ReadOptions,
    parts: FrameParts,
) -> Result<Frame, IoError> {
    let (file, name, format) = open_input(path, options)?;
    if !matches!(format, Format::Hdf5 | Format::Npz) {
        return Err(not_an_array_format(&name, array, format));
    }
    let attributes = parts == FrameParts::WithAttributes;
    let (file, lines) = read_any(file, &name, format, options, attributes, Some(array))?;
    Ok(Frame::new(path, file, lines))
}

/// Reads positions, and the other point attributes when `attributes` is set; with the line
/// of each particle where the reader counts lines.
fn read_any(
    reader: impl Read,
    name: &str,
    format: Format,
    options: &ReadOptions,
    attributes: bool,
    array: Option<&str>,
) -> Result<(ParticleFile, LineIndex), IoError> {
    check_dim(name, options.dim)?;
    let reader = BufReader::new(reader);
    let mut positions = match format {
        Format::Csv => csv::read(reader, name, options.dim, attributes)?,
        Format::Xyz => xyz::read(reader, name)?,
        Format::Ply => ply::read(reader, name, attributes)?,
        Format::Vtk => vtk::read(reader, name, attributes)?,
        Format::Vtu => vtk_xml::read(reader, name, vtk_xml::Kind::UnstructuredGrid, attributes)?,
        Format::Vtp => vtk_xml::read(reader, name, vtk_xml::Kind::PolyData, attributes)?,
        Format::Bgeo => bgeo::read(reader, name, attributes)?,
        Format::Hdf5 => pysph::read(reader, name, false, array, attributes)?,
        Format::Npz => pysph::read(reader, name, true, array, attributes)?,
    };
    let n = positions.coords.len() / positions.stride.max(1);
    if let Some(miss) = positions.near_miss.take() {
        // Reading 2D on purpose (`dim = 2`) takes the two axes found.
        if options.dim != Some(2) {
            return Err(IoError::NearMissColumn {
                file: name.to_owned(),
                at: miss.at,
                vertex_property: miss.vertex_property,
                name: miss.name,
                axis: ['x', 'y', 'z'][miss.axis],
                kept: positions.names.join(", "),
            });
        }
    }
    let attributes = std::mem::take(&mut positions.attributes);
    let skipped = std::mem::take(&mut positions.skipped);
    debug_assert!(attributes.iter().all(|a| a.column().len() == n));
    let mut names = std::mem::take(&mut positions.names);
    if names.is_empty() {
        names = match format {
            Format::Vtk => vec!["POINTS".to_owned()],
            Format::Bgeo => vec!["P".to_owned()],
            Format::Vtu | Format::Vtp => vec!["Points".to_owned()],
            Format::Csv | Format::Xyz | Format::Ply | Format::Hdf5 | Format::Npz => (1..=positions
                .stride)
                .map(|k| format!("column {k}"))
                .collect(),
        };
    }
    let empty = positions.empty.take();
    let lines = std::mem::take(&mut positions.lines);
    let (set, dropped) = apply_dimension(positions, name, options.dim)?;
    if set.is_empty() {
        return Err(IoError::NoParticles {
            file: name.to_owned(),
            dim: Some(set.dim()),
            detail: empty.unwrap_or_else(|| {
                match format {
                    Format::Csv => "the file has no data row",
                    Format::Xyz => "the file has no particle line",
                    Format::Ply => "its element vertex has 0 elements",
                    Format::Vtk => "its POINTS section holds 0 points",
                    Format::Vtu | Format::Vtp => "its <Piece> has NumberOfPoints=\"0\"",
                    Format::Bgeo => "its header declares 0 points",
                    Format::Hdf5 | Format::Npz => "its particle array is empty",
                }
                .to_owned()
            }),
        });
    }
    // A vector array's dropped component is its axis letter; a column is dropped by name.
    let dropped = dropped.map(|axis| match names.len() {
        1 => out::AXES[axis].to_owned(),
        _ => names.remove(axis),
    });
    let file = ParticleFile {
        set,
        attributes,
        skipped,
        position_columns: PositionColumns { names, dropped },
    };
    Ok((file, lines))
}

/// Errors: a requested dimension other than 2 or 3.
fn check_dim(name: &str, dim: Option<usize>) -> Result<(), IoError> {
    match dim {
        Some(d) if d != 2 && d != 3 => Err(IoError::dimension(
            name,
            format!("dimension must be 2 or 3, got {d}"),
        )),
        _ => Ok(()),
    }
}

/// Whether coordinate `axis` has the same value for every particle (vacuously for none).
fn is_constant(coords: &[f64], stride: usize, axis: usize) -> bool {
    let mut values = coords.iter().skip(axis).step_by(stride);
    match values.next() {
        Some(&first) => values.all(|&v| v == first),
        None => true,
    }
}

/// The dimension policy of the crate docs: the set, and the axis of the file dropped to make
/// it 2D (if one was).
fn apply_dimension(
    p: Positions,
    name: &str,
    dim: Option<usize>,
) -> Result<(AnyParticleSet, Option<usize>), IoError> {
    let padded_zero = p.padded_2d && p.coords.iter().skip(2).step_by(3).all(|&z| z == 0.0);
    dimension_of(&p.coords, p.stride, padded_zero, name, dim, |axis| {
        is_constant(&p.coords, 3, axis)
    })
}

/// The dimension policy on rows of `stride` (2 or 3) values: `padded_zero` says the file
/// declares a 2D set padded with z = 0 and every z is 0; `constant(axis)` whether an axis has
/// one value over the whole file (asked only to drop one).
pub(crate) fn dimension_of(
    coords: &[f64],
    stride: usize,
    padded_zero: bool,
    name: &str,
    dim: Option<usize>,
    constant: impl Fn(usize) -> bool,
) -> Result<(AnyParticleSet, Option<usize>), IoError> {
    debug_assert!(stride == 2 || stride == 3);
    if stride == 2 {
        if dim == Some(3) {
            return Err(IoError::dimension(
                name,
                "dim = 3 requested but the file holds 2D positions (no z coordinate)",
            ));
        }
        return Ok((build::<2>(coords, 2, [0, 1], name)?, None));
    }
    match dim {
        Some(3) => Ok((build::<3>(coords, 3, [0, 1, 2], name)?, None)),
        None if !padded_zero => Ok((build::<3>(coords, 3, [0, 1, 2], name)?, None)),
        _ => {
            let dropped = [2, 1, 0]
                .into_iter()
                .find(|&axis| constant(axis))
                .ok_or_else(|| {
                    IoError::dimension(
                        name,
                        "dim = 2 requested but none of x, y, z is constant over all particles, so \
                         no axis can be dropped",
                    )
                })?;
            let kept = match dropped {
                2 => [0, 1],
                1 => [0, 2],
                _ => [1, 2],
            };
            Ok((build::<2>(coords, 3, kept, name)?, Some(dropped)))
        }
    }
}

/// Builds a `D`-dimensional set from rows of `stride` values, taking the axes `axes`.
fn build<const D: usize>(
    coords: &[f64],
    stride: usize,
    axes: [usize; D],
    name: &str,
) -> Result<AnyParticleSet, IoError>
where
    AnyParticleSet: From<ParticleSet<D>>,
    Dim<D>: SupportedDim,
{
    let points: Vec<Point<D>> = coords
        .chunks_exact(stride)
        .map(|row| Point::<D>::from_fn(|a, _| row[axes[a]]))
        .collect();
    // Readers reject non-finite values where they know the line; this is the backstop.
    ParticleSet::new(points)
        .map(AnyParticleSet::from)
        .map_err(|e| match e {
            CoreError::NonFiniteCoordinate { index, axis, value } => IoError::NonFinite {
                file: name.to_owned(),
                at: Location::Item {
                    kind: "particle",
                    index,
                },
                index,
                axis: axes[axis],
                value,
            },
            other => IoError::Particles {
                file: name.to_owned(),
                source: other,
            },
        })
}

/// Reads the numeric column named `column` (matched like position names: case-insensitive,
/// spaces, quotes and unit suffix ignored) of a CSV file with a header, e.g. the `boundary`
/// labels written by `boundary detect`. Errors name the file and the line.
pub fn read_csv_column(path: &Path, column: &str) -> Result<Vec<f64>, IoError> {
    let name = path.display().to_string();
    let file = std::fs::File::open(path).map_err(|e| IoError::read(&name, e))?;
    csv::read_column(BufReader::new(file), &name, column)
}

/// Writes the positions of `set` and the extra `columns` to `path`; the format is `format` or
/// the one the extension of `path` names. The columns are checked (length, names) before the
/// file is created. The write is atomic ([`write_atomic`]): a reader sees the old file or the
/// whole new one, a failure leaves no file behind, and `path` may name the file the set was
/// read from.
pub fn write_particles(
    path: &Path,
    format: Option<Format>,
    set: &AnyParticleSet,
    columns: &[(&str, Column<'_>)],
) -> Result<(), IoError> {
    write_particles_through(path, format, set, columns, |file| Box::new(file))
}

/// [`write_particles`] through `sink` (see [`atomic::write_atomic_through`]).
pub(crate) fn write_particles_through(
    path: &Path,
    format: Option<Format>,
    set: &AnyParticleSet,
    columns: &[(&str, Column<'_>)],
    sink: fn(&mut std::fs::File) -> Box<dyn Write + '_>,
) -> Result<(), IoError> {
    let name = path.display().to_string();
    let format = match format {
        Some(f) => f,
        None => {
            Format::from_path(path).ok_or_else(|| IoError::UnknownFormat { file: name.clone() })?
        }
    };
    check_columns(&name, format, set, columns)?;
    let gzip = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("gz"));
    atomic::write_atomic_through(path, sink, |out| {
        if gzip {
            // `.bgeo.gz` (and any other name ending in .gz): gzip-compressed.
            let mut gz = flate2::write::GzEncoder::new(out, flate2::Compression::default());
            write_body(&mut gz, format, set, columns)?;
            gz.finish()?;
            Ok(())
        } else {
            write_body(out, format, set, columns)
        }
    })
}

/// Writes particles in `format` to `writer`; errors call the destination `<output>`.
pub fn write_particles_to(
    writer: impl Write,
    format: Format,
    set: &AnyParticleSet,
    columns: &[(&str, Column<'_>)],
) -> Result<(), IoError> {
    const NAME: &str = "<output>";
    check_columns(NAME, format, set, columns)?;
    let mut out = BufWriter::new(writer);
    write_body(&mut out, format, set, columns).map_err(|e| IoError::write(NAME, e))?;
    out.flush().map_err(|e| IoError::write(NAME, e))
}

fn check_columns(
    name: &str,
    format: Format,
    set: &AnyParticleSet,
    columns: &[(&str, Column<'_>)],
) -> Result<(), IoError> {
    let column_error = |column: &str, message: String| IoError::Column {
        file: name.to_owned(),
        name: column.to_owned(),
        message,
    };
    if !format.can_write() {
        return Err(IoError::ReadOnlyFormat {
            file: name.to_owned(),
            format,
        });
    }
    if format == Format::Bgeo {
        // BGEO stores 32-bit floats: a coordinate beyond their range would become infinite.
        if let Some((i, axis)) = (0..set.len())
            .flat_map(|i| (0..set.dim()).map(move |a| (i, a)))
            .find(|&(i, a)| set.coords(i)[a].abs() > f64::from(f32::MAX))
        {
            return Err(column_error(
                out::AXES[axis],
                format!(
                    "coordinate {} of particle {i} does not fit BGEO's 32-bit float",
                    set.coords(i)[axis]
                ),
            ));
        }
    }
    for (k, (column, values)) in columns.iter().enumerate() {
        if values.len() != set.len() {
            return Err(column_error(
                column,
                format!("{} values for {} particles", values.len(), set.len()),
            ));
        }
        if column.is_empty()
            || !column
                .chars()
                .all(|c| c.is_ascii_graphic() && !",;#\"'".contains(c))
        {
            return Err(column_error(
                column,
                "a column name must be non-empty printable ASCII without spaces, quotes, ',', ';' \
                 or '#'"
                    .into(),
            ));
        }
        if text::position_axis(column).is_some() {
            return Err(column_error(
                column,
                "the name would be read back as a position column".into(),
            ));
        }
        if columns[..k]
            .iter()
            .any(|(other, _)| other.eq_ignore_ascii_case(column))
        {
            return Err(column_error(column, "duplicate column name".into()));
        }
        if format == Format::Ply {
            let property = ply::property_name(column);
            if text::position_axis(&property).is_some() {
                return Err(column_error(
                    column,
                    format!("its PLY property name {property} would be read back as a position"),
                ));
            }
            if let Some((other, _)) = columns[..k]
                .iter()
                .find(|(other, _)| ply::property_name(other).eq_ignore_ascii_case(&property))
            {
                return Err(column_error(
                    column,
                    format!("it and column {other} would both be the PLY property {property}"),
                ));
            }
        }
        if format == Format::Bgeo {
            if let Err((column, message)) = bgeo::check(&columns[k..=k]) {
                return Err(column_error(&column, message));
            }
        }
        if let (Format::Ply | Format::Vtk, Column::Float(values)) = (format, values) {
            if let Some((i, v)) = values.iter().enumerate().find(|(_, v)| !v.is_finite()) {
                return Err(column_error(
                    column,
                    format!(
                        "value {v} of particle {i} cannot be written in {}, which has no text \
                         for non-finite reals",
                        format.name().to_ascii_uppercase()
                    ),
                ));
            }
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
        Format::Vtu => vtk_xml::write(out, set, columns, vtk_xml::Kind::UnstructuredGrid),
        Format::Vtp => vtk_xml::write(out, set, columns, vtk_xml::Kind::PolyData),
        Format::Bgeo => bgeo::write(out, set, columns),
        // Refused by `check_columns` before any file is created.
        Format::Hdf5 | Format::Npz => Err(std::io::Error::new(
            std::io::ErrorKind::Unsupported,
            format!("{format} files are read only"),
        )),
    }
}

/// Writing helpers shared by the formats.
pub(crate) mod out {
    use super::Column;
    use std::fmt;

    /// A real in the shortest text that reads back to the same `f64`: plain decimal for
    /// moderate magnitudes, scientific notation below 1e-5 and from 1e16 on (so that `1e300`
    /// is not written as 301 digits).
    pub(crate) struct Real(pub f64);

    impl fmt::Display for Real {
        fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            let v = self.0;
            let a = v.abs();
            if v == 0.0 || !v.is_finite() || (1e-5..1e16).contains(&a) {
                write!(f, "{v}")
            } else {
                write!(f, "{v:e}")
            }
        }
    }

    /// Writes value `i` of `column`.
    pub(crate) fn value(
        out: &mut dyn std::io::Write,
        column: &Column<'_>,
        i: usize,
    ) -> std::io::Result<()> {
        match column {
            Column::Int(v) => write!(out, "{}", v[i]),
            Column::Float(v) => write!(out, "{}", Real(v[i])),
            Column::Byte(v) => write!(out, "{}", v[i]),
        }
    }

    /// The PLY type of a column: `uchar` for bytes, `int` when every integer fits 32 bits,
    /// else `double` (the VTK writer maps `uchar` to `unsigned_char`).
    pub(crate) fn binary_type(column: &Column<'_>) -> &'static str {
        match column {
            Column::Byte(_) => "uchar",
            Column::Int(v) if v.iter().all(|&x| i32::try_from(x).is_ok()) => "int",
            _ => "double",
        }
    }

    /// Writes value `i` of `column` as the type [`binary_type`] chose.
    pub(crate) fn typed_value(
        out: &mut dyn std::io::Write,
        column: &Column<'_>,
        ty: &str,
        i: usize,
    ) -> std::io::Result<()> {
        match (column, ty) {
            (Column::Int(v), "double") => write!(out, "{}", Real(v[i] as f64)),
            _ => value(out, column, i),
        }
    }

    /// Axis names.
    pub(crate) const AXES: [&str; 3] = ["x", "y", "z"];
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn format_names_and_extensions() {
        for f in [
            Format::Csv,
            Format::Xyz,
            Format::Ply,
            Format::Vtk,
            Format::Vtu,
            Format::Vtp,
            Format::Bgeo,
            Format::Hdf5,
            Format::Npz,
        ] {
            assert_eq!(f.name().parse::<Format>(), Ok(f));
            assert_eq!(f.to_string(), f.name());
        }
        assert_eq!(Format::from_path(Path::new("a/b.CSV")), Some(Format::Csv));
        assert_eq!(Format::from_path(Path::new("b.txt")), Some(Format::Xyz));
        assert_eq!(Format::from_path(Path::new("b.Ply")), Some(Format::Ply));
        assert_eq!(Format::from_path(Path::new("b.vtk")), Some(Format::Vtk));
        assert_eq!(Format::from_path(Path::new("b.vtu")), Some(Format::Vtu));
        assert_eq!(Format::from_path(Path::new("b.VTP")), Some(Format::Vtp));
        assert_eq!(Format::from_path(Path::new("b.bgeo")), Some(Format::Bgeo));
        assert_eq!(
            Format::from_path(Path::new("a/b.bgeo.GZ")),
            Some(Format::Bgeo)
        );
        assert_eq!(Format::from_path(Path::new("b.csv.gz")), None);
        assert_eq!(Format::from_path(Path::new("b.bgeo.sc")), None);
        assert_eq!(Format::from_path(Path::new("noext")), None);
        assert!("pdb".parse::<Format>().unwrap_err().contains("pdb"));
    }

    #[test]
    fn real_text_reads_back_exactly() {
        for v in [
            0.0,
            -0.0,
            1.0,
            0.1,
            1.0 / 3.0,
            1e-7,
            -2.5e-300,
            1e300,
            f64::MAX,
            f64::MIN_POSITIVE,
            5e-324,
            123456789.123,
            1e16 - 2.0,
        ] {
            let text = out::Real(v).to_string();
            assert_eq!(
                text.parse::<f64>().unwrap().to_bits(),
                v.to_bits(),
                "{text}"
            );
            assert!(text.len() <= 25, "{text}");
        }
    }

    fn positions(rows: &[[f64; 3]]) -> Positions {
        Positions {
            coords: rows.iter().flatten().copied().collect(),
            stride: 3,
            ..Positions::default()
        }
    }

    #[test]
    fn dim_2_drops_the_one_constant_axis() {
        let rows = [[0.0, 5.0, 1.0], [1.0, 5.0, 2.0], [2.0, 5.0, 0.5]];
        let (set, dropped) = apply_dimension(positions(&rows), "f", Some(2)).unwrap();
        assert_eq!((set.dim(), dropped), (2, Some(1)));
        assert_eq!(set.coords(2), &[2.0, 0.5]);
        // Without dim the file is 3D.
        assert_eq!(
            apply_dimension(positions(&rows), "f", None)
                .unwrap()
                .0
                .dim(),
            3
        );
    }

    #[test]
    fn several_constant_axes_drop_z_then_y() {
        let rows = [[0.0, 5.0, 1.0], [1.0, 5.0, 1.0]];
        let (set, _) = apply_dimension(positions(&rows), "f", Some(2)).unwrap();
        assert_eq!(set.coords(1), &[1.0, 5.0]);
        let rows = [[3.0, 5.0, 1.0], [3.0, 5.0, 2.0]];
        let (set, _) = apply_dimension(positions(&rows), "f", Some(2)).unwrap();
        assert_eq!(set.coords(1), &[3.0, 2.0]);
        let rows = [[3.0, 5.0, 1.0], [3.0, 6.0, 2.0]];
        let (set, _) = apply_dimension(positions(&rows), "f", Some(2)).unwrap();
        assert_eq!(set.coords(1), &[6.0, 2.0]);
    }

    #[test]
    fn dim_2_without_constant_axis_and_dim_3_on_2d_are_errors() {
        let rows = [[0.0, 5.0, 1.0], [1.0, 6.0, 2.0]];
        let e = apply_dimension(positions(&rows), "f.csv", Some(2)).unwrap_err();
        assert!(e.to_string().contains("f.csv"), "{e}");
        let p = Positions {
            coords: vec![0.0, 1.0],
            stride: 2,
            ..Positions::default()
        };
        let e = apply_dimension(p, "g.csv", Some(3)).unwrap_err();
        assert!(matches!(e, IoError::Dimension { .. }), "{e}");
        assert!(e.to_string().contains("g.csv"), "{e}");
    }

    #[test]
    fn padded_2d_marker_only_applies_to_zero_z() {
        let mut p = positions(&[[0.0, 5.0, 0.0], [1.0, 6.0, 0.0]]);
        p.padded_2d = true;
        assert_eq!(apply_dimension(p, "f", None).unwrap().0.dim(), 2);
        let mut p = positions(&[[0.0, 5.0, 0.0], [1.0, 6.0, 1.0]]);
        p.padded_2d = true;
        assert_eq!(apply_dimension(p, "f", None).unwrap().0.dim(), 3);
    }

    #[test]
    fn bad_output_columns_are_errors_saying_why() {
        let set = ParticleSet::from_rows(&[[0.0, 0.0]]).unwrap().to_any();
        for (name, needle) in [
            ("a b", "printable"),
            ("", "printable"),
            ("Pos.x", "position"),
            ("z", "position"),
        ] {
            let e = check_columns("o.csv", Format::Csv, &set, &[(name, Column::Int(&[1]))])
                .unwrap_err();
            assert!(e.to_string().contains(needle), "{e}");
        }
        let e = check_columns(
            "o.csv",
            Format::Csv,
            &set,
            &[("b", Column::Float(&[1.0, 2.0]))],
        )
        .unwrap_err();
        assert!(e.to_string().contains("2 values for 1 particles"), "{e}");
        let e = check_columns(
            "o.csv",
            Format::Csv,
            &set,
            &[("b", Column::Int(&[1])), ("B", Column::Int(&[1]))],
        )
        .unwrap_err();
        assert!(e.to_string().contains("duplicate"), "{e}");
        let nan = [f64::NAN];
        assert!(check_columns("o.csv", Format::Csv, &set, &[("m", Column::Float(&nan))]).is_ok());
        for format in [Format::Ply, Format::Vtk] {
            let e = check_columns("o", format, &set, &[("m", Column::Float(&nan))]).unwrap_err();
            assert!(e.to_string().contains("particle 0"), "{e}");
        }
    }
}
