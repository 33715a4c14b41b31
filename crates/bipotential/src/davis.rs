//! Davis's (1968) associated equivalent of a non-associative Mohr-Coulomb material
//! `(c, φ, ψ)`: the associative material `(c*, φ*, ψ* = φ*)` with
//! `β = cos φ cos ψ / (1 − sin φ sin ψ)`, `c* = β c`, `tan φ* = β tan φ`. Davis matched the
//! shear strength on the velocity characteristics of the non-associative material in plane
//! strain (Davis 1968, in Lee (ed.) *Soil Mechanics: Selected Topics*; Sloan 2013,
//! Géotechnique 63(7), 531–572; Tschuchnigg et al. 2015 for its use in strength reduction).
//! The one implementation of the transform: `[material] flow = "davis"` and
//! `[stability] dilatancy = "davis"` both call it.
use crate::DruckerPragerParameters;

/// Davis's factor `β = cos φ cos ψ / (1 − sin φ sin ψ)` (angles in radians): exactly 1 when
/// associative (`ψ = φ`), `cos φ` at `ψ = 0`, and at most 1 (`1 − β` has the sign of
/// `1 − cos(φ − ψ)`).
pub fn davis_beta(friction: f64, dilatancy: f64) -> f64 {
    if dilatancy == friction {
        return 1.0;
    }
    friction.cos() * dilatancy.cos() / (1.0 - friction.sin() * dilatancy.sin())
}

/// Davis's associated equivalent `(c*, φ*)` of `(c, φ, ψ)` (Pa, radians):
/// `c* = β c`, `tan φ* = β tan φ`, with [`davis_beta`]; its flow is associative, `ψ* = φ*`.
/// An associative material (`ψ = φ`) is returned unchanged, bit for bit.
pub fn davis_equivalent(cohesion: f64, friction: f64, dilatancy: f64) -> (f64, f64) {
    if dilatancy == friction {
        return (cohesion, friction);
    }
    let beta = davis_beta(friction, dilatancy);
    (beta * cohesion, (beta * friction.tan()).atan())
}

impl DruckerPragerParameters {
    /// These parameters with Davis's associated equivalent strength ([`davis_equivalent`],
    /// angles in degrees here): `cohesion = c*`, `friction_angle = φ*`,
    /// `dilatancy_angle = φ*` (the same value, so the flow rule's `κ` is exactly 0); the
    /// elasticity and the cone fit as given (`PlaneStrain` then fits `φ*`). Unchanged, bit
    /// for bit, when already associative.
    pub fn davis_equivalent(&self) -> Self {
        if self.dilatancy_angle == self.friction_angle {
            return *self;
        }
        let (cohesion, friction) = davis_equivalent(
            self.cohesion,
            self.friction_angle.to_radians(),
            self.dilatancy_angle.to_radians(),
        );
        let friction_angle = friction.to_degrees();
        Self {
            cohesion,
            friction_angle,
            dilatancy_angle: friction_angle,
            ..*self
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{ConeFit, DruckerPrager};

    /// Hand values: φ = 30°, ψ = 0 gives β = cos 30° = 0.866025, c* = 0.866025 c,
    /// φ* = atan(0.866025 tan 30°) = atan(0.5) = 26.5651°.
    #[test]
    fn thirty_degrees_without_dilatancy() {
        let (phi, c) = (30f64.to_radians(), 10.0e3);
        let beta = davis_beta(phi, 0.0);
        assert!((beta - 0.866_025_403_784).abs() < 1e-12, "{beta}");
        let (c_star, phi_star) = davis_equivalent(c, phi, 0.0);
        assert!((c_star - 8_660.254_037_84).abs() < 1e-8, "{c_star}");
        assert!((phi_star.to_degrees() - 26.565_051_177).abs() < 1e-9);
    }

    /// φ = 30°, ψ = 10°: β = cos 30° cos 10° / (1 − sin 30° sin 10°)
    /// = 0.852869 / 0.913176 = 0.933958 (by hand, 6 digits).
    #[test]
    fn thirty_and_ten_degrees() {
        let beta = davis_beta(30f64.to_radians(), 10f64.to_radians());
        assert!((beta - 0.933_958).abs() < 1e-6, "{beta}");
        // Symmetric in (φ, ψ), and never above 1.
        assert_eq!(beta, davis_beta(10f64.to_radians(), 30f64.to_radians()));
        for (p, s) in [(45.0f64, 0.0f64), (27.0, 14.2906), (5.0, 4.9)] {
            assert!(davis_beta(p.to_radians(), s.to_radians()) < 1.0);
        }
    }

    #[test]
    fn associative_is_unchanged_bit_for_bit() {
        for deg in [0.0f64, 1e-3, 20.0, 27.0, 33.3, 60.0] {
            let phi = deg.to_radians();
            assert_eq!(davis_beta(phi, phi), 1.0);
            assert_eq!(davis_equivalent(1234.5, phi, phi), (1234.5, phi));
        }
        let p = DruckerPragerParameters {
            young_modulus: 1e9,
            poisson_ratio: 0.3,
            friction_angle: 27.0,
            cohesion: 2e3,
            dilatancy_angle: 27.0,
            cone_fit: ConeFit::PlaneStrain,
        };
        assert_eq!(p.davis_equivalent(), p);
    }

    /// The footing's soil (φ = 27°, ψ = 14.2906°): the equivalent is associative to the bit
    /// (κ = 0: the symmetric Newton system), with φ* and c* of the radians formula.
    #[test]
    fn parameters_become_associative() {
        let p = DruckerPragerParameters {
            young_modulus: 1e9,
            poisson_ratio: 0.3,
            friction_angle: 27.0,
            cohesion: 2e3,
            dilatancy_angle: 14.2906,
            cone_fit: ConeFit::PlaneStrain,
        };
        let d = p.davis_equivalent();
        let beta = davis_beta(27f64.to_radians(), 14.2906f64.to_radians());
        assert_eq!(d.cohesion, beta * 2e3);
        assert_eq!(
            d.friction_angle,
            (beta * 27f64.to_radians().tan()).atan().to_degrees()
        );
        assert_eq!(d.dilatancy_angle, d.friction_angle);
        assert!(d.friction_angle < 27.0 && d.cohesion < 2e3);
        assert_eq!(
            (d.young_modulus, d.poisson_ratio, d.cone_fit),
            (p.young_modulus, p.poisson_ratio, p.cone_fit)
        );
        let material = DruckerPrager::try_new(d).unwrap();
        assert_eq!(material.alpha(), 0.0);
        assert!(material.flow_rule::<4>().is_associative());
        assert!(!DruckerPrager::try_new(p)
            .unwrap()
            .flow_rule::<4>()
            .is_associative());
    }
}
