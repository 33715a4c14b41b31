//! The one error type of the output writers.
use std::path::PathBuf;

/// Why a VTU/PVD file or a PNG plot could not be written.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The file could not be created or written.
    #[error("cannot write {}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// plotters failed to draw or encode the PNG.
    #[error("cannot plot {}: {message}", path.display())]
    Plot { path: PathBuf, message: String },
    /// An input is inconsistent (lengths, indices), empty or not finite; nothing was written.
    #[error("invalid `{field}`: {message}")]
    Invalid {
        field: &'static str,
        message: String,
    },
}

impl OutputError {
    pub(crate) fn invalid(field: &'static str, message: impl Into<String>) -> Self {
        Self::Invalid {
            field,
            message: message.into(),
        }
    }

    pub(crate) fn io(path: &std::path::Path, source: std::io::Error) -> Self {
        Self::Io {
            path: path.to_path_buf(),
            source,
        }
    }

    pub(crate) fn plot(path: &std::path::Path, message: impl std::fmt::Display) -> Self {
        Self::Plot {
            path: path.to_path_buf(),
            message: message.to_string(),
        }
    }
}
