//! Duvaut–Lions relaxation through the solver (`docs/derivations.md`, 'Duvaut–Lions
//! relaxation'): one material point, `W = V S₀`, `q = −(W σₙ + V Δε)` (strain driven, the
//! `return_map` of `crates/talus/src/analysis/verification/material_point.rs`), under a
//! constant deviatoric strain rate. The overstress of a von Mises point obeys eq. DL7,
//! `x_{n+1} = (x_n + 2G h ε̇)/(1 + h/τ)`, whose closed form is
//! `x_n = 2Gτε̇ (1 − (τ/(τ+h))ⁿ)` from the yield surface; the continuous
//! `x(t) = 2Gτε̇ (1 − e^{−t/τ})` is its limit at O(h).
use nalgebra::{SMatrix, SVector};
use talus_bipotential::mandel::{deviator, identity};
use talus_bipotential::{ConeFit, DruckerPrager, DruckerPragerParameters, FlowRule, Relaxation};
use talus_ssn::faer::Mat;
use talus_ssn::{Operator, ReducedSystem, Rho, Settings, Solver};

const E: f64 = 2e7;
const NU: f64 = 0.3;
const VOLUME: f64 = 3e-3;

fn material(phi: f64, theta: f64) -> DruckerPrager {
    DruckerPrager::try_new(DruckerPragerParameters {
        young_modulus: E,
        poisson_ratio: NU,
        friction_angle: phi,
        cohesion: 1e4,
        dilatancy_angle: theta,
        cone_fit: if phi == 0.0 {
            ConeFit::Explicit { k_d: 2f64.sqrt() }
        } else {
            ConeFit::PlaneStrain
        },
    })
    .unwrap()
}

/// One strain-driven step of the point from `sigma_n` by `d_eps` (a strain), with `rule`
/// and ρ factor `rho`: the stress and `z = −V Δεᵖ`.
fn step(
    m: &DruckerPrager,
    rule: FlowRule<4>,
    sigma_n: &SVector<f64, 4>,
    d_eps: &SVector<f64, 4>,
    rho: f64,
) -> (SVector<f64, 4>, SVector<f64, 4>) {
    let s: SMatrix<f64, 4, 4> = m.compliance() * VOLUME;
    let w = Mat::from_fn(4, 4, |i, j| s[(i, j)]);
    let q = (-(s * sigma_n + d_eps * VOLUME)).as_slice().to_vec();
    let system = ReducedSystem::try_new(Operator::Dense(w), q, vec![rule]).unwrap();
    let settings = Settings {
        rho: Rho::PerPointDiagonal { factor: rho },
        tolerance: 1e-14,
        ..Settings::default()
    };
    let mut solver = Solver::new(system, settings).unwrap();
    let mut sigma = sigma_n.as_slice().to_vec();
    solver.solve(&mut sigma).unwrap();
    let z = SVector::from_column_slice(solver.z());
    (SVector::from_column_slice(&sigma), z)
}

fn relaxed(m: &DruckerPrager, tau: f64, h: f64) -> FlowRule<4> {
    m.flow_rule::<4>().with_relaxation(Some(
        Relaxation::duvaut_lions(tau, h, VOLUME, E, NU).unwrap(),
    ))
}

/// Overstress `‖dev σ‖ − R` of a von Mises point after `n` steps of `h` at deviatoric
/// strain rate `rate` (1/s) along a fixed unit deviator, from the yield surface.
fn von_mises_overstress(tau: f64, h: f64, n: usize, rate: f64, rho: f64) -> Vec<f64> {
    let m = material(0.0, 0.0);
    let radius = 2f64.sqrt() * 1e4;
    let d = SVector::<f64, 4>::new(1.0, -1.0, 0.0, 0.6);
    let d = deviator(&d) / deviator(&d).norm();
    let mut sigma = d * radius - identity::<4>() * 5e4;
    let rule = relaxed(&m, tau, h);
    let mut out = Vec::new();
    for _ in 0..n {
        let (s, _) = step(&m, rule, &sigma, &(d * (rate * h)), rho);
        sigma = s;
        out.push(deviator(&sigma).norm() - radius);
    }
    out
}

