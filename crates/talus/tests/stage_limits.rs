//! A staged scene's steps are its stages' (`[time] steps` stays 0): the cap on steps and
//! the size estimate count them, and a cap error names the stage that passes it.
use talus::model::fem::stages::Stages;
use talus::model::fem::{FromScene, Model};
use talus::model::size::SizeEstimate;
use talus::scene::scales::MAX_STEPS;
use talus::scene::{Scene, SceneError};

/// A small elastic block on a fixed base, with `stages`.
fn staged(stages: &str) -> String {
    format!(
        "gravity = [0.0, -9.81]\n\
         [mesh.rectangle]\nx = [0.0, 4.0]\ny = [0.0, 4.0]\ncells = [2, 2]\norder = \"P1\"\n\n\
         [[region]]\nname = \"top\"\nbox = [[0.0, 2.0], [4.0, 4.0]]\n\n\
         [material]\nmodel = \"elastic\"\nyoung_modulus = 2.0e7\npoisson_ratio = 0.25\n\
         density = 2000.0\n\n\
         [[boundary]]\nname = \"base\"\nnodes = {{ box = [[0.0, 0.0], [4.0, 0.0]] }}\nfix = \"xy\"\n\n\
         [analysis]\nkind = \"quasi_static\"\n\n\
         [time]\nstep = 1.0\n\n{stages}"
    )
}

fn stage(name: &str, steps: &str, extra: &str) -> String {
    format!("[[stage]]\nname = \"{name}\"\nsteps = {steps}\n{extra}\n")
}

fn line_of(text: &str, needle: &str) -> Option<usize> {
    text.lines().position(|l| l == needle).map(|l| l + 1)
}

/// Both ways a staged model is built refuse the scene with the same error.
fn refused(text: &str) -> SceneError {
    let scene = Scene::parse(text, None).expect("parses");
    let by_stages = Stages::<4>::of(&scene)
        .err()
        .expect("Stages::of refuses it");
    let by_model = Model::from_scene(&scene)
        .err()
        .expect("from_scene refuses it");
    assert_eq!(by_stages.to_string(), by_model.to_string());
    by_stages
}

#[test]
fn stages_whose_steps_pass_the_cap_in_all_are_refused_naming_the_stage() {
    let half = MAX_STEPS / 2 + 1;
    let text = staged(&format!(
        "{}{}",
        stage("dig", &half.to_string(), "deactivate = [\"top\"]"),
        stage("rest", &half.to_string(), "")
    ));
    let err = refused(&text);
    let msg = err.to_string();
    assert_eq!(err.field, "stage[1].steps", "{msg}");
    // The second stage's `steps` line.
    let lines: Vec<usize> = (text.lines().enumerate())
        .filter(|(_, l)| *l == format!("steps = {half}"))
        .map(|(k, _)| k + 1)
        .collect();
    assert_eq!(err.line, lines.get(1).copied(), "{msg}");
    for says in [&(2 * half).to_string(), &MAX_STEPS.to_string()] {
        assert!(msg.contains(says.as_str()), "`{says}` not in: {msg}");
    }
    assert!(!msg.contains("time.steps"), "{msg}");
}

#[test]
fn stages_whose_steps_overflow_are_refused_not_wrapped() {
    // Three times i64::MAX overflows a 64-bit sum: wrapped, it would pass the cap.
    let big = i64::MAX.to_string();
    let text = staged(&format!(
        "{}{}{}",
        stage("a", &big, "deactivate = [\"top\"]"),
        stage("b", &big, ""),
        stage("c", &big, "")
    ));
    let err = refused(&text);
    assert_eq!(err.field, "stage[0].steps", "{err}");
    assert_eq!(err.line, line_of(&text, &format!("steps = {big}")), "{err}");
}

#[test]
fn stages_within_the_cap_build() {
    let text = staged(&format!(
        "{}{}",
        stage(
            "dig",
            &(MAX_STEPS / 2).to_string(),
            "deactivate = [\"top\"]"
        ),
        stage("rest", &(MAX_STEPS / 2).to_string(), "")
    ));
    let scene = Scene::parse(&text, None).expect("parses");
    let stages = Stages::<4>::of(&scene).expect("checked").expect("staged");
    stages.model(&scene, 1).expect("built");
}

#[test]
fn the_size_estimate_of_a_staged_scene_counts_its_stages_steps() {
    let text = staged(&format!(
        "{}{}",
        stage("dig", "3", "deactivate = [\"top\"]"),
        stage("rest", "4", "")
    ));
    let scene = Scene::parse(&text, None).expect("parses");
    assert_eq!(scene.spec.time.steps, 0);
    assert_eq!(scene.spec.total_steps(), 7);
    let estimate = SizeEstimate::of_fem(&scene).expect("estimated");
    assert_eq!(estimate.steps, 7);
}
