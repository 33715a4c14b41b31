//! `talus.Scene`: a scene's TOML text, checked by the CLI's own parser and model builder
//! (`SceneFile::parse`, then `Model::from_scene` or `MpmModel::from_scene`, which hold the
//! checks of `crates/talus/src/scene/check.rs`), so every error is the CLI's.
use std::path::PathBuf;

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use talus::model::mpm::MpmModel;
use talus::scene::{SceneError, SceneFile};

use crate::errors::scene_error;

/// A validated FEM (`[mesh]`) or MPM (`[grid]`) scene.
#[pyclass(module = "talus._talus", frozen)]
pub struct Scene {
    pub source: String,
    pub path: Option<PathBuf>,
    pub kind: &'static str,
}

/// Parses and builds the model of `source`: the checks `talus run` makes before stepping.
pub fn validate(source: &str, path: Option<PathBuf>) -> Result<SceneFile, SceneError> {
    let file = SceneFile::parse(source, path)?;
    match &file {
        SceneFile::Fem(scene) => talus::model::fem::stages::check_before_run::<2, 4>(scene)?,
        SceneFile::Fem3(scene) => talus::model::fem::stages::check_before_run::<3, 6>(scene)?,
        SceneFile::Mpm(scene) => {
            MpmModel::from_scene(scene)?;
        }
        SceneFile::Mpm3(scene) => {
            MpmModel::from_scene_3d(scene)?;
        }
    }
    Ok(file)
}

fn kind(file: &SceneFile) -> &'static str {
    match file {
        SceneFile::Fem(_) => "fem",
        SceneFile::Fem3(_) => "fem",
        SceneFile::Mpm(_) | SceneFile::Mpm3(_) => "mpm",
    }
}

impl Scene {
    fn checked(py: Python<'_>, source: String, path: Option<PathBuf>) -> PyResult<Self> {
        let (text, at) = (source.clone(), path.clone());
        match py.detach(move || validate(&text, at)) {
            Ok(file) => Ok(Self {
                kind: kind(&file),
                source,
                path,
            }),
            Err(e) => {
                let value = lookup(&source, &e.field)
                    .map(|v| to_python(py, &v))
                    .transpose()?;
                Err(scene_error(py, &e, value))
            }
        }
    }

    fn table(&self, py: Python<'_>) -> PyResult<toml::Table> {
        toml::from_str(&self.source).map_err(|e| {
            let e = SceneError {
                file: self.path.clone(),
                field: "toml".into(),
                line: None,
                message: e.to_string(),
            };
            scene_error(py, &e, None)
        })
    }
}

#[pymethods]
impl Scene {
    /// Reads and checks a scene file.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let source = std::fs::read_to_string(&path).map_err(|e| {
            let err = SceneError {
                file: Some(path.clone()),
                field: "file".into(),
                line: None,
                message: e.to_string(),
            };
            let shown = PyString::new(py, &path.display().to_string());
            scene_error(py, &err, Some(shown.into_any().unbind()))
        })?;
        Self::checked(py, source, Some(path))
    }

    /// Checks a scene given as TOML text; relative paths in it (a mesh file) are relative
    /// to `path`'s folder when given, else to the working directory.
    #[staticmethod]
    #[pyo3(signature = (text, path=None))]
    fn from_toml(py: Python<'_>, text: String, path: Option<PathBuf>) -> PyResult<Self> {
        Self::checked(py, text, path)
    }

    /// Checks a scene given as nested dicts and lists (the TOML document's tables).
    #[staticmethod]
    #[pyo3(signature = (d, path=None))]
    fn from_dict(py: Python<'_>, d: &Bound<'_, PyDict>, path: Option<PathBuf>) -> PyResult<Self> {
        let toml::Value::Table(table) = from_python(d.as_any())? else {
            return Err(PyTypeError::new_err(
                "a scene dict must map names to values",
            ));
        };
        let text = toml::to_string(&table)
            .map_err(|e| PyTypeError::new_err(format!("not a TOML document: {e}")))?;
        Self::checked(py, text, path)
    }

    /// The TOML document as nested dicts and lists.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let table = self.table(py)?;
        Ok(to_python(py, &toml::Value::Table(table))?.into_bound(py))
    }

    /// The value at a dotted TOML path (`material.friction_angle`, `boundary[3].velocity`).
    fn get<'py>(&self, py: Python<'py>, field: &str) -> PyResult<Bound<'py, PyAny>> {
        match lookup(&self.source, field) {
            Some(v) => Ok(to_python(py, &v)?.into_bound(py)),
            None => Err(pyo3::exceptions::PyKeyError::new_err(field.to_string())),
        }
    }

    /// A new scene with `field` (a dotted TOML path) set to `value`, checked as a file.
    /// A type error from the parser is reported at `field`.
    fn set(&self, py: Python<'_>, field: &str, value: &Bound<'_, PyAny>) -> PyResult<Self> {
        let mut table = self.table(py)?;
        let mut new = from_python(value)?;
        let path = split(field).ok_or_else(|| bad_path(py, field, value, "not a dotted path"))?;
        let old = lookup(&self.source, field);
        // An int given for a float field is the float: `set("material.cohesion", 0)`.
        if let (Some(toml::Value::Float(_)), toml::Value::Integer(i)) = (&old, &new) {
            new = toml::Value::Float(*i as f64);
        }
        put(&mut table, &path, new).map_err(|why| bad_path(py, field, value, &why))?;
        let text =
            toml::to_string(&table).map_err(|e| bad_path(py, field, value, &e.to_string()))?;
        let at = self.path.clone();
        let checked = py.detach({
            let text = text.clone();
            move || validate(&text, at)
        });
        match checked {
            Ok(file) => Ok(Self {
                kind: kind(&file),
                source: text,
                path: self.path.clone(),
            }),
            Err(mut e) => {
                // Lines are of the rewritten text, not of the file: dropped. The schema's
                // errors name "toml": the field set is the one at fault.
                e.line = None;
                if e.field == "toml" {
                    e.field = field.to_string();
                }
                let value = if e.field == field {
                    Some(value.clone().unbind())
                } else {
                    lookup(&text, &e.field)
                        .map(|v| to_python(py, &v))
                        .transpose()?
                };
                Err(scene_error(py, &e, value))
            }
        }
    }

    /// The scene's TOML text.
    fn to_toml(&self) -> String {
        self.source.clone()
    }

    /// `"fem"` (a `[mesh]`) or `"mpm"` (a `[grid]`).
    #[getter]
    fn kind(&self) -> &'static str {
        self.kind
    }

    /// The file the scene was read from, or `None`.
    #[getter]
    fn path(&self) -> Option<String> {
        self.path.as_ref().map(|p| p.display().to_string())
    }

    fn __repr__(&self) -> String {
        match &self.path {
            Some(p) => format!("Scene.load({:?}) [{}]", p.display().to_string(), self.kind),
            None => format!("Scene.from_toml(...) [{}]", self.kind),
        }
    }
}

