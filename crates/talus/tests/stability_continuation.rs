//! The continued factor-of-safety search (issue 24, item 5; `docs/stability.md`, 'Search'):
//! each trial from the largest stable trial's state, the next factor extrapolated from the
//! trials' load–displacement curve. Its bracket keeps its meaning — the lower end a trial
//! the criterion calls stable, the upper one a trial it calls failing — and brackets what
//! the blind search (every trial from the loading's equilibrium, doubling and bisection)
//! brackets. Limit analysis gives one collapse factor whatever the load path for
//! associative perfect plasticity (the uniqueness of the limit load, Chen 1975, ch. 2;
//! Drucker, Prager & Greenberg 1952), so a bracket from another path must agree.
mod common;

use talus::analysis::stability::{self, Analysis, Criterion, StabilityRun, Verdict};
use talus::run::RunOptions;
use talus::scene::Scene;

/// `scenes/vertical_cut.toml` (Tresca, associative) on 16 × 8 cells, by `method`.
fn cut(method: &str) -> Scene {
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
    Scene::parse(&text, None).unwrap()
}

fn bracket(run: &StabilityRun) -> (f64, f64) {
    let [lo, hi] = run.factor_of_safety.bracket;
    (lo.expect("lo"), hi.expect("hi"))
}

/// The criterion of the scene, its scale `U` from the loading (as `search` sets it).
fn criterion(scene: &Scene) -> Criterion {
    let mut analysis = Analysis::new(scene).unwrap().unwrap();
    let equilibrium = analysis.equilibrium(scene).unwrap();
    let mut c = analysis.criterion.clone();
    c.set_scale(&equilibrium.state.displacement);
    c
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
            new.trials
                .iter()
                .map(|t| t.newton_iterations)
                .sum::<usize>(),
            old.trials.len(),
            old.trials
                .iter()
                .map(|t| t.newton_iterations)
                .sum::<usize>(),
        );
        // Each within the other's bracket widened by both widths.
        assert!(
            (fn_ - fo).abs() <= (hn - ln) + (ho - lo),
            "{method}: {fn_} [{ln}, {hn}] vs {fo} [{lo}, {ho}]"
        );
        assert!(hn - ln <= 0.005 * ln && ho - lo <= 0.005 * lo);

        // The bracket's meaning: the lower end a trial the criterion calls stable, the
        // upper one a trial it calls failing, judged again from their increments.
        let c = criterion(&scene);
        let judged = |f: f64| {
            let t = new.trials.iter().find(|t| t.factor == f).expect("a trial");
            let n = (1..=t.increments.len())
                .find(|&n| c.judge(&t.increments[..n]).is_some())
                .expect("a verdict");
            assert_eq!(
                n,
                t.increments.len(),
                "{method} F = {f}: judged at its last step"
            );
            (t.verdict, c.judge(&t.increments).unwrap())
        };
        assert_eq!(judged(ln), (Verdict::Stable, Verdict::Stable), "{method}");
        let (v, again) = judged(hn);
        assert!(v.fails() && again.fails(), "{method}: {v:?} {again:?}");

        // Each trial started from the largest stable trial before it and below it (the
        // equilibrium before any), and only stable trials are starts.
        for (k, t) in new.trials.iter().enumerate() {
            let expected = new.trials[..k]
                .iter()
                .filter(|p| p.verdict == Verdict::Stable && p.factor < t.factor)
                .map(|p| p.factor)
                .fold(None, |m: Option<f64>, f| Some(m.map_or(f, |m| m.max(f))));
            // A stable trial above a failing one is no start (the bracket ignores it).
            if let (Some(e), Some(s)) = (expected, t.start) {
                assert!(
                    s <= e,
                    "{method}: trial {k} from {s}, largest stable below {e}"
                );
            }
            assert!(
                t.start.is_none_or(|s| new.trials[..k]
                    .iter()
                    .any(|p| p.factor == s && p.verdict == Verdict::Stable)),
                "{method}: trial {k} starts from {:?}",
                t.start
            );
            assert!(
                t.start.is_some() == expected.is_some(),
                "{method}: trial {k}"
            );
        }
        // The blind search restarts every trial from the equilibrium.
        assert!(old.trials.iter().all(|t| t.start.is_none()));
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
