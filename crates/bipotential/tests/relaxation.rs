//! Duvaut–Lions relaxation of the flow rule (`docs/derivations.md`, 'Duvaut–Lions
//! relaxation', eqs. DL1–DL6): the Jacobian blocks against central differences in every
//! region, the one-point step against the blend of eq. DL3, and the tangent's monotonicity
//! modulus of eq. DL6.
use crate::common;

use common::{check_sigma_block, return_map};
use talus_bipotential::mandel::{deviator, hydrostatic_axis, identity};
use talus_bipotential::{
    ConeFit, DruckerPrager, DruckerPragerParameters, FlowRule, Region, Relaxation, SMatrix,
    SVector, YieldSet,
};

const E: f64 = 1e9;
const NU: f64 = 0.3;

fn soil(phi: f64, theta: f64, fit: ConeFit) -> DruckerPrager {
    DruckerPrager::try_new(DruckerPragerParameters {
        young_modulus: E,
        poisson_ratio: NU,
        friction_angle: phi,
        cohesion: 2e3,
        dilatancy_angle: theta,
        cone_fit: fit,
    })
    .unwrap()
}

fn relaxed<const D: usize>(m: &DruckerPrager, tau_over_h: f64, volume: f64) -> FlowRule<D> {
    let n = Relaxation::duvaut_lions(tau_over_h * 0.01, 0.01, volume, E, NU).unwrap();
    m.flow_rule::<D>().with_relaxation(Some(n))
}

/// Relative distance of `x` to the nearest region boundary of the rule's set (kinks).
fn off_kinks<const D: usize>(rule: &FlowRule<D>, x: &SVector<f64, D>) -> f64 {
    match rule.yield_set() {
        YieldSet::Cone(c) => {
            let xa = x - c.apex();
            let xn = xa.dot(c.axis());
            let r = (xa - c.axis() * xn).norm();
            let eta = c.eta();
            ((r - eta * xn).abs()).min((eta * r + xn).abs()) / xa.norm()
        }
        YieldSet::Cylinder(c) => {
            let r = (x - c.axis() * x.dot(c.axis())).norm();
            (r - c.radius()).abs() / c.radius()
        }
        YieldSet::Everywhere => 1.0,
    }
}

/// `dF/dσ = I − D` and `dF/dz = ρ G` (eq. DL4) against central differences of
/// `natural_map_residual`; returns the region.
fn fd_case<const D: usize>(
    rule: &FlowRule<D>,
    sigma: SVector<f64, D>,
    z: SVector<f64, D>,
    rho: f64,
) -> Region {
    let (h_s, h_z) = (1e-6 * sigma.norm(), 1e-6 * z.norm());
    let (lin, d_z, expected_z) = check_sigma_block(rule, sigma, z, rho, h_s, h_z);
    let f = rule.natural_map_residual(&sigma, &z, rho);
    assert!((lin.residual - f).amax() <= 1e-12 * sigma.norm());
    let scale = rule.relaxation().map_or(0.0, |n| n.volumetric()).max(rho);
    assert!(
        (d_z - expected_z).amax() <= 1e-6 * scale,
        "dF/dz ({:?}):\n{d_z}\nvs\n{expected_z}",
        lin.region
    );
    lin.region
}

/// Random `(σ, z)` off the kinks, `z` a volume `V` times a strain, `ρ = 2G/V`
/// (`docs/derivations.md`, 'ρ per point'); the regions hit.
fn fd_sweep<const D: usize>(
    rule: &FlowRule<D>,
    volume: f64,
    sigma_scale: f64,
    strain: f64,
) -> Vec<Region> {
    let rho = E / (1.0 + NU) / volume;
    let mut seen = Vec::new();
    for k in 0..400 {
        let t = k as f64;
        let sigma = SVector::<f64, D>::from_fn(|i, _| {
            sigma_scale * ((i as f64 + 1.3) * (t * 0.37 + 0.1)).sin() - sigma_scale / 3.0
        });
        let z = SVector::<f64, D>::from_fn(|i, _| {
            volume * strain * ((i as f64 + 0.7) * (t * 0.53 + 0.2)).cos()
        });
        let p = sigma + rule.relaxation().map_or(SVector::zeros(), |n| n.apply(&z));
        let x = p - rule.shifted(&z) * rho;
        if off_kinks(rule, &x) < 1e-3 {
            continue;
        }
        let region = fd_case(rule, sigma, z, rho);
        if !seen.contains(&region) {
            seen.push(region);
        }
    }
    seen
}

