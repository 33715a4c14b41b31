//! A sub-step that fails and is redone as two halves keeps its predictor: the halves start
//! from `σₙ + (h/2) σ̇`, not from the elastic predictor, which at the mechanism's onset is
//! much further from the solution (`docs/solver.md`, "Non-associative Newton at the
//! mechanism's onset").
use talus::run::solver_settings;
use talus::scene::builtin_footing_with_cells;
use talus::simulation::{Model, Predictor, StepSettings, Stepper};

#[test]
fn paper_footing_halved_steps_start_from_the_extrapolated_rate() {
    let mut scene = builtin_footing_with_cells([32, 14]);
    // Three iterations are too few for the early steps (4–7 from the extrapolated rate), so
    // some steps after the first fail and are halved.
    scene.spec.solver.max_iterations = 3;
    let model = Model::from_scene(&scene).expect("model");
    let mut state = model.initial_state(&scene).expect("K0 state");
    let mut stepper = Stepper::new(
        &model,
        StepSettings::with_solver(solver_settings(&scene), 8),
    );
    let h = scene.spec.time.step;
    let first = stepper.advance(&mut state, h).expect("step 1");
    assert_eq!(
        first.predictors[0],
        Predictor::Elastic,
        "step 1 starts from rest"
    );
    let mut halved = 0;
    for step in 2..=8 {
        let record = stepper
            .advance(&mut state, h)
            .expect("step converges when halved");
        assert_eq!(record.predictors.len(), record.substeps);
        if record.substeps > 1 {
            halved += 1;
            assert!(
                record
                    .predictors
                    .iter()
                    .all(|p| *p == Predictor::Extrapolated),
                "step {step}: halves started from {:?}",
                record.predictors
            );
        }
    }
    assert!(halved > 0, "the test needs at least one halved step");
}
