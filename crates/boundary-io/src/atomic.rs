//! Atomic file writes: a reader sees the old file or the whole new one, never a part.
//!
//! [`write_atomic`] writes to a temporary file in the destination's directory, named
//! `.<name>.tmp-<pid>-<n>` (hidden, and with no extension a reader of outputs would take for a
//! format), flushes it and syncs it to the disk, then renames it over the destination. On any
//! error the temporary file is removed and the error names the destination. A file that was
//! already at the destination (the input itself, when a tool writes over it) is untouched
//! until the rename, which replaces it in one step.

use crate::IoError;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Makes the temporary names of one process distinct across threads.
static NEXT: AtomicU64 = AtomicU64::new(0);

/// The marker in every temporary file name: `.<name>` + this + `<pid>-<n>`.
pub const TEMP_MARKER: &str = ".tmp-";

/// Whether `file_name` is a temporary file [`write_atomic`] makes for the destination named
/// `destination` (in the same directory), by this process or by any other.
pub fn is_temp_name_for(file_name: &str, destination: &str) -> bool {
    file_name
        .strip_prefix('.')
        .and_then(|rest| rest.strip_prefix(destination))
        .and_then(|rest| rest.strip_prefix(TEMP_MARKER))
        .is_some_and(|id| {
            id.split_once('-').is_some_and(|(pid, n)| {
                !pid.is_empty()
                    && !n.is_empty()
                    && pid.bytes().all(|b| b.is_ascii_digit())
                    && n.bytes().all(|b| b.is_ascii_digit())
            })
        })
}

/// Writes `path` atomically: `body` writes the content to a buffered temporary file in the
/// same directory, which is then flushed, synced and renamed onto `path`. On any error
/// (creating, writing, syncing, renaming) no temporary file is left behind, a file already at
/// `path` is left as it was, and the error names `path`.
///
/// ```
/// let dir = tempfile::tempdir().expect("temporary directory");
/// let path = dir.path().join("counts.csv");
/// boundary_io::write_atomic(&path, |out| out.write_all(b"frame,boundary\n0,12\n"))?;
/// assert_eq!(std::fs::read_to_string(&path)?, "frame,boundary\n0,12\n");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_atomic(
    path: &Path,
    body: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<(), IoError> {
    write_atomic_through(path, plain, body)
}

/// The file itself, as [`write_atomic`] writes to it.
fn plain(file: &mut File) -> Box<dyn Write + '_> {
    Box::new(file)
}

/// [`write_atomic`] with the temporary file seen through `sink` (tests put a failing writer
/// there: a disk that fills up in the middle of the file).
pub(crate) fn write_atomic_through(
    path: &Path,
    sink: fn(&mut File) -> Box<dyn Write + '_>,
    body: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<(), IoError> {
    let name = path.display().to_string();
    let fail = |e: std::io::Error| IoError::write(&name, e);
    let temp = temp_path(path).map_err(fail)?;
    let mut file = File::options()
        .write(true)
        .create_new(true)
        .open(&temp)
        .map_err(fail)?;
    let written = (|| {
        {
            let mut out = BufWriter::new(sink(&mut file));
            body(&mut out)?;
            out.flush()?;
        }
        file.sync_all()?;
        drop(file);
        std::fs::rename(&temp, path)
    })();
    if let Err(e) = written {
        let _ = std::fs::remove_file(&temp);
        return Err(fail(e));
    }
    sync_directory(path);
    Ok(())
}

/// `<dir>/.<name>.tmp-<pid>-<n>` beside `path`.
fn temp_path(path: &Path) -> std::io::Result<PathBuf> {
    let file_name = path.file_name().ok_or_else(|| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "the path names no file (it ends in `..` or is a root)",
        )
    })?;
    let n = NEXT.fetch_add(1, Ordering::Relaxed);
    let mut temp = std::ffi::OsString::from(".");
    temp.push(file_name);
    temp.push(format!("{TEMP_MARKER}{}-{n}", std::process::id()));
    Ok(path.with_file_name(temp))
}

