use std::path::{Path, PathBuf};

use toml::de::{DeTable, DeValue};

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
        let source = std::fs::read_to_string(path).map_err(|e| SceneError {
            file: Some(path.to_path_buf()),
            field: "file".into(),
            line: None,
            message: e.to_string(),
        })?;
        Self::parse(&source, Some(path.to_path_buf()))
    }

    pub fn parse(source: &str, path: Option<PathBuf>) -> Result<Self, SceneError> {
        match toml::from_str::<SceneSpec>(source) {
            Ok(spec) => Ok(Self {
                spec,
                source: source.to_string(),
                path,
            }),
            Err(e) => Err(SceneError {
                file: path,
                field: "toml".into(),
                line: e.span().map(|s| line_of_offset(source, s.start)),
                message: e.message().to_string(),
            }),
        }
    }

    /// An error at `field` (a path such as `material.young_modulus` or `boundary[1].nodes`),
    /// with the line where that field stands in the file.
    pub fn error(&self, field: &str, message: impl Into<String>) -> SceneError {
        SceneError {
            file: self.path.clone(),
            field: field.to_string(),
            line: self.line_of(field),
            message: message.into(),
        }
    }

    /// Relative paths in the scene are relative to the scene file.
    pub fn resolve(&self, relative: &str) -> PathBuf {
        match self.path.as_ref().and_then(|p| p.parent()) {
            Some(dir) => dir.join(relative),
            None => PathBuf::from(relative),
        }
    }

    fn line_of(&self, field: &str) -> Option<usize> {
        let doc = DeTable::parse(&self.source).ok()?;
        let mut span = doc.span();
        let root = DeValue::Table(doc.into_inner());
        let mut value = &root;
        for segment in field.split('.') {
            let (key, index) = match segment.split_once('[') {
                Some((k, rest)) => (k, rest.trim_end_matches(']').parse::<usize>().ok()),
                None => (segment, None),
            };
            let next = value.get(key)?;
            span = next.span();
            value = next.get_ref();
            if let Some(i) = index {
                let item = value.get(i)?;
                span = item.span();
                value = item.get_ref();
            }
        }
        Some(line_of_offset(&self.source, span.start))
    }
}

fn line_of_offset(source: &str, offset: usize) -> usize {
    source[..offset.min(source.len())]
        .bytes()
        .filter(|b| *b == b'\n')
        .count()
        + 1
}
