//! Stability at the extremes (`docs/extremes.md`): a few of the fastest cases of the matrix
//! of `src/bin/extremes.rs`, on the 16 × 7 P2 footing. Each run either converges at every
//! step with finite values everywhere (history, final stress, velocities, displacements) or
//! stops with a clear error, asserted on its message; never a NaN, a panic, or a step
//! returned as converged above the tolerance.
#[path = "../src/bin/extremes.rs"]
mod extremes;

use extremes::{jaky, paper_theta, run_case, Case, Loading, Measured, Outcome};

fn run(name: &str, case: &Case) -> Measured {
    let out = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("extremes")
        .join(name);
    let m = run_case(case, &out);
    match &m.outcome {
        Outcome::Converged | Outcome::Error(_) => m,
        other => panic!("{name} ({}): {other:?}", case.label),
    }
}

/// Every step converged, with a finite force.
fn assert_converged(name: &str, case: &Case) -> Measured {
    let m = run(name, case);
    assert_eq!(m.outcome, Outcome::Converged, "{name} ({})", case.label);
    assert_eq!(m.steps, case.steps, "{name}");
    if let Some(f) = m.final_force {
        assert!(f.is_finite() && f > 0.0, "{name}: final force {f}");
    }
    assert!(m.settlement.is_some_and(f64::is_finite), "{name}");
    m
}

/// The run stopped with an error whose first line contains every one of `needles`.
fn assert_error(name: &str, case: &Case, needles: &[&str]) {
    let m = run(name, case);
    let Outcome::Error(msg) = &m.outcome else {
        panic!(
            "{name} ({}): expected an error, got {:?}",
            case.label, m.outcome
        )
    };
    for n in needles {
        assert!(msg.contains(n), "{name}: `{n}` not in `{msg}`");
    }
}

/// Either every step converged or the run stopped with a non-convergence error naming the
/// step (both are acceptable at these extremes; a NaN or a panic is not).
fn assert_converged_or_clear_failure(name: &str, case: &Case) -> Measured {
    let m = run(name, case);
    if let Outcome::Error(msg) = &m.outcome {
        assert!(
            msg.starts_with("step ") && msg.contains("did not converge"),
            "{name}: unclear error `{msg}`"
        );
    } else {
        assert_eq!(m.steps, case.steps, "{name}");
    }
    m
}

fn von_mises(k0: f64, cohesion: f64) -> Case {
    Case {
        phi: 0.0,
        theta: 0.0,
        k0,
        cohesion,
        ..Case::base()
    }
}

#[test]
fn extremes_von_mises_phi0() {
    // φ = 0 with Jaky's K₀ = 1 (a hydrostatic start) runs; the load is about (2 + π) c b
    // plus the surcharge's q b.
    let m = assert_converged("von_mises", &von_mises(jaky(0.0), 2e3));
    let f = m.final_force.unwrap();
    assert!(f > 10e3 && f < 25e3, "von Mises footing force {f}");
    // The paper's K₀ = 0.546 puts deep points outside the cylinder ‖dev σ‖ ≤ √2 c: refused,
    // naming the field.
    assert_error(
        "von_mises_k0",
        &von_mises(0.546, 2e3),
        &["initial_stress.k0", "outside the yield cone"],
    );
    // A cylinder of radius 0 is refused before any step.
    assert_error(
        "von_mises_c0",
        &von_mises(1.0, 0.0),
        &["material.cohesion", "friction_angle = 0"],
    );
}

#[test]
fn extremes_purely_frictional_c0() {
    let c0 = assert_converged(
        "frictional_c0",
        &Case {
            cohesion: 0.0,
            ..Case::base()
        },
    );
    let base_force = 224.5e3;
    let f = c0.final_force.unwrap();
    assert!(f > 0.5 * base_force && f < base_force, "c = 0 force {f}");
}

#[test]
fn extremes_nearly_incompressible_nu0499() {
    assert_converged(
        "nu0499",
        &Case {
            nu: 0.499,
            ..Case::base()
        },
    );
    // Much closer to 1/2 the compliance is singular to round-off along the hydrostatic
    // axis: a clear non-convergence error is acceptable, not a NaN.
    assert_converged_or_clear_failure(
        "nu04999999",
        &Case {
            nu: 0.4999999,
            ..Case::base()
        },
    );
}

#[test]
fn extremes_large_step_h1() {
    // The same 1 mm in 50 steps of 1 s: steps may be halved, but every one converges.
    let h = 1.0;
    assert_converged(
        "h1",
        &Case {
            h,
            loading: Loading::Velocity(extremes::BASE_VELOCITY * extremes::BASE_H / h),
            ..Case::base()
        },
    );
}

#[test]
fn extremes_non_associative_theta0() {
    assert_converged(
        "theta0",
        &Case {
            theta: 0.0,
            ..Case::base()
        },
    );
}

#[test]
fn extremes_high_friction() {
    // Jaky's K₀ = 1 − sin 45° is outside the plane-strain cone: refused, naming the field.
    let jaky45 = Case {
        phi: 45.0,
        theta: paper_theta(45.0),
        k0: jaky(45.0),
        ..Case::base()
    };
    assert_error("phi45_jaky", &jaky45, &["initial_stress.k0", "yield cone"]);
    assert_converged(
        "phi60",
        &Case {
            phi: 60.0,
            theta: paper_theta(60.0),
            k0: 0.5,
            ..Case::base()
        },
    );
}

#[test]
fn extremes_past_collapse() {
    // 10 × the plateau onset (5 mm) in 50 steps: the force stays on its plateau.
    let m = assert_converged_or_clear_failure(
        "collapse_velocity",
        &Case {
            loading: Loading::Velocity(10.0 * extremes::PLATEAU_ONSET / (50.0 * extremes::BASE_H)),
            ..Case::base()
        },
    );
    if m.outcome == Outcome::Converged {
        let f = m.final_force.unwrap();
        assert!((f - 227e3).abs() < 0.05 * 227e3, "plateau force {f}");
    }
    // A pressure twice the capacity, no footing: no static equilibrium exists, the soil
    // under it accelerates and the run ends in collapse (`docs/scenes.md`, 'Collapse').
    assert_error(
        "collapse_pressure",
        &Case {
            loading: Loading::Pressure(900e3),
            ..Case::base()
        },
        &[
            "collapse at step",
            "the loads exceed what the body can carry",
        ],
    );
}