/// Makes the rename durable where the system allows it (the directory's entry is synced on
/// Unix; elsewhere, and where the file system refuses, the rename stands as the system keeps
/// it).
fn sync_directory(path: &Path) {
    #[cfg(unix)]
    {
        let dir = match path.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        if let Ok(d) = File::open(dir) {
            let _ = d.sync_all();
        }
    }
    #[cfg(not(unix))]
    let _ = path;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Column, Format};
    use boundary_core::ParticleSet;
    use std::io::ErrorKind;

    /// A disk that fills up after 3000 bytes: the middle of every file the tests write.
    struct FullDisk<'a> {
        file: &'a mut File,
        left: usize,
    }

    impl Write for FullDisk<'_> {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            if self.left == 0 {
                return Err(std::io::Error::new(
                    ErrorKind::StorageFull,
                    "no space left on device",
                ));
            }
            let n = buf.len().min(self.left);
            self.left -= n;
            self.file.write(&buf[..n])
        }

        fn flush(&mut self) -> std::io::Result<()> {
            self.file.flush()
        }
    }

    fn full_disk(file: &mut File) -> Box<dyn Write + '_> {
        Box::new(FullDisk { file, left: 3000 })
    }

    fn names(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    fn lattice() -> boundary_core::AnyParticleSet {
        let rows: Vec<[f64; 3]> = (0..1000)
            .map(|k| {
                [
                    f64::from(k % 10),
                    f64::from((k / 10) % 10),
                    f64::from(k / 100),
                ]
            })
            .collect();
        ParticleSet::from_rows(&rows).unwrap().to_any()
    }

    #[test]
    fn a_disk_full_in_the_middle_of_a_file_leaves_no_file_in_any_format() {
        let set = lattice();
        let flags: Vec<i64> = (0..1000).map(|k| k % 2).collect();
        let margin: Vec<f64> = (0..1000).map(|k| f64::from(k) / 7.0).collect();
        let columns = [
            ("boundary", Column::Int(&flags)),
            ("margin", Column::Float(&margin)),
        ];
        for (format, file_name) in [
            (Format::Csv, "out.csv"),
            (Format::Xyz, "out.xyz"),
            (Format::Ply, "out.ply"),
            (Format::Vtk, "out.vtk"),
            (Format::Vtu, "out.vtu"),
            (Format::Vtp, "out.vtp"),
            (Format::Bgeo, "out.bgeo"),
            (Format::Bgeo, "out.bgeo.gz"),
        ] {
            let dir = tempfile::tempdir().unwrap();
            let path = dir.path().join(file_name);
            let error =
                crate::write_particles_through(&path, Some(format), &set, &columns, full_disk)
                    .expect_err(file_name);
            let message = error.to_string();
            assert!(
                message.contains(&path.display().to_string()) && message.contains("no space"),
                "{file_name}: {message}"
            );
            assert_eq!(names(dir.path()), Vec::<String>::new(), "{file_name}");
            // The same write on a disk with room succeeds (the content is over 3000 bytes, so
            // the failure above was in the middle of the file).
            crate::write_particles(&path, Some(format), &set, &columns).unwrap();
            assert!(
                std::fs::metadata(&path).unwrap().len() > 3000,
                "{file_name}"
            );
            assert_eq!(names(dir.path()), vec![file_name.to_owned()]);
        }
    }

    #[test]
    fn a_failed_write_leaves_the_old_file_as_it_was() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("frame.csv");
        std::fs::write(&path, "x,y\n0,0\n1,1\n").unwrap();
        let error = write_atomic_through(&path, full_disk, |out| {
            out.write_all(b"x,y,boundary\n")?;
            for k in 0..1000 {
                writeln!(out, "{k},{k},1")?;
            }
            Ok(())
        })
        .unwrap_err();
        assert!(error
            .to_string()
            .starts_with(&format!("cannot write {}", path.display())));
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "x,y\n0,0\n1,1\n");
        assert_eq!(names(dir.path()), vec!["frame.csv".to_owned()]);
    }

    #[test]
    fn a_body_that_fails_leaves_no_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("summary.csv");
        let error = write_atomic(&path, |out| {
            out.write_all(b"frame\n")?;
            Err(std::io::Error::other("stopped"))
        })
        .unwrap_err();
        assert_eq!(
            error.to_string(),
            format!("cannot write {}: stopped", path.display())
        );
        assert_eq!(names(dir.path()), Vec::<String>::new());
    }

    #[test]
    fn an_unwritable_directory_is_an_error_naming_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("missing").join("out.csv");
        let error = write_atomic(&path, |out| out.write_all(b"x\n")).unwrap_err();
        assert!(
            error
                .to_string()
                .starts_with(&format!("cannot write {}: ", path.display())),
            "{error}"
        );
        assert_eq!(names(dir.path()), Vec::<String>::new());
        // A directory where the file should go: the rename fails, the temporary file goes.
        let path = dir.path().join("taken.csv");
        std::fs::create_dir(&path).unwrap();
        let error = write_atomic(&path, |out| out.write_all(b"x\n")).unwrap_err();
        assert!(error.to_string().contains("taken.csv"), "{error}");
        assert_eq!(names(dir.path()), vec!["taken.csv".to_owned()]);
    }

    #[test]
    fn temporary_names_are_hidden_and_recognised() {
        let path = Path::new("out").join("frame_7.vtu");
        let temp = temp_path(&path).unwrap();
        let name = temp.file_name().unwrap().to_string_lossy().into_owned();
        assert!(name.starts_with(".frame_7.vtu.tmp-"), "{name}");
        assert_eq!(temp.parent(), path.parent());
        assert_eq!(Format::from_path(&temp), None);
        assert!(is_temp_name_for(&name, "frame_7.vtu"));
        assert!(is_temp_name_for(".f.csv.tmp-12-0", "f.csv"));
        assert!(!is_temp_name_for(".f.csv.tmp-12-0", "f.cs"));
        assert!(!is_temp_name_for("f.csv.tmp-12-0", "f.csv"));
        assert!(!is_temp_name_for(".f.csv.tmp-12", "f.csv"));
        assert!(!is_temp_name_for(".f.csv.tmp-x-0", "f.csv"));
        assert!(!is_temp_name_for(".f.csv.tmp-12-0.csv", "f.csv"));
        assert!(temp_path(Path::new("/")).is_err());
    }
}
