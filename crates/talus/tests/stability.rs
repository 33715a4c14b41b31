//! Factor of safety (`docs/stability.md`): the published cases of `talus verify`, the
//! bracket, the by-hand check of the criterion, and the errors of `[stability]`.
use talus::scene::Scene;
use talus::verification::{slope_cases, vertical_cut_case, CaseResult};

fn assert_passed(results: &[CaseResult]) {
    for r in results {
        println!(
            "{}: {} = {} (reference {}, error {:.3e}, tolerance {}, {:.1} s)",
            r.case,
            r.quantity,
            r.computed,
            r.reference,
            r.error(),
            r.tolerance,
            r.seconds
        );
    }
    for r in results {
        assert!(r.passed(), "{r:?}");
    }
}

/// Griffiths & Lane (1999) example 1 within 3% of Bishop & Morgenstern's 1.38, the
/// bracket within 0.005, and the scene reduced by hand at 0.98 F at rest, at 1.02 F failing.
#[test]
fn slope_factor_of_safety_bracket_and_by_hand() {
    assert_passed(&slope_cases());
}

/// γH_c/c of a vertical cut in Tresca soil within 3% of Pastor et al. (2000).
#[test]
fn vertical_cut_stability_number() {
    assert_passed(&vertical_cut_case());
}

const SLOPE: &str = include_str!("../../../scenes/slope.toml");

fn error_of(text: &str) -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/slope.toml");
    let scene = match Scene::parse(text, Some(path)) {
        Ok(s) => s,
        Err(e) => return e.to_string(),
    };
    let out = std::env::temp_dir().join("talus-stability-errors");
    let options = talus::run::RunOptions {
        out_dir: out,
        progress: false,
        write_fields: false,
    };
    match talus::stability::Analysis::new(&scene) {
        Err(e) => e.to_string(),
        Ok(None) => "no [stability]".into(),
        Ok(Some(_)) => match talus::run::run_scene(&scene, &options) {
            Err(e) => format!("run_scene: {e}"),
            Ok(_) => "accepted".into(),
        },
    }
}

#[test]
fn bad_stability_input_names_the_field_and_value() {
    let with = |from: &str, to: &str| {
        assert!(SLOPE.contains(from), "{from}");
        error_of(&SLOPE.replacen(from, to, 1))
    };
    let cases = [
        (
            with("tolerance = 0.005", "tolerance = -0.1"),
            ["stability.tolerance", "-0.1"],
        ),
        (
            with(
                "tolerance = 0.005",
                "tolerance = 0.005\nbracket = [2.0, 1.0]",
            ),
            ["stability.bracket", "[2, 1]"],
        ),
        (
            with("tolerance = 0.005", "tolerance = 0.005\nmonitor = \"toe\""),
            ["stability.monitor", "\"toe\""],
        ),
        (
            with("tolerance = 0.005", "tolerance = 0.005\ntrial_steps = 1"),
            ["stability.trial_steps", "1 must"],
        ),
        (
            with(
                "method = \"strength_reduction\"",
                "method = \"gravity_increase\"",
            ),
            ["stability.dilatancy", "\"fixed\""],
        ),
        (
            with("dilatancy = \"fixed\"", "dilatancy = \"rotated\""),
            ["rotated", "scaled"],
        ),
        (
            with("kind = \"quasi_static\"", "kind = \"dynamic\""),
            ["analysis", "quasi_static"],
        ),
        (
            with("[4.0, 1.0]]", "[8.0, 1.0]]"),
            ["gravity_ramp", "t = 8 s"],
        ),
        (error_of(SLOPE), ["run_scene", "stability"]),
    ];
    for (message, needles) in cases {
        for n in needles {
            assert!(message.contains(n), "`{n}` not in: {message}");
        }
    }
}
