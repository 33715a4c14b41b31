//! One material point solved by the real solver: `W = S`, `q = −S σ_trial`, so that
//! `z = S (σ − σ_trial) = −Δεᵖ` (an implicit return mapping in natural-map form).
use nalgebra::{SMatrix, SVector};
use talus_bipotential::mandel::{deviator, hydrostatic_axis, trace};
use talus_bipotential::{ConeFit, DruckerPrager, DruckerPragerParameters};
use talus_ssn::faer::Mat;
use talus_ssn::{Operator, ReducedSystem, Settings, Solver};

use super::{CaseResult, Check};

pub(crate) fn soil(phi: f64, theta: f64) -> DruckerPrager {
    DruckerPrager::try_new(DruckerPragerParameters {
        young_modulus: 1e9,
        poisson_ratio: 0.3,
        friction_angle: phi,
        cohesion: 2e3,
        dilatancy_angle: theta,
        cone_fit: ConeFit::PlaneStrain,
    })
    .expect("valid verification material")
}

/// `(σ, Δεᵖ)` of the implicit return of `trial`.
pub(crate) fn return_map(
    material: &DruckerPrager,
    trial: &SVector<f64, 4>,
) -> Option<(SVector<f64, 4>, SVector<f64, 4>)> {
    let s: SMatrix<f64, 4, 4> = material.compliance();
    let w = Mat::from_fn(4, 4, |i, j| s[(i, j)]);
    let q = (-(s * trial)).as_slice().to_vec();
    let system =
        ReducedSystem::try_new(Operator::Dense(w), q, vec![material.flow_rule::<4>()]).ok()?;
    let mut solver = Solver::new(system, Settings::default()).ok()?;
    let mut sigma = trial.as_slice().to_vec();
    solver.solve(&mut sigma).ok()?;
    let sigma = SVector::from_column_slice(&sigma);
    Some((sigma, s * (trial - sigma)))
}

fn shear_trial(k: usize) -> SVector<f64, 4> {
    let a = k as f64 * 0.7 + 0.3;
    let dev = deviator(&SVector::<f64, 4>::from_fn(|i, _| {
        ((i as f64 + 1.0) * a).sin()
    }));
    dev / dev.norm() * 1e5 - SVector::from_fn(|i, _| if i < 3 { 2e4 } else { 0.0 })
}

/// `tr Δεᵖ / ‖dev Δεᵖ‖ = k_d tan θ` on plastic flow (`docs/conventions.md`, 'Flow rule').
pub fn dilatancy_ratio() -> Vec<CaseResult> {
    [(30.0, 0.0), (30.0, 15.0), (27.0, 14.2906), (30.0, 30.0)]
        .into_iter()
        .map(|(phi, theta)| {
            let m = soil(phi, theta);
            let mut worst = f64::NAN;
            let reference = m.k_d() * f64::to_radians(theta).tan();
            for k in 0..6 {
                let Some((_, eps)) = return_map(&m, &shear_trial(k)) else {
                    continue;
                };
                let ratio = trace(&eps) / deviator(&eps).norm();
                if worst.is_nan() || (ratio - reference).abs() > (worst - reference).abs() {
                    worst = ratio;
                }
            }
            CaseResult {
                case: format!("dilatancy_ratio_phi{phi}_theta{theta}"),
                quantity: "tr Δεᵖ / ‖dev Δεᵖ‖ (worst of 6 returns)".into(),
                reference,
                computed: worst,
                tolerance: 1e-10,
                check: Check::Absolute,
                seconds: 0.0,
                source:
                    "plastic potential g = ‖dev σ‖/k_d + p tan θ (docs/conventions.md, Flow rule)"
                        .into(),
            }
        })
        .collect()
}

/// Hydrostatic tension beyond the apex returns to `p = c / tan φ`.
pub fn apex_return() -> Vec<CaseResult> {
    let m = soil(30.0, 10.0);
    let trial = SVector::<f64, 4>::new(1e5, 1e5, 1e5, 0.0);
    let p = return_map(&m, &trial)
        .map(|(s, _)| trace(&s) / 3.0)
        .unwrap_or(f64::NAN);
    vec![CaseResult {
        case: "apex_return_hydrostatic_tension".into(),
        quantity: "p after return (Pa)".into(),
        reference: 2e3 / f64::to_radians(30.0).tan(),
        computed: p,
        tolerance: 1e-12,
        check: Check::Relative,
        seconds: 0.0,
        source: "apex of the cone, p = c / tan φ (eq. 7)".into(),
    }]
}

/// Associative flow is normal to the yield surface: `1 − cos(Δεᵖ, ∇f) = 0`.
pub fn associative_normality() -> Vec<CaseResult> {
    let m = soil(30.0, 30.0);
    let mut worst: f64 = 0.0;
    for k in 0..6 {
        let Some((sigma, eps)) = return_map(&m, &shear_trial(k)) else {
            return vec![];
        };
        let s = deviator(&sigma);
        let grad = s / (m.k_d() * s.norm())
            + hydrostatic_axis::<4>() * (f64::to_radians(30.0).tan() / 3f64.sqrt());
        worst = worst.max(1.0 - eps.dot(&grad) / (eps.norm() * grad.norm()));
    }
    vec![CaseResult {
        case: "associative_normality".into(),
        quantity: "1 − cos(Δεᵖ, ∇f) (worst of 6 returns)".into(),
        reference: 0.0,
        computed: worst,
        tolerance: 1e-12,
        check: Check::Absolute,
        seconds: 0.0,
        source: "normality rule, θ = φ".into(),
    }]
}
