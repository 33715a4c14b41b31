use nalgebra::{SMatrix, SVector};
use talus_cone::{SecondOrderCone, VonMisesCylinder};

use crate::mandel::{self, deviator, hydrostatic_axis, trace};
use crate::{ConeFit, FlowRule, MaterialError};

/// What a user gives: SI units (Pa) and angles in degrees.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct DruckerPragerParameters {
    /// E > 0, Pa.
    pub young_modulus: f64,
    /// ν ∈ (−1, 0.5).
    pub poisson_ratio: f64,
    /// φ ∈ [0°, 90°); φ = 0 is von Mises.
    pub friction_angle: f64,
    /// c ≥ 0, Pa.
    pub cohesion: f64,
    /// θ ∈ [0°, φ]; θ = φ is associative, θ = 0 plastically incompressible.
    pub dilatancy_angle: f64,
    pub cone_fit: ConeFit,
}

/// A validated Drucker-Prager material (eqs. 7–10), tension positive, `p = tr σ / 3`.
///
/// Yield function `f(σ) = ‖dev σ‖/k_d + p tan φ − c`, plastic potential
/// `g(σ) = ‖dev σ‖/k_d + p tan θ`, so `tr ε̇ᵖ / ‖dev ε̇ᵖ‖ = k_d tan θ` on plastic flow.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DruckerPrager {
    params: DruckerPragerParameters,
    /// Radians.
    phi: f64,
    theta: f64,
    k_d: f64,
    /// Duvaut–Lions `τ` (s); `None`: rate-independent.
    relaxation_time: Option<f64>,
}

fn invalid(name: &'static str, value: f64, expected: &'static str) -> MaterialError {
    MaterialError::InvalidParameter {
        name,
        value,
        expected,
    }
}

impl DruckerPrager {
    /// Validates every parameter and names the first one out of its domain.
    pub fn try_new(params: DruckerPragerParameters) -> Result<Self, MaterialError> {
        let p = &params;
        let finite = [
            ("young_modulus", p.young_modulus),
            ("poisson_ratio", p.poisson_ratio),
            ("friction_angle", p.friction_angle),
            ("cohesion", p.cohesion),
            ("dilatancy_angle", p.dilatancy_angle),
        ];
        for (name, value) in finite {
            if !value.is_finite() {
                return Err(invalid(name, value, "a finite number"));
            }
        }
        if p.young_modulus <= 0.0 {
            return Err(invalid(
                "young_modulus",
                p.young_modulus,
                "a value > 0 (Pa)",
            ));
        }
        if !(p.poisson_ratio > -1.0 && p.poisson_ratio < 0.5) {
            return Err(invalid(
                "poisson_ratio",
                p.poisson_ratio,
                "a value in (-1, 0.5)",
            ));
        }
        if !(0.0..90.0).contains(&p.friction_angle) {
            return Err(invalid(
                "friction_angle",
                p.friction_angle,
                "degrees in [0, 90)",
            ));
        }
        if !(p.dilatancy_angle >= 0.0 && p.dilatancy_angle <= p.friction_angle) {
            return Err(invalid(
                "dilatancy_angle",
                p.dilatancy_angle,
                "degrees in [0, friction_angle]",
            ));
        }
        if p.cohesion < 0.0 {
            return Err(invalid("cohesion", p.cohesion, "a value >= 0 (Pa)"));
        }
        let phi = p.friction_angle.to_radians();
        // The apex of the cone lies at c / tan φ on the axis (`flow_rule`): a tiny φ beside a
        // cohesion overflows it (φ = 1e-300° with c = 1e8 Pa).
        // A positive angle whose radians underflow to 0 (4.9e-324°) would be neither a cone
        // nor the von Mises cylinder; √3 c / tan φ is the apex `flow_rule` builds.
        let apex = 3f64.sqrt() * p.cohesion / phi.tan();
        if p.friction_angle > 0.0 && !(phi > 0.0 && apex.is_finite()) {
            return Err(invalid(
                "friction_angle",
                p.friction_angle,
                "0 (von Mises) or degrees in (0, 90) with cohesion / tan(friction_angle) \
                 finite (the apex of the cone)",
            ));
        }
        let k_d = p.cone_fit.k_d(phi);
        // `flow_rule` builds the cone of slope η = k_d tan φ / √3, or the cylinder of radius
        // k_d c at φ = 0: a k_d of 4.9e-324 passes "> 0" yet flattens the cone, and one of
        // 1e300 overflows either.
        let set_is_finite = if phi == 0.0 {
            (k_d * p.cohesion).is_finite()
        } else {
            let eta = k_d * phi.tan() / 3f64.sqrt();
            eta.is_finite() && eta > 0.0
        };
        if !(k_d.is_finite() && k_d > 0.0 && set_is_finite) {
            return Err(invalid(
                "cone_fit.k_d",
                k_d,
                "a finite value > 0 whose cone slope k_d tan(friction_angle) / sqrt(3), or \
                 cylinder radius k_d cohesion, is finite and > 0",
            ));
        }
        if phi == 0.0 && p.cohesion == 0.0 {
            // A cylinder of radius 0 carries no deviatoric stress: a fluid, not a solid.
            return Err(invalid(
                "cohesion",
                p.cohesion,
                "a value > 0 when friction_angle = 0 (von Mises)",
            ));
        }
        Ok(Self {
            params,
            phi,
            theta: p.dilatancy_angle.to_radians(),
            k_d,
            relaxation_time: None,
        })
    }

