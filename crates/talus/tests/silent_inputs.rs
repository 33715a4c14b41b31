//! Inputs that used to give silent nonsense or never end (issue 27's corpus, 'Factor of
//! safety' and 'Analysis and loads'), now each refused with the field and the value.
use talus::analysis::stability::Analysis;
use talus::model::fem::{FromScene, Model};
use talus::scene::Scene;

const SLOPE: &str = include_str!("../../../scenes/slope.toml");
const CIRCULAR: &str = include_str!("../../../scenes/circular_footing.toml");

fn scene_dir() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/x.toml")
}

/// The error of setting up the factor-of-safety analysis of the slope edited `from` → `to`.
fn stability_error(from: &str, to: &str) -> talus::scene::SceneError {
    assert!(SLOPE.contains(from), "test setup: {from}");
    let scene = Scene::parse(&SLOPE.replacen(from, to, 1), Some(scene_dir())).unwrap();
    match Analysis::new(&scene) {
        Err(talus::run::RunError::Scene(e)) => e,
        Err(e) => panic!("not a scene error: {e}"),
        Ok(_) => panic!("accepted: {to}"),
    }
}

/// `gravity_increase` of a weightless body looped forever (58 546 trials in 60 s).
#[test]
fn gravity_increase_without_weight_is_refused() {
    let text = SLOPE
        .replacen(
            "method = \"strength_reduction\"",
            "method = \"gravity_increase\"",
            1,
        )
        .replacen("dilatancy = \"fixed\"\n", "", 1)
        .replacen("gravity = [0.0, -10.0]", "gravity = [0.0, 0.0]", 1);
    let scene = Scene::parse(&text, Some(scene_dir())).unwrap();
    let err = match Analysis::new(&scene) {
        Err(talus::run::RunError::Scene(e)) => e,
        Err(e) => panic!("{e}"),
        Ok(_) => panic!("accepted"),
    };
    assert_eq!(err.field, "gravity");
    assert!(err.message.contains("[0, 0]"), "{err}");
}

/// A monitor on a node every condition holds made every trial "stable".
#[test]
fn a_stability_monitor_on_a_fixed_node_is_refused() {
    let with_monitor = SLOPE.replacen(
        "tolerance = 0.005",
        "tolerance = 0.005\nmonitor = \"crest\"",
        1,
    );
    // The crest is free: accepted (the witness).
    let scene = Scene::parse(&with_monitor, Some(scene_dir())).unwrap();
    assert!(Analysis::new(&scene).is_ok());
    // The same monitor at the fixed base's corner.
    let at_base = with_monitor.replacen("point = [20.0, 10.0]", "point = [0.0, 0.0]", 1);
    let scene = Scene::parse(&at_base, Some(scene_dir())).unwrap();
    let err = match Analysis::new(&scene) {
        Err(talus::run::RunError::Scene(e)) => e,
        Err(e) => panic!("{e}"),
        Ok(_) => panic!("accepted"),
    };
    assert_eq!(err.field, "stability.monitor");
    assert!(err.message.contains("holds still"), "{err}");
}

/// A huge bracket or first guess ended in an unnamed 'plastic_strain entry 0 is not finite'.
#[test]
fn huge_brackets_and_first_guesses_are_refused_at_their_fields() {
    let err = stability_error(
        "tolerance = 0.005",
        "tolerance = 0.005\nbracket = [1.0, 1e300]",
    );
    assert_eq!(err.field, "stability.bracket");
    assert!(err.message.contains("1e300"), "{err}");
    let err = stability_error(
        "tolerance = 0.005",
        "tolerance = 0.005\nbracket = [1e-3, 2.0]",
    );
    assert_eq!(err.field, "stability.bracket");
    let err = stability_error(
        "tolerance = 0.005",
        "tolerance = 0.005\nfirst_guess = 1e300",
    );
    assert_eq!(err.field, "stability.first_guess");
    assert!(err.message.contains("1e300"), "{err}");
    let err = stability_error("tolerance = 0.005", "tolerance = 0.005\nfirst_guess = 1e-5");
    assert_eq!(err.field, "stability.first_guess");
}

/// A pressure on the axis r = 0 of an axisymmetric scene applied nothing.
#[test]
fn an_axisymmetric_load_on_the_axis_is_refused() {
    let from = "[[pressure]]\nedges = { box = [[0.25, -1e-9], [1.0, 1e-9]] }";
    assert!(CIRCULAR.contains(from), "test setup");
    let text = CIRCULAR.replacen(from, "[[pressure]]\nedges = \"left\"", 1);
    let scene = Scene::parse(&text, None).unwrap();
    let err = Model::from_scene(&scene).err().expect("refused");
    assert_eq!(err.field, "pressure[0].edges");
    assert!(err.message.contains("axis r = 0"), "{err}");
    // Off the axis, the same scene is accepted (the witness).
    assert!(Model::from_scene(&Scene::parse(CIRCULAR, None).unwrap()).is_ok());
}
