use talus_bipotential::DruckerPrager;

use crate::scene::{InitialStressSpec, Locate, Scene, SceneError};

use super::Model;

/// The K₀ stress at every Gauss point (Mandel, flat), checked against the yield cone.
pub fn k0_stress(
    scene: &Scene,
    model: &Model,
    spec: &InitialStressSpec,
) -> Result<Vec<f64>, SceneError> {
    // In equilibrium with the gravity of the start, t = 0 (`gravity_ramp` scales it).
    let ramp = crate::scene::check::ramp(scene, "gravity_ramp", &scene.spec.gravity_ramp)?;
    let g = scene.spec.gravity.map(|g| -g[1]).unwrap_or(0.0);
    let g = ramp.map_or(g, |r| g * r.at(0.0));
    let gamma = scene.spec.material.density * g;
    let sigma = k0_stress_at(
        scene,
        &model.material,
        gamma,
        spec,
        &model.assembly.gauss_points,
    )?;
    Ok(sigma.into_iter().flatten().collect())
}

/// The K₀ stress (Mandel, Pa) at each of `points` (m) under a ground of unit weight
/// `gamma = ρ g` (N/m³): `σ_yy = −(surcharge + γ (surface − y))`, `σ_xx = σ_zz = K₀ σ_yy`.
/// Errors name `initial_stress.*`: a point above the surface, a state outside the cone.
pub fn k0_stress_at(
    scene: &impl Locate,
    material: &DruckerPrager,
    gamma: f64,
    spec: &InitialStressSpec,
    points: &[[f64; 2]],
) -> Result<Vec<[f64; 4]>, SceneError> {
    if !(spec.k0.is_finite() && spec.k0 > 0.0) {
        return Err(scene.error(
            "initial_stress.k0",
            format!("{} must be finite and > 0", spec.k0),
        ));
    }
    if !spec.surface.is_finite() {
        return Err(scene.error("initial_stress.surface", "must be finite"));
    }
    if !(spec.surcharge.is_finite() && spec.surcharge >= 0.0) {
        return Err(scene.error(
            "initial_stress.surcharge",
            format!("{} Pa must be finite and >= 0", spec.surcharge),
        ));
    }
    let mut sigma = Vec::with_capacity(points.len());
    for x in points {
        let depth = spec.surface - x[1];
        if depth < -1e-9 * spec.surface.abs().max(1.0) {
            return Err(scene.error(
                "initial_stress.surface",
                format!(
                    "point ({:.4}, {:.4}) lies above the surface y = {}",
                    x[0], x[1], spec.surface
                ),
            ));
        }
        let vertical = -(spec.surcharge + gamma * depth.max(0.0));
        let s =
            nalgebra::SVector::<f64, 4>::new(spec.k0 * vertical, vertical, spec.k0 * vertical, 0.0);
        let f = material.yield_function(&s);
        if f > 1e-9 * s.norm().max(material.parameters().cohesion) {
            let (lo, hi) = k0_bounds(material);
            return Err(scene.error(
                "initial_stress.k0",
                format!(
                    "K₀ = {} puts the point at depth {depth:.3} m outside the yield cone (f = {f:.3e} Pa); \
                     without cohesion the cone admits {lo:.4} ≤ K₀ ≤ {hi:.4} (Jaky's 1 − sin φ = {:.4})",
                    spec.k0,
                    1.0 - material.parameters().friction_angle.to_radians().sin()
                ),
            ));
        }
        sigma.push([s[0], s[1], s[2], s[3]]);
    }
    Ok(sigma)
}

/// The K₀ for which `(−K₀ s, −s, −K₀ s)` lies in the cone for every depth when c = 0:
/// `|1 − K₀| √(2/3) / k_d ≤ tan φ (1 + 2K₀) / 3` (cohesion only widens the interval).
/// Jaky's `1 − sin φ` falls below it for φ ≳ 36° with the plane-strain fit, because the fit
/// matches Mohr-Coulomb in plastic flow, not in this stress state.
pub fn k0_bounds_without_cohesion(model: &Model) -> (f64, f64) {
    k0_bounds(&model.material)
}

/// [`k0_bounds_without_cohesion`] of a material.
pub fn k0_bounds(material: &DruckerPrager) -> (f64, f64) {
    let a = (2.0f64 / 3.0).sqrt() / material.k_d();
    let t = material.parameters().friction_angle.to_radians().tan() / 3.0;
    // K₀ ≤ 1: a (1 − K₀) ≤ t (1 + 2K₀); K₀ ≥ 1: a (K₀ − 1) ≤ t (1 + 2K₀).
    let lo = (a - t) / (a + 2.0 * t);
    let hi = if a > 2.0 * t {
        (a + t) / (a - 2.0 * t)
    } else {
        f64::INFINITY
    };
    (lo.max(0.0), hi)
}
