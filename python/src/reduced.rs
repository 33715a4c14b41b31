//! `read_siconos` and `solve_reduced`: the path of `talus reduced FILE`
//! (`crates/talus/src/cli/reduced.rs`) with the problem given as arrays. The arrays are put
//! back into a [`SiconosProblem`] so that `reduced_system_from_siconos` builds the same
//! operator and flow rules as for a file.
use std::path::PathBuf;

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use talus_ssn::siconos::{SiconosMatrix, SiconosModel, SiconosProblem};
use talus_ssn::{reduced_system_from_siconos, Report, Rho, Settings, SolveError, Solver};

use crate::errors::raise;

/// The parts of a Siconos plasticity file as a dict (`talus.read_siconos` shapes it).
#[pyfunction]
pub fn read_siconos<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyDict>> {
    let problem = SiconosProblem::from_path(&path)
        .map_err(|e| raise(py, "SiconosError", (e.to_string(),)))?;
    let d = PyDict::new(py);
    let n = problem.n();
    d.set_item("n", n)?;
    d.set_item("cone_dimension", problem.cone_dimension)?;
    match problem.matrix {
        SiconosMatrix::Dense { values, .. } => {
            let dense = Array2::from_shape_vec((n, n), values)
                .map_err(|e| raise(py, "SiconosError", (e.to_string(),)))?;
            d.set_item("dense", dense.into_pyarray(py))?;
        }
        SiconosMatrix::Sparse { triplets, .. } => {
            // In the file's order: duplicates are summed by the solver as for the file.
            let rows: Vec<i64> = triplets.iter().map(|t| t.0 as i64).collect();
            let cols: Vec<i64> = triplets.iter().map(|t| t.1 as i64).collect();
            let values: Vec<f64> = triplets.iter().map(|t| t.2).collect();
            d.set_item("rows", rows.into_pyarray(py))?;
            d.set_item("cols", cols.into_pyarray(py))?;
            d.set_item("values", values.into_pyarray(py))?;
        }
    }
    d.set_item("q", problem.q.into_pyarray(py))?;
    match problem.model {
        SiconosModel::DruckerPrager { eta, theta } => {
            d.set_item("model", "drucker_prager")?;
            d.set_item("eta", eta.into_pyarray(py))?;
            d.set_item("theta", theta.into_pyarray(py))?;
        }
        SiconosModel::VonMises { sigma_y } => {
            d.set_item("model", "von_mises")?;
            d.set_item("sigma_y", sigma_y.into_pyarray(py))?;
        }
    }
    Ok(d)
}

/// Solves `z = Wσ + q` with `σ_i = P_K(σ_i − ρ y(z_i))` per cone, as `talus reduced`.
/// `W` is `dense` (n×n) or the triplets `rows, cols, values`; `model` is `drucker_prager`
/// (`eta`, `theta`) or `von_mises` (`sigma_y`). Returns `(σ, report, converged)`.
#[pyfunction]
#[pyo3(signature = (n, q, model, dense, rows, cols, values, eta, theta, sigma_y,
                    tol, rho_factor, global_rho, max_iterations))]
