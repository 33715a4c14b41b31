//! `talus.run`: the CLI's `run_scene` / `run_mpm_scene` in-process, the GIL released
//! while it steps. `history.csv` and `summary.json` are the run loop's own outputs
//! (`crates/talus/src/run/steps.rs`); without `out` they go to a temporary folder that is
//! read back and removed, so the arrays hold the values of the CLI's file.
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use numpy::ndarray::Array2;
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use talus::model::fem::stages::final_model;
use talus::run::checkpoint::Checkpoint;
use talus::run::fem::{resume_scene, run_scene, run_scene_3d};
use talus::run::mpm::{resume_mpm_scene, run_mpm_scene, run_mpm_scene_3d};
use talus::run::{RunError, RunOptions};
use talus::scene::SceneFile;

use crate::errors::{raise, scene_error};
use crate::scene::Scene;
use crate::watch::Watch;

/// What a finished run leaves besides its files: the final state's arrays, flat with
/// their row lengths.
enum Final {
    Fem {
        /// 2 in 2D, 3 in 3D: the width of `nodes` and `displacement`.
        dim: usize,
        nodes: Vec<f64>,
        cells: Vec<Vec<usize>>,
        displacement: Vec<f64>,
        /// Mandel components per Gauss point: 4 in 2D, 6 in 3D.
        stress: Vec<f64>,
        plastic_strain: Vec<f64>,
        gauss_element: Vec<usize>,
    },
    Mpm {
        /// 2 in 2D, 3 in 3D: the width of `position` and `velocity`.
        dim: usize,
        position: Vec<f64>,
        velocity: Vec<f64>,
        /// Mandel components per particle: 4 in 2D, 6 in 3D.
        stress: Vec<f64>,
        plastic_strain: Vec<f64>,
    },
}

/// A folder of its own for a run without `out`.
pub(crate) fn scratch() -> PathBuf {
    static COUNT: AtomicUsize = AtomicUsize::new(0);
    let n = COUNT.fetch_add(1, Ordering::Relaxed);
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_nanos())
        .unwrap_or(0);
    std::env::temp_dir().join(format!("talus-py-{}-{n}-{nanos}", std::process::id()))
}

fn step(
    file: &SceneFile,
    options: &RunOptions,
    resumed: Option<Checkpoint<serde_json::Value>>,
) -> Result<Final, RunError> {
    match file {
        SceneFile::Fem(scene) => {
            let summary = match resumed {
                Some(c) => resume_scene(scene, c, options)?,
                None => run_scene(scene, options)?,
            };
            // The mesh of the run's end (a staged run's last stage), rebuilt from the scene.
            let model = final_model::<2, 4>(scene)?;
            let state = summary.final_state;
            Ok(Final::Fem {
                dim: 2,
                nodes: model.mesh.nodes.into_iter().flatten().collect(),
                cells: model.mesh.triangles,
                displacement: state.displacement.into_iter().flatten().collect(),
                stress: state.sigma,
                plastic_strain: state.plastic_strain,
                gauss_element: model.assembly.gauss_element,
            })
        }
        SceneFile::Fem3(scene) => {
            let summary = run_scene_3d(scene, options, resumed)?;
            let model = final_model::<3, 6>(scene)?;
            let state = summary.final_state;
            Ok(Final::Fem {
                dim: 3,
                nodes: model.mesh.nodes.into_iter().flatten().collect(),
                cells: model.mesh.tetrahedra,
                displacement: state.displacement.into_iter().flatten().collect(),
                stress: state.sigma,
                plastic_strain: state.plastic_strain,
                gauss_element: model.assembly.gauss_element,
            })
        }
        SceneFile::Mpm(scene) => {
            let p = match resumed {
                Some(c) => resume_mpm_scene(scene, c, options)?,
                None => run_mpm_scene(scene, options)?,
            }
            .particles;
            Ok(Final::Mpm {
                dim: 2,
                position: p.position.into_iter().flatten().collect(),
                velocity: p.velocity.into_iter().flatten().collect(),
                stress: p.stress.into_iter().flatten().collect(),
                plastic_strain: p.plastic_strain,
            })
        }
        SceneFile::Mpm3(scene) => {
            let p = run_mpm_scene_3d(scene, options, resumed)?.particles;
            Ok(Final::Mpm {
                dim: 3,
                position: p.position.into_iter().flatten().collect(),
                velocity: p.velocity.into_iter().flatten().collect(),
                stress: p.stress.into_iter().flatten().collect(),
                plastic_strain: p.plastic_strain,
            })
        }
    }
}

