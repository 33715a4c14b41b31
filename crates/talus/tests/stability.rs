//! Factor of safety (`docs/stability.md`): the published cases of `talus verify`, the
//! bracket, the by-hand check of the criterion, and the errors of `[stability]`.
use talus::analysis::verification::{
    slope_cases, vertical_cut_case, vertical_cut_fenicsx_case, CaseResult,
};
use talus::scene::Scene;

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
    let cases = slope_cases();
    assert_passed(&cases);
    // The run's files: one history row per trial after the loading's, summary.json's
    // factor_of_safety (also the run's last line), the mechanism.
    let dir = talus::analysis::verification::case_dir("slope");
    let summary = talus::output::Summary::read(&dir.join("summary.json")).unwrap();
    let fos = summary.factor_of_safety.clone().unwrap();
    assert_eq!(fos.value, Some(cases[0].computed));
    assert_eq!(fos.method, "strength_reduction");
    let [lo, hi] = fos.bracket;
    assert!(lo.unwrap() < fos.value.unwrap() && fos.value.unwrap() < hi.unwrap());
    let sentence = summary.sentence();
    assert!(
        sentence.contains(&format!(
            "factor of safety {:.4} in [{:.4}, {:.4}]",
            fos.value.unwrap(),
            lo.unwrap(),
            hi.unwrap()
        )),
        "{sentence}"
    );
    let history = std::fs::read_to_string(dir.join("history.csv")).unwrap();
    let rows: Vec<Vec<&str>> = history
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(rows.len(), fos.trials + 1);
    assert_eq!(rows[0][2], "equilibrium");
    for r in &rows[1..] {
        assert!(
            ["stable", "fails", "not_at_rest", "not_converged"].contains(&r[2]),
            "{r:?}"
        );
    }
    // The bracket's ends are trials with those outcomes.
    let outcome = |f: f64| {
        rows[1..]
            .iter()
            .find(|r| r[1].parse::<f64>().unwrap() == f)
            .map(|r| r[2])
    };
    assert_eq!(outcome(lo.unwrap()), Some("stable"));
    assert!(matches!(
        outcome(hi.unwrap()),
        Some("fails" | "not_at_rest")
    ));
    for file in ["mechanism.png", "mechanism.vtu"] {
        assert!(
            std::fs::metadata(dir.join(file)).unwrap().len() > 1000,
            "{file}"
        );
    }
}

/// γH_c/c of a vertical cut in Tresca soil within 3% of Pastor et al. (2000).
#[test]
fn vertical_cut_stability_number() {
    assert_passed(&vertical_cut_case());
}

/// γH_c/c of FEniCSx's vertical cut (φ = ψ = 30°) within 2% of Chen's (1975) 6.69.
#[test]
fn fenicsx_vertical_cut_stability_number() {
    assert_passed(&vertical_cut_fenicsx_case());
}

const SLOPE: &str = include_str!("../../../scenes/slope.toml");

fn error_of(text: &str) -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/slope.toml");
    let scene = match Scene::parse(text, Some(path)) {
        Ok(s) => s,
        Err(e) => return e.to_string(),
    };
    let out = std::env::temp_dir().join("talus-stability-errors");
    let options = talus::run::RunOptions::new(out);
    match talus::analysis::stability::Analysis::new(&scene) {
        Err(e) => e.to_string(),
        Ok(None) => "no [stability]".into(),
        Ok(Some(_)) => match talus::run::fem::run_scene(&scene, &options) {
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
    // The trials' Newton tolerance: negative, zero, NaN, infinite (as the error prints it).
    for (value, shown) in [
        ("-1e-10", "-0.0000000001"),
        ("0.0", "0"),
        ("nan", "NaN"),
        ("inf", "inf"),
    ] {
        let message = with(
            "tolerance = 0.005",
            &format!("tolerance = 0.005\nnewton_tolerance = {value}"),
        );
        for n in ["stability.newton_tolerance", &format!("{shown} must")] {
            assert!(message.contains(n), "`{n}` not in: {message}");
        }
    }
}
