//! Typed errors. Every error about input names the file and, where known, the line and column (or
//! byte offset) and what was expected, formatted like a compiler message: `file:line:column: message`.

use std::fmt;
use std::path::{Path, PathBuf};

pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Where in an input file something went wrong.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Location {
    pub file: PathBuf,
    pub line: Option<usize>,
    pub column: Option<usize>,
    pub byte: Option<u64>,
}

impl Location {
    pub fn file(file: impl AsRef<Path>) -> Self {
        Self {
            file: file.as_ref().to_path_buf(),
            ..Default::default()
        }
    }

    pub fn line(file: impl AsRef<Path>, line: usize, column: Option<usize>) -> Self {
        Self {
            line: Some(line),
            column,
            ..Self::file(file)
        }
    }

    pub fn byte(file: impl AsRef<Path>, byte: u64) -> Self {
        Self {
            byte: Some(byte),
            ..Self::file(file)
        }
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
            if let Some(col) = self.column {
                write!(f, ":{col}")?;
            }
        }
        if let Some(byte) = self.byte {
            write!(f, ": at byte {byte}")?;
        }
        Ok(())
    }
}

#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A file could not be read or written.
    #[error("{}: {error}", path.display())]
    Io {
        path: PathBuf,
        error: std::io::Error,
    },
    /// Input that does not say what Appel expects: a scene, a mesh, a formula.
    #[error("{location}: {message}")]
    Input { location: Location, message: String },
    /// A request that cannot be carried out, such as an image too large for memory.
    #[error("{0}")]
    Invalid(String),
    /// The render was stopped before it finished (Ctrl-C); nothing was written.
    #[error("interrupted: the render was stopped before it finished, and nothing was written")]
    Cancelled,
}

impl Error {
    pub fn io(path: impl AsRef<Path>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.as_ref().to_path_buf(),
            error: source,
        }
    }

    pub fn input(location: Location, message: impl Into<String>) -> Self {
        Error::Input {
            location,
            message: message.into(),
        }
    }
}