    /// This material with Duvaut–Lions relaxation time `τ` (s, finite and > 0;
    /// `docs/derivations.md`, 'Duvaut–Lions relaxation'); `None`: rate-independent.
    pub fn with_relaxation_time(self, tau: Option<f64>) -> Result<Self, MaterialError> {
        Ok(Self {
            relaxation_time: tau.map(crate::check_relaxation_time).transpose()?,
            ..self
        })
    }

    /// The Duvaut–Lions `τ` (s), if relaxed.
    pub fn relaxation_time(&self) -> Option<f64> {
        self.relaxation_time
    }

    pub fn parameters(&self) -> &DruckerPragerParameters {
        &self.params
    }

    /// The deviatoric normalisation of eq. 7 given by the cone fit.
    pub fn k_d(&self) -> f64 {
        self.k_d
    }

    /// `α = tan φ − tan θ` (eq. 20): 0 when associative.
    pub fn alpha(&self) -> f64 {
        self.phi.tan() - self.theta.tan()
    }

    pub fn is_von_mises(&self) -> bool {
        self.phi == 0.0
    }

    /// Shear modulus `G = E / (2(1+ν))`, Pa.
    pub fn shear_modulus(&self) -> f64 {
        self.params.young_modulus / (2.0 * (1.0 + self.params.poisson_ratio))
    }

    /// Elastic compliance `S` (1/Pa), Mandel notation.
    pub fn compliance<const D: usize>(&self) -> SMatrix<f64, D, D> {
        mandel::isotropic_compliance(self.params.young_modulus, self.params.poisson_ratio)
    }

    /// `f(σ) = ‖dev σ‖/k_d + p tan φ − c` (Pa); the elastic domain is `f ≤ 0`.
    pub fn yield_function<const D: usize>(&self, sigma: &SVector<f64, D>) -> f64 {
        deviator(sigma).norm() / self.k_d + trace(sigma) / 3.0 * self.phi.tan()
            - self.params.cohesion
    }

    /// `g(σ) = ‖dev σ‖/k_d + p tan θ` (Pa), the plastic potential: `ε̇ᵖ = λ ∂g/∂σ`.
    pub fn plastic_potential<const D: usize>(&self, sigma: &SVector<f64, D>) -> f64 {
        deviator(sigma).norm() / self.k_d + trace(sigma) / 3.0 * self.theta.tan()
    }

    /// The bipotential of eq. 10, `b(ε̇ᵖ, σ)` (Pa/s), or `None` where it is `+∞`.
    ///
    /// Finite when `σ ∈ K` and `ε̇ᵖ` is admissible, `tr ε̇ᵖ ≥ k_d tan θ ‖dev ε̇ᵖ‖` (eq. 9 prints
    /// `≤`; with tension positive plastic flow dilates, and `≥` is what makes
    /// `b(ε̇ᵖ, σ) ≥ σ : ε̇ᵖ` hold, with equality exactly on the flow rule). At φ = 0 (von
    /// Mises) the admissible rates are isochoric and `b = k_d c ‖dev ε̇ᵖ‖`. Membership is
    /// tested to `1e-12` of the data's scale.
    pub fn bipotential<const D: usize>(
        &self,
        eps_p: &SVector<f64, D>,
        sigma: &SVector<f64, D>,
    ) -> Option<f64> {
        const TOL: f64 = 1e-12;
        let c = self.params.cohesion;
        let tr = trace(eps_p);
        let dev_norm = deviator(eps_p).norm();
        let rate_scale = eps_p.norm();
        let stress_scale = sigma.norm().max(c);
        if self.yield_function(sigma) > TOL * stress_scale {
            return None;
        }
        if self.is_von_mises() {
            return (tr.abs() <= TOL * rate_scale).then_some(self.k_d * c * dev_norm);
        }
        let (tan_phi, tan_theta) = (self.phi.tan(), self.theta.tan());
        if tr < self.k_d * tan_theta * dev_norm - TOL * rate_scale {
            return None;
        }
        let p = trace(sigma) / 3.0;
        Some(tr * c / tan_phi + self.k_d * (p - c / tan_phi) * (tan_theta - tan_phi) * dev_norm)
    }

    /// The flow rule in Mandel coordinates: the cone with `n = −e`, apex `√3 (c/tan φ) e`,
    /// `η = k_d tan φ / √3` and shift `κ = k_d α / √3` (`docs/conventions.md`, 'Drucker-Prager
    /// cone' and 'Flow rule'); at φ = 0 the cylinder `‖dev σ‖ ≤ k_d c`.
    pub fn flow_rule<const D: usize>(&self) -> FlowRule<D> {
        let e = hydrostatic_axis::<D>();
        let sqrt3 = 3f64.sqrt();
        let c = self.params.cohesion;
        // The constructors cannot fail on validated parameters; the fallbacks keep this total.
        if self.is_von_mises() {
            let cyl = VonMisesCylinder::try_new(e, self.k_d * c);
            return FlowRule::cylinder(cyl.unwrap_or_else(|_| unreachable_set()));
        }
        let tan_phi = self.phi.tan();
        let apex = e * (sqrt3 * c / tan_phi);
        let cone = SecondOrderCone::try_new(-e, apex, self.k_d * tan_phi / sqrt3);
        FlowRule::cone(
            cone.unwrap_or_else(|_| unreachable_set()),
            self.k_d * self.alpha() / sqrt3,
        )
    }
}

#[cold]
fn unreachable_set<T>() -> T {
    unreachable!("validated Drucker-Prager parameters always give a valid yield set")
}
