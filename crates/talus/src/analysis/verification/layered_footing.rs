//! Bearing capacity of a rigid rough strip footing (width `b`) on two layers of weightless,
//! associative Tresca clay (`scenes/footing_two_layers.toml`): an upper layer of thickness
//! `H = b/2` and strength `c1` over a half-space of strength `c2`. The limit pressure is
//! written `q_u = c1 N_c*`.
//!
//! - Equal strengths, `c2 = c1`: Prandtl's (1920) `N_c = 2 + π` (Tresca, rough or smooth
//!   footing), which also shows that two `[[material]]`s of equal strength behave as one.
//! - A weaker lower layer, `c2 < c1`: no published table value could be found and checked
//!   for this case (Merifield, Sloan & Yu 1999, Géotechnique 49(4), give rigorous lower and
//!   upper bounds of `N_c*`; Michalowski 2002, Soils and Foundations 42(1), upper bounds),
//!   so the check is a bracket, not a published comparison: the limit load never
//!   decreases when a material is strengthened (a stress field admissible for the weaker
//!   ground is admissible for the stronger one; lower-bound theorem), hence
//!   `(2 + π) c2/c1 ≤ N_c*(c2/c1) ≤ 2 + π`, and `N_c*` must rise with `c2/c1`.
//!   The discretization error is measured by one refinement of the mesh.
use std::f64::consts::PI;
use std::time::Instant;

use super::{CaseResult, Check};
use crate::model::fem::{FromScene, Model, ReactionForce};
use crate::run::fem::run_scene;
use crate::run::RunOptions;
use crate::scene::{MeshSpec, Scene};

const BASE: &str = include_str!("../../../../../scenes/footing_two_layers.toml");

/// `H/b` of the scene.
pub const THICKNESS_OVER_WIDTH: f64 = 0.5;
/// `c2/c1` of the scene.
pub const SCENE_STRENGTH_RATIO: f64 = 0.5;
/// The relative discretization error allowed on the coarse mesh (the tolerance of the P2
/// Prandtl cases, whose coarse-mesh errors are 1–3%): the bracket's slack, and the bound on
/// the change under one refinement.
pub const DISCRETIZATION: f64 = 0.05;

/// Prandtl's factor for Tresca clay, `N_c = 2 + π`.
pub fn tresca_nc() -> f64 {
    2.0 + PI
}

/// One run's outcome.
#[derive(Debug, Clone, PartialEq)]
pub struct LayeredRun {
    /// `c2/c1`.
    pub strength_ratio: f64,
    /// `q_u / c1 = 2 × reaction / (b c1)` at the end of the loading.
    pub nc: f64,
    pub cells: [usize; 2],
    pub elements: usize,
    /// Elements of the lower material (those below the interface `y = −H`).
    pub lower_elements: usize,
    pub max_newton_iterations: usize,
    /// Relative change of the force over the last 10% of the steps.
    pub plateau: f64,
    /// `(settlement m, F = 2 × reaction N/m)` per step, starting at rest.
    pub curve: Vec<(f64, f64)>,
    /// Where the final velocity field moves: the farthest surface node heaving by more than
    /// 2% of the footing speed (m from the centre), the deepest node moving by more than 2%
    /// (m), and the domain's `[L, D]`.
    pub heave_to: f64,
    pub moving_to_depth: f64,
    pub domain: [f64; 2],
    pub seconds: f64,
}

/// The scene with `c2 = strength_ratio × c1` and the mesh refined `refinement` times: each
/// refinement doubles the cells in both directions and takes the square root of the
/// grading ratios, so the interface stays a grid line (the top `8 × 2^refinement` cells
/// fill the upper layer).
pub fn layered_scene(strength_ratio: f64, refinement: u32) -> Option<Scene> {
    let (c1, c2_base) = (1.0e4, 5.0e3);
    let c2 = strength_ratio * c1;
    let k = 1usize << refinement;
    let ratio = 1.12f64.powf(1.0 / k as f64);
    let text = BASE
        .replacen(
            &format!("cohesion = {c2_base:.1e}"),
            &format!("cohesion = {c2:?}"),
            1,
        )
        .replacen(
            "cells = [36, 22]",
            &format!("cells = [{}, {}]", 36 * k, 22 * k),
            1,
        )
        .replacen(
            "ratio = [1.12, 1.12]",
            &format!("ratio = [{ratio:?}, {ratio:?}]"),
            1,
        );
    let scene = Scene::parse(&text, None).ok()?;
    // The replacements took: the materials and mesh are those asked for.
    let materials = scene.spec.material.all();
    let MeshSpec::Rectangle { cells, .. } = &scene.spec.mesh else {
        return None;
    };
    (materials.len() == 2
        && materials[0].cohesion() == c1
        && materials[1].cohesion() == c2
        && *cells == [36 * k, 22 * k])
    .then_some(scene)
}

