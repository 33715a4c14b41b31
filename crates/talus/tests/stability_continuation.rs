//! The continued factor-of-safety search (issue 24, item 5; `docs/stability.md`, 'Search'):
//! each trial from the largest stable trial's state, the next factor extrapolated from the
//! trials' load–displacement curve. Its bracket keeps its meaning — the lower end a trial
//! the criterion calls stable, the upper one a trial it calls failing — and brackets what
//! the blind search (every trial from the loading's equilibrium, doubling and bisection)
//! brackets. Limit analysis gives one collapse factor whatever the load path for
//! associative perfect plasticity (the uniqueness of the limit load, Chen 1975, ch. 2;
//! Drucker, Prager & Greenberg 1952), so a bracket from another path must agree.
use crate::common;
use talus::analysis::stability::{self, Analysis, StabilityRun, Trial, Verdict};
use talus::model::fem::State;
use talus::run::RunOptions;
use talus::scene::Scene;

/// `scenes/vertical_cut.toml` (Tresca, associative) on 16 × 8 cells, by `method`, with
/// `from` replaced by `to` (nothing when `from` is empty).
fn cut_with(method: &str, from: &str, to: &str) -> Scene {
    let text = include_str!("../../../scenes/vertical_cut.toml");
    assert!(text.contains("cells = [32, 16]"), "test setup");
    let text = text
        .replacen("cells = [32, 16]", "cells = [16, 8]", 1)
        .replacen("plots = true", "plots = false", 1)
        .replacen(
            "method = \"gravity_increase\"",
            &format!("method = \"{method}\""),
            1,
        );
    assert!(text.contains(from), "test setup: {from}");
    let text = if from.is_empty() {
        text
    } else {
        text.replacen(from, to, 1)
    };
    Scene::parse(&text, None).unwrap()
}

fn cut(method: &str) -> Scene {
    cut_with(method, "", "")
}

/// Newton iterations of a search's trials.
fn trial_iterations(run: &StabilityRun) -> usize {
    run.trials.iter().map(|t| t.newton_iterations).sum()
}

/// Two searches bracket the same collapse factor: each factor within the other's bracket
/// widened by both widths.
fn assert_same_collapse(label: &str, a: &StabilityRun, b: &StabilityRun) {
    let ((la, ha), (lb, hb)) = (bracket(a), bracket(b));
    let (fa, fb) = (
        a.factor_of_safety.value.expect("a factor"),
        b.factor_of_safety.value.expect("a factor"),
    );
    assert!(
        (fa - fb).abs() <= (ha - la) + (hb - lb),
        "{label}: {fa} [{la}, {ha}] vs {fb} [{lb}, {hb}]"
    );
}

fn bracket(run: &StabilityRun) -> (f64, f64) {
    let [lo, hi] = run.factor_of_safety.bracket;
    (lo.expect("lo"), hi.expect("hi"))
}

/// The end state of the stable trial at `f` of `trials`, re-run from the equilibrium
/// along its chain of starts (the criterion's steps as the analysis has them).
fn end_state(analysis: &mut Analysis, trials: &[Trial], f: f64, equilibrium: &State) -> State {
    let t = trials.iter().find(|t| t.factor == f).expect("a trial");
    let start = t.start.map(|s| end_state(analysis, trials, s, equilibrium));
    let start = (start.as_ref().unwrap_or(equilibrium), t.start);
    let (again, state) = analysis.trial_from(f, start, equilibrium).unwrap();
    assert_eq!(again.verdict, Verdict::Stable, "F = {f} again");
    state.expect("a stable trial's state")
}

#[test]
fn the_continued_search_brackets_what_the_blind_search_brackets() {
    for method in ["gravity_increase", "strength_reduction"] {
        let scene = cut(method);
        let out = |name: &str| {
            RunOptions::new(common::target_tmp_dir(
                "stability_continuation",
                &format!("{method}_{name}"),
            ))
        };
        let new = stability::run(&scene, &out("continued")).unwrap();
        let old = stability::run_blind(&scene, &out("blind")).unwrap();
        let (fn_, fo) = (
            new.factor_of_safety.value.expect("a factor"),
            old.factor_of_safety.value.expect("a factor"),
        );
        let ((ln, hn), (lo, ho)) = (bracket(&new), bracket(&old));
        println!(
            "{method}: continued {fn_} in [{ln}, {hn}] ({} trials, {} Newton iterations), \
             blind {fo} in [{lo}, {ho}] ({} trials, {} Newton iterations)",
            new.trials.len(),
            trial_iterations(&new),
            old.trials.len(),
            trial_iterations(&old),
        );
        assert_same_collapse(method, &new, &old);
        assert!(hn - ln <= 0.005 * ln && ho - lo <= 0.005 * lo);

        // The bracket's meaning, checked beyond the search's steps: its ends run again
        // from their start states for 30 steps, the lower one comes to rest, the upper
        // one fails (a trial merely not at rest within the search's steps would not).
        let mut analysis = Analysis::new(&scene).unwrap().unwrap();
        let equilibrium = analysis.equilibrium(&scene).unwrap().state;
        analysis.criterion.set_scale(&equilibrium.displacement);
        assert!(analysis.settings.continuation);
        let trial_steps = analysis.criterion.max_steps;
        for f in [ln, hn] {
            let t = new.trials.iter().find(|t| t.factor == f).expect("a trial");
            // The start states re-run with the search's steps, the end with 30.
            let start = t
                .start
                .map(|s| end_state(&mut analysis, &new.trials, s, &equilibrium));
            analysis.criterion.max_steps = 30;
            let start = (start.as_ref().unwrap_or(&equilibrium), t.start);
            let (again, _) = analysis.trial_from(f, start, &equilibrium).unwrap();
            analysis.criterion.max_steps = trial_steps;
            println!(
                "{method}: F = {f} from {:?} again: {:?} in {} steps",
                t.start,
                again.verdict,
                again.steps()
            );
            if f == ln {
                assert_eq!(again.verdict, Verdict::Stable, "{method} F = {f}");
            } else {
                assert!(again.fails(), "{method} F = {f}: {:?}", again.verdict);
            }
        }

        // Each trial started from the largest stable trial before it below the smallest
        // failing one before it (the equilibrium before any), and below its own factor.
        for (k, t) in new.trials.iter().enumerate() {
            let earlier = &new.trials[..k];
            let hi = earlier
                .iter()
                .filter(|p| p.fails())
                .map(|p| p.factor)
                .fold(f64::INFINITY, f64::min);
            let expected = earlier
                .iter()
                .filter(|p| p.verdict == Verdict::Stable && p.factor < hi)
                .map(|p| p.factor)
                .reduce(f64::max);
            assert_eq!(t.start, expected, "{method}: trial {k} at F = {}", t.factor);
            assert!(t.start.is_none_or(|s| s < t.factor), "{method}: trial {k}");
        }
        // The blind search restarts every trial from the equilibrium, at the loading's
        // Newton tolerance.
        assert!(old.trials.iter().all(|t| t.start.is_none()));
        assert_eq!(old.factor_of_safety.newton_tolerance, Some(1e-12));
    }
}

