//! What FEM and MPM scenes share as files: TOML parsing into a spec, and errors placed on
//! the line where their field stands.
use std::path::{Path, PathBuf};

use serde::de::DeserializeOwned;
use serde::Serialize;
use toml::de::{DeTable, DeValue};

use super::SceneError;

/// A parsed scene file: its spec, and the source kept to locate errors found after parsing.
/// FEM and MPM scenes are [`Scene`](super::Scene) and [`MpmScene`](super::MpmScene).
#[derive(Debug, Clone)]
pub struct SceneDocument<S> {
    pub spec: S,
    pub source: String,
    /// The file, or `None` for a built-in or in-memory scene.
    pub path: Option<PathBuf>,
}

impl<S: DeserializeOwned + Serialize> SceneDocument<S> {
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
}

/// A parsed scene that can place an error on the line of a field path such as
/// `material.young_modulus` or `wall[1].friction`.
pub trait Locate {
    fn error(&self, field: &str, message: impl Into<String>) -> SceneError;
}

/// Reads a scene file.
pub(super) fn read(path: &Path) -> Result<String, SceneError> {
    std::fs::read_to_string(path).map_err(|e| SceneError {
        file: Some(path.to_path_buf()),
        field: "file".into(),
        line: None,
        message: e.to_string(),
    })
}

/// Parses `source` into a spec; a TOML or schema error names the line it found, and so
/// does an array longer than its field (`cells = [32, 14, 3]`), which the TOML reader
/// would otherwise cut silently.
pub(super) fn parse_spec<S: DeserializeOwned + Serialize>(
    source: &str,
    path: Option<&PathBuf>,
) -> Result<S, SceneError> {
    let spec = toml::from_str::<S>(source).map_err(|e| SceneError {
        file: path.cloned(),
        field: "toml".into(),
        line: e.span().map(|s| line_of_offset(source, s.start)),
        message: e.message().to_string(),
    })?;
    // Read back: every array of the file must have the length of the spec's.
    if let (Ok(given), Ok(toml::Value::Table(read))) = (
        toml::from_str::<toml::Table>(source),
        toml::Value::try_from(&spec),
    ) {
        if let Some((field, n, expected)) = longer_array("", &given, &read) {
            return Err(error_at(
                source,
                path,
                &field,
                format!("{n} values given, {expected} expected"),
            ));
        }
    }
    Ok(spec)
}

/// The first array of `given` whose length differs from the same field of `read`, as
/// `(field path, given length, read length)`.
fn longer_array(
    at: &str,
    given: &toml::Table,
    read: &toml::Table,
) -> Option<(String, usize, usize)> {
    given.iter().find_map(|(key, g)| {
        let field = if at.is_empty() {
            key.clone()
        } else {
            format!("{at}.{key}")
        };
        compare(&field, g, read.get(key)?)
    })
}

fn compare(field: &str, given: &toml::Value, read: &toml::Value) -> Option<(String, usize, usize)> {
    match (given, read) {
        (toml::Value::Table(g), toml::Value::Table(r)) => longer_array(field, g, r),
        (toml::Value::Array(g), toml::Value::Array(r)) => {
            if g.len() != r.len() {
                return Some((field.to_string(), g.len(), r.len()));
            }
            g.iter().zip(r).enumerate().find_map(|(i, (g, r))| {
                // Arrays of tables are located by index (`boundary[1].velocity`); a row
                // of numbers by its array.
                match g {
                    toml::Value::Table(_) => compare(&format!("{field}[{i}]"), g, r),
                    _ => compare(field, g, r),
                }
            })
        }
        _ => None,
    }
}

/// An error at `field` with the line where that field stands in `source`.
pub(super) fn error_at(
    source: &str,
    path: Option<&PathBuf>,
    field: &str,
    message: String,
) -> SceneError {
    SceneError {
        file: path.cloned(),
        field: field.to_string(),
        line: line_of_field(source, field),
        message,
    }
}

/// As [`error_at`], but a field absent from the file (a missing key) is placed on the line
/// of its nearest enclosing table or array entry.
pub(super) fn error_near(
    source: &str,
    path: Option<&PathBuf>,
    field: &str,
    message: String,
) -> SceneError {
    let mut at = field;
    let line = loop {
        if let Some(line) = line_of_field(source, at) {
            break Some(line);
        }
        match at.rfind(['.', '[']) {
            Some(i) => at = &at[..i],
            None => break None,
        }
    };
    SceneError {
        file: path.cloned(),
        field: field.to_string(),
        line,
        message,
    }
}

/// The line of a field path (`a.b[2].c`) in `source`, if it is there.
fn line_of_field(source: &str, field: &str) -> Option<usize> {
    let doc = DeTable::parse(source).ok()?;
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
    Some(line_of_offset(source, span.start))
}

fn line_of_offset(source: &str, offset: usize) -> usize {
    source[..offset.min(source.len())]
        .bytes()
        .filter(|b| *b == b'\n')
        .count()
        + 1
}
