//! `[material] relaxation_time = τ` (issue 24, item 2): Duvaut–Lions relaxation
//! (`docs/derivations.md`, 'Duvaut–Lions relaxation'; `docs/scenes.md`, 'Regions and
//! materials'). The key is checked in one place (`DruckerPrager::with_relaxation_time`);
//! absent, the rules are the rate-independent ones bit for bit; the one-element triaxial
//! follows the backward-Euler Duvaut–Lions overstress (eq. DL8); a shrinking τ converges to
//! the rate-independent footing at first order.
use crate::common;
use talus::model::fem::{FromScene, Model, ReactionForce};
use talus::model::mpm::MpmModel;
use talus::scene::MpmScene;
use talus_engine::Stepper;

use common::{
    fem, fem_error, footing_soil, footing_two_layers, replaced, with_material_key, FOOTING,
};

const TRIAXIAL: &str = include_str!("../../../scenes/triaxial.toml");
const COLUMN: &str = include_str!("../../../scenes/column_a1.toml");
const CAVITY: &str = include_str!("../../../scenes/cavity_expansion.toml");
/// `text` with `relaxation_time = {tau}` after its first `cone_fit` line.
fn with_tau(text: &str, tau: &str) -> String {
    with_material_key(text, &format!("relaxation_time = {tau}"))
}

/// The footing on a coarse mesh (16 × 7 P2 cells), `steps` steps.
fn coarse_footing(steps: usize) -> String {
    let text = replaced(FOOTING, "cells = [32, 14]", "cells = [16, 7]");
    replaced(&text, "steps = 300", &format!("steps = {steps}"))
}

/// A negative, zero, NaN or infinite τ is refused naming the field, its line and the value
/// (in `[material]`, in a `[[material]]` list, in an MPM scene); an elastic material
/// refuses the key.
#[test]
fn bad_relaxation_times_are_refused_naming_the_field_and_the_value() {
    for (tau, shown) in [
        ("-0.01", "-0.01"),
        ("0.0", "= 0"),
        ("nan", "NaN"),
        ("inf", "inf"),
        ("-inf", "-inf"),
    ] {
        let text = with_tau(FOOTING, tau);
        let e = fem_error(&text);
        let m = e.to_string();
        assert_eq!(e.field, "material.relaxation_time", "{m}");
        assert_eq!(
            e.line,
            Some(common::line_of(&text, &format!("relaxation_time = {tau}"))),
            "{m}"
        );
        assert!(
            m.contains(shown) && m.contains("τ > 0"),
            "`{shown}` not in: {m}"
        );
    }
    // In a list: the second material.
    let soil = footing_soil();
    let list = footing_two_layers(&with_tau(soil, "0.5"), &with_tau(soil, "-2.0"));
    let e = fem_error(&list);
    assert_eq!(e.field, "material[1].relaxation_time", "{e}");
    assert!(e.to_string().contains("-2"), "{e}");
    // MPM shares the check.
    let scene = MpmScene::parse(&with_tau(COLUMN, "0.0"), None).unwrap();
    let e = MpmModel::from_scene(&scene).err().expect("refused");
    assert_eq!(e.field, "material.relaxation_time", "{e}");
    // Elastic: a Drucker-Prager key.
    let elastic = "[material]\nmodel = \"elastic\"\nyoung_modulus = 1.0e9\npoisson_ratio = 0.3\n\
                   density = 2.0e3\nrelaxation_time = 0.01\n";
    let e = fem_error(&replaced(FOOTING, &format!("[material]\n{soil}"), elastic));
    assert_eq!(e.field, "material.relaxation_time", "{e}");
    assert!(e.to_string().contains("Drucker-Prager key"), "{e}");
}

/// A valid τ reaches every point's rule as `N = (τ/h)(V S₀)⁻¹` (its deviatoric modulus is
/// `2G τ/(h V)`), and the MPM materials carry it.
#[test]
fn a_relaxation_time_reaches_the_rules_of_fem_and_mpm() {
    let h = 0.01;
    let model = Model::from_scene(&fem(&with_tau(FOOTING, "0.02"))).unwrap();
    let rules = model.step_flow_rules(h).unwrap();
    let two_g = 1.0e9 / 1.3;
    for (p, rule) in rules.iter().enumerate() {
        let n = rule.relaxation().expect("relaxed");
        let expected = two_g * 0.02 / (h * model.assembly.gauss_volumes[p]);
        assert!((n.deviatoric() / expected - 1.0).abs() < 1e-14);
    }
    assert!(model.flow_rules().iter().all(|r| r.relaxation().is_none()));
    let scene = MpmScene::parse(&with_tau(COLUMN, "0.05"), None).unwrap();
    let mpm = MpmModel::from_scene(&scene).unwrap();
    assert_eq!(mpm.mpm.materials()[0].relaxation_time(), Some(0.05));
}