/// Runs the scene with `c2/c1 = strength_ratio`, `refinement` times refined.
pub fn layered_footing(strength_ratio: f64, refinement: u32) -> Option<LayeredRun> {
    let start = Instant::now();
    let scene = layered_scene(strength_ratio, refinement)?;
    let MeshSpec::Rectangle { x, y, cells, .. } = scene.spec.mesh.clone() else {
        return None;
    };
    let model = Model::from_scene(&scene).ok()?;
    let out = super::stability::case_dir(&format!(
        "layered-footing-{strength_ratio}-{}x{}",
        cells[0], cells[1]
    ));
    let summary = run_scene(&scene, &RunOptions::new(out)).ok()?;
    let b = 1.0;
    let c1 = scene.spec.material.all()[0].cohesion();
    let force: Vec<f64> = summary
        .records
        .iter()
        .map(|r| 2.0 * r.reaction_force())
        .collect();
    let n = force.len();
    let last = *force.last()?;
    let plateau = (last - force[n - 1 - n / 10]) / last;

    let speed = 0.04;
    let velocity = model
        .assembly
        .dofs()
        .scatter(
            &summary.final_state.velocity_free,
            &summary.final_state.velocity_prescribed,
        )
        .ok()?;
    let nodes = &model.mesh.nodes;
    let heave_to = (0..nodes.len())
        .filter(|&k| nodes[k][1] == 0.0 && velocity[k][1] > 0.02 * speed)
        .map(|k| nodes[k][0])
        .fold(0.0, f64::max);
    let moving_to_depth = (0..nodes.len())
        .filter(|&k| velocity[k][0].hypot(velocity[k][1]) > 0.02 * speed)
        .map(|k| -nodes[k][1])
        .fold(0.0, f64::max);
    let element_materials = model.element_materials();
    Some(LayeredRun {
        strength_ratio,
        nc: last / (b * c1),
        cells,
        elements: model.mesh.triangles.len(),
        lower_elements: element_materials.iter().filter(|&&m| m == 1).count(),
        max_newton_iterations: summary
            .records
            .iter()
            .map(|r| r.max_newton_iterations)
            .max()
            .unwrap_or(0),
        plateau,
        curve: std::iter::once((0.0, 0.0))
            .chain(summary.displacements.iter().copied().zip(force))
            .collect(),
        heave_to,
        moving_to_depth,
        domain: [x[1] - x[0], y[1] - y[0]],
        seconds: start.elapsed().as_secs_f64(),
    })
}

fn nc_of(run: Option<&LayeredRun>) -> f64 {
    run.map(|r| r.nc).unwrap_or(f64::NAN)
}

fn cells_of(run: Option<&LayeredRun>) -> String {
    run.map(|r| format!("{}×{}", r.cells[0], r.cells[1]))
        .unwrap_or_else(|| "failed".into())
}

/// Case (a): `c2 = c1` gives Prandtl's `2 + π` within [`DISCRETIZATION`].
pub fn equal_strengths_case(run: Option<&LayeredRun>) -> CaseResult {
    CaseResult {
        case: "layered_footing_equal_strengths_p2".into(),
        quantity: format!(
            "q_u / c, two [[material]]s with c2 = c1, rough footing, {} cells",
            cells_of(run)
        ),
        reference: tresca_nc(),
        computed: nc_of(run),
        tolerance: DISCRETIZATION,
        check: Check::Relative,
        seconds: run.map(|r| r.seconds).unwrap_or(0.0),
        source: "Prandtl (1920), N_c = 2 + π (Tresca, φ = 0)".into(),
    }
}

/// The bracket's source line.
const BRACKET: &str = "bracket, not a published comparison: the limit load never decreases \
                       with the strength (lower-bound theorem), so (2 + π) c2/c1 ≤ N_c* ≤ \
                       2 + π (Prandtl 1920); no citable table value of Merifield, Sloan & Yu \
                       (1999) or Michalowski (2002) was at hand";

