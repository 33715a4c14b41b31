//! Checks of the sections FEM and MPM scenes share (`[material]`, `[time]`, `[solver]`),
//! each error naming the field and its value.
use talus_bipotential::{DruckerPrager, DruckerPragerParameters, MaterialError};

use super::source::Locate;
use super::{MaterialSpec, Ramp, SceneError, SolverSpec, TimeSpec};

/// The Drucker-Prager material of `[material]` (density is checked by its user).
pub fn material(scene: &impl Locate, m: &MaterialSpec) -> Result<DruckerPrager, SceneError> {
    DruckerPrager::try_new(DruckerPragerParameters {
        young_modulus: m.young_modulus,
        poisson_ratio: m.poisson_ratio,
        friction_angle: m.friction_angle,
        cohesion: m.cohesion,
        dilatancy_angle: m.dilatancy_angle.unwrap_or(m.friction_angle),
        cone_fit: m.cone_fit,
    })
    .map_err(|e| {
        let MaterialError::InvalidParameter { name, .. } = &e;
        let field = format!("material.{}", name.split('.').next().unwrap_or(name));
        scene.error(&field, e.to_string())
    })
}

/// `h` finite and positive, at least one step.
pub fn time(scene: &impl Locate, ts: &TimeSpec) -> Result<(), SceneError> {
    if !(ts.step.is_finite() && ts.step > 0.0) {
        return Err(scene.error("time.step", format!("{} s must be finite and > 0", ts.step)));
    }
    if ts.steps == 0 {
        return Err(scene.error("time.steps", "must be at least 1"));
    }
    Ok(())
}

/// Tolerance and ρ factor finite and positive, at least one iteration.
pub fn solver(scene: &impl Locate, sv: &SolverSpec) -> Result<(), SceneError> {
    if !(sv.tolerance.is_finite() && sv.tolerance > 0.0) {
        return Err(scene.error(
            "solver.tolerance",
            format!("{} must be finite and > 0", sv.tolerance),
        ));
    }
    if !(sv.rho_factor.is_finite() && sv.rho_factor > 0.0) {
        return Err(scene.error(
            "solver.rho_factor",
            format!("{} must be finite and > 0", sv.rho_factor),
        ));
    }
    if sv.max_iterations == 0 {
        return Err(scene.error("solver.max_iterations", "must be at least 1"));
    }
    Ok(())
}

/// The load programme `ramp` of `field` (`traction[1].ramp`, `gravity_ramp`), if given.
pub fn ramp(
    scene: &impl Locate,
    field: &str,
    points: &Option<Vec<[f64; 2]>>,
) -> Result<Option<Ramp>, SceneError> {
    points
        .as_deref()
        .map(|p| Ramp::try_new(p).map_err(|e| scene.error(field, e.to_string())))
        .transpose()
}