/// Without the key, every Gauss point's step rule is the rate-independent rule of
/// `Model::flow_rules` (whose code the relaxation left as it was), with no relaxation, and
/// the material has no relaxation time: the solver sees the problem it saw before, so the
/// run is the rate-independent one bit for bit (a run is a function of its model). Against
/// the code before the change, `docs/derivations.md`, 'Duvaut–Lions relaxation', records
/// the comparison of `history.csv` byte for byte.
#[test]
fn without_the_key_the_rules_and_the_run_are_rate_independent_bit_for_bit() {
    let scene = fem(&coarse_footing(15));
    let model = Model::from_scene(&scene).unwrap();
    let h = scene.spec.time.step;
    for hh in [h, h / 2.0, h / 16.0] {
        let rules = model.step_flow_rules(hh).unwrap();
        assert_eq!(rules, model.flow_rules());
        assert!(rules.iter().all(|r| r.relaxation().is_none()));
    }
    assert_eq!(model.materials[0].relaxation_time(), None);
}

/// The reactions (the reported boundary's, along its motion) and Newton iterations per step
/// of the scene `text` (the footing, the cavity) with relaxation time `tau` (s; `None`:
/// rate-independent).
fn footing_run(text: &str, tau: Option<f64>) -> (Vec<f64>, f64) {
    let text = match tau {
        Some(t) => with_tau(text, &format!("{t:e}")),
        None => text.to_string(),
    };
    let scene = fem(&text);
    let model = Model::from_scene(&scene).unwrap();
    let mut state = model.initial_state(&scene).unwrap();
    let mut stepper = Stepper::new(&model, scene.spec.solver.fem());
    let (mut reactions, mut iterations) = (Vec::new(), 0);
    for _ in 0..scene.spec.time.steps {
        let r = stepper
            .advance(&mut state, scene.spec.time.step)
            .unwrap_or_else(|e| panic!("τ = {tau:?}: {e}"));
        iterations += r.newton_iterations;
        reactions.push(r.reaction_force());
    }
    (reactions, iterations as f64 / scene.spec.time.steps as f64)
}

/// The τ/h of [`coarse_ladder`], each half the one before.
const LADDER: [f64; 4] = [0.04, 0.02, 0.01, 0.005];

/// The coarse footing (non-associative, 120 steps of h = 1e-2 s, past the mechanism's
/// onset) rate-independent, then at each τ/h of [`LADDER`]: the reactions of every step,
/// and the largest reaction of the rate-independent run (the scale of the differences).
/// Run once for the tests that read it.
struct Ladder {
    reference: Vec<f64>,
    scale: f64,
    relaxed: Vec<Vec<f64>>,
}

fn coarse_ladder() -> &'static Ladder {
    static LADDER_RUNS: std::sync::OnceLock<Ladder> = std::sync::OnceLock::new();
    LADDER_RUNS.get_or_init(|| {
        let text = coarse_footing(120);
        let h = 1e-2;
        let (reference, iterations) = footing_run(&text, None);
        eprintln!("τ = 0: {iterations:.2} iterations/step");
        let relaxed = LADDER
            .iter()
            .map(|ratio| {
                let (reactions, its) = footing_run(&text, Some(ratio * h));
                eprintln!("τ/h = {ratio}: {its:.2} iterations/step");
                reactions
            })
            .collect();
        let scale = reference.iter().fold(0.0f64, |m, r| m.max(r.abs()));
        Ladder {
            reference,
            scale,
            relaxed,
        }
    })
}

impl Ladder {
    /// The largest difference of `reactions` from the rate-independent run over the steps,
    /// relative to its largest reaction.
    fn error(&self, reactions: &[f64]) -> f64 {
        largest_difference(reactions, &self.reference, self.scale)
    }
}

/// The largest difference of `reactions` from `reference` over the steps, over `scale`.
fn largest_difference(reactions: &[f64], reference: &[f64], scale: f64) -> f64 {
    reactions
        .iter()
        .zip(reference)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
        / scale
}

