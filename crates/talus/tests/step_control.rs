//! The step control (`docs/solver.md`, 'The step control') on a scene built to fold: the
//! paper footing on 64 × 28 cells at h = 0.1 s and 0.1 mm/s (the same settlement per step
//! as the paper's h = 1e-2 s at 1 mm/s, with a hundredth of the inertia per step). Its
//! non-associative step problem at the full h loses its solution near step 43
//! (`docs/solver.md`, 'Why the full step fails there'): the nested halving of before
//! (4 halvings, each step from the full h) stopped there, "did not converge". With the
//! default settings the run goes on at the sub-step sizes that have a solution. The same
//! scene with associative flow has no fold and takes one sub-step per step, as before.
use crate::common;
/// `(sub-steps, accepted, failed)` Newton iterations per step of `talus run` on the folding
/// footing with `dilatancy_angle` as given, after `steps` steps.
fn run(name: &str, dilatancy: &str, steps: usize) -> Vec<(usize, usize, usize)> {
    let ratio = 1.1f64.powf(14.0 / 28.0);
    let text = common::FOOTING
        .replace("cells = [32, 14]", "cells = [64, 28]")
        .replace("ratio = [1.0, 1.1]", &format!("ratio = [1.0, {ratio:?}]"))
        .replace("step = 1.0e-2", "step = 1.0e-1")
        .replace("velocity = [0.0, -1.0e-3]", "velocity = [0.0, -1.0e-4]")
        .replace("steps = 300", &format!("steps = {steps}"))
        .replace("plots = true", "plots = false")
        .replace(
            "dilatancy_angle = 14.2906",
            &format!("dilatancy_angle = {dilatancy}"),
        );
    for key in [
        "cells = [64, 28]",
        "step = 1.0e-1",
        "velocity = [0.0, -1.0e-4]",
    ] {
        assert!(text.contains(key), "the scene kept {key}");
    }
    let (out, _, _) = common::talus_run("step_control", name, &text);
    let column = |name: &str| common::history_column(&out, name);
    let (s, a, f) = (
        column("substeps"),
        column("newton_iterations"),
        column("failed_newton_iterations"),
    );
    // Step 0, the initial state, left out.
    (1..s.len())
        .map(|k| (s[k] as usize, a[k] as usize, f[k] as usize))
        .collect()
}

#[test]
fn a_footing_that_folds_at_the_full_step_finishes_with_the_default_settings() {
    let steps = run("non_associative", "14.2906", 45);
    assert_eq!(steps.len(), 45, "every step taken");
    // The scene must fold: steps split into eighths or less of h (else this test is empty).
    let most = steps.iter().map(|s| s.0).max().unwrap();
    assert!(
        most >= 8,
        "the scene must need small sub-steps: at most {most} per step"
    );
    // Before the fold, one sub-step per step.
    assert!(steps[..40].iter().all(|s| s.0 == 1), "{:?}", &steps[..40]);
}

#[test]
fn associative_flow_takes_one_sub_step_per_step() {
    let steps = run("associative", "27.0", 45);
    assert_eq!(steps.len(), 45);
    assert!(steps.iter().all(|&(s, _, f)| s == 1 && f == 0), "{steps:?}");
}
