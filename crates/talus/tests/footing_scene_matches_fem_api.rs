//! The paper footing built from its scene (`scenes/footing.toml`) and the same footing
//! built with talus-fem's API alone (`crates/fem/tests/common/footing.rs`, which the
//! FEM stepping tests of talus-fem use) are one model: the same loads, prescribed
//! velocities and K₀ state bit for bit, hence the same steps.
#[path = "../../fem/tests/common/footing.rs"]
mod footing;

use talus::model::fem::{FromScene, Model, ReactionForce};
use talus::scene::builtin_footing_with_cells;
use talus_engine::{StepSettings, Stepper};

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

#[test]
fn the_footing_scene_and_the_fem_api_build_the_same_model() {
    let scene = builtin_footing_with_cells([32, 14]);
    let from_scene = Model::from_scene(&scene).unwrap();
    let mut scene_state = from_scene.initial_state(&scene).unwrap();
    let (by_hand, mut state) = footing::paper_footing([32, 14]);
    assert_eq!(bits(&from_scene.force_free), bits(&by_hand.force_free));
    assert_eq!(
        bits(&from_scene.force_prescribed),
        bits(&by_hand.force_prescribed)
    );
    assert_eq!(
        bits(&from_scene.prescribed_velocity),
        bits(&by_hand.prescribed_velocity)
    );
    assert_eq!(from_scene.reaction_dofs, by_hand.reaction_dofs);
    assert_eq!(bits(&scene_state.sigma), bits(&state.sigma));
    assert_eq!(scene.spec.time.step, footing::H);
    let mut a = Stepper::new(&from_scene, scene.spec.solver.fem());
    let mut b = Stepper::new(&by_hand, StepSettings::fem());
    for step in 1..=5 {
        let ra = a.advance(&mut scene_state, footing::H).unwrap();
        let rb = b.advance(&mut state, footing::H).unwrap();
        assert_eq!(bits(&scene_state.sigma), bits(&state.sigma), "step {step}");
        assert_eq!(ra.reaction_force(), rb.reaction_force(), "step {step}");
    }
}
