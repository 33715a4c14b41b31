//! Verification cases: each reproduces a closed form, a published value or an independent
//! computation, and reports `(case, quantity, reference, computed, tolerance)`. Run by
//! `talus verify` (and so by `cargo xtask verify`); the integration tests assert the same
//! cases pass.
mod axisymmetric_elastic;
mod cavity_expansion;
mod convergence_order;
mod elastic;
mod layered_footing;
mod material_point;
mod prandtl;
mod stability;
mod stages;
mod three_d;
mod triaxial;
mod water;

use std::time::Instant;

use crate::model::fem::{FromScene, Model, ReactionForce, State};
use crate::run::fem::solver_settings;
use crate::scene::Scene;
use talus_engine::{StepSettings, Stepper};

pub use axisymmetric_elastic::{
    circular_punch, lame, lame_axisymmetric, lame_errors, lame_scene, punch_stiffness,
    sneddon_stiffness,
};
pub use cavity_expansion::{
    cavity_expansion_case, cavity_pressure, thick_cylinder_collapse, Cavity, CAVITY,
    CAVITY_EXPANSION,
};
pub use convergence_order::newton_convergence_order;
pub use elastic::{elastic_patch_test, elastic_step_identity};
pub use layered_footing::{
    equal_strengths_case, layered_footing, layered_footing_cases, layered_scene,
    strong_over_weak_cases, tresca_nc, LayeredRun, DISCRETIZATION, SCENE_STRENGTH_RATIO,
    THICKNESS_OVER_WIDTH,
};
pub use material_point::{apex_return, associative_normality, dilatancy_ratio};
pub use prandtl::{prandtl, prandtl_refinement, PrandtlRun};
pub use stability::{
    case_dir, slope_by_hand, slope_cases, vertical_cut_case, vertical_cut_fenicsx_case,
    CHEN_REFERENCE, CUT_REFERENCE, SLOPE_REFERENCE,
};
pub use stages::{cut_in_lifts_case, cut_scenes, staged_factor, CUT_IN_LIFTS};
pub use three_d::{
    block_column_case, circular_footing_case, circular_footing_nc, extrapolated,
    extruded_slope_cases, extruded_slope_runs, extruded_slope_scenes, square_footing_clay_case,
    square_footing_nc, BLOCK_3D, SQUARE_FOOTING_CLAY_3D, TRESCA_SQUARE_NC,
};
pub use triaxial::{
    run_triaxial, triaxial_compression, triaxial_dilatancy_ratio, triaxial_peak_deviator,
    triaxial_scene, TriaxialRun,
};
pub use water::{submerged_slope_case, submerged_slope_scenes};

/// One verified quantity.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CaseResult {
    pub case: String,
    pub quantity: String,
    pub reference: f64,
    pub computed: f64,
    /// Bound on `error()`.
    pub tolerance: f64,
    pub check: Check,
    pub seconds: f64,
    /// Where the reference comes from.
    pub source: String,
}

/// How `computed` is compared with `reference`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Check {
    /// `|computed − reference| / |reference| ≤ tolerance`.
    Relative,
    /// `|computed − reference| ≤ tolerance` (zero references).
    Absolute,
    /// `computed ≥ reference − tolerance` (one-sided: more is fine).
    AtLeast,
    /// `computed ≤ reference + tolerance` (one-sided: less is fine).
    AtMost,
}

impl CaseResult {
    /// The error compared with the tolerance (0 on the good side of a one-sided check).
    pub fn error(&self) -> f64 {
        let d = self.computed - self.reference;
        match self.check {
            Check::Relative => d.abs() / self.reference.abs(),
            Check::Absolute => d.abs(),
            Check::AtLeast => (-d).max(0.0) + if d.is_nan() { f64::NAN } else { 0.0 },
            Check::AtMost => d.max(0.0) + if d.is_nan() { f64::NAN } else { 0.0 },
        }
    }

    /// Passes when the error is within tolerance (a NaN never passes).
    pub fn passed(&self) -> bool {
        self.error() <= self.tolerance
    }
}

/// Runs `scene` to its end with its solver settings: the model, the final state and the
/// last step's reported reaction (`reaction_force`); `None` if a step fails.
pub(crate) fn run_to_end(scene: &Scene) -> Option<(Model, State, f64)> {
    let model = Model::from_scene(scene).ok()?;
    let mut state = model.initial_state(scene).ok()?;
    let mut stepper = Stepper::new(
        &model,
        StepSettings::with_solver(solver_settings(scene), scene.spec.solver.max_step_halvings),
    );
    let mut reaction = f64::NAN;
    for _ in 0..scene.spec.time.steps {
        reaction = stepper
            .advance(&mut state, scene.spec.time.step)
            .ok()?
            .reaction_force();
    }
    Some((model, state, reaction))
}

/// Times `f` and stamps the seconds on every result it returns.
pub(crate) fn timed(f: impl FnOnce() -> Vec<CaseResult>) -> Vec<CaseResult> {
    let start = Instant::now();
    let mut results = f();
    let seconds = start.elapsed().as_secs_f64();
    for r in &mut results {
        r.seconds = seconds;
    }
    results
}

/// Every case; `quick` keeps the coarser Prandtl meshes only (and the layered footing's
/// two coarse runs). With `figures`, the PNGs of the cases are written there
/// (`verification_*.png`).
pub fn all_cases(quick: bool, figures: Option<&std::path::Path>) -> Vec<CaseResult> {
    let mut out = Vec::new();
    out.extend(timed(dilatancy_ratio));
    out.extend(timed(apex_return));
    out.extend(timed(associative_normality));
    out.extend(timed(elastic_patch_test));
    out.extend(timed(elastic_step_identity));
    out.extend(timed(triaxial_compression));
    out.extend(timed(lame_axisymmetric));
    out.extend(timed(circular_punch));
    out.extend(timed(cavity_expansion_case));
    out.extend(prandtl::all_prandtl_cases(quick, figures));
    // Rows stamp their own runs' seconds; `quick` keeps c2/c1 = 0.5 and 1 on the coarse mesh.
    out.extend(layered_footing_cases(quick));
    out.extend(timed(|| newton_convergence_order(figures)));
    // Each stamps its own seconds (the slope's by-hand runs apart from its search).
    out.extend(slope_cases());
    out.extend(vertical_cut_case());
    out.extend(vertical_cut_fenicsx_case());
    out.extend(cut_in_lifts_case());
    out.extend(submerged_slope_case());
    // 3D: each stamps its own seconds.
    out.extend(block_column_case());
    out.extend(square_footing_clay_case());
    out.extend(extruded_slope_cases());
    out.extend(circular_footing_case());
    out
}
