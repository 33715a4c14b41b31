//! The material of a strength-reduction trial: the Mohr-Coulomb strength `(c, φ, ψ)` divided
//! by `F` (`docs/stability.md`, 'Strength reduction' and 'Dilatancy'), then matched by a
//! Drucker-Prager cone.
pub use talus_bipotential::davis_beta;
use talus_bipotential::{
    davis_equivalent, ConeFit, DruckerPrager, DruckerPragerParameters, MaterialError,
};

use crate::scene::DilatancyRule;

/// Mohr-Coulomb strength: cohesion (Pa), friction and dilatancy angles (radians).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Strength {
    pub cohesion: f64,
    pub friction: f64,
    pub dilatancy: f64,
}

impl Strength {
    /// The strength of a scene's Drucker-Prager parameters (angles in degrees there).
    pub fn of(p: &DruckerPragerParameters) -> Self {
        Self {
            cohesion: p.cohesion,
            friction: p.friction_angle.to_radians(),
            dilatancy: p.dilatancy_angle.to_radians(),
        }
    }

    /// `c/F`, `tan φ_F = tan φ / F` and the dilatancy by `rule`:
    /// - `Scaled`: `tan ψ_F = tan ψ / F`;
    /// - `Fixed`: `ψ_F = min(ψ, φ_F)` (a dilatancy above the friction angle is refused by
    ///   the cone, eq. 9);
    /// - `Davis`: Davis's (1968) associated equivalent of the reduced non-associative
    ///   strength, with `β` from the reduced angles (Tschuchnigg et al. 2015):
    ///   `β = cos φ_F cos ψ_F / (1 − sin φ_F sin ψ_F)` with `tan ψ_F = tan ψ / F`, then
    ///   `c* = β c/F`, `tan φ* = β tan φ_F`, `ψ* = φ*` (`talus_bipotential::davis_equivalent`,
    ///   the transform `[material] flow = "davis"` uses too).
    pub fn reduced(&self, f: f64, rule: DilatancyRule) -> Self {
        let cohesion = self.cohesion / f;
        let friction = (self.friction.tan() / f).atan();
        let scaled_psi = (self.dilatancy.tan() / f).atan();
        match rule {
            DilatancyRule::Scaled => Self {
                cohesion,
                friction,
                dilatancy: scaled_psi,
            },
            DilatancyRule::Fixed => Self {
                cohesion,
                friction,
                dilatancy: self.dilatancy.min(friction),
            },
            DilatancyRule::Davis => {
                let (cohesion, friction) = davis_equivalent(cohesion, friction, scaled_psi);
                Self {
                    cohesion,
                    friction,
                    dilatancy: friction,
                }
            }
        }
    }
}

/// The Drucker-Prager cone that collapses like Mohr-Coulomb `(c, φ, ψ)` in plane strain
/// with non-associative flow: `(k_d, tan θ)` of eq. 7 for the same `c` and `tan φ`
/// (`docs/stability.md`, 'Plane-strain matching'). At collapse `ε̇ᵖ_zz = 0` gives
/// `s_zz = −(T/3)‖s‖` with `T = k_d tan θ`; matching the dilatancy `ε̇_v / γ̇ = sin ψ` gives
/// `T = √2 sin ψ / √(1 + sin²ψ/3)`, and matching the strength `R = c cos φ − s_m sin φ`
/// gives `1/k_d = T tan φ / 6 + √(1 − T²/6) / (√2 cos φ)`. Associative (ψ = φ) this is
/// `ConeFit::PlaneStrain`, `3√2/√(9 + 12 tan²φ)`; ψ = 0 gives `√2 cos φ`.
pub fn plane_strain_match(friction: f64, dilatancy: f64) -> (f64, f64) {
    let s = dilatancy.sin();
    let t = 2f64.sqrt() * s / (1.0 + s * s / 3.0).sqrt();
    let inv_kd =
        t * friction.tan() / 6.0 + (1.0 - t * t / 6.0).sqrt() / (2f64.sqrt() * friction.cos());
    let k_d = 1.0 / inv_kd;
    (k_d, t / k_d)
}