/// Richardson's `2 R(τ/2) − R(τ)` (eq. DL10), step by step.
fn richardson(coarse: &[f64], fine: &[f64]) -> Vec<f64> {
    coarse.iter().zip(fine).map(|(c, f)| 2.0 * f - c).collect()
}

/// A shrinking τ converges to the rate-independent footing (non-associative, coarse mesh,
/// 120 steps of h = 1e-2 s, past the mechanism's onset): the largest reaction difference
/// over the run, relative to the largest reaction, falls as τ¹ (eq. DL9: the overstress is
/// `τ C ε̇ᵖ`). Measured: τ/h = 0.04, 0.02, 0.01, 0.005 give 7.5e-2, 3.9e-2, 2.0e-2, 1.0e-2,
/// orders 0.93, 0.95, 0.97 (so about `2 τ/h` here: E = 1e9 makes the overstress
/// `τ E ε̇ᵖ` large against c = 2 kPa).
#[test]
fn shrinking_tau_converges_to_the_rate_independent_footing_at_first_order() {
    let ladder = coarse_ladder();
    let errors: Vec<(f64, f64)> = LADDER
        .iter()
        .zip(&ladder.relaxed)
        .map(|(ratio, reactions)| (*ratio, ladder.error(reactions)))
        .collect();
    for (ratio, err) in &errors {
        eprintln!("τ/h = {ratio}: max |ΔR|/max R = {err:.3e}");
    }
    for w in errors.windows(2) {
        let order = (w[0].1 / w[1].1).ln() / (w[0].0 / w[1].0).ln();
        eprintln!("order between τ/h = {} and {}: {order:.3}", w[0].0, w[1].0);
        assert!((0.85..=1.15).contains(&order), "{errors:?}");
    }
    assert!(
        errors[0].1 > 1e-4,
        "τ = 0.4 h must change the run: {errors:?}"
    );
}

/// Richardson's extrapolation in τ (eq. DL10): two relaxed runs at τ and τ/2 combined step
/// by step as `2 R(τ/2) − R(τ)` cancel DL9's first-order term, so what is left falls at
/// second order as τ shrinks, and the combination gains more on its finer run at every
/// halving. Measured on the coarse footing (the ladder above): the pairs (0.04, 0.02),
/// (0.02, 0.01), (0.01, 0.005) h give 4.27e-3, 1.32e-3, 3.95e-4 (orders 1.70, 1.74)
/// against their finer runs' 3.93e-2, 2.03e-2, 1.04e-2 (9.2, 15.4, 26.2 times closer). With
/// a reaction not linear in τ to leading order, or pairs not a factor 2 apart, the order
/// would be about 1 and the gain would not grow.
#[test]
fn richardson_extrapolation_in_tau_converges_at_second_order() {
    let ladder = coarse_ladder();
    let mut rows: Vec<(f64, f64, f64)> = Vec::new();
    for (i, pair) in ladder.relaxed.windows(2).enumerate() {
        let extrapolated = richardson(&pair[0], &pair[1]);
        let (fine, combined) = (ladder.error(&pair[1]), ladder.error(&extrapolated));
        eprintln!(
            "τ/h = {} and {}: finer run {fine:.3e}, extrapolated {combined:.3e} ({:.1}× closer)",
            LADDER[i],
            LADDER[i + 1],
            fine / combined
        );
        rows.push((LADDER[i], fine, combined));
    }
    for w in rows.windows(2) {
        let order = (w[0].2 / w[1].2).ln() / (w[0].0 / w[1].0).ln();
        eprintln!(
            "extrapolation's order between τ/h = {} and {}: {order:.3}",
            w[0].0, w[1].0
        );
        assert!((1.5..=2.5).contains(&order), "{rows:?}");
        assert!(
            w[1].1 / w[1].2 > w[0].1 / w[0].2,
            "the gain must grow: {rows:?}"
        );
    }
    assert!(
        rows.iter().all(|(_, fine, combined)| combined < fine),
        "{rows:?}"
    );
}

