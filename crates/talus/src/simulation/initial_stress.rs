use crate::scene::{InitialStressSpec, Scene, SceneError};

use super::Model;

/// The K₀ stress at every Gauss point (Mandel, flat), checked against the yield cone.
pub fn k0_stress(
    scene: &Scene,
    model: &Model,
    spec: &InitialStressSpec,
) -> Result<Vec<f64>, SceneError> {
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
    let gamma = scene.spec.material.density * scene.spec.gravity.map(|g| -g[1]).unwrap_or(0.0);
    let mut sigma = vec![0.0; 4 * model.n_points()];
    for (p, x) in model.assembly.gauss_points.iter().enumerate() {
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
        let f = model.material.yield_function(&s);
        if f > 1e-9 * s.norm().max(model.material.parameters().cohesion) {
            return Err(scene.error(
                "initial_stress.k0",
                format!(
                    "K₀ = {} puts the point at depth {depth:.3} m outside the yield cone (f = {f:.3e} Pa); Jaky's 1 − sin φ = {:.3}",
                    spec.k0,
                    1.0 - model.material.parameters().friction_angle.to_radians().sin()
                ),
            ));
        }
        sigma[4 * p..4 * p + 4].copy_from_slice(s.as_slice());
    }
    Ok(sigma)
}