/// The Drucker-Prager material of strength `s` with the scene's elasticity and cone fit.
/// `PlaneStrain` uses [`plane_strain_match`] (so a non-associative `ψ` keeps its plane-strain
/// collapse load); the other fits, and `PlaneStrain` when associative (`ψ = φ`, where the
/// match is `ConeFit::PlaneStrain` up to round-off), take `k_d` of `φ` and `θ = ψ` as a scene
/// does: an associative strength (any rule's on an associative scene, `Davis`'s always)
/// gives `θ = φ` to the bit, `κ = 0`, the symmetric (Cholesky) Newton system. The match's
/// round-off used to put `θ` one ulp below `φ` for about one angle in six.
pub fn drucker_prager(
    scene: &DruckerPragerParameters,
    s: &Strength,
) -> Result<DruckerPrager, MaterialError> {
    let (cone_fit, dilatancy) = match scene.cone_fit {
        ConeFit::PlaneStrain if s.dilatancy < s.friction => {
            let (k_d, tan_theta) = plane_strain_match(s.friction, s.dilatancy);
            (ConeFit::Explicit { k_d }, tan_theta.atan())
        }
        fit => (fit, s.dilatancy),
    };
    let friction_angle = s.friction.to_degrees();
    DruckerPrager::try_new(DruckerPragerParameters {
        friction_angle,
        cohesion: s.cohesion,
        // Round-off must not put θ above φ (the cone refuses it).
        dilatancy_angle: dilatancy.to_degrees().min(friction_angle),
        cone_fit,
        ..*scene
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plane_strain_match_is_the_associative_fit_and_sqrt2_cos_phi() {
        for deg in [5.0f64, 20.0, 35.0] {
            let phi = deg.to_radians();
            let (k_d, tan_theta) = plane_strain_match(phi, phi);
            assert!((k_d - ConeFit::PlaneStrain.k_d(phi)).abs() < 1e-14);
            assert!((tan_theta - phi.tan()).abs() < 1e-14);
            let (k_d, tan_theta) = plane_strain_match(phi, 0.0);
            assert!((k_d - 2f64.sqrt() * phi.cos()).abs() < 1e-15);
            assert_eq!(tan_theta, 0.0);
        }
    }

    /// An independent check of the matching: the plane-strain collapse state of the matched
    /// cone, built from its flow rule, has Mohr-Coulomb's radius and dilatancy ratio.
    #[test]
    fn matched_cone_collapses_like_mohr_coulomb_in_plane_strain() {
        let (phi, psi, c): (f64, f64, f64) = (30f64.to_radians(), 10f64.to_radians(), 1.0);
        let (k_d, tan_theta) = plane_strain_match(phi, psi);
        // At s_m = −2 (compression): s_zz = −(k_d tanθ/3)‖s‖, ‖s‖² = 2R² + 1.5 s_zz², on f = 0.
        let s_m = -2.0;
        let beta = k_d * tan_theta / 3.0;
        // Solve f = ‖s‖/k_d + (s_m − β‖s‖/2) tan φ − c = 0 for ‖s‖.
        let norm = (c - s_m * phi.tan()) / (1.0 / k_d - beta * phi.tan() / 2.0);
        let r = (norm * norm * (1.0 - 1.5 * beta * beta) / 2.0).sqrt();
        let mc = c * phi.cos() - s_m * phi.sin();
        assert!((r - mc).abs() < 1e-12 * mc, "{r} vs {mc}");
        // Flow: ε̇ = s/(k_d‖s‖) + tanθ/3 I; principal in-plane difference 2R/(k_d‖s‖).
        let gamma = 2.0 * r / (k_d * norm);
        assert!((tan_theta / gamma - psi.sin()).abs() < 1e-12);
    }

    /// An associative strength (the `Davis` rule's always, any rule's on an associative
    /// scene) gives the scene's `PlaneStrain` cone with `θ = φ` to the bit, `κ = 0`: the
    /// symmetric Newton system. The match alone put θ one ulp below φ for about one angle
    /// in six (35 of the 178 angles here).
    #[test]
    fn associative_strength_gives_an_associative_cone() {
        let scene = DruckerPragerParameters {
            young_modulus: 1e8,
            poisson_ratio: 0.3,
            friction_angle: 20.0,
            cohesion: 1e4,
            dilatancy_angle: 0.0,
            cone_fit: ConeFit::PlaneStrain,
        };
        for k in 1..90 {
            let phi = (k as f64).to_radians();
            for (psi, rule) in [(0.0, DilatancyRule::Davis), (phi, DilatancyRule::Scaled)] {
                let s = Strength {
                    cohesion: 1e4,
                    friction: phi,
                    dilatancy: psi,
                }
                .reduced(1.37, rule);
                let m = drucker_prager(&scene, &s).unwrap();
                assert!(m.flow_rule::<4>().is_associative(), "{k}° {rule:?}");
                assert!((m.k_d() / ConeFit::PlaneStrain.k_d(s.friction) - 1.0).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn reductions() {
        let s = Strength {
            cohesion: 10.0,
            friction: 30f64.to_radians(),
            dilatancy: 10f64.to_radians(),
        };
        let f = 2.0;
        let r = s.reduced(f, DilatancyRule::Scaled);
        assert!((r.friction.tan() - s.friction.tan() / 2.0).abs() < 1e-15);
        assert!((r.dilatancy.tan() - s.dilatancy.tan() / 2.0).abs() < 1e-15);
        assert_eq!(r.cohesion, 5.0);
        let fixed = s.reduced(f, DilatancyRule::Fixed);
        assert_eq!(fixed.dilatancy, s.dilatancy);
        // ψ above φ_F is capped.
        assert_eq!(
            s.reduced(10.0, DilatancyRule::Fixed).dilatancy,
            s.reduced(10.0, DilatancyRule::Fixed).friction
        );
        // Davis at ψ = 0: β = cos φ_F.
        let s0 = Strength {
            dilatancy: 0.0,
            ..s
        };
        let d = s0.reduced(f, DilatancyRule::Davis);
        let phi_f = (s.friction.tan() / f).atan();
        assert!((d.cohesion - phi_f.cos() * 5.0).abs() < 1e-14);
        assert!((d.friction.tan() - phi_f.cos() * phi_f.tan()).abs() < 1e-15);
        assert_eq!(d.dilatancy, d.friction);
    }
}
