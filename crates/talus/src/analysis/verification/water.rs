//! A drained water table against Archimedes (`docs/scenes.md`, 'Water'): hydrostatic water
//! is in equilibrium on its own, so Griffiths & Lane's slope (`scenes/slope.toml`) fully
//! submerged, γ_sat = 20 kN/m³ under a level above its crest, has the factor of safety of
//! the same dry slope with the buoyant unit weight γ_sat − γ_w.
use std::time::Instant;

use super::stability::scene_path;
use super::{case_dir, CaseResult, Check};
use crate::analysis::stability;
use crate::run::RunOptions;
use crate::scene::{Scene, WATER_UNIT_WEIGHT};

/// The slope dry with the buoyant unit weight, and submerged under a level at 20 m (its
/// crest is at 10 m), from `scenes/slope.toml` (ρ = 2000 kg/m³, g = 10 m/s²).
pub fn submerged_slope_scenes() -> Result<(Scene, Scene), String> {
    let path = scene_path("slope.toml");
    let text = std::fs::read_to_string(&path).map_err(|e| e.to_string())?;
    if !(text.contains("density = 2.0e3") && text.contains("gravity = [0.0, -10.0]")) {
        return Err("scenes/slope.toml no longer has ρ = 2.0e3 and g = 10".into());
    }
    let buoyant = (2.0e4 - WATER_UNIT_WEIGHT) / 10.0;
    let dry = text.replace("density = 2.0e3", &format!("density = {buoyant:?}"));
    let wet = format!("{text}\n[water]\nlevel = 20.0\nunit_weight = {WATER_UNIT_WEIGHT:?}\n");
    let parse = |t: &str| Scene::parse(t, Some(path.clone())).map_err(|e| e.to_string());
    Ok((parse(&dry)?, parse(&wet)?))
}

/// The submerged slope's factor against the buoyant dry slope's.
pub fn submerged_slope_case() -> Vec<CaseResult> {
    let start = Instant::now();
    let factor = |scene: &Scene, name: &str| {
        stability::run(scene, &RunOptions::new(case_dir(name)))
            .ok()?
            .factor_of_safety
            .value
    };
    let (computed, reference) = submerged_slope_scenes()
        .ok()
        .and_then(|(dry, wet)| Some((factor(&wet, "submerged")?, factor(&dry, "buoyant")?)))
        .unwrap_or((f64::NAN, f64::NAN));
    vec![CaseResult {
        case: "submerged_slope_equals_buoyant_dry_slope".into(),
        quantity: "F submerged (reference: F of the dry slope of unit weight γ_sat − γ_w)".into(),
        reference,
        computed,
        tolerance: 0.005,
        check: Check::Relative,
        seconds: start.elapsed().as_secs_f64(),
        source: "Archimedes: hydrostatic pore pressure is in equilibrium on its own; \
                 effective stress (Terzaghi 1943)"
            .into(),
    }]
}
