//! Errors of file input/output and argument checks.

use std::path::PathBuf;

/// What went wrong reading or writing an asset file, or with a generator argument.
#[derive(Debug, thiserror::Error)]
pub enum AssetError {
    /// A file or directory could not be read, created or written.
    #[error("{path}: {source}")]
    Io {
        /// The file or directory concerned.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// An OBJ file holds a line this crate's reader does not understand.
    #[error("{path}:{line}: {message}")]
    Parse {
        /// The OBJ file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong and how to fix it.
        message: String,
    },
    /// A generator or writer argument is out of range.
    #[error("{name} = {value}: {requirement}")]
    InvalidArgument {
        /// The argument's name.
        name: &'static str,
        /// The given value, as text.
        value: String,
        /// What the value must satisfy.
        requirement: String,
    },
}

impl AssetError {
    /// An [`AssetError::Io`] for `path`.
    pub(crate) fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Io {
            path: path.into(),
            source,
        }
    }
}
