//! Quadratic convergence of the semi-smooth Newton method: the observed order
//! `p = log(r_{k+1} / r_k) / log(r_k / r_{k−1})` over the last iterations above round-off.
use talus_ssn::siconos::SiconosProblem;
use talus_ssn::{reduced_system_from_siconos, Settings, Solver};

use super::{CaseResult, Check};
use crate::run::fem::run_scene;
use crate::run::RunOptions;
use crate::scene::builtin_footing;

/// Orders from one residual history: one per triple of successive residuals above the
/// history's round-off, taken as ten times its smallest value (the floor differs between
/// problems: about 1e-13 relative on the Siconos footings, 1e-12 on the FEM footing).
fn orders(history: &[f64]) -> Vec<f64> {
    let floor = 10.0 * history.iter().copied().fold(f64::INFINITY, f64::min);
    let r: Vec<f64> = history.iter().copied().filter(|v| *v > floor).collect();
    r.windows(3)
        .filter(|w| w[1] < w[0] && w[2] < w[1])
        .map(|w| (w[2] / w[1]).ln() / (w[1] / w[0]).ln())
        .collect()
}

/// The last observed order of each history (where one exists), as a median.
fn median_last_order(histories: &[Vec<f64>]) -> (f64, usize) {
    // Two orders at least: the first may still include the last change of active set.
    let mut last: Vec<f64> = histories
        .iter()
        .map(|h| orders(h))
        .filter(|o| o.len() >= 2)
        .filter_map(|o| o.last().copied())
        .collect();
    last.sort_by(|a, b| a.total_cmp(b));
    let n = last.len();
    (if n == 0 { f64::NAN } else { last[n / 2] }, n)
}

pub fn newton_convergence_order(figures: Option<&std::path::Path>) -> Vec<CaseResult> {
    let mut out = Vec::new();
    // The paper footing: relative residual histories of the first 60 steps.
    let mut scene = builtin_footing();
    scene.spec.time.steps = 60;
    let out_dir = super::stability::case_dir("convergence-order");
    let summary = run_scene(&scene, &RunOptions::new(out_dir)).ok();
    let records = summary.map(|s| s.records).unwrap_or_default();
    let histories: Vec<Vec<f64>> = records
        .iter()
        .flat_map(|r| r.merit_histories.clone())
        .collect();
    if let Some(dir) = figures {
        let residuals: Vec<(usize, Vec<f64>)> = records
            .iter()
            .enumerate()
            .flat_map(|(i, r)| r.residual_histories.iter().map(move |h| (i + 1, h.clone())))
            .collect();
        let path = dir.join("verification_newton_residuals.png");
        if let Err(e) =
            crate::output::plot_newton_residuals(&path, &residuals, scene.spec.solver.tolerance)
        {
            tracing::warn!(error = %e, "figure not written");
        }
    }
    let (p, n) = median_last_order(&histories);
    out.push(CaseResult {
        case: "quadratic_convergence_paper_footing".into(),
        quantity: format!(
            "‖F_ρ‖₂: median last observed order over the {n} of 60 steps with ≥ 4 iterates above round-off"
        ),
        reference: 1.8,
        computed: p,
        tolerance: 0.0,
        check: Check::AtLeast,
        seconds: 0.0,
        source: "local quadratic convergence of semi-smooth Newton (Kanzow et al. 2009)".into(),
    });
    // Siconos footing_100 (non-associative), from σ = 0.
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../data/siconos-plasticity/plasticity_2d_footing_100.dat"
    );
    let history = SiconosProblem::from_path(std::path::Path::new(path))
        .ok()
        .and_then(|p| reduced_system_from_siconos::<3>(&p).ok())
        .and_then(|system| {
            let n = system.operator().size();
            let mut solver = Solver::new(system, Settings::default()).ok()?;
            let mut sigma = vec![0.0; n];
            solver.solve(&mut sigma).ok().map(|r| {
                r.merit_history
                    .iter()
                    .map(|v| v / r.scale)
                    .collect::<Vec<f64>>()
            })
        })
        .unwrap_or_default();
    let (p, _) = median_last_order(&[history]);
    out.push(CaseResult {
        case: "quadratic_convergence_siconos_footing_100".into(),
        quantity: "‖F_ρ‖₂: last observed order above round-off (non-associative, from σ = 0)"
            .into(),
        reference: 1.8,
        computed: p,
        tolerance: 0.0,
        check: Check::AtLeast,
        seconds: 0.0,
        source: "local quadratic convergence of semi-smooth Newton".into(),
    });
    out
}
