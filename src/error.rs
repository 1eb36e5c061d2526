//! Errors of the PD pipeline and the exit codes they map to.
//!
//! Exit codes (documented in docs/guide/outputs.md): 0 ok, 1 the run failed (numerical failure), 2 bad input
//! (a mesh, scene or option that cannot be used).

use std::fmt;
use std::path::{Path, PathBuf};

use pdcontact_importers::ImportError;

/// Anything that stops a command.
#[derive(Debug)]
pub enum Error {
    /// A mesh file that cannot be read.
    Import(ImportError),
    /// Input that can be read but not used: a scene key, an inverted element, a missing set.
    Input(String),
    /// A run that failed numerically (NaN, blow-up, missed contacts, no convergence).
    Numerical(String),
    /// An output that could not be written.
    Output { path: PathBuf, message: String },
}

impl Error {
    /// The process exit code for this error.
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::Numerical(_) => 1,
            Error::Output { .. } => 1,
            Error::Import(_) | Error::Input(_) => 2,
        }
    }

    /// An input error.
    pub fn input(msg: impl Into<String>) -> Error {
        Error::Input(msg.into())
    }

    /// A numerical failure.
    pub fn numerical(msg: impl Into<String>) -> Error {
        Error::Numerical(msg.into())
    }

    /// An output error for a path.
    pub fn output(path: &Path, err: impl fmt::Display) -> Error {
        Error::Output {
            path: path.to_path_buf(),
            message: err.to_string(),
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Import(e) => write!(f, "{e}"),
            Error::Input(m) => write!(f, "{m}"),
            Error::Numerical(m) => write!(f, "run failed: {m}"),
            Error::Output { path, message } => {
                write!(f, "{}: cannot write: {message}", path.display())
            }
        }
    }
}

impl std::error::Error for Error {}

impl From<ImportError> for Error {
    fn from(e: ImportError) -> Error {
        Error::Import(e)
    }
}

/// Result alias for the pipeline.
pub type Result<T> = std::result::Result<T, Error>;
