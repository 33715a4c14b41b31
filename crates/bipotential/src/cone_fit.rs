/// How the Drucker-Prager cone is matched to Mohr-Coulomb. Every fit keeps the apex at
/// `p = c / tan φ` and sets the deviatoric normalisation `k_d` of eq. 7,
/// `f(σ) = ‖dev σ‖ / k_d + p tan φ − c`:
/// - `PlaneStrain`: `k_d = 3√2 / √(9 + 12 tan²φ)`, exact Mohr-Coulomb collapse loads in
///   associative plane strain (1.2189 at φ = 27°);
/// - `OuterCone` (triaxial compression corners): `k_d = 2√6 cos φ / (3 − sin φ)`;
/// - `InnerCone` (triaxial extension corners): `k_d = 2√6 cos φ / (3 + sin φ)`;
/// - `Explicit { k_d }`: the value given (for example √2, the paper's unspecified choice).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(rename_all = "snake_case", deny_unknown_fields)
)]
pub enum ConeFit {
    PlaneStrain,
    OuterCone,
    InnerCone,
    Explicit { k_d: f64 },
}

impl ConeFit {
    /// `k_d` for the friction angle `phi` in radians.
    pub fn k_d(&self, phi: f64) -> f64 {
        let six = 6f64.sqrt();
        match *self {
            ConeFit::PlaneStrain => {
                let t = phi.tan();
                3.0 * 2f64.sqrt() / (9.0 + 12.0 * t * t).sqrt()
            }
            ConeFit::OuterCone => 2.0 * six * phi.cos() / (3.0 - phi.sin()),
            ConeFit::InnerCone => 2.0 * six * phi.cos() / (3.0 + phi.sin()),
            ConeFit::Explicit { k_d } => k_d,
        }
    }

    /// A short name for outputs and reports.
    pub fn name(&self) -> &'static str {
        match self {
            ConeFit::PlaneStrain => "plane_strain",
            ConeFit::OuterCone => "outer_cone",
            ConeFit::InnerCone => "inner_cone",
            ConeFit::Explicit { .. } => "explicit",
        }
    }
}
