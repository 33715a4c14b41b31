use std::path::{Path, PathBuf};

use super::source::{error_near, parse_spec, read, Locate};
use super::{MpmSceneSpec, SceneError};

/// A parsed MPM scene with its source, kept to locate errors found after parsing.
#[derive(Debug, Clone)]
pub struct MpmScene {
    pub spec: MpmSceneSpec,
    pub source: String,
    pub path: Option<PathBuf>,
}

impl MpmScene {
    pub fn from_path(path: &Path) -> Result<Self, SceneError> {
        let source = read(path)?;
        Self::parse(&source, Some(path.to_path_buf()))
    }

    pub fn parse(source: &str, path: Option<PathBuf>) -> Result<Self, SceneError> {
        Ok(Self {
            spec: parse_spec(source, path.as_ref())?,
            source: source.to_string(),
            path,
        })
    }

    /// An error at `field` (`wall[1].friction`), with the line where it stands, or where
    /// it belongs when it is missing.
    pub fn error(&self, field: &str, message: impl Into<String>) -> SceneError {
        error_near(&self.source, self.path.as_ref(), field, message.into())
    }
}

impl Locate for MpmScene {
    fn error(&self, field: &str, message: impl Into<String>) -> SceneError {
        MpmScene::error(self, field, message)
    }
}
