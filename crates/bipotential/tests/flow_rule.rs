//! The Drucker-Prager flow rule in natural-map form (eqs. 7–10, 20), checked against the
//! closed forms of `docs/conventions.md` ('Drucker-Prager cone', 'Flow rule') and against
//! finite differences.
use crate::common;

use approx::assert_relative_eq;
use common::{check_sigma_block, return_map};
use talus_bipotential::mandel::{deviator, hydrostatic_axis, trace};
use talus_bipotential::{
    ConeFit, DruckerPrager, DruckerPragerParameters, FlowRule, Region, SVector,
};

fn soil(phi: f64, theta: f64, fit: ConeFit) -> DruckerPrager {
    DruckerPrager::try_new(DruckerPragerParameters {
        young_modulus: 1e9,
        poisson_ratio: 0.3,
        friction_angle: phi,
        cohesion: 2e3,
        dilatancy_angle: theta,
        cone_fit: fit,
    })
    .unwrap()
}

/// Trial stresses mostly deviatoric (the return lands on the smooth surface, not the apex).
fn shear_trials<const D: usize>() -> Vec<SVector<f64, D>> {
    let mut out = Vec::new();
    for k in 0..12 {
        let a = k as f64 * 0.7;
        let v = SVector::<f64, D>::from_fn(|i, _| ((i as f64 + 1.0) * (a + 0.3)).sin());
        let dev = deviator(&v);
        let dev = dev / dev.norm();
        let p = -2e4 * (1.0 + k as f64); // compression
        out.push(
            dev * 1e5 * (1.0 + 0.3 * k as f64)
                + SVector::from_fn(|i, _| if i < 3 { p } else { 0.0 }),
        );
    }
    out
}

fn dilatancy_ratio_case<const D: usize>() {
    for fit in [
        ConeFit::PlaneStrain,
        ConeFit::OuterCone,
        ConeFit::Explicit { k_d: 2f64.sqrt() },
    ] {
        for (phi, theta) in [
            (30.0, 0.0),
            (30.0, 10.0),
            (30.0, 15.0),
            (30.0, 30.0),
            (27.0, 14.3),
            (45.0, 5.0),
        ] {
            let m = soil(phi, theta, fit);
            let rule = m.flow_rule::<D>();
            for trial in shear_trials::<D>() {
                assert!(m.yield_function(&trial) > 0.0);
                let (sigma, z) = return_map(&m, &rule, &trial);
                let eps_p = -z;
                // On the yield surface, and off the apex.
                assert!(m.yield_function(&sigma).abs() <= 1e-10 * trial.norm());
                assert!(deviator(&sigma).norm() > 1e-3 * trial.norm());
                let ratio = trace(&eps_p) / deviator(&eps_p).norm();
                let expected = m.k_d() * theta.to_radians().tan();
                assert!(
                    (ratio - expected).abs() <= 1e-10,
                    "phi {phi} theta {theta} {fit:?}: ratio {ratio} vs k_d tan θ {expected}"
                );
                // Flow is along ∂g/∂σ: dev ε̇ᵖ parallel to dev σ.
                let cos = deviator(&eps_p).dot(&deviator(&sigma))
                    / (deviator(&eps_p).norm() * deviator(&sigma).norm());
                assert_relative_eq!(cos, 1.0, epsilon = 1e-12);
            }
        }
    }
}

#[test]
fn dilatancy_ratio_plane_strain() {
    dilatancy_ratio_case::<4>();
}

#[test]
fn dilatancy_ratio_3d() {
    dilatancy_ratio_case::<6>();
}

#[test]
fn incompressible_flow_for_zero_dilatancy() {
    let m = soil(35.0, 0.0, ConeFit::PlaneStrain);
    let rule = m.flow_rule::<4>();
    for trial in shear_trials::<4>() {
        let (_, z) = return_map(&m, &rule, &trial);
        assert!(
            trace(&z).abs() <= 1e-10 * z.norm(),
            "tr ε̇ᵖ = {:e}",
            trace(&z)
        );
    }
}