/// The deviator `q = F/(π R²)` (Pa) of each step of the triaxial sample
/// (`scenes/triaxial.toml`) made von Mises (φ = ψ = 0, c = 55 kPa, outer cone: `q_y = 2c`),
/// relaxed by `tau` (s) if given; every step must be taken whole (no halving).
fn von_mises_triaxial(tau: Option<f64>) -> Vec<f64> {
    let mut text = TRIAXIAL.to_string();
    for (from, to) in [
        ("friction_angle = 30.0", "friction_angle = 0.0".to_string()),
        (
            "dilatancy_angle = 20.0",
            "dilatancy_angle = 0.0".to_string(),
        ),
        ("cohesion = 5.0e3", "cohesion = 5.5e4".to_string()),
        (
            "cone_fit = \"outer_cone\"",
            match tau {
                Some(t) => format!("cone_fit = \"outer_cone\"\nrelaxation_time = {t:e}"),
                None => "cone_fit = \"outer_cone\"".to_string(),
            },
        ),
    ] {
        text = replaced(&text, from, &to);
    }
    let scene = fem(&text);
    let model = Model::from_scene(&scene).unwrap();
    let mut state = model.initial_state(&scene).unwrap();
    let mut stepper = Stepper::new(&model, scene.spec.solver.fem());
    let area = std::f64::consts::PI * 0.025 * 0.025;
    (0..scene.spec.time.steps)
        .map(|_| {
            let r = stepper.advance(&mut state, scene.spec.time.step).unwrap();
            // One implicit step each: the closed form is that of steps of h.
            assert_eq!(r.substeps, 1, "a halved step at t = {}", r.time);
            r.reaction_force() / area
        })
        .collect()
}

/// The triaxial sample made von Mises and relaxed, τ = 0.1 s. Under the constant axial rate
/// `ė` with the cell pressure held, `q̇ = E ė − (q − q_y)/τ'`, `τ' = 3Gτ/E` (the flow is
/// deviatoric, `ε̇ᵖ = (σ − p)/(2Gτ)`, eq. DL1), and each implicit step is its backward Euler
/// (eq. DL8): `x_{n+1} = (x_n + E h ė)/(1 + h/τ')`, `x = q − q_y`, whose closed form from the
/// first fully plastic step m is `x_n = x* + (x_m − x*)(1 + h/τ')^{m−n}`, `x* = E ė τ'`.
/// Matched to 1e-5 of `x*` (measured 3.8e-6: the quasi-static inertia of the scene,
/// `inertia_ratio = 1e-4`, whose trace the rate-independent control shows too: 5.0e-5 of
/// x* off `q_y`).
#[test]
fn triaxial_overstress_follows_the_backward_euler_duvaut_lions_closed_form() {
    let (e, nu, c, tau, h, rate) = (5.0e7, 0.3, 5.5e4, 0.1, 0.05, 1.0e-2);
    let q_y = 2.0 * c;
    let tau_prime = 3.0 * e / (2.0 * (1.0 + nu)) * tau / e;
    let x_star = e * rate * tau_prime;
    let x: Vec<f64> = von_mises_triaxial(Some(tau))
        .iter()
        .map(|q| q - q_y)
        .collect();
    // Elastic steps: q = E ė t; the first step past q_y is partly elastic.
    let m = x.iter().position(|v| *v > 0.0).expect("yields") + 1;
    assert!((3..10).contains(&m), "first fully plastic step {m}");
    let mut worst = 0.0f64;
    for (n, x_n) in x.iter().enumerate().skip(m) {
        let closed = x_star + (x[m] - x_star) * (1.0 + h / tau_prime).powi(m as i32 - n as i32);
        worst = worst.max((x_n - closed).abs() / x_star);
    }
    // The control: without relaxation q stays at q_y once yielded.
    let plain = von_mises_triaxial(None);
    let control = plain[m..]
        .iter()
        .fold(0.0f64, |w, q| w.max((q - q_y).abs() / x_star));
    eprintln!(
        "x* = {x_star:.6e} Pa, x_end = {:.6e}, worst |x_n − closed form|/x* = {worst:.2e}, \
         rate-independent |q − q_y|/x* = {control:.2e}",
        x[x.len() - 1]
    );
    assert!(worst <= 1e-5, "{worst:e}");
    assert!(
        (x[x.len() - 1] / x_star - 1.0).abs() < 1e-5,
        "relaxed to x*"
    );
}

