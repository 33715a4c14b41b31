//! A cylindrical cavity expanded by a prescribed wall displacement
//! (`scenes/cavity_expansion.toml`): once the whole wall has yielded, the cavity pressure is
//! the Mohr-Coulomb thick cylinder's collapse pressure (`docs/axisymmetry.md`, 'Cavity
//! expansion'), which the cone `k_d = √2 cos φ`, ψ = 0, reproduces in plane strain.
use super::{run_to_end, CaseResult, Check};
use crate::scene::Scene;

pub const CAVITY_EXPANSION: &str = include_str!("../../../../../scenes/cavity_expansion.toml");

/// The shipped scene's dimensions and soil (the case checks that its text still says so).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cavity {
    /// Cavity and outer radius, strip height (m).
    pub a: f64,
    pub b: f64,
    pub height: f64,
    /// Initial and outer pressure, cohesion (Pa); friction angle (degrees).
    pub p0: f64,
    pub cohesion: f64,
    pub phi: f64,
}

/// `scenes/cavity_expansion.toml`'s.
pub const CAVITY: Cavity = Cavity {
    a: 1.0,
    b: 2.0,
    height: 0.05,
    p0: 1.0e5,
    cohesion: 2.0e4,
    phi: 30.0,
};

impl Cavity {
    /// The wall's push (N on the whole circumference) at cavity pressure `p` (Pa).
    pub fn wall_push(&self, p: f64) -> f64 {
        2.0 * std::f64::consts::PI * self.a * self.height * p
    }

    /// The collapse pressure (Pa) at friction angle `phi` (degrees).
    pub fn collapse_pressure(&self, phi: f64) -> f64 {
        thick_cylinder_collapse(self.a, self.b, self.p0, self.cohesion, phi)
    }
}

/// The collapse pressure (Pa, compression positive) of a Mohr-Coulomb thick cylinder
/// `a ≤ r ≤ b` in plane strain, outer pressure `p0`, every point yielding with `σ_r` the
/// major and `σ_θ` the minor principal stress: equilibrium `dσ_r/dr = −(σ_r − σ_θ)/r` and
/// `σ_r + H = N (σ_θ + H)` (`H = c cot φ`, `N = (1 + sin φ)/(1 − sin φ)`) give
/// `(p_a + H) = (p0 + H)(b/a)^((N − 1)/N)`, `(N − 1)/N = 2 sin φ/(1 + sin φ)`.
/// At φ = 0 it is Hill's (1950) Tresca cylinder, `p0 + 2c ln(b/a)`.
pub fn thick_cylinder_collapse(a: f64, b: f64, p0: f64, c: f64, phi_deg: f64) -> f64 {
    if phi_deg == 0.0 {
        return p0 + 2.0 * c * (b / a).ln();
    }
    let s = phi_deg.to_radians().sin();
    let h = c / phi_deg.to_radians().tan();
    (p0 + h) * (b / a).powf(2.0 * s / (1.0 + s)) - h
}

/// The cavity pressure (Pa) at the end of the scene's run, from the wall's reaction on the
/// whole circumference; `None` if the run fails.
pub fn cavity_pressure(scene: &Scene) -> Option<f64> {
    let (_, _, push) = run_to_end(scene)?;
    Some(push / CAVITY.wall_push(1.0))
}

/// The shipped scene's cavity pressure at `u(a)` = 24 mm against the collapse pressure, to
/// 1e-5 (measured 1.1e-6: `σ_zz` reaches plane plastic flow's `s_zz = 0`, where the cone
/// is Mohr-Coulomb, only asymptotically, from above).
pub fn cavity_expansion_case() -> Vec<CaseResult> {
    for line in [
        "x = [1.0, 2.0]",
        "y = [0.0, 0.05]",
        "cohesion = 2.0e4",
        "friction_angle = 30.0",
        "dilatancy_angle = 0.0",
        "stress = [-1.0e5, -1.0e5, 0.0, -1.0e5]",
        "value = 1.0e5",
        "velocity = [1.0e-3, 0.0]",
        "step = 0.2",
        "steps = 120",
    ] {
        assert!(
            CAVITY_EXPANSION.contains(line),
            "scenes/cavity_expansion.toml lost `{line}`"
        );
    }
    let scene = Scene::parse(CAVITY_EXPANSION, None).expect("scenes/cavity_expansion.toml parses");
    vec![CaseResult {
        case: "cavity_expansion".into(),
        quantity: "cavity pressure p_a (Pa) at u(a) = 24 mm, ψ = 0".into(),
        reference: CAVITY.collapse_pressure(CAVITY.phi),
        computed: cavity_pressure(&scene).unwrap_or(f64::NAN),
        tolerance: 1e-5,
        check: Check::Relative,
        seconds: 0.0,
        source: "Mohr-Coulomb thick cylinder at collapse (Yu 2000, Cavity Expansion Methods \
                 in Geomechanics, ch. 3); docs/axisymmetry.md (Cavity expansion)"
            .into(),
    }]
}
