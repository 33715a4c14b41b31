//! A sub-step that fails and is redone as two halves keeps its predictor: the halves start
//! from `σₙ + (h/2) σ̇`, not from the elastic predictor, which at the mechanism's onset is
//! much further from the solution (`docs/solver.md`, "Non-associative Newton at the
//! mechanism's onset").
use crate::common;

use common::footing::{paper_footing, H};
use talus_engine::{Predictor, StepSettings, Stepper};
use talus_ssn::Settings;

#[test]
fn paper_footing_halved_steps_start_from_the_extrapolated_rate() {
    let (model, mut state) = paper_footing([32, 14]);
    // Three iterations are too few for the early steps (4–7 from the extrapolated rate), so
    // some steps after the first fail and are halved.
    let solver = Settings {
        max_iterations: 3,
        ..Settings::fem()
    };
    let mut stepper = Stepper::new(&model, StepSettings::with_solver(solver, 8));
    let h = H;
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
