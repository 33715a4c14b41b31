use std::fmt;
use std::path::PathBuf;

/// A scene that cannot be run, located by field path (`boundary[2].nodes`) and line.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneError {
    pub file: Option<PathBuf>,
    pub field: String,
    pub line: Option<usize>,
    pub message: String,
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let file = self
            .file
            .as_ref()
            .map(|p| p.display().to_string())
            .unwrap_or_else(|| "scene".into());
        match self.line {
            Some(line) => write!(f, "{file}:{line}: {}: {}", self.field, self.message),
            None => write!(f, "{file}: {}: {}", self.field, self.message),
        }
    }
}

impl std::error::Error for SceneError {}
