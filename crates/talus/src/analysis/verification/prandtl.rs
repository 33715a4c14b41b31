//! Prandtl's bearing capacity `q_u = c N_c` of a rigid strip footing on weightless,
//! associative Drucker-Prager soil with the plane-strain cone fit (Prandtl 1920;
//! `N_c = (N_q − 1) cot φ`, `N_q = e^{π tan φ} tan²(45° + φ/2)`), on the half model of
//! `scenes/prandtl_phi30.toml`.
use super::{timed, CaseResult, Check};
use crate::model::fem::ReactionForce;
use crate::run::fem::run_scene;
use crate::run::RunOptions;
use crate::scene::Scene;

const BASE: &str = include_str!("../../../../../scenes/prandtl_phi30.toml");

/// Prandtl's bearing capacity factor.
pub fn prandtl_nc(phi_deg: f64) -> f64 {
    let phi = phi_deg.to_radians();
    let nq = (std::f64::consts::PI * phi.tan()).exp()
        * (std::f64::consts::FRAC_PI_4 + phi / 2.0).tan().powi(2);
    (nq - 1.0) / phi.tan()
}

/// One run's outcome.
#[derive(Debug, Clone, PartialEq)]
pub struct PrandtlRun {
    /// `q_u / c = 2 × reaction / (b c)` at the end of the loading.
    pub nc: f64,
    pub elements: usize,
    pub max_newton_iterations: usize,
    /// `(settlement m, F = 2 × reaction N/m)` per step, starting at rest.
    pub curve: Vec<(f64, f64)>,
}

/// Runs the half-model footing with friction angle `phi_deg`, `order` ("P1"/"P2") and
/// `cells` = [nx, ny] (the domain grows with φ so the mechanism is never cut).
pub fn prandtl(phi_deg: f64, order: &str, cells: [usize; 2]) -> Option<PrandtlRun> {
    // The mechanism reaches 4.8 b sideways at 30°, 6.3 b at 35°: L = 9 b, H = 4 b covers all.
    let text = BASE
        .replacen(
            "friction_angle = 30.0",
            &format!("friction_angle = {phi_deg:.1}"),
            1,
        )
        .replacen(
            "dilatancy_angle = 30.0",
            &format!("dilatancy_angle = {phi_deg:.1}"),
            1,
        )
        .replacen("x = [0.0, 7.0]", "x = [0.0, 9.0]", 1)
        .replacen("y = [-3.5, 0.0]", "y = [-4.0, 0.0]", 1)
        .replacen(
            "cells = [40, 28]",
            &format!("cells = [{}, {}]", cells[0], cells[1]),
            1,
        )
        .replacen("order = \"P2\"", &format!("order = \"{order}\""), 1);
    let scene = Scene::parse(&text, None).ok()?;
    let out = super::stability::case_dir(&format!(
        "prandtl-{phi_deg}-{order}-{}x{}",
        cells[0], cells[1]
    ));
    let summary = run_scene(&scene, &RunOptions::new(out)).ok()?;
    let b = 1.0;
    let c = scene.spec.material.single()?.cohesion();
    let force = 2.0 * summary.records.last()?.reaction_force();
    Some(PrandtlRun {
        nc: force / (b * c),
        elements: 2 * cells[0] * cells[1],
        max_newton_iterations: summary
            .records
            .iter()
            .map(|r| r.max_newton_iterations)
            .max()
            .unwrap_or(0),
        curve: std::iter::once((0.0, 0.0))
            .chain(
                summary
                    .displacements
                    .iter()
                    .zip(&summary.records)
                    .map(|(d, r)| (*d, 2.0 * r.reaction_force())),
            )
            .collect(),
    })
}

fn case(
    phi: f64,
    order: &str,
    cells: [usize; 2],
    tolerance: f64,
    figure: Option<&std::path::Path>,
) -> Vec<CaseResult> {
    let run = prandtl(phi, order, cells);
    if let (Some(path), Some(r)) = (figure, &run) {
        let title = format!(
            "Prandtl strip footing, φ = {phi}°, {order}: c N_c = {:.1} kN/m",
            prandtl_nc(phi) * 10.0
        );
        if let Err(e) = crate::output::plot_force_displacement(path, &r.curve, &title) {
            tracing::warn!(error = %e, "figure not written");
        }
    }
    vec![CaseResult {
        case: format!("prandtl_strip_footing_phi{phi}_{}", order.to_lowercase()),
        quantity: format!("q_u / c, {}×{} cells", cells[0], cells[1]),
        reference: prandtl_nc(phi),
        computed: run.map(|r| r.nc).unwrap_or(f64::NAN),
        tolerance,
        check: Check::Relative,
        seconds: 0.0,
        source: "Prandtl (1920), N_c = (N_q − 1) cot φ".into(),
    }]
}

/// Errors of φ = 30° P2 on three meshes and the observed order in the cell size.
pub fn prandtl_refinement() -> Vec<CaseResult> {
    let meshes = [[20usize, 14usize], [30, 21], [40, 28]];
    let errors: Vec<f64> = meshes
        .iter()
        .map(|m| {
            prandtl(30.0, "P2", *m)
                .map(|r| (r.nc - prandtl_nc(30.0)).abs() / prandtl_nc(30.0))
                .unwrap_or(f64::NAN)
        })
        .collect();
    let order = (errors[0] / errors[2]).ln() / (meshes[2][0] as f64 / meshes[0][0] as f64).ln();
    vec![CaseResult {
        case: "prandtl_refinement_phi30_p2".into(),
        quantity: format!(
            "error finest / coarsest, {}×{} → {}×{} cells (errors {:.2}%, {:.2}%, {:.2}%; observed order {order:.2})",
            meshes[0][0],
            meshes[0][1],
            meshes[2][0],
            meshes[2][1],
            100.0 * errors[0],
            100.0 * errors[1],
            100.0 * errors[2]
        ),
        reference: 1.0,
        computed: errors[2] / errors[0],
        tolerance: 0.0,
        check: Check::AtMost,
        seconds: 0.0,
        source: "mesh refinement must reduce the error (the footing edge is singular: a low order is expected)".into(),
    }]
}

/// φ = 10°, 20°, 30°, 35° with P2 (5%) and P1 (10%: linear triangles lock under plastic
/// flow and overestimate), and the refinement study unless `quick`.
pub(crate) fn all_prandtl_cases(quick: bool, figures: Option<&std::path::Path>) -> Vec<CaseResult> {
    let mut out = Vec::new();
    for phi in [10.0, 20.0, 30.0, 35.0] {
        let figure = figures
            .filter(|_| phi == 30.0)
            .map(|d| d.join("verification_prandtl_phi30_p2.png"));
        out.extend(timed(|| case(phi, "P2", [40, 28], 0.05, figure.as_deref())));
        if !quick {
            out.extend(timed(|| case(phi, "P1", [40, 28], 0.10, None)));
        }
    }
    if !quick {
        out.extend(timed(prandtl_refinement));
    }
    out
}