/// Eq. DL4 against central differences, at points of each region: interior, lateral
/// surface and the apex (the polar cone), for κ = 0 and κ > 0, in plane strain and 3D,
/// and for the von Mises cylinder (interior and lateral). A wrong `(I − D) N / ρ` term, or
/// its absence, fails the `dF/dz` check everywhere outside the interior.
#[test]
fn relaxed_jacobian_blocks_match_central_differences() {
    for tau_over_h in [0.05, 1.0, 20.0] {
        for (phi, theta) in [(27.0, 14.2906), (30.0, 30.0), (30.0, 0.0)] {
            let m = soil(phi, theta, ConeFit::PlaneStrain);
            let seen = fd_sweep(&relaxed::<4>(&m, tau_over_h, 1e-3), 1e-3, 3e4, 4e-5);
            assert_eq!(
                seen.len(),
                3,
                "τ/h {tau_over_h}, φ {phi}, θ {theta}: {seen:?}"
            );
            let seen = fd_sweep(&relaxed::<6>(&m, tau_over_h, 2e-2), 2e-2, 3e4, 4e-5);
            assert_eq!(
                seen.len(),
                3,
                "3D τ/h {tau_over_h}, φ {phi}, θ {theta}: {seen:?}"
            );
        }
        let vm = soil(0.0, 0.0, ConeFit::Explicit { k_d: 2f64.sqrt() });
        let seen = fd_sweep(&relaxed::<4>(&vm, tau_over_h, 1e-3), 1e-3, 3e3, 2e-6);
        assert_eq!(seen.len(), 2, "von Mises τ/h {tau_over_h}: {seen:?}");
    }
}

/// Without a relaxation the rule is the rate-independent one, bit for bit; an elastic
/// point never takes one.
#[test]
fn no_relaxation_is_the_rate_independent_rule_bit_for_bit() {
    let m = soil(27.0, 14.2906, ConeFit::PlaneStrain);
    let plain = m.flow_rule::<4>();
    assert!(plain.relaxation().is_none());
    assert_eq!(plain.with_relaxation(None), plain);
    let n = Relaxation::duvaut_lions(0.01, 0.01, 1.0, E, NU).unwrap();
    assert!(FlowRule::<4>::elastic()
        .with_relaxation(Some(n))
        .relaxation()
        .is_none());
    let material = talus_bipotential::Material::DruckerPrager(m);
    assert_eq!(
        material.point_flow_rule::<4>(0.0, 0.01, 1e-3).unwrap(),
        plain
    );
}

/// `N = (τ/h)(V S₀)⁻¹` (eq. DL2): `N S_i = (τ/h) I`.
#[test]
fn overstress_modulus_is_tau_over_h_times_the_inverse_compliance_block() {
    let (tau, h, volume) = (0.3, 0.01, 2.5e-3);
    let n = Relaxation::duvaut_lions(tau, h, volume, E, NU).unwrap();
    let s: SMatrix<f64, 4, 4> = soil(27.0, 14.2906, ConeFit::PlaneStrain).compliance() * volume;
    let err = (n.matrix::<4>() * s - SMatrix::<f64, 4, 4>::identity() * (tau / h)).amax();
    assert!(err <= 1e-12 * tau / h, "{err:e}");
    let z = SVector::<f64, 4>::new(1.0, -2.0, 0.5, 3.0);
    assert!((n.apply(&z) - n.matrix::<4>() * z).amax() <= 1e-12 * n.volumetric());
}

fn trials() -> Vec<SVector<f64, 4>> {
    let mut out = Vec::new();
    for k in 0..10 {
        let a = k as f64 * 0.7 + 0.3;
        let dev = deviator(&SVector::<f64, 4>::from_fn(|i, _| {
            ((i as f64 + 1.0) * a).sin()
        }));
        let p = -2e4 * (1.0 + k as f64);
        out.push(dev / dev.norm() * 1e5 * (1.0 + 0.3 * k as f64) + identity::<4>() * p);
    }
    // Hydrostatic tension past the apex: a return to the apex.
    out.push(SVector::<f64, 4>::new(1e5, 1e5, 1e5, 0.0));
    out
}

/// The one-point relaxed step (`W = S`, `q = −S σ_tr`) is the Duvaut–Lions blend of eq. DL3,
/// `σ = (σ_tr + (h/τ) σ₀)/(1 + h/τ)`, `σ₀` the rate-independent return of the same trial,
/// for associative and non-associative Drucker-Prager (lateral and apex returns) and von
/// Mises. An overstress in `y(z)` instead of `z` fails it for κ > 0.
#[test]
fn one_point_step_is_the_duvaut_lions_blend() {
    for (phi, theta) in [(27.0, 14.2906), (30.0, 30.0), (35.0, 0.0), (0.0, 0.0)] {
        let fit = if phi == 0.0 {
            ConeFit::Explicit { k_d: 2f64.sqrt() }
        } else {
            ConeFit::PlaneStrain
        };
        let m = soil(phi, theta, fit);
        for trial in trials() {
            if phi == 0.0 && deviator(&trial).norm() < 1e-9 {
                continue;
            }
            let (sigma0, _) = return_map(&m, &m.flow_rule::<4>(), &trial);
            for r in [0.1, 1.0, 10.0] {
                let (sigma, z) = return_map(&m, &relaxed::<4>(&m, 1.0 / r, 1.0), &trial);
                let blend = (trial + sigma0 * r) / (1.0 + r);
                let err = (sigma - blend).norm() / trial.norm();
                assert!(err <= 1e-12, "φ {phi} θ {theta} h/τ {r}: {err:e}");
                // The overstress σ − σ₀ = (τ/h) C Δεᵖ, Δεᵖ = −z (eq. DL1).
                let over = m.compliance::<4>().try_inverse().unwrap() * (-z) / r;
                assert!((sigma - sigma0 - over).norm() <= 1e-10 * trial.norm());
            }
        }
    }
}

