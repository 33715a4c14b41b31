//! Scenes outside their own scales are refused up front (`docs/scenes.md`, 'Limits'), each
//! error naming the field, its line and the range that works: arrays of the wrong length,
//! time steps against the elastic wave time and the prescribed motion, stresses against E,
//! caps on steps and halvings, MPM bodies smaller than a particle spacing.
use talus::model::fem::{FromScene, Model};
use talus::model::mpm::MpmModel;
use talus::scene::{MpmScene, Scene, SceneError};

use crate::common;
use common::replaced as with;

fn fem(from: &str, to: &str) -> (String, SceneError) {
    let text = with(include_str!("../../../scenes/footing.toml"), from, to);
    let err = match Scene::parse(&text, None) {
        Err(e) => e,
        Ok(scene) => Model::from_scene(&scene).err().expect("refused"),
    };
    (text, err)
}

fn mpm(from: &str, to: &str) -> (String, SceneError) {
    let text = with(include_str!("../../../scenes/mpm_footing.toml"), from, to);
    let err = match MpmScene::parse(&text, None) {
        Err(e) => e,
        Ok(scene) => MpmModel::from_scene(&scene).err().expect("refused"),
    };
    (text, err)
}

fn line_of(text: &str, needle: &str) -> Option<usize> {
    text.lines()
        .position(|l| l.starts_with(needle))
        .map(|l| l + 1)
}

fn assert_names(err: &SceneError, field: &str, text: &str, line: &str, says: &[&str]) {
    let msg = err.to_string();
    assert_eq!(err.field, field, "{msg}");
    assert_eq!(err.line, line_of(text, line), "{msg}");
    for s in says {
        assert!(msg.contains(s), "`{s}` not in: {msg}");
    }
}

/// Found by `fuzz_scene_reader.rs`: a zero count beside a huge one has no Gauss point, so
/// the size estimate passed it, and the x coordinates were then allocated (34 GB: the
/// process aborted; `u64::MAX` cells: a capacity-overflow panic).
#[test]
fn a_zero_cell_count_is_refused_before_allocating() {
    for cells in ["[4294967295, 0]", "[0, 18446744073709551615]", "[0, 14]"] {
        let (text, err) = fem("cells = [32, 14]", &format!("cells = {cells}"));
        assert_names(
            &err,
            "mesh.rectangle.cells",
            &text,
            "cells",
            &[cells, "must be ≥ 1 in x and in y"],
        );
    }
}

/// Found by `fuzz_scene_reader.rs`: a load whose value times its ramp multiplier
/// overflowed was left out of the stress check (only finite stresses were compared with E),
/// and the model's loads held -inf.
#[test]
fn a_load_overflowing_with_its_ramp_is_refused() {
    let (text, err) = fem(
        "value = [0.0, -20.0e3]   # Pa",
        "value = [0.0, -20.0e3]\nramp = [[0.0, 1e304]]",
    );
    assert_names(
        &err,
        "traction[0].value",
        &text,
        "value = [0.0, -20.0e3]",
        &["overflows", "largest ramp multiplier"],
    );
}

/// Found by `fuzz_scene_reader.rs`: a K₀ `surface` far above the body was checked against
/// E only through the body's own height, so `surface = 1e305` gave an initial stress of
/// -inf, and `surface = 1e6` one of 2.0e10 Pa, 20 times E, both accepted; `k0 = 1e305`
/// was refused by the flow rule without naming the scene's field.
#[test]
fn a_k0_stress_that_overflows_or_exceeds_e_is_refused_at_its_field() {
    let (text, err) = fem("surface = 0.0", "surface = 1e305");
    assert_names(
        &err,
        "initial_stress.surface",
        &text,
        "surface = 1e305",
        &["overflows"],
    );
    // The initial state is built after the model (`talus run` does both before step 1).
    let text = with(
        include_str!("../../../scenes/footing.toml"),
        "k0 = 0.546",
        "k0 = 1e305",
    );
    let scene = Scene::parse(&text, None).expect("parses");
    let model = Model::from_scene(&scene).expect("the model builds");
    let err = model.initial_state(&scene).expect_err("refused");
    assert_names(
        &err,
        "initial_stress.k0",
        &text,
        "k0 = 1e305",
        &["overflows"],
    );
    let (text, err) = fem("surface = 0.0", "surface = 1e6");
    assert_names(
        &err,
        "material.young_modulus",
        &text,
        "young_modulus",
        &["(initial_stress.surface)", "must be at most"],
    );
}

