//! `talus.factor_of_safety`: `talus run` on a `[stability]` scene (`docs/stability.md`)
//! in-process, the GIL released; its `history.csv` (one row per trial) and `summary.json`
//! are returned as text for the Python half to shape.
use std::path::PathBuf;

use pyo3::prelude::*;
use pyo3::types::PyDict;
use talus::run::{RunError, RunOptions};
use talus::scene::SceneFile;

use crate::errors::{raise, scene_error};
use crate::run::scratch;
use crate::scene::Scene;
use crate::watch::Watch;

/// Strength reduction or gravity increase on `scene` (2D or 3D); a dict with `history_csv` and
/// `summary_json`. `callback(progress)` is called after every trial.
#[pyfunction]
#[pyo3(signature = (scene, out=None, callback=None))]
pub fn factor_of_safety<'py>(
    py: Python<'py>,
    scene: &Scene,
    out: Option<PathBuf>,
    callback: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let file = SceneFile::parse(&scene.source, scene.path.clone())
        .map_err(|e| scene_error(py, &e, None))?;
    let keep = out.is_some();
    let dir = out.unwrap_or_else(scratch);
    let watch = Watch::new(callback);
    let options = RunOptions {
        write_fields: keep,
        observer: Some(watch.observer()),
        ..RunOptions::new(dir.clone())
    };
    // One search for 2D and 3D (`analysis::stability` is generic over the Mandel size).
    let ran = match file {
        SceneFile::Fem(fem) => watch.detach_on_pool(py, move || {
            talus::analysis::stability::run(&fem, &options).map(|_| ())
        }),
        SceneFile::Fem3(fem) => watch.detach_on_pool(py, move || {
            talus::analysis::stability::run(&fem, &options).map(|_| ())
        }),
        _ => {
            let why = "a factor of safety needs a finite-element scene ([mesh])".to_string();
            return Err(raise(py, "RunError", (why, PyDict::new(py))));
        }
    };
    let d = PyDict::new(py);
    if let Ok(history) = std::fs::read_to_string(dir.join("history.csv")) {
        d.set_item("history_csv", history)?;
    }
    if let Ok(summary) = std::fs::read_to_string(dir.join("summary.json")) {
        d.set_item("summary_json", summary)?;
    }
    if !keep {
        let _ = std::fs::remove_dir_all(&dir);
    }
    watch.raise_stop(py, &d)?;
    match ran {
        Ok(_) => Ok(d),
        Err(RunError::Scene(e)) => Err(scene_error(py, &e, None)),
        Err(e) => {
            // The loading did not reach equilibrium (summary.json: not_converged).
            let not_converged = d
                .get_item("summary_json")?
                .is_some_and(|s| s.to_string().contains("\"not_converged\""));
            let class = if not_converged {
                "NotConverged"
            } else {
                "RunError"
            };
            Err(raise(py, class, (e.to_string(), d)))
        }
    }
}
