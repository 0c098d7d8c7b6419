//! Writing to standard output and standard error without panicking.
//!
//! `println!` panics when stdout is a closed pipe (`boundary methods | head`: Rust ignores
//! SIGPIPE, so the write fails with `EPIPE`). Every line the CLI prints on stdout goes through
//! [`out`], which turns `EPIPE` into [`CliError::BrokenPipe`] (`main` then exits quietly with
//! status 0: the reader asked for no more); diagnostics go through [`err`], which drops what
//! cannot be written (a closed stderr has no one to tell).

use crate::error::CliError;
use std::fmt::Arguments;
use std::io::{ErrorKind, Write};

/// Writes one line (`args` and a newline) to stdout and flushes it.
pub fn out(args: Arguments<'_>) -> Result<(), CliError> {
    let mut stdout = std::io::stdout().lock();
    stdout
        .write_fmt(args)
        .and_then(|()| stdout.write_all(b"\n"))
        .and_then(|()| stdout.flush())
        .map_err(|e| {
            if e.kind() == ErrorKind::BrokenPipe {
                CliError::BrokenPipe
            } else {
                CliError::Stdout(e)
            }
        })
}

/// Writes one line to stderr; a failure to write is ignored.
pub fn err(args: Arguments<'_>) {
    let mut stderr = std::io::stderr().lock();
    let _ = stderr
        .write_fmt(args)
        .and_then(|()| stderr.write_all(b"\n"));
}

/// `println!` that returns [`CliError::BrokenPipe`] instead of panicking.
macro_rules! outln {
    ($($arg:tt)*) => {
        $crate::output::out(format_args!($($arg)*))
    };
}

/// `eprintln!` that never panics.
macro_rules! errln {
    ($($arg:tt)*) => {
        $crate::output::err(format_args!($($arg)*))
    };
}

pub(crate) use {errln, outln};