#[allow(clippy::too_many_arguments)]
pub fn solve_reduced<'py>(
    py: Python<'py>,
    n: usize,
    q: PyReadonlyArray1<'py, f64>,
    model: &str,
    dense: Option<PyReadonlyArray2<'py, f64>>,
    rows: Option<PyReadonlyArray1<'py, i64>>,
    cols: Option<PyReadonlyArray1<'py, i64>>,
    values: Option<PyReadonlyArray1<'py, f64>>,
    eta: Option<PyReadonlyArray1<'py, f64>>,
    theta: Option<PyReadonlyArray1<'py, f64>>,
    sigma_y: Option<PyReadonlyArray1<'py, f64>>,
    tol: f64,
    rho_factor: f64,
    global_rho: bool,
    max_iterations: usize,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyDict>, bool)> {
    let bad = |m: String| raise(py, "InvalidProblem", (m,));
    let vec = |a: &PyReadonlyArray1<'py, f64>| a.as_array().iter().copied().collect::<Vec<_>>();
    let matrix = match (dense, rows, cols, values) {
        (Some(w), None, None, None) => SiconosMatrix::Dense {
            n,
            values: w.as_array().iter().copied().collect(),
        },
        (None, Some(r), Some(c), Some(v)) => {
            let (r, c, v) = (r.as_array(), c.as_array(), v.as_array());
            if r.len() != v.len() || c.len() != v.len() {
                return Err(bad(format!(
                    "W: {} rows, {} columns and {} values",
                    r.len(),
                    c.len(),
                    v.len()
                )));
            }
            let index = |i: i64, what: &str| {
                usize::try_from(i)
                    .ok()
                    .filter(|&i| i < n)
                    .ok_or_else(|| bad(format!("W: {what} index {i} outside 0..{n}")))
            };
            let mut triplets = Vec::with_capacity(v.len());
            for ((&i, &j), &x) in r.iter().zip(c.iter()).zip(v.iter()) {
                triplets.push((index(i, "row")?, index(j, "column")?, x));
            }
            SiconosMatrix::Sparse { n, triplets }
        }
        _ => return Err(bad("W: give a dense matrix or sparse triplets".into())),
    };
    let model = match (model, eta, theta, sigma_y) {
        ("drucker_prager", Some(eta), Some(theta), None) => SiconosModel::DruckerPrager {
            eta: vec(&eta),
            theta: vec(&theta),
        },
        ("von_mises", None, None, Some(s)) => SiconosModel::VonMises { sigma_y: vec(&s) },
        (m, ..) => {
            return Err(bad(format!(
                "cones: model {m:?} needs eta and theta (drucker_prager) or sigma_y (von_mises)"
            )))
        }
    };
    let n_cones = match &model {
        SiconosModel::DruckerPrager { eta, theta } if eta.len() == theta.len() => eta.len(),
        SiconosModel::VonMises { sigma_y } => sigma_y.len(),
        _ => return Err(bad("cones: eta and theta differ in length".into())),
    };
    if n != 3 * n_cones {
        return Err(bad(format!(
            "W is {n}×{n} but {n_cones} cones of dimension 3 need n = {}",
            3 * n_cones
        )));
    }
    let problem = SiconosProblem {
        cone_dimension: 3,
        n_cones,
        matrix,
        q: vec(&q),
        model,
    };
    if problem.q.len() != n {
        return Err(bad(format!(
            "q has length {}, W is {n}×{n}",
            problem.q.len()
        )));
    }
    let rho = if global_rho {
        Rho::GlobalDiagonal { factor: rho_factor }
    } else {
        Rho::PerPointDiagonal { factor: rho_factor }
    };
    let settings = Settings {
        tolerance: tol,
        rho,
        max_iterations,
        ..Settings::reduced()
    };
    // On a worker of rayon's pool, as a run steps (`Watch::detach_on_pool`).
    let solve = move || -> Result<(Vec<f64>, Report), SolveError> {
        let system = reduced_system_from_siconos::<3>(&problem)?;
        let mut solver = Solver::new(system, settings)?;
        let mut sigma = vec![0.0; problem.n()];
        let report = match solver.solve(&mut sigma) {
            Ok(r) => r,
            Err(SolveError::NotConverged(r)) => *r,
            Err(e) => return Err(e),
        };
        Ok((sigma, report))
    };
    let solved = py.detach(move || talus_ssn::on_pool(solve));
    let (sigma, report) = solved.map_err(|e| bad(e.to_string()))?;
    let sigma_inf = sigma.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let converged = report.is_converged();
    Ok((
        sigma.into_pyarray(py).into_any(),
        report_dict(py, &report, sigma_inf)?,
        converged,
    ))
}

/// The report as `talus reduced --json` prints it.
fn report_dict<'py>(py: Python<'py>, r: &Report, sigma_inf: f64) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("status", r.status.as_str())?;
    d.set_item("iterations", r.iterations)?;
    d.set_item("residual", r.residual)?;
    d.set_item("seconds", r.seconds)?;
    d.set_item("relative_residual", r.residual / sigma_inf.max(1.0))?;
    d.set_item("sigma_inf", sigma_inf)?;
    d.set_item("residual_history", r.residual_history.clone())?;
    d.set_item("backtracks", r.backtracks)?;
    d.set_item("rho_min", r.rho_range.0)?;
    d.set_item("rho_max", r.rho_range.1)?;
    match r.round_off_floor {
        Some(f) => {
            let floor = PyDict::new(py);
            floor.set_item("reached", f.reached)?;
            floor.set_item("estimate", f.estimate)?;
            d.set_item("round_off_floor", floor)?;
        }
        None => d.set_item("round_off_floor", py.None())?,
    }
    Ok(d)
}