/// τ/h against the plateau's (last step's) and the run's largest reaction difference from
/// the rate-independent run of `text` (steps of `h`), and Newton iterations per step, as
/// table rows, then the row of Richardson's `2 R(0.01 h) − R(0.02 h)` (eq. DL10); asserts
/// that the differences fall with τ.
fn tau_table(name: &str, text: &str, h: f64) {
    let (reference, iterations) = footing_run(text, None);
    let last = reference[reference.len() - 1];
    let scale = reference.iter().fold(0.0f64, |m, r| m.max(r.abs()));
    eprintln!("{name}, τ = 0: plateau {last:.2}, {iterations:.2} iterations/step");
    let row = |label: String, reactions: &[f64], its: f64| {
        let plateau = reactions[reactions.len() - 1] / last - 1.0;
        let worst = largest_difference(reactions, &reference, scale);
        eprintln!("| {label} | {plateau:+.3e} | {worst:.3e} | {its:.2} |");
        worst
    };
    let mut previous = f64::INFINITY;
    let mut pair = Vec::new();
    for ratio in [1.0, 0.1, 0.02, 0.01, 0.001] {
        let (reactions, its) = footing_run(text, Some(ratio * h));
        let worst = row(ratio.to_string(), &reactions, its);
        assert!(worst < previous, "τ/h = {ratio}: {worst} after {previous}");
        previous = worst;
        if ratio == 0.02 || ratio == 0.01 {
            pair.push((reactions, its));
        }
    }
    let extrapolated = richardson(&pair[0].0, &pair[1].0);
    row(
        "2 R(0.01 h) − R(0.02 h)".into(),
        &extrapolated,
        pair[0].1 + pair[1].1,
    );
}

/// The τ table of issue 24 on the paper footing (`scenes/footing.toml`, 300 steps)
/// (`docs/derivations.md`, eq. DL9's table). A measurement (about 4 min, τ = h being
/// slow): `cargo test --release -p talus --test suite relaxation:: -- --ignored --nocapture`.
#[test]
#[ignore]
fn tau_table_on_the_paper_footing() {
    tau_table("paper footing", FOOTING, 1e-2);
}

/// The same on the non-associative cavity driven by displacement
/// (`scenes/cavity_expansion.toml`, 120 steps of 0.2 s), whose wall push the reaction
/// follows (`docs/derivations.md`, eq. DL9).
#[test]
#[ignore]
fn tau_table_on_the_cavity() {
    tau_table("cavity", CAVITY, 0.2);
}

/// With `relaxation_time = h` the paper footing (32 × 14, 300 steps of h = 1e-2 s) takes
/// every step whole, at most 15 Newton iterations in any (issue 24's target): the step
/// problem is unique for τ ≥ μ h (eq. DL6), and its solves reach the round-off floor of the
/// relaxed map, whose `N z` term scales z's rounding by ρ + ‖N‖ (`talus-ssn`'s
/// `stopping::floor_estimate`). Measured 2026-11-26: 5.3 iterations per step, at most 10;
/// before the floor counted `N`, 57.4 per step over 4 798 sub-steps.
#[test]
fn the_paper_footing_with_tau_equal_to_h_takes_every_step_whole() {
    let scene = fem(&with_tau(FOOTING, "1.0e-2"));
    let model = Model::from_scene(&scene).unwrap();
    let mut state = model.initial_state(&scene).unwrap();
    let mut stepper = Stepper::new(&model, scene.spec.solver.fem());
    let h = scene.spec.time.step;
    assert_eq!(h, 1e-2, "τ = h");
    for k in 1..=scene.spec.time.steps {
        let r = stepper
            .advance(&mut state, h)
            .unwrap_or_else(|e| panic!("step {k}: {e}"));
        assert_eq!(r.substeps, 1, "step {k} was split");
        assert!(
            r.max_newton_iterations <= 15,
            "step {k}: {} iterations",
            r.max_newton_iterations
        );
    }
}

/// A relaxed material ends its solves at the round-off floor (`docs/solver.md`, 'The
/// round-off floor'): `talus run` says so once at `warn`, not once a step, and counts
/// them in its last line.
#[test]
fn the_round_off_floor_of_a_relaxed_run_is_warned_once_and_counted() {
    let text = replaced(&with_tau(FOOTING, "1.0e-2"), "steps = 300", "steps = 20");
    let text = replaced(&text, "plots = true", "plots = false");
    let (_, stdout, stderr) = common::talus_run("relaxation", "floor_once", &text);
    let warned = stderr.matches("accepted at the round-off floor").count();
    let counted: usize = stdout
        .split(" accepted at the round-off floor")
        .next()
        .and_then(|head| head.rsplit('(').next())
        .and_then(|n| n.trim().parse().ok())
        .unwrap_or_else(|| panic!("no count in the last line: {stdout}"));
    assert_eq!(warned, 1, "{stderr}");
    // Each of the 20 steps is one sub-step (τ = h), and ends at the floor or below the
    // tolerance: at least one at the floor, since one was warned.
    assert!((1..=20).contains(&counted), "{counted}: {stdout}");
}