/// `history.csv` as its header and its rows of numbers.
fn read_history(path: &Path) -> Result<(Vec<String>, Vec<f64>, usize), String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .ok_or_else(|| format!("{}: empty", path.display()))?
        .split(',')
        .map(str::to_string)
        .collect();
    let mut values = Vec::new();
    let mut rows = 0;
    for (i, line) in lines.enumerate() {
        let row: Vec<&str> = line.split(',').collect();
        if row.len() != header.len() {
            return Err(format!(
                "{}: row {} has {} columns",
                path.display(),
                i + 1,
                row.len()
            ));
        }
        for v in row {
            values.push(
                v.parse::<f64>()
                    .map_err(|e| format!("{}: row {}: {v:?}: {e}", path.display(), i + 1))?,
            );
        }
        rows += 1;
    }
    Ok((header, values, rows))
}

/// Runs `scene`; returns a dict with `history` (column → array), `summary_json` (the
/// text of `summary.json`) and the final state. Files are kept only when `out` is given.
/// `callback(progress: dict)` is called after every step; `False` stops the run. With
/// `checkpoint_every > 0` (and `out`), a checkpoint every that many steps
/// (`docs/scenes.md`, 'Checkpoints and resume').
#[pyfunction]
#[pyo3(signature = (scene, out=None, callback=None, checkpoint_every=0))]
pub fn run<'py>(
    py: Python<'py>,
    scene: &Scene,
    out: Option<PathBuf>,
    callback: Option<Py<PyAny>>,
    checkpoint_every: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let file = SceneFile::parse(&scene.source, scene.path.clone())
        .map_err(|e| scene_error(py, &e, None))?;
    if checkpoint_every > 0 && out.is_none() {
        let why = "checkpoint_every needs out: the checkpoint is written there".to_string();
        return Err(raise(py, "RunError", (why, PyDict::new(py))));
    }
    let keep = out.is_some();
    let dir = out.unwrap_or_else(scratch);
    let watch = Watch::new(callback);
    let options = RunOptions {
        write_fields: keep,
        observer: Some(watch.observer()),
        checkpoint_every,
        ..RunOptions::new(dir.clone())
    };
    let stepped = watch.detach_on_pool(py, move || step(&file, &options, None));
    finish(py, stepped, &dir, keep, &watch)
}

/// Continues the run whose checkpoint is in `out` (`talus resume OUT`): its scene is
/// the checkpoint's, checked against the file it came from.
#[pyfunction]
#[pyo3(signature = (out, callback=None))]
pub fn resume<'py>(
    py: Python<'py>,
    out: PathBuf,
    callback: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let refused = |py: Python<'py>, e: String| raise(py, "RunError", (e, PyDict::new(py)));
    let checkpoint = talus::run::checkpoint::read(&out).map_err(|e| refused(py, e.to_string()))?;
    let source = checkpoint
        .current_scene()
        .map_err(|e| refused(py, e.to_string()))?;
    let file = SceneFile::parse(&source, checkpoint.scene.path.clone())
        .map_err(|e| scene_error(py, &e, None))?;
    let watch = Watch::new(callback);
    let options = RunOptions {
        write_fields: true,
        observer: Some(watch.observer()),
        ..RunOptions::new(out.clone())
    };
    let stepped = watch.detach_on_pool(py, move || step(&file, &options, Some(checkpoint)));
    finish(py, stepped, &out, true, &watch)
}