/// Case (b): `N_c*` at `H/b = 0.5` for the strength ratios of `sweep` (increasing; the last
/// is 1), each within the bracket up to [`DISCRETIZATION`], rising with `c2/c1`; with
/// `refined`, the scene's ratio again on the mesh refined once, whose change bounds the
/// discretization error.
pub fn strong_over_weak_cases(
    sweep: &[Option<LayeredRun>],
    refined: Option<Option<&LayeredRun>>,
) -> Vec<CaseResult> {
    let mut out = Vec::new();
    let hb = THICKNESS_OVER_WIDTH;
    for run in sweep.iter().flatten().filter(|r| r.strength_ratio < 1.0) {
        let r = run.strength_ratio;
        let name = format!("layered_footing_h{hb}_c{r}");
        let weak = tresca_nc() * r;
        out.push(CaseResult {
            case: name.clone(),
            quantity: format!(
                "N_c* = q_u / c1, H/b = {hb}, c2/c1 = {r}, {} cells: at least the weak \
                 half-space's (2 + π) c2/c1",
                cells_of(Some(run))
            ),
            reference: weak,
            computed: run.nc,
            tolerance: DISCRETIZATION * weak,
            check: Check::AtLeast,
            seconds: run.seconds,
            source: BRACKET.into(),
        });
        out.push(CaseResult {
            case: name,
            quantity: format!(
                "N_c* = q_u / c1, H/b = {hb}, c2/c1 = {r}, {} cells: at most the strong \
                 half-space's 2 + π",
                cells_of(Some(run))
            ),
            reference: tresca_nc(),
            computed: run.nc,
            tolerance: DISCRETIZATION * tresca_nc(),
            check: Check::AtMost,
            seconds: run.seconds,
            source: BRACKET.into(),
        });
    }
    // A failed run leaves a NaN, which fails.
    let ncs: Vec<f64> = sweep.iter().map(|r| nc_of(r.as_ref())).collect();
    let ratios: Vec<String> = sweep
        .iter()
        .flatten()
        .map(|r| format!("{}: {:.3}", r.strength_ratio, r.nc))
        .collect();
    let rises: Vec<f64> = ncs.windows(2).map(|w| w[1] - w[0]).collect();
    let rise = if rises.iter().any(|d| d.is_nan()) {
        f64::NAN
    } else {
        rises.into_iter().fold(f64::INFINITY, f64::min)
    };
    out.push(CaseResult {
        case: format!("layered_footing_h{hb}_monotone"),
        quantity: format!(
            "smallest rise of N_c* between successive c2/c1 (c2/c1: N_c* = {})",
            ratios.join(", ")
        ),
        reference: 0.0,
        computed: rise,
        tolerance: 0.0,
        check: Check::AtLeast,
        seconds: sweep.iter().flatten().map(|r| r.seconds).sum(),
        source: "a stronger lower layer never lowers the limit load (lower-bound theorem)".into(),
    });
    if let Some(fine) = refined {
        let coarse = sweep
            .iter()
            .flatten()
            .find(|r| r.strength_ratio == SCENE_STRENGTH_RATIO);
        let (nc0, nc1) = (nc_of(coarse), nc_of(fine));
        out.push(CaseResult {
            case: format!("layered_footing_h{hb}_c{SCENE_STRENGTH_RATIO}_refinement"),
            quantity: format!(
                "N_c* {} cells {nc0:.4} → {} cells {nc1:.4}: relative change, the bracket's \
                 allowance bounds it",
                cells_of(coarse),
                cells_of(fine)
            ),
            reference: nc1,
            computed: nc0,
            tolerance: DISCRETIZATION,
            check: Check::Relative,
            seconds: fine.map(|r| r.seconds).unwrap_or(0.0),
            source: "one refinement (cells doubled, grading ratio square-rooted)".into(),
        });
    }
    out
}

/// Case (a) and case (b), each row with its own runs' seconds. `quick`: `c2/c1 ∈ {0.5, 1}`
/// on the coarse mesh (about 4 s in release on 2 cores); otherwise also `0.25` and `0.75`,
/// and `0.5` and `1` again on the mesh refined once (about 20 s).
pub fn layered_footing_cases(quick: bool) -> Vec<CaseResult> {
    let ratios: &[f64] = if quick {
        &[SCENE_STRENGTH_RATIO, 1.0]
    } else {
        &[0.25, SCENE_STRENGTH_RATIO, 0.75, 1.0]
    };
    let sweep: Vec<Option<LayeredRun>> = ratios.iter().map(|&r| layered_footing(r, 0)).collect();
    let equal = sweep.last().and_then(|r| r.as_ref());
    let mut out = vec![equal_strengths_case(equal)];
    if quick {
        out.extend(strong_over_weak_cases(&sweep, None));
    } else {
        out.push(equal_strengths_case(layered_footing(1.0, 1).as_ref()));
        let fine = layered_footing(SCENE_STRENGTH_RATIO, 1);
        out.extend(strong_over_weak_cases(&sweep, Some(fine.as_ref())));
    }
    out
}