/// `S^{1/2}`, `S^{−1/2}` of the isotropic compliance: `(2G)^{∓1/2}` on deviators,
/// `(3K)^{∓1/2}` on the hydrostatic axis.
fn compliance_roots() -> (SMatrix<f64, 4, 4>, SMatrix<f64, 4, 4>) {
    let (two_g, three_k) = (E / (1.0 + NU), E / (1.0 - 2.0 * NU));
    let e = hydrostatic_axis::<4>();
    let vol = e * e.transpose();
    let dev = SMatrix::<f64, 4, 4>::identity() - vol;
    (
        dev / two_g.sqrt() + vol / three_k.sqrt(),
        dev * two_g.sqrt() + vol * three_k.sqrt(),
    )
}

/// Eq. DL6: at a lateral return the one-point tangent `T = ρ A⁻¹ G S` (`A = I − D + ρ G S`,
/// the `C_i S_i` of the Schur step) has, in the energy metric, the smallest symmetric
/// eigenvalue `(1 − rμ)/(1 + r)`, `r = h/τ`, `μ = (sec β − 1)/2`, `β` the angle between the
/// yield normal and the flow direction in the metric of `C = S⁻¹`; `−μ` without relaxation.
/// Associative (`β = 0`): `C_i = T S⁻¹` is symmetric.
#[test]
fn tangent_monotonicity_modulus_is_one_minus_r_mu_over_one_plus_r() {
    let (s_half, s_minus_half) = compliance_roots();
    let ratio = (1.0 + NU) / (1.0 - 2.0 * NU); // 3K / 2G
    for (phi, theta) in [(27.0, 14.2906), (30.0, 0.0), (30.0, 30.0)] {
        let m = soil(phi, theta, ConeFit::PlaneStrain);
        let s = m.compliance::<4>();
        let eta = m.k_d() * f64::tan(phi.to_radians()) / 3f64.sqrt();
        let eta_g = m.k_d() * f64::tan(theta.to_radians()) / 3f64.sqrt();
        let cos_beta = (1.0 + ratio * eta * eta_g)
            / ((1.0 + ratio * eta * eta).sqrt() * (1.0 + ratio * eta_g * eta_g).sqrt());
        let mu = (1.0 / cos_beta - 1.0) / 2.0;
        if phi == 27.0 {
            // The footing's soil (scenes/footing.toml): μ = 0.0175 (by hand, docs).
            assert!((mu - 0.0175).abs() < 5e-4, "μ = {mu}");
        }
        for trial in trials().into_iter().take(10) {
            for r in [f64::INFINITY, 10.0, 1.0, 0.1] {
                let rule = if r.is_finite() {
                    relaxed::<4>(&m, 1.0 / r, 1.0)
                } else {
                    m.flow_rule::<4>()
                };
                let (sigma, z) = return_map(&m, &rule, &trial);
                let rho = 2.0 * m.shear_modulus();
                let lin = rule.natural_map_linearization(&sigma, &z, rho);
                assert_eq!(lin.region, Region::Boundary);
                let g = lin.coupling * rho;
                let a = SMatrix::<f64, 4, 4>::identity() - lin.projection_jacobian + g * s;
                let c = a.try_inverse().unwrap() * g;
                let t = s_half * c * s * s_minus_half;
                let sym = (t + t.transpose()) * 0.5;
                let min = sym.symmetric_eigenvalues().min();
                let expected = if r.is_finite() {
                    (1.0 - r * mu) / (1.0 + r)
                } else {
                    -mu
                };
                assert!(
                    (min - expected).abs() <= 1e-9,
                    "φ {phi} θ {theta} h/τ {r}: {min} vs {expected}"
                );
                if phi == theta {
                    let asym = (c - c.transpose()).amax() / c.amax();
                    assert!(asym <= 1e-12, "C not symmetric: {asym:e}");
                }
            }
        }
    }
}

/// Bad relaxation moduli and times are refused naming the parameter and the value.
#[test]
fn bad_relaxation_times_are_refused() {
    let m = soil(27.0, 14.2906, ConeFit::PlaneStrain);
    for tau in [-1.0, 0.0, f64::NAN, f64::INFINITY] {
        let e = m.with_relaxation_time(Some(tau)).unwrap_err().to_string();
        assert!(
            e.contains("relaxation_time") && e.contains(&format!("{tau}")),
            "{e}"
        );
        assert!(Relaxation::duvaut_lions(tau, 0.01, 1.0, E, NU).is_err());
    }
    assert!(Relaxation::duvaut_lions(0.1, 0.0, 1.0, E, NU).is_err());
    assert!(Relaxation::duvaut_lions(0.1, 0.01, -1.0, E, NU).is_err());
    let ok = m.with_relaxation_time(Some(0.5)).unwrap();
    assert_eq!(ok.relaxation_time(), Some(0.5));
    assert_eq!(ok.with_relaxation_time(None).unwrap(), m);
}
