//! One input read once: its particles, their other attributes and where each particle is
//! written in the file, so that a tool never opens the file again, not even to name the line
//! of a bad value found after reading.

use crate::{Attribute, Column, ParticleFile, PositionColumns};
use boundary_core::AnyParticleSet;
use std::path::{Path, PathBuf};

/// The line on which each particle of a text file is written, kept as runs of consecutive
/// lines: a file without blank or comment lines between its rows is one run, so the index
/// costs two numbers, not one per particle.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct LineIndex {
    /// `(first particle, its 1-based line)` of each run, by particle.
    runs: Vec<(usize, usize)>,
    /// Particles indexed.
    len: usize,
}

impl LineIndex {
    /// Records that the next particle (number `self.len`) is written on `line`.
    pub(crate) fn push(&mut self, line: usize) {
        let continues = self
            .runs
            .last()
            .is_some_and(|&(first, at)| at + (self.len - first) == line);
        if !continues {
            self.runs.push((self.len, line));
        }
        self.len += 1;
    }

    /// The 1-based line of particle `index` (0-based, in file order); `None` when the reader
    /// kept no lines (binary formats, XYZ) or the file has fewer particles.
    pub fn line(&self, index: usize) -> Option<usize> {
        if index >= self.len {
            return None;
        }
        let run = self.runs.partition_point(|&(first, _)| first <= index);
        let (first, at) = self.runs[run.checked_sub(1)?];
        Some(at + (index - first))
    }
}

/// What to read of a particle file besides the positions (see [`crate::read_frame`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrameParts {
    /// The positions only: nothing else is parsed, as in [`crate::read_particles`].
    Positions,
    /// The positions and every other point attribute the reader keeps, as in
    /// [`crate::read_particle_file`].
    WithAttributes,
}

/// A particle file read into memory once: the set, its other point attributes, the
/// coordinates used and the line of each particle. Everything a tool needs after reading
/// (an attribute, a line for a message) comes from here.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// The file read, named in messages.
    pub path: PathBuf,
    /// The positions, after the dimension policy (and the radii, once a tool attaches them).
    pub set: AnyParticleSet,
    /// Every other per-particle attribute the reader keeps, in file order (empty when read
    /// with [`FrameParts::Positions`]).
    pub attributes: Vec<Attribute>,
    /// Attributes the file has but the reader could not keep, each with the reason.
    pub skipped: Vec<String>,
    /// The file's coordinates the positions were read from ("2D from x, y").
    pub position_columns: PositionColumns,
    /// The line of each particle (CSV; empty for other formats).
    pub lines: LineIndex,
}

impl Frame {
    /// Builds a frame of `path` from what a reader returned.
    pub(crate) fn new(path: &Path, file: ParticleFile, lines: LineIndex) -> Self {
        Frame {
            path: path.to_path_buf(),
            set: file.set,
            attributes: file.attributes,
            skipped: file.skipped,
            position_columns: file.position_columns,
            lines,
        }
    }

    /// The 1-based line of particle `index` in the file, where the format has lines that
    /// the reader counted (CSV); see [`LineIndex::line`].
    pub fn line(&self, index: usize) -> Option<usize> {
        self.lines.line(index)
    }

    /// The attribute `name`: the exact name, else the one name equal ignoring ASCII case;
    /// `None` when there is none, or several that differ only in case.
    pub fn attribute(&self, name: &str) -> Option<&Attribute> {
        if let Some(a) = self.attributes.iter().find(|a| a.name == name) {
            return Some(a);
        }
        let mut folded = self
            .attributes
            .iter()
            .filter(|a| a.name.eq_ignore_ascii_case(name));
        match (folded.next(), folded.next()) {
            (Some(a), None) => Some(a),
            _ => None,
        }
    }

    /// The attributes as columns for [`crate::write_particles`], leaving out those whose name
    /// equals (ignoring ASCII case) one in `except`: the columns the caller writes itself.
    pub fn columns<'a>(&'a self, except: &[&str]) -> Vec<(&'a str, Column<'a>)> {
        crate::attribute_columns(&self.attributes, except)
    }
}

#[cfg(test)]
mod tests {
    use super::LineIndex;

    #[test]
    fn runs_of_lines_give_each_particle_its_line() {
        let mut index = LineIndex::default();
        for line in [5, 6, 7, 9, 12, 13] {
            index.push(line);
        }
        assert_eq!(index.runs.len(), 3);
        let lines: Vec<Option<usize>> = (0..7).map(|i| index.line(i)).collect();
        assert_eq!(
            lines,
            [Some(5), Some(6), Some(7), Some(9), Some(12), Some(13), None]
        );
        assert_eq!(LineIndex::default().line(0), None);
    }
}