#[test]
fn an_array_longer_than_its_field_is_refused() {
    let (text, err) = fem("cells = [32, 14]", "cells = [32, 14, 3]");
    assert_names(
        &err,
        "mesh.rectangle.cells",
        &text,
        "cells",
        &["3 values given, 2 expected"],
    );
    let (text, err) = fem(
        "velocity = [0.0, -1.0e-3]",
        "velocity = [0.0, -1.0e-3, 5.0]",
    );
    assert_names(
        &err,
        "boundary[3].velocity",
        &text,
        "velocity",
        &["3 values given"],
    );
    let (text, err) = mpm(
        "region = [[-0.25, 0.0], [0.25, 0.1875]]",
        "region = [[-0.25, 0.0, 1.0], [0.25, 0.1875]]",
    );
    assert_names(
        &err,
        "prescribed[0].region",
        &text,
        "region",
        &["3 values given"],
    );
}

#[test]
fn a_time_step_far_from_the_wave_time_is_refused() {
    for h in ["1e30", "1e-300"] {
        let (text, err) = fem("step = 1.0e-2", &format!("step = {h}"));
        assert_names(
            &err,
            "time.step",
            &text,
            "step =",
            &["elastic wave time", "use h from"],
        );
    }
}

#[test]
fn a_boundary_moving_more_than_the_body_in_a_step_is_refused() {
    // 1e-3 m/s × 2000 s = 2 m per step against a body 1 m deep; the wave time allows it.
    let (text, err) = fem("step = 1.0e-2", "step = 2.0e3");
    assert_names(
        &err,
        "time.step",
        &text,
        "step =",
        &["boundary[3].velocity", "use h ≤ 1.000e3 s"],
    );
    // MPM: a box may move at most one cell (0.0625 m) per step.
    let (text, err) = mpm("step = 1.0e-2", "step = 1.0e2");
    assert_names(
        &err,
        "time.step",
        &text,
        "step =",
        &["one grid cell", "use h ≤ 6.250e1 s"],
    );
}

#[test]
fn stresses_out_of_proportion_with_e_are_refused() {
    let cases = [
        (
            "young_modulus = 1.0e9",
            "young_modulus = 1e300",
            "(traction",
        ),
        (
            "young_modulus = 1.0e9",
            "young_modulus = 1e-300",
            "(traction",
        ),
        (
            "density = 2.0e3",
            "density = 1e300",
            "(ρ |g| H from material.density, H = 1.0000e0 m)",
        ),
    ];
    for (from, to, cause) in cases {
        let (text, err) = fem(from, to);
        assert_names(
            &err,
            "material.young_modulus",
            &text,
            "young_modulus",
            &[cause, "their ratio"],
        );
    }
    let (text, err) = fem("cohesion = 2.0e3", "cohesion = 1e300");
    assert_names(
        &err,
        "material.cohesion",
        &text,
        "cohesion",
        &["at most 1e6"],
    );
}

#[test]
fn steps_and_halvings_are_capped() {
    let (text, err) = fem("steps = 300", "steps = 1000000000");
    assert_names(&err, "time.steps", &text, "steps", &["100000000"]);
    let (text, err) = fem("[time]", "[solver]\nmax_step_halvings = 1000\n\n[time]");
    assert_names(
        &err,
        "solver.max_step_halvings",
        &text,
        "max_step_halvings",
        &["use 0 to 16"],
    );
    let (text, err) = mpm("[time]", "[solver]\nmax_step_halvings = 17\n\n[time]");
    assert_names(
        &err,
        "solver.max_step_halvings",
        &text,
        "max_step_halvings",
        &["use 0 to 16"],
    );
}

#[test]
fn an_mpm_body_smaller_than_a_particle_spacing_is_refused() {
    let (text, err) = mpm("spacing = 0.0625", "spacing = 1e300");
    assert_names(
        &err,
        "body[0].rectangle",
        &text,
        "rectangle",
        &["less than one particle spacing"],
    );
    let (text, err) = mpm(
        "rectangle = [[-1.0, -1.0], [1.0, 0.0]]",
        "rectangle = [[-1.0, -1.0], [1.0, -0.99]]",
    );
    assert_names(
        &err,
        "body[0].rectangle",
        &text,
        "rectangle",
        &["use grid.spacing ≤ 2.000e-2 m"],
    );
}