#[test]
fn associative_normality() {
    // θ = φ: the plastic strain increment is normal to the yield surface, ε̇ᵖ ∥ ∇f.
    let m = soil(30.0, 30.0, ConeFit::PlaneStrain);
    let rule = m.flow_rule::<4>();
    assert!(rule.is_associative());
    for trial in shear_trials::<4>() {
        let (sigma, z) = return_map(&m, &rule, &trial);
        let s = deviator(&sigma);
        let grad = s / (m.k_d() * s.norm())
            + hydrostatic_axis::<4>() * (30f64.to_radians().tan() / 3f64.sqrt());
        let eps = -z;
        assert_relative_eq!(
            eps.dot(&grad) / (eps.norm() * grad.norm()),
            1.0,
            epsilon = 1e-12
        );
    }
}

#[test]
fn return_to_apex_under_hydrostatic_tension() {
    // Pure hydrostatic tension beyond the apex returns to p = c / tan φ, s = 0.
    for theta in [0.0, 10.0, 30.0] {
        let m = soil(30.0, theta, ConeFit::PlaneStrain);
        let rule = m.flow_rule::<4>();
        let trial = SVector::<f64, 4>::new(1e5, 1e5, 1e5, 0.0);
        let (sigma, _) = return_map(&m, &rule, &trial);
        let p_apex = 2e3 / 30f64.to_radians().tan();
        assert_relative_eq!(trace(&sigma) / 3.0, p_apex, max_relative = 1e-12);
        assert!(deviator(&sigma).norm() <= 1e-9 * p_apex);
    }
}

#[test]
fn von_mises_radius_and_incompressibility() {
    let m = soil(0.0, 0.0, ConeFit::Explicit { k_d: 2f64.sqrt() });
    assert!(m.is_von_mises());
    let rule = m.flow_rule::<4>();
    for trial in shear_trials::<4>() {
        let (sigma, z) = return_map(&m, &rule, &trial);
        assert_relative_eq!(
            deviator(&sigma).norm(),
            2f64.sqrt() * 2e3,
            max_relative = 1e-12
        );
        assert!(trace(&z).abs() <= 1e-12 * z.norm());
    }
}

fn fd_blocks_case<const D: usize>(
    rule: &FlowRule<D>,
    sigma: SVector<f64, D>,
    z: SVector<f64, D>,
    rho: f64,
) -> Region {
    let h_s = 1e-6 * sigma.norm().max(1.0);
    let h_z = 1e-6 * z.norm().max(1e-12);
    let (lin, d_z, expected_z) = check_sigma_block(rule, sigma, z, rho, h_s, h_z);
    assert!(
        (d_z - expected_z).amax() <= 1e-6 * expected_z.amax().max(rho),
        "dF/dz:\n{d_z}\nvs\n{expected_z}"
    );
    lin.region
}

#[test]
fn jacobian_blocks_match_finite_differences() {
    let m = soil(27.0, 14.3, ConeFit::PlaneStrain);
    let rule = m.flow_rule::<4>();
    let rho = 2.0 * m.shear_modulus();
    let mut seen = std::collections::HashSet::new();
    for k in 0..200 {
        let t = k as f64;
        let sigma = SVector::<f64, 4>::from_fn(|i, _| {
            3e4 * ((i as f64 + 1.3) * (t * 0.37 + 0.1)).sin() - 1e4
        });
        let z =
            SVector::<f64, 4>::from_fn(|i, _| 4e-5 * ((i as f64 + 0.7) * (t * 0.53 + 0.2)).cos());
        // Stay off region boundaries, where the map is not differentiable.
        let x = sigma - rule.shifted(&z) * rho;
        let cone = match rule.yield_set() {
            talus_bipotential::YieldSet::Cone(c) => *c,
            _ => unreachable!(),
        };
        let xa = x - cone.apex();
        let xn = xa.dot(cone.axis());
        let r = (xa - cone.axis() * xn).norm();
        let eta = cone.eta();
        if (r - eta * xn).abs() < 1e-3 * xa.norm() || (eta * r + xn).abs() < 1e-3 * xa.norm() {
            continue;
        }
        seen.insert(fd_blocks_case(&rule, sigma, z, rho));
    }
    assert_eq!(seen.len(), 3, "all three regions exercised: {seen:?}");
}