/// For this associative material the bracket's ends keep their verdicts on the blind
/// search's path too: the lower end, tried from the loading's equilibrium, comes to rest,
/// and the upper end fails (uniqueness of the limit load: the verdict is the factor's,
/// not the path's, away from the collapse factor's immediate neighbourhood).
#[test]
fn the_bracket_ends_keep_their_verdicts_from_the_equilibrium() {
    let scene = cut("gravity_increase");
    let new = stability::run(
        &scene,
        &RunOptions::new(common::target_tmp_dir("stability_continuation", "ends")),
    )
    .unwrap();
    let (lo, hi) = bracket(&new);
    let mut analysis = Analysis::new(&scene).unwrap().unwrap();
    let equilibrium = analysis.equilibrium(&scene).unwrap();
    analysis
        .criterion
        .set_scale(&equilibrium.state.displacement);
    analysis.criterion.max_steps = 30;
    let at_lo = analysis.trial(lo, &equilibrium.state).unwrap();
    let at_hi = analysis.trial(hi, &equilibrium.state).unwrap();
    println!(
        "from the equilibrium: F = {lo} {:?} in {} steps, F = {hi} {:?} in {} steps",
        at_lo.verdict,
        at_lo.steps(),
        at_hi.verdict,
        at_hi.steps()
    );
    assert_eq!(at_lo.verdict, Verdict::Stable);
    assert!(at_hi.fails(), "{:?}", at_hi.verdict);
}

/// The trials' Newton tolerance (`[stability] newton_tolerance`, default 1e-10 or a looser
/// `[solver] tolerance`) trades Newton iterations, not the bracket: the search at the
/// default and at the loading's 1e-12 bracket the same collapse factor (each within the
/// other's bracket widened by both widths), the default with fewer iterations.
#[test]
fn the_trials_newton_tolerance_trades_iterations_not_the_bracket() {
    let scene = cut("gravity_increase");
    let analysis = Analysis::new(&scene).unwrap().unwrap();
    assert_eq!(analysis.settings.newton_tolerance, 1e-10);
    let with = |from: &str, to: &str| cut_with("gravity_increase", from, to);
    // A looser [solver] tolerance is kept (scenes/slope_3d.toml's 1e-8).
    let loose = with("[stability]", "[solver]\ntolerance = 1e-8\n\n[stability]");
    let loose = Analysis::new(&loose).unwrap().unwrap();
    assert_eq!(loose.settings.newton_tolerance, 1e-8);
    let tight = with("[stability]", "[stability]\nnewton_tolerance = 1e-12");
    let out = |name: &str| RunOptions::new(common::target_tmp_dir("stability_continuation", name));
    let default = stability::run(&scene, &out("tolerance_default")).unwrap();
    let strict = stability::run(&tight, &out("tolerance_strict")).unwrap();
    let ((ld, hd), (ls, hs)) = (bracket(&default), bracket(&strict));
    let (fd, fs) = (
        default.factor_of_safety.value.expect("a factor"),
        strict.factor_of_safety.value.expect("a factor"),
    );
    println!(
        "trials at 1e-10: {fd} in [{ld}, {hd}], {} Newton iterations; at 1e-12: {fs} in \
         [{ls}, {hs}], {}",
        trial_iterations(&default),
        trial_iterations(&strict)
    );
    assert_same_collapse("trials at 1e-10 and 1e-12", &default, &strict);
    assert!(trial_iterations(&default) < trial_iterations(&strict));
    // summary.json says which tolerance the trials used.
    assert_eq!(default.factor_of_safety.newton_tolerance, Some(1e-10));
    assert_eq!(strict.factor_of_safety.newton_tolerance, Some(1e-12));
}
