//! Construction rejects every parameter outside its domain, naming it.
use talus_bipotential::{ConeFit, DruckerPrager, DruckerPragerParameters, MaterialError};

fn base() -> DruckerPragerParameters {
    DruckerPragerParameters {
        young_modulus: 1e9,
        poisson_ratio: 0.3,
        friction_angle: 27.0,
        cohesion: 2e3,
        dilatancy_angle: 10.0,
        cone_fit: ConeFit::PlaneStrain,
    }
}

fn rejected(p: DruckerPragerParameters, name: &str) {
    match DruckerPrager::try_new(p) {
        Err(e @ MaterialError::InvalidParameter { .. }) => {
            let msg = e.to_string();
            assert!(msg.contains(name), "message `{msg}` should name {name}");
        }
        Ok(_) => panic!("{name}: accepted {p:?}"),
    }
}

#[test]
fn rejects_out_of_domain_parameters() {
    rejected(
        DruckerPragerParameters {
            friction_angle: 90.0,
            ..base()
        },
        "friction_angle",
    );
    rejected(
        DruckerPragerParameters {
            friction_angle: -1.0,
            ..base()
        },
        "friction_angle",
    );
    rejected(
        DruckerPragerParameters {
            dilatancy_angle: 28.0,
            ..base()
        },
        "dilatancy_angle",
    );
    rejected(
        DruckerPragerParameters {
            dilatancy_angle: -0.1,
            ..base()
        },
        "dilatancy_angle",
    );
    rejected(
        DruckerPragerParameters {
            poisson_ratio: 0.5,
            ..base()
        },
        "poisson_ratio",
    );
    rejected(
        DruckerPragerParameters {
            poisson_ratio: -1.0,
            ..base()
        },
        "poisson_ratio",
    );
    rejected(
        DruckerPragerParameters {
            young_modulus: 0.0,
            ..base()
        },
        "young_modulus",
    );
    rejected(
        DruckerPragerParameters {
            young_modulus: -5.0,
            ..base()
        },
        "young_modulus",
    );
    rejected(
        DruckerPragerParameters {
            cohesion: -1.0,
            ..base()
        },
        "cohesion",
    );
    rejected(
        DruckerPragerParameters {
            cohesion: f64::NAN,
            ..base()
        },
        "cohesion",
    );
    rejected(
        DruckerPragerParameters {
            young_modulus: f64::INFINITY,
            ..base()
        },
        "young_modulus",
    );
    rejected(
        DruckerPragerParameters {
            friction_angle: f64::NAN,
            ..base()
        },
        "friction_angle",
    );
    rejected(
        DruckerPragerParameters {
            cone_fit: ConeFit::Explicit { k_d: 0.0 },
            ..base()
        },
        "k_d",
    );
    rejected(
        DruckerPragerParameters {
            cone_fit: ConeFit::Explicit { k_d: f64::NAN },
            ..base()
        },
        "k_d",
    );
    rejected(
        DruckerPragerParameters {
            friction_angle: 0.0,
            dilatancy_angle: 0.0,
            cohesion: 0.0,
            ..base()
        },
        "cohesion",
    );
}

/// A k_d that is finite and > 0 yet flattens or overflows the set `flow_rule` builds (the
/// fuzz test's mutated scenes found the first: k_d = 4.9e-324 in `column_newton_fine`).
#[test]
fn rejects_a_k_d_whose_yield_set_underflows_or_overflows() {
    for (friction_angle, cohesion, k_d) in [
        (10.0, 2e3, 4.9e-324),
        (89.0, 2e3, 1e307),
        (0.0, 1e300, 1e300),
    ] {
        rejected(
            DruckerPragerParameters {
                friction_angle,
                dilatancy_angle: 0.0,
                cohesion,
                cone_fit: ConeFit::Explicit { k_d },
                ..base()
            },
            "k_d",
        );
    }
    // Small and large values whose set is representable stay accepted and build.
    for (friction_angle, k_d) in [(27.0, 1e-300), (0.0, 1e-300), (27.0, 1e300)] {
        let m = DruckerPrager::try_new(DruckerPragerParameters {
            friction_angle,
            dilatancy_angle: 0.0,
            cone_fit: ConeFit::Explicit { k_d },
            ..base()
        })
        .expect("representable set");
        let _ = m.flow_rule::<4>();
    }
}

#[test]
fn accepts_the_extremes_of_each_domain() {
    for p in [
        DruckerPragerParameters {
            friction_angle: 0.0,
            dilatancy_angle: 0.0,
            ..base()
        },
        DruckerPragerParameters {
            friction_angle: 89.9,
            dilatancy_angle: 89.9,
            ..base()
        },
        DruckerPragerParameters {
            cohesion: 0.0,
            ..base()
        },
        DruckerPragerParameters {
            poisson_ratio: 0.4999,
            ..base()
        },
        DruckerPragerParameters {
            dilatancy_angle: 27.0,
            ..base()
        },
    ] {
        let m = DruckerPrager::try_new(p).unwrap();
        let rule = m.flow_rule::<4>();
        assert!(rule.kappa().is_finite() && rule.kappa() >= 0.0);
    }
}

/// Found by `crates/talus/tests/fuzz_scene_reader.rs`: φ = 1e-300° passed validation with
/// c = 1e8 Pa, and `flow_rule` then panicked ("validated Drucker-Prager parameters always
/// give a valid yield set") on the apex c / tan φ = inf.
#[test]
fn a_friction_angle_whose_apex_overflows_is_refused() {
    let tiny = DruckerPragerParameters {
        friction_angle: 1e-300,
        dilatancy_angle: 0.0,
        cohesion: 1e8,
        ..base()
    };
    rejected(tiny, "friction_angle");
    let msg = DruckerPrager::try_new(tiny).unwrap_err().to_string();
    assert!(msg.contains("cohesion / tan(friction_angle)"), "{msg}");
    // Without cohesion the apex is the origin: valid, and its flow rule is built.
    let cohesionless = DruckerPrager::try_new(DruckerPragerParameters {
        cohesion: 0.0,
        ..tiny
    })
    .unwrap();
    let _ = cohesionless.flow_rule::<4>();
}

/// A positive friction angle whose radians underflow to 0 (4.9e-324°) is neither a cone nor
/// the von Mises cylinder: refused by name, never a flow rule that panics.
#[test]
fn a_friction_angle_that_underflows_to_zero_radians_is_refused() {
    for cohesion in [0.0, 1e3] {
        let p = DruckerPragerParameters {
            friction_angle: 4.9e-324,
            dilatancy_angle: 0.0,
            cohesion,
            ..base()
        };
        rejected(p, "friction_angle");
    }
}