fn bad_path(py: Python<'_>, field: &str, value: &Bound<'_, PyAny>, why: &str) -> PyErr {
    let e = SceneError {
        file: None,
        field: field.to_string(),
        line: None,
        message: why.to_string(),
    };
    scene_error(py, &e, Some(value.clone().unbind()))
}

/// One segment of a dotted path: a key, or a key and an index (`boundary[3]`).
type Segment = (String, Option<usize>);

/// `a.b[2].c` as segments; `None` when a segment is empty or an index is not a number.
fn split(field: &str) -> Option<Vec<Segment>> {
    field
        .split('.')
        .map(|s| match s.split_once('[') {
            Some((k, rest)) => {
                let i = rest.strip_suffix(']')?.parse().ok()?;
                (!k.is_empty()).then(|| (k.to_string(), Some(i)))
            }
            None => (!s.is_empty()).then(|| (s.to_string(), None)),
        })
        .collect()
}

/// The value at `field` in the TOML `source`.
fn lookup(source: &str, field: &str) -> Option<toml::Value> {
    let table: toml::Table = toml::from_str(source).ok()?;
    let mut value = toml::Value::Table(table);
    for (key, index) in split(field)? {
        value = value.get(&key)?.clone();
        if let Some(i) = index {
            value = value.get(i)?.clone();
        }
    }
    Some(value)
}

/// Sets the value at `path`, creating missing tables on the way (not array entries).
fn put(table: &mut toml::Table, path: &[Segment], value: toml::Value) -> Result<(), String> {
    let ((key, index), rest) = path.split_first().ok_or("empty path")?;
    if rest.is_empty() && index.is_none() {
        table.insert(key.clone(), value);
        return Ok(());
    }
    let entry = table
        .entry(key.clone())
        .or_insert_with(|| toml::Value::Table(toml::Table::new()));
    let entry = match index {
        Some(i) => {
            let toml::Value::Array(items) = entry else {
                return Err(format!("{key} is not an array"));
            };
            let n = items.len();
            let item = items
                .get_mut(*i)
                .ok_or_else(|| format!("{key} has {n} entries, no [{i}]"))?;
            if rest.is_empty() {
                *item = value;
                return Ok(());
            }
            item
        }
        None => entry,
    };
    match entry {
        toml::Value::Table(t) => put(t, rest, value),
        _ => Err(format!("{key} is not a table")),
    }
}

fn to_python(py: Python<'_>, v: &toml::Value) -> PyResult<Py<PyAny>> {
    Ok(match v {
        toml::Value::String(s) => s.into_pyobject(py)?.into_any().unbind(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any().unbind(),
        toml::Value::Float(f) => f.into_pyobject(py)?.into_any().unbind(),
        toml::Value::Boolean(b) => PyBool::new(py, *b).to_owned().into_any().unbind(),
        toml::Value::Datetime(d) => d.to_string().into_pyobject(py)?.into_any().unbind(),
        toml::Value::Array(items) => {
            let items = items
                .iter()
                .map(|x| to_python(py, x))
                .collect::<PyResult<Vec<_>>>()?;
            PyList::new(py, items)?.into_any().unbind()
        }
        toml::Value::Table(t) => {
            let d = PyDict::new(py);
            for (k, x) in t {
                d.set_item(k, to_python(py, x)?)?;
            }
            d.into_any().unbind()
        }
    })
}

/// A Python value as TOML: bool, int, float, str, list/tuple (also NumPy arrays through
/// `tolist`), dict.
fn from_python(v: &Bound<'_, PyAny>) -> PyResult<toml::Value> {
    if v.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(v.extract()?));
    }
    if v.is_instance_of::<PyInt>() {
        return Ok(toml::Value::Integer(v.extract()?));
    }
    if v.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(v.extract()?));
    }
    if v.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(v.extract()?));
    }
    if let Ok(d) = v.cast::<PyDict>() {
        let mut t = toml::Table::new();
        for (k, x) in d.iter() {
            t.insert(k.extract()?, from_python(&x)?);
        }
        return Ok(toml::Value::Table(t));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let items = v
            .try_iter()?
            .map(|x| from_python(&x?))
            .collect::<PyResult<Vec<_>>>()?;
        return Ok(toml::Value::Array(items));
    }
    if v.hasattr("tolist")? {
        // NumPy scalars and arrays.
        return from_python(&v.call_method0("tolist")?);
    }
    Err(PyTypeError::new_err(format!(
        "{} cannot be a TOML value",
        v.get_type().name()?
    )))
}
