//! A material of a layered ground: Drucker-Prager, or elastic (a structure, a stiff layer
//! that never yields). Each point's flow rule may sit under a pore pressure, which moves
//! the yield set along the hydrostatic axis: yield acts on the effective stress
//! `σ' = σ + p_w I` (tension positive), so the total stress lies in `K − p_w I`.
use nalgebra::{SMatrix, SVector};
use talus_cone::SecondOrderCone;

use crate::mandel::{self, hydrostatic_axis};
use crate::{DruckerPrager, FlowRule, MaterialError, Relaxation, YieldSet};

/// Isotropic linear elasticity: `E > 0` (Pa), `ν ∈ (−1, 0.5)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Elastic {
    young_modulus: f64,
    poisson_ratio: f64,
}

impl Elastic {
    pub fn try_new(young_modulus: f64, poisson_ratio: f64) -> Result<Self, MaterialError> {
        if !(young_modulus.is_finite() && young_modulus > 0.0) {
            return Err(MaterialError::InvalidParameter {
                name: "young_modulus",
                value: young_modulus,
                expected: "a finite E > 0 (Pa)",
            });
        }
        if !(poisson_ratio.is_finite() && poisson_ratio > -1.0 && poisson_ratio < 0.5) {
            return Err(MaterialError::InvalidParameter {
                name: "poisson_ratio",
                value: poisson_ratio,
                expected: "ν in (-1, 0.5)",
            });
        }
        Ok(Self {
            young_modulus,
            poisson_ratio,
        })
    }

    pub fn young_modulus(&self) -> f64 {
        self.young_modulus
    }

    pub fn poisson_ratio(&self) -> f64 {
        self.poisson_ratio
    }
}

/// What a point is made of.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Material {
    DruckerPrager(DruckerPrager),
    Elastic(Elastic),
}

impl Material {
    /// Elastic compliance `S` (1/Pa), Mandel notation.
    pub fn compliance<const D: usize>(&self) -> SMatrix<f64, D, D> {
        match self {
            Material::DruckerPrager(m) => m.compliance(),
            Material::Elastic(m) => mandel::isotropic_compliance(m.young_modulus, m.poisson_ratio),
        }
    }

    pub fn young_modulus(&self) -> f64 {
        match self {
            Material::DruckerPrager(m) => m.parameters().young_modulus,
            Material::Elastic(m) => m.young_modulus,
        }
    }

    pub fn poisson_ratio(&self) -> f64 {
        match self {
            Material::DruckerPrager(m) => m.parameters().poisson_ratio,
            Material::Elastic(m) => m.poisson_ratio,
        }
    }

    /// The Drucker-Prager material, if this is one.
    pub fn drucker_prager(&self) -> Option<&DruckerPrager> {
        match self {
            Material::DruckerPrager(m) => Some(m),
            Material::Elastic(_) => None,
        }
    }

    /// The Duvaut–Lions relaxation time `τ` (s) of a relaxed Drucker-Prager material.
    pub fn relaxation_time(&self) -> Option<f64> {
        self.drucker_prager()
            .and_then(DruckerPrager::relaxation_time)
    }

    /// The Duvaut–Lions relaxation `N = (τ/h)(V S₀)⁻¹` ([`Relaxation::duvaut_lions`]) of a
    /// point of volume `V` (its compliance block is `V S₀`) in a step of length `h` (s);
    /// `None` without `τ`.
    pub fn relaxation(&self, h: f64, volume: f64) -> Result<Option<Relaxation>, MaterialError> {
        self.relaxation_time()
            .map(|tau| {
                Relaxation::duvaut_lions(tau, h, volume, self.young_modulus(), self.poisson_ratio())
            })
            .transpose()
    }

    /// [`Material::flow_rule`] with the point's [`Material::relaxation`]; exactly
    /// [`Material::flow_rule`] without `τ`.
    pub fn point_flow_rule<const D: usize>(
        &self,
        pore_pressure: f64,
        h: f64,
        volume: f64,
    ) -> Result<FlowRule<D>, MaterialError> {
        let rule = self.flow_rule::<D>(pore_pressure);
        Ok(rule.with_relaxation(self.relaxation(h, volume)?))
    }

    /// The flow rule of a point under the pore pressure `p_w` (Pa, compression positive):
    /// the yield set translated by `−p_w I` (its apex moves by `−√3 p_w e`, `e` the unit
    /// hydrostatic axis); without pore pressure, [`DruckerPrager::flow_rule`] exactly. A
    /// von Mises cylinder and an elastic point do not move. Rate-independent: a relaxed
    /// material's point rule is [`Material::point_flow_rule`].
    pub fn flow_rule<const D: usize>(&self, pore_pressure: f64) -> FlowRule<D> {
        match self {
            Material::Elastic(_) => FlowRule::elastic(),
            Material::DruckerPrager(m) => {
                let rule = m.flow_rule::<D>();
                if pore_pressure == 0.0 {
                    return rule;
                }
                match rule.yield_set() {
                    YieldSet::Cone(cone) => {
                        let shift: SVector<f64, D> =
                            hydrostatic_axis::<D>() * (3f64.sqrt() * pore_pressure);
                        let moved =
                            SecondOrderCone::try_new(*cone.axis(), cone.apex() - shift, cone.eta());
                        match moved {
                            Ok(c) => FlowRule::cone(c, rule.kappa()),
                            // A finite shift of a valid cone is a valid cone.
                            Err(_) => rule,
                        }
                    }
                    _ => rule,
                }
            }
        }
    }
}

impl From<DruckerPrager> for Material {
    fn from(m: DruckerPrager) -> Self {
        Material::DruckerPrager(m)
    }
}

impl From<Elastic> for Material {
    fn from(m: Elastic) -> Self {
        Material::Elastic(m)
    }
}
