//! Rust errors raised as the Python exception classes of `talus/_errors.py`, so that one
//! class hierarchy serves both halves of the package.
use pyo3::prelude::*;
use talus::scene::SceneError;

/// An instance of `talus._errors.<class>` built from `args`, as a `PyErr`.
pub fn raise<'py, A>(py: Python<'py>, class: &str, args: A) -> PyErr
where
    A: pyo3::call::PyCallArgs<'py>,
{
    let made = py
        .import("talus._errors")
        .and_then(|m| m.getattr(class))
        .and_then(|c| c.call1(args));
    match made {
        Ok(instance) => PyErr::from_value(instance),
        Err(e) => e,
    }
}

/// `talus.SceneError(field, value, reason, line, file)`; `value` is the field's value in
/// the scene text when it is there (`None` for a missing field).
pub fn scene_error(py: Python<'_>, e: &SceneError, value: Option<Py<PyAny>>) -> PyErr {
    raise(
        py,
        "SceneError",
        (
            e.field.clone(),
            value,
            e.message.clone(),
            e.line,
            e.file.as_ref().map(|p| p.display().to_string()),
        ),
    )
}
