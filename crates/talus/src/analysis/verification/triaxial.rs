//! Drained triaxial compression, axisymmetric (`scenes/triaxial.toml`): the peak deviator
//! `q = σ_1 − σ_3` and the dilatancy ratio `dε_v/dε_1` at the plateau against the closed
//! forms of the Drucker-Prager cone (`docs/axisymmetry.md`, 'Triaxial compression').
use super::{CaseResult, Check};
use crate::model::fem::FromScene;
use crate::model::fem::Model;
use crate::model::fem::ReactionForce;
use crate::run::fem::solver_settings;
use crate::scene::Scene;
use talus_engine::{StepSettings, Stepper};

const SCENE: &str = include_str!("../../../../../scenes/triaxial.toml");

/// Sample radius and height of the scene (m).
const RADIUS: f64 = 0.025;
const HEIGHT: f64 = 0.1;

/// Peak deviator `q = σ_1 − σ_3` (Pa, compression positive) of triaxial compression under
/// cell pressure `p_c` for `f = ‖dev σ‖/k_d + p tan φ − c` (`docs/conventions.md`): with
/// `σ_2 = σ_3 = −p_c`, `σ_1 = −(p_c + q)`, `‖dev σ‖ = √(2/3) q` and `p = −(p_c + q/3)`,
/// `f = 0` gives `q = (c + p_c tan φ) / (√(2/3)/k_d − tan φ / 3)`.
pub fn triaxial_peak_deviator(k_d: f64, phi_deg: f64, c: f64, p_c: f64) -> f64 {
    let t = phi_deg.to_radians().tan();
    (c + p_c * t) / ((2.0f64 / 3.0).sqrt() / k_d - t / 3.0)
}

/// `dε_v/dε_1` of plastic flow in triaxial compression (both tension positive, so it is
/// negative when the sample dilates): the potential `g = ‖dev σ‖/k_d + p tan θ` gives
/// `ε̇ᵖ = λ (n̂/k_d + tan θ/3 · 1)`, `n̂ = dev σ/‖dev σ‖` with axial component `−√(2/3)`, so
/// `ε̇ᵖ_v = λ tan θ` and `ε̇ᵖ_1 = λ (tan θ/3 − √(2/3)/k_d)`.
pub fn triaxial_dilatancy_ratio(k_d: f64, theta_deg: f64) -> f64 {
    let t = theta_deg.to_radians().tan();
    t / (t / 3.0 - (2.0f64 / 3.0).sqrt() / k_d)
}

/// `scenes/triaxial.toml` with the cone fit `fit` (TOML value), friction `phi` and
/// dilatancy `theta` (degrees), and its analysis geometry replaced by `geometry`.
pub fn triaxial_scene(fit: &str, phi: f64, theta: f64, geometry: &str) -> Scene {
    let mut text = SCENE.to_string();
    for (from, to) in [
        ("friction_angle = 30.0", format!("friction_angle = {phi:?}")),
        (
            "dilatancy_angle = 20.0",
            format!("dilatancy_angle = {theta:?}"),
        ),
        ("cone_fit = \"outer_cone\"", format!("cone_fit = \"{fit}\"")),
        (
            "geometry = \"axisymmetric\"",
            format!("geometry = \"{geometry}\""),
        ),
    ] {
        assert!(text.contains(from), "scenes/triaxial.toml lost `{from}`");
        text = text.replacen(from, &to, 1);
    }
    Scene::parse(&text, None).expect("scenes/triaxial.toml with edited material parses")
}

/// What a triaxial run measured at its end.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriaxialRun {
    /// Deviator from the platen's reaction, `F / (π R²)` (Pa).
    pub q: f64,
    /// `Δε_v / Δε_1` over the last third of the run (the plateau), from the displacement
    /// of the top outer corner: `ε_1 = u_y/H`, `ε_r = ε_θ = u_r/R`, `ε_v = ε_1 + 2 ε_r`.
    pub dilatancy_ratio: f64,
    pub k_d: f64,
}