/// Eq. DL7's closed form to 1e-10 of `2Gτε̇`, at every step, for h/τ from 0.1 to 10 and
/// two ρ factors (the answer must not depend on the solver's ρ).
#[test]
fn von_mises_overstress_follows_the_discrete_duvaut_lions_recursion() {
    let two_g = E / (1.0 + NU);
    let rate = 1e-3;
    for (tau, h) in [(0.5, 0.05), (0.1, 0.1), (0.01, 0.1)] {
        let x_star = two_g * tau * rate;
        let q = tau / (tau + h);
        for rho in [1.0, 10.0] {
            let x = von_mises_overstress(tau, h, 40, rate, rho);
            let mut worst = 0.0f64;
            for (n, x_n) in x.iter().enumerate() {
                let closed = x_star * (1.0 - q.powi(n as i32 + 1));
                let err = (x_n - closed).abs() / x_star;
                assert!(
                    err <= 1e-10,
                    "τ {tau} h {h} ρ×{rho} n {n}: {x_n} vs {closed} ({err:e})"
                );
                worst = worst.max(err);
            }
            eprintln!("τ {tau} h {h} ρ×{rho}: worst |x_n − closed form| / 2Gτε̇ = {worst:.1e}");
        }
    }
}

/// The continuous overstress `2Gτε̇ (1 − e^{−t/τ})` at `t = τ` is approached at O(h): the
/// error halves with h (measured ratios 1.9–2.0; the leading term is
/// `x* e^{−1} h/(2τ)`).
#[test]
fn discrete_overstress_converges_to_the_continuous_one_at_first_order() {
    let (tau, rate) = (0.2, 1e-3);
    let x_star = E / (1.0 + NU) * tau * rate;
    let exact = x_star * (1.0 - (-1.0f64).exp());
    let mut errors = Vec::new();
    for n in [10usize, 20, 40, 80] {
        let h = tau / n as f64;
        let x = von_mises_overstress(tau, h, n, rate, 1.0);
        let err = (x[n - 1] - exact).abs() / x_star;
        let leading = (-1.0f64).exp() * h / (2.0 * tau);
        assert!(
            (err / leading - 1.0).abs() < 0.1,
            "n {n}: {err:e} vs {leading:e}"
        );
        errors.push(err);
    }
    eprintln!("error at t = τ for h = τ/10, τ/20, τ/40, τ/80: {errors:?}");
    for w in errors.windows(2) {
        let ratio = w[0] / w[1];
        assert!((1.85..=2.05).contains(&ratio), "{errors:?}");
    }
}

/// Non-associative Drucker-Prager through the solver: each relaxed step is the blend
/// `(σ_tr + (h/τ) σ₀)/(1 + h/τ)` of eq. DL3, `σ₀` the solver's rate-independent return of
/// the same trial, along a sheared and compressed path (lateral returns), for two ρ.
#[test]
fn drucker_prager_steps_are_the_blend_whatever_rho() {
    let m = material(27.0, 14.2906);
    let (tau, h) = (0.03, 0.01);
    let r = h / tau;
    let c = m.compliance::<4>().try_inverse().unwrap();
    let d_eps = SVector::<f64, 4>::new(-2e-4, 1.5e-4, 0.0, 1e-4);
    let mut sigma = -identity::<4>() * 5e4;
    let mut worst = 0.0f64;
    for n in 0..30 {
        let trial = sigma + c * d_eps;
        let (sigma0, _) = step(&m, m.flow_rule::<4>(), &sigma, &d_eps, 10.0);
        let blend = (trial + sigma0 * r) / (1.0 + r);
        let (a, _) = step(&m, relaxed(&m, tau, h), &sigma, &d_eps, 1.0);
        let (b, _) = step(&m, relaxed(&m, tau, h), &sigma, &d_eps, 10.0);
        for s in [a, b] {
            let err = (s - blend).norm() / trial.norm();
            assert!(err <= 1e-11, "step {n}: {err:e}");
            worst = worst.max(err);
        }
        sigma = a;
    }
    eprintln!("worst |σ − blend| / |σ_tr| over 30 steps, ρ × 1 and × 10: {worst:.1e}");
    assert!(
        m.yield_function(&sigma) > 0.0,
        "the path must end plastic, overstressed"
    );
}