/// What a run left: its files read back (and removed unless `keep`), what stopped it
/// raised, or the result dict.
fn finish<'py>(
    py: Python<'py>,
    stepped: Result<Final, RunError>,
    dir: &Path,
    keep: bool,
    watch: &Watch,
) -> PyResult<Bound<'py, PyDict>> {
    let history = read_history(&dir.join("history.csv"));
    let summary = std::fs::read_to_string(dir.join("summary.json"));
    if !keep {
        let _ = std::fs::remove_dir_all(dir);
    }
    let d = PyDict::new(py);
    if let Ok(summary) = &summary {
        d.set_item("summary_json", summary)?;
    }
    if let Ok((header, values, rows)) = &history {
        let columns = PyDict::new(py);
        let n = header.len();
        for (j, name) in header.iter().enumerate() {
            let column: Vec<f64> = (0..*rows).map(|i| values[i * n + j]).collect();
            columns.set_item(name, column.into_pyarray(py))?;
        }
        d.set_item("history", columns)?;
    }
    watch.raise_stop(py, &d)?;
    let state = match stepped {
        Ok(state) => state,
        Err(e @ RunError::Collapsed(_)) => return Err(raise(py, "Collapsed", (e.to_string(), d))),
        Err(RunError::Scene(e)) => return Err(scene_error(py, &e, None)),
        Err(e @ (RunError::Step { .. } | RunError::MpmStep { .. })) => {
            // summary.json says whether the step did not converge or failed otherwise.
            let not_converged = summary
                .as_ref()
                .is_ok_and(|s| s.contains("\"not_converged\""));
            let class = if not_converged {
                "NotConverged"
            } else {
                "RunError"
            };
            return Err(raise(py, class, (e.to_string(), d)));
        }
        Err(e) => return Err(raise(py, "RunError", (e.to_string(), d))),
    };
    if let Err(e) = history {
        return Err(raise(py, "RunError", (e, d)));
    }
    let fields = PyDict::new(py);
    match state {
        Final::Fem {
            dim,
            nodes,
            cells,
            displacement,
            stress,
            plastic_strain,
            gauss_element,
        } => {
            d.set_item("kind", "fem")?;
            let per_cell = cells.first().map_or(0, Vec::len);
            let n_cells = cells.len();
            let flat: Vec<i64> = cells.into_iter().flatten().map(|i| i as i64).collect();
            let cells = Array2::from_shape_vec((n_cells, per_cell), flat)
                .map_err(|e| raise(py, "RunError", (e.to_string(), PyDict::new(py))))?;
            let n_points = plastic_strain.len();
            let bad_shape = |e: numpy::ndarray::ShapeError| {
                raise(py, "RunError", (e.to_string(), PyDict::new(py)))
            };
            let stress = Array2::from_shape_vec((n_points, 2 * dim), stress).map_err(bad_shape)?;
            let element: Vec<i64> = gauss_element.into_iter().map(|e| e as i64).collect();
            let (n_nodes, n_disp) = (nodes.len() / dim, displacement.len() / dim);
            let nodes = Array2::from_shape_vec((n_nodes, dim), nodes).map_err(bad_shape)?;
            let displacement =
                Array2::from_shape_vec((n_disp, dim), displacement).map_err(bad_shape)?;
            d.set_item("dimension", dim)?;
            fields.set_item("nodes", nodes.into_pyarray(py))?;
            fields.set_item("cells", cells.into_pyarray(py))?;
            fields.set_item("displacement", displacement.into_pyarray(py))?;
            fields.set_item("stress", stress.into_pyarray(py))?;
            fields.set_item("plastic_strain", plastic_strain.into_pyarray(py))?;
            fields.set_item("gauss_element", element.into_pyarray(py))?;
        }
        Final::Mpm {
            dim,
            position,
            velocity,
            stress,
            plastic_strain,
        } => {
            d.set_item("kind", "mpm")?;
            d.set_item("dimension", dim)?;
            let n = plastic_strain.len();
            let bad_shape = |e: numpy::ndarray::ShapeError| {
                raise(py, "RunError", (e.to_string(), PyDict::new(py)))
            };
            let stress = Array2::from_shape_vec((n, 2 * dim), stress).map_err(bad_shape)?;
            let position = Array2::from_shape_vec((n, dim), position).map_err(bad_shape)?;
            let velocity = Array2::from_shape_vec((n, dim), velocity).map_err(bad_shape)?;
            fields.set_item("positions", position.into_pyarray(py))?;
            fields.set_item("velocity", velocity.into_pyarray(py))?;
            fields.set_item("stress", stress.into_pyarray(py))?;
            fields.set_item("plastic_strain", plastic_strain.into_pyarray(py))?;
        }
    }
    d.set_item("state", fields)?;
    Ok(d)
}
