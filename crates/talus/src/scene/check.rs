//! Checks of the sections FEM and MPM scenes share (`[material]`, `[time]`, `[solver]`),
//! each error naming the field and its value.
use talus_bipotential::{DruckerPrager, DruckerPragerParameters, Elastic, Material, MaterialError};

use super::source::Locate;
use super::{MaterialModel, MaterialSpec, Ramp, SceneError, SolverSpec, TimeSpec};

/// The material at `field` (`material` or `material[k]`): Drucker-Prager with its
/// required keys, or elastic without them; densities finite and positive when given (the
/// density's presence is checked by its user).
pub fn material(
    scene: &impl Locate,
    field: &str,
    m: &MaterialSpec,
) -> Result<Material, SceneError> {
    for (key, value) in [
        ("density", m.density),
        ("saturated_density", m.saturated_density),
    ] {
        if let Some(v) = value.filter(|v| !(v.is_finite() && *v > 0.0)) {
            return Err(scene.error(
                &format!("{field}.{key}"),
                format!("{v} kg/m³ must be finite and > 0"),
            ));
        }
    }
    let named = |e: MaterialError| {
        let MaterialError::InvalidParameter { name, .. } = &e;
        let key = name.split('.').next().unwrap_or(name);
        scene.error(&format!("{field}.{key}"), e.to_string())
    };
    match m.model {
        MaterialModel::Elastic => {
            let given = [
                ("friction_angle", m.friction_angle.is_some()),
                ("cohesion", m.cohesion.is_some()),
                ("dilatancy_angle", m.dilatancy_angle.is_some()),
                ("cone_fit", m.cone_fit.is_some()),
            ];
            if let Some((key, _)) = given.iter().find(|(_, g)| *g) {
                return Err(scene.error(
                    &format!("{field}.{key}"),
                    "is a Drucker-Prager key; model = \"elastic\" takes young_modulus, \
                     poisson_ratio, density, saturated_density and reduce",
                ));
            }
            Ok(Material::Elastic(
                Elastic::try_new(m.young_modulus, m.poisson_ratio).map_err(named)?,
            ))
        }
        MaterialModel::DruckerPrager => {
            let required = |key: &str, value: Option<f64>| {
                value.ok_or_else(|| {
                    scene.error(
                        &format!("{field}.{key}"),
                        "is required by model = \"drucker_prager\" (the default)",
                    )
                })
            };
            let friction_angle = required("friction_angle", m.friction_angle)?;
            let cohesion = required("cohesion", m.cohesion)?;
            let cone_fit = m.cone_fit.ok_or_else(|| {
                scene.error(
                    &format!("{field}.cone_fit"),
                    "is required by model = \"drucker_prager\": one of \"plane_strain\", \
                     \"outer_cone\", \"inner_cone\" or { explicit = { k_d = ... } }",
                )
            })?;
            let dp = DruckerPrager::try_new(DruckerPragerParameters {
                young_modulus: m.young_modulus,
                poisson_ratio: m.poisson_ratio,
                friction_angle,
                cohesion,
                dilatancy_angle: m.dilatancy_angle.unwrap_or(friction_angle),
                cone_fit,
            })
            .map_err(named)?;
            Ok(Material::DruckerPrager(dp))
        }
    }
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