/// Runs `scene` (a variant of `scenes/triaxial.toml`) to its end; `None` if it fails.
pub fn run_triaxial(scene: &Scene) -> Option<TriaxialRun> {
    let model = Model::from_scene(scene).ok()?;
    let corner = model
        .mesh
        .nodes
        .iter()
        .position(|p| (p[0] - RADIUS).abs() < 1e-12 && (p[1] - HEIGHT).abs() < 1e-12)?;
    let mut state = model.initial_state(scene).ok()?;
    let mut stepper = Stepper::new(
        &model,
        StepSettings::with_solver(solver_settings(scene), scene.spec.solver.max_step_halvings),
    );
    let steps = scene.spec.time.steps;
    let mut from = None;
    let mut reaction = f64::NAN;
    for step in 1..=steps {
        if step == steps - steps / 3 {
            from = Some(state.displacement[corner]);
        }
        reaction = stepper
            .advance(&mut state, scene.spec.time.step)
            .ok()?
            .reaction_force();
    }
    let (u0, u1) = (from?, state.displacement[corner]);
    let d1 = (u1[1] - u0[1]) / HEIGHT;
    let dr = (u1[0] - u0[0]) / RADIUS;
    Some(TriaxialRun {
        q: reaction / (std::f64::consts::PI * RADIUS * RADIUS),
        dilatancy_ratio: (d1 + 2.0 * dr) / d1,
        k_d: model.materials[0].drucker_prager()?.k_d(),
    })
}

const SOURCE: &str = "closed form for the Drucker-Prager cone, docs/axisymmetry.md \
                      (Triaxial compression); outer cone = Mohr-Coulomb 2(c cos φ + p sin φ)/(1 − sin φ)";

/// Two cone fits × θ = 0 and θ = φ (φ = 30°, c = 5 kPa, p_c = 100 kPa): `q` to 1e-6
/// relative, `dε_v/dε_1` to 1e-6 (relative; absolute where it is 0).
pub fn triaxial_compression() -> Vec<CaseResult> {
    let (phi, c, p_c) = (30.0, 5.0e3, 1.0e5);
    let mut out = Vec::new();
    for fit in ["outer_cone", "plane_strain"] {
        for theta in [0.0, phi] {
            let run = run_triaxial(&triaxial_scene(fit, phi, theta, "axisymmetric"));
            let case = format!("triaxial_{fit}_theta{theta:.0}");
            let k_d = run.map_or(f64::NAN, |r| r.k_d);
            out.push(CaseResult {
                case: case.clone(),
                quantity: "peak q = σ1 − σ3 (Pa) from the platen reaction".into(),
                reference: triaxial_peak_deviator(k_d, phi, c, p_c),
                computed: run.map_or(f64::NAN, |r| r.q),
                tolerance: 1e-6,
                check: Check::Relative,
                seconds: 0.0,
                source: SOURCE.into(),
            });
            let reference = triaxial_dilatancy_ratio(k_d, theta);
            out.push(CaseResult {
                case,
                quantity: "dε_v/dε_1 at the plateau".into(),
                reference,
                computed: run.map_or(f64::NAN, |r| r.dilatancy_ratio),
                tolerance: 1e-6,
                check: if reference == 0.0 {
                    Check::Absolute
                } else {
                    Check::Relative
                },
                seconds: 0.0,
                source: SOURCE.into(),
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use talus_bipotential::ConeFit;

    /// The outer cone passes through Mohr-Coulomb's compression corners, so its triaxial
    /// peak is Mohr-Coulomb's: `(σ_1 − σ_3)/2 = c cos φ + (σ_1 + σ_3)/2 · sin φ` (compression
    /// positive) with `σ_3 = p_c`, `σ_1 = p_c + q` gives `q = 2 (c cos φ + p_c sin φ) /
    /// (1 − sin φ)`: an independent check of the closed form.
    #[test]
    fn outer_cone_peak_is_mohr_coulombs() {
        for phi in [10.0f64, 27.0, 30.0, 40.0] {
            let (c, p) = (5.0e3, 1.0e5);
            let k_d = ConeFit::OuterCone.k_d(phi.to_radians());
            let (s, co) = (phi.to_radians().sin(), phi.to_radians().cos());
            let mc = 2.0 * (c * co + p * s) / (1.0 - s);
            let q = triaxial_peak_deviator(k_d, phi, c, p);
            assert!((q - mc).abs() < 1e-10 * mc, "φ = {phi}: {q} vs {mc}");
        }
    }

    /// `dε_v/‖dev ε‖` of the same flow is `k_d tan θ` (`docs/conventions.md`, 'Flow rule'):
    /// with `ε_1 = a`, `ε_2 = ε_3 = b`, `‖dev ε‖ = √(2/3) |a − b|`.
    #[test]
    fn dilatancy_ratio_agrees_with_the_flow_rule() {
        for (k_d, theta) in [(1.2, 10.0f64), (1.7, 30.0), (0.9, 45.0)] {
            let r = triaxial_dilatancy_ratio(k_d, theta);
            // ε_v = a + 2b = r a  ⇒  b = (r − 1) a / 2.
            let (a, b) = (-1.0, -(r - 1.0) / 2.0);
            let dev = (2.0f64 / 3.0).sqrt() * (a - b).abs();
            let expected = k_d * theta.to_radians().tan();
            assert!(((a + 2.0 * b) / dev - expected).abs() < 1e-12);
        }
    }
}
