use std::path::{Path, PathBuf};

use super::source::{error_at, parse_spec, read, Locate};
use super::{SceneError, SceneSpec};

/// A parsed scene with its source, kept to locate errors found after parsing.
#[derive(Debug, Clone)]
pub struct Scene {
    pub spec: SceneSpec,
    pub source: String,
    /// The file, or `None` for the built-in scene.
    pub path: Option<PathBuf>,
}

/// The paper's footing (Fig. 3), shipped in the binary: `scenes/footing.toml`.
pub fn builtin_footing() -> Scene {
    Scene::parse(include_str!("../../../../scenes/footing.toml"), None)
        .expect("the built-in scene is valid")
}

impl Scene {
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

    /// An error at `field` (a path such as `material.young_modulus` or `boundary[1].nodes`),
    /// with the line where that field stands in the file.
    pub fn error(&self, field: &str, message: impl Into<String>) -> SceneError {
        error_at(&self.source, self.path.as_ref(), field, message.into())
    }

    /// Relative paths in the scene are relative to the scene file.
    pub fn resolve(&self, relative: &str) -> PathBuf {
        match self.path.as_ref().and_then(|p| p.parent()) {
            Some(dir) => dir.join(relative),
            None => PathBuf::from(relative),
        }
    }
}

impl Locate for Scene {
    fn error(&self, field: &str, message: impl Into<String>) -> SceneError {
        Scene::error(self, field, message)
    }
}