#[test]
fn bipotential_inequality_and_equality_on_the_flow_rule() {
    let m = soil(27.0, 14.3, ConeFit::PlaneStrain);
    let rule = m.flow_rule::<4>();
    // Equality at solutions of the flow rule (eq. 6).
    for trial in shear_trials::<4>() {
        let (sigma, z) = return_map(&m, &rule, &trial);
        let eps = -z;
        let b = m
            .bipotential(&eps, &sigma)
            .expect("flow-rule pair is admissible");
        assert_relative_eq!(b, sigma.dot(&eps), max_relative = 1e-9);
    }
    // b(ε̇, σ') ≥ σ' : ε̇ for admissible pairs (eq. 5 with the inequality the right way).
    let tan_t = 14.3f64.to_radians().tan();
    let talus_bipotential::YieldSet::Cone(cone) = *rule.yield_set() else {
        panic!("cone expected")
    };
    let mut checked = 0;
    for k in 0..400 {
        let t = k as f64;
        // σ' = apex + s (n + f η u): inside K for f ∈ [0, 1].
        let u = deviator(&SVector::<f64, 4>::from_fn(|i, _| {
            ((i as f64 + 1.1) * (t * 0.41 + 0.3)).sin()
        }));
        let f = (t * 0.77).sin().abs();
        let sigma = cone.apex()
            + (cone.axis() + u / u.norm() * (f * cone.eta()))
                * (1e3 * (1.0 + (t * 0.1).cos().abs() * 50.0));
        assert!(m.yield_function(&sigma) <= 1e-9 * sigma.norm());
        let dev = deviator(&SVector::<f64, 4>::from_fn(|i, _| {
            ((i as f64 + 2.0) * (t * 0.29)).cos()
        }));
        let extra = (t * 0.13).sin().abs();
        let tr = m.k_d() * tan_t * dev.norm() + extra * dev.norm();
        let eps = dev + SVector::from_fn(|i, _| if i < 3 { tr / 3.0 } else { 0.0 });
        let b = m.bipotential(&eps, &sigma).expect("admissible pair");
        assert!(
            b >= sigma.dot(&eps) - 1e-9 * b.abs().max(1.0),
            "b {b} < σ:ε̇ {}",
            sigma.dot(&eps)
        );
        checked += 1;
    }
    assert!(checked > 100);
    // Outside K, or contracting plastic flow, the bipotential is +∞.
    let outside = SVector::<f64, 4>::new(1e6, 1e6, 1e6, 0.0);
    assert_eq!(m.bipotential(&SVector::zeros(), &outside), None);
    let contracting = SVector::<f64, 4>::new(-1.0, -1.0, -1.0, 0.0);
    assert_eq!(m.bipotential(&contracting, &SVector::zeros()), None);
}

#[test]
fn cone_fits_match_their_formulas() {
    let k = |fit: ConeFit, phi: f64| fit.k_d(phi.to_radians());
    assert_relative_eq!(k(ConeFit::PlaneStrain, 27.0), 1.2189, max_relative = 1e-4);
    // Outer ≥ plane strain ≥ inner for φ > 0; all equal √(8/3)·… at φ = 0: 2√6/3.
    for phi in [5.0, 20.0, 35.0, 60.0] {
        assert!(k(ConeFit::OuterCone, phi) > k(ConeFit::InnerCone, phi));
    }
    assert_relative_eq!(
        k(ConeFit::OuterCone, 0.0),
        2.0 * 6f64.sqrt() / 3.0,
        max_relative = 1e-15
    );
    assert_relative_eq!(
        k(ConeFit::InnerCone, 0.0),
        2.0 * 6f64.sqrt() / 3.0,
        max_relative = 1e-15
    );
    assert_relative_eq!(
        k(ConeFit::PlaneStrain, 0.0),
        2f64.sqrt(),
        max_relative = 1e-15
    );
}

#[test]
fn yield_set_geometry_matches_the_yield_function() {
    // Points of the cone's surface have f = 0; the apex sits at p = c / tan φ.
    let m = soil(27.0, 14.3, ConeFit::PlaneStrain);
    let rule = m.flow_rule::<4>();
    let talus_bipotential::YieldSet::Cone(cone) = rule.yield_set() else {
        panic!("cone expected")
    };
    assert_relative_eq!(m.yield_function(cone.apex()), 0.0, epsilon = 1e-9);
    assert_relative_eq!(
        trace(cone.apex()) / 3.0,
        2e3 / 27f64.to_radians().tan(),
        max_relative = 1e-14
    );
    let dir = deviator(&SVector::<f64, 4>::new(1.0, -0.4, -0.6, 0.9));
    let on_surface = cone.apex() + (cone.axis() + dir / dir.norm() * cone.eta()) * 1e4;
    assert!(m.yield_function(&on_surface).abs() <= 1e-10 * on_surface.norm());
}
