//! Nothing silent (issue 27): a factor-of-safety search that found no mechanism gave a
//! number (a confined box: "factor of safety 16515072"); a body that fell away in the
//! loading was labelled `equilibrium`; a load programme faster than the step was sampled
//! without a word. And the search from a given equilibrium (`stability::search`, for
//! construction stages) is the run's.
use std::path::{Path, PathBuf};
use std::process::Command;

use talus::analysis::stability::{self, Analysis, Equilibrium, SearchStatus, TRIAL_COLUMNS};
use talus::model::fem::{FromScene, Model};
use talus::output::{RunStatus, Summary};
use talus::run::{RunError, RunOptions};
use talus::scene::{MpmScene, Scene};

/// A 2 m × 2 m box held on its four sides, under gravity ramped over 2 steps: no mechanism
/// at any strength.
const BOX: &str = r#"title = "confined box"
gravity = [0.0, -10.0]
gravity_ramp = [[0.0, 0.0], [2.0, 1.0]]

[mesh.rectangle]
x = [0.0, 2.0]
y = [0.0, 2.0]
cells = [4, 4]
order = "P2"

[material]
young_modulus = 1.0e8
poisson_ratio = 0.3
friction_angle = 20.0
cohesion = 1.0e4
dilatancy_angle = 0.0
cone_fit = "plane_strain"
density = 2.0e3

[[boundary]]
nodes = "bottom"
fix = "xy"

[[boundary]]
nodes = "left"
fix = "xy"

[[boundary]]
nodes = "right"
fix = "xy"

[[boundary]]
nodes = "top"
fix = "xy"

[analysis]
kind = "quasi_static"
inertia_ratio = 1e-6

[time]
step = 1.0
steps = 2

[stability]
method = "strength_reduction"
dilatancy = "fixed"
"#;

/// The box without its supports, its gravity ramped over 6 steps: it falls.
fn unsupported() -> String {
    let start = BOX.find("[[boundary]]").unwrap();
    let end = BOX.find("[analysis]").unwrap();
    let text = format!("{}{}", &BOX[..start], &BOX[end..]);
    text.replacen("[2.0, 1.0]]", "[6.0, 1.0]]", 1)
        .replacen("steps = 2", "steps = 6", 1)
}

/// The vertical cut of `scenes/vertical_cut.toml` on 8 × 4 cells: a real factor in 0.4 s.
fn coarse_cut() -> String {
    let text = include_str!("../../../scenes/vertical_cut.toml");
    assert!(text.contains("cells = [32, 16]"), "test setup");
    text.replacen("cells = [32, 16]", "cells = [8, 4]", 1)
        .replacen("plots = true", "plots = false", 1)
}

fn dir(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("stability_silent")
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// `talus run` on `text` written in `dir`: exit code, stdout, stderr; outputs in `dir/out`.
fn talus_run(dir: &Path, text: &str) -> (i32, String, String) {
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, text).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_talus"))
        .arg("run")
        .arg(&scene)
        .arg("--out")
        .arg(dir.join("out"))
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// history.csv's rows after the header, split at the commas.
fn rows(path: &Path) -> (String, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().to_string();
    let rows = lines
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    (header, rows)
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn a_confined_box_has_no_mechanism_and_no_factor() {
    let d = dir("confined_box");
    let (code, stdout, stderr) = talus_run(&d, BOX);
    assert_eq!(code, 0, "{stderr}");
    let out = d.join("out");
    let raw = json(&out.join("summary.json"));
    let fos = &raw["factor_of_safety"];
    assert!(fos["value"].is_null(), "{fos}");
    assert_eq!(fos["status"], "no_mechanism");
    assert_eq!(fos["bracket"], serde_json::json!([100.0, null]));
    assert_eq!(fos["within_tolerance"], false);
    let summary = Summary::read(&out.join("summary.json")).unwrap();
    assert_eq!(summary.status, RunStatus::Finished);
    assert_eq!(summary.error, None);
    let sentence = summary.sentence();
    assert!(
        sentence.contains("NO FAILURE up to F = 100.0000")
            && !sentence.contains("factor of safety 1"),
        "{sentence}"
    );
    assert!(stdout.contains("NO FAILURE up to F = 100"), "{stdout}");
    // Every trial came to rest, the last at the search's end F = 100, and no further.
    let (header, rows) = rows(&out.join("history.csv"));
    assert_eq!(header, TRIAL_COLUMNS);
    assert_eq!(rows.len(), fos["trials"].as_u64().unwrap() as usize + 1);
    assert_eq!(rows[0][2], "equilibrium");
    assert!(rows[1..].iter().all(|r| r[2] == "stable"), "{rows:?}");
    let factors: Vec<f64> = rows[1..].iter().map(|r| r[1].parse().unwrap()).collect();
    assert_eq!(factors.last(), Some(&100.0));
    assert!(factors.iter().all(|f| *f <= 100.0), "{factors:?}");
    // No failing trial: no mechanism to draw.
    assert!(!out.join("mechanism.vtu").exists());
    assert!(!out.join("mechanism.png").exists());
}

#[test]
fn an_unsupported_body_collapses_in_the_loading() {
    let text = unsupported();
    let d = dir("unsupported");
    let (code, stdout, stderr) = talus_run(&d, &text);
    assert_eq!(code, 4, "collapsed exits 4: {stdout}{stderr}");
    assert!(stderr.contains("collapse at step 3"), "{stderr}");
    let out = d.join("out");
    let summary = Summary::read(&out.join("summary.json")).unwrap();
    assert_eq!(summary.status, RunStatus::Collapsed);
    let collapse = summary.collapse.expect("collapse");
    assert_eq!((collapse.step, collapse.time), (3, 3.0));
    assert_eq!((summary.steps, summary.steps_requested), (3, 6));
    assert!(summary.factor_of_safety.is_none(), "no trials: no factor");
    let error = summary.error.clone().unwrap();
    assert!(error.contains("the loading collapsed"), "{error}");
    assert!(summary.sentence().contains("COLLAPSED"));
    // history.csv: the loading's row says so; no trial rows, no mechanism.
    let (header, rows) = rows(&out.join("history.csv"));
    assert_eq!(header, TRIAL_COLUMNS);
    assert_eq!(rows.len(), 1, "{rows:?}");
    assert_eq!(
        (rows[0][2].as_str(), rows[0][7].as_str()),
        ("collapsed", "3")
    );
    assert!(!out.join("mechanism.vtu").exists());
    // The library says the same.
    let scene = Scene::parse(&text, None).unwrap();
    match stability::run(&scene, &RunOptions::new(d.join("lib"))) {
        Err(RunError::Collapsed(c)) => assert_eq!(c.step, 3),
        other => panic!("{:?}", other.map(|r| r.factor_of_safety)),
    }
}

/// A loading too short for the collapse watch (2 steps) leaves the body falling: every
/// trial fails, down to the search's end, and no number is given.
#[test]
fn a_body_that_never_comes_to_rest_has_no_stable_factor() {
    let text = unsupported()
        .replacen("[6.0, 1.0]]", "[2.0, 1.0]]", 1)
        .replacen("steps = 6", "steps = 2", 1);
    let scene = Scene::parse(&text, None).unwrap();
    let d = dir("never_at_rest");
    let ran = stability::run(&scene, &RunOptions::new(&d)).unwrap();
    assert_eq!(ran.status, SearchStatus::NoStableFactor);
    assert_eq!(ran.factor_of_safety.value, None);
    assert_eq!(ran.factor_of_safety.status, "no_stable_factor");
    assert_eq!(ran.factor_of_safety.bracket, [None, Some(0.01)]);
    assert!(ran.trials.iter().all(|t| t.fails()));
    let summary = Summary::read(&d.join("summary.json")).unwrap();
    assert!(
        summary
            .sentence()
            .contains("FAILS at every factor down to F = 0.0100"),
        "{}",
        summary.sentence()
    );
    assert!(summary.error.unwrap().contains("every trial failed"));
}

/// `search` from the equilibrium a caller computed (here the same loading, its increment
/// given as 0 and the criterion's scale cleared) finds the factor `run` finds, with the
/// same trials.
#[test]
fn search_from_a_given_equilibrium_is_the_run() {
    for method in ["gravity_increase", "strength_reduction"] {
        let text = coarse_cut().replacen(
            "method = \"gravity_increase\"",
            &format!("method = \"{method}\""),
            1,
        );
        let scene = Scene::parse(&text, None).unwrap();
        let d = dir(&format!("search_{method}"));
        let ran = stability::run(&scene, &RunOptions::new(d.join("run"))).unwrap();
        assert_eq!(ran.status, SearchStatus::Found, "{method}");
        let value = ran.factor_of_safety.value.expect("a factor");
        assert!(value > 1.0 && value < 1.5, "{method}: {value}");

        let end = scene.spec.time.step * scene.spec.time.steps as f64;
        let model = Model::from_scene(&scene).unwrap();
        let mut analysis = Analysis::from_model(&scene, model, end).unwrap().unwrap();
        let loaded = analysis.equilibrium(&scene).unwrap();
        let given = Equilibrium {
            state: loaded.state,
            steps: 0,
            newton_iterations: 0,
            seconds: 0.0,
            last_increment: 0.0,
        };
        analysis.criterion.scale = 0.0; // search sets it from the state
        let csv = d.join("stage").join("trials.csv");
        std::fs::create_dir_all(csv.parent().unwrap()).unwrap();
        let found = stability::search(
            &mut analysis,
            given,
            &csv,
            &RunOptions::new(d.join("stage")),
        )
        .unwrap();
        assert_eq!(found.factor_of_safety, ran.factor_of_safety, "{method}");
        assert_eq!(found.trials.len(), ran.trials.len());
        // The same rows but for the seconds; row 0 the given equilibrium, its rest level
        // from the state's displacement.
        let (header, searched) = rows(&csv);
        let (_, history) = rows(&d.join("run").join("history.csv"));
        assert_eq!(header, TRIAL_COLUMNS);
        assert_eq!(searched.len(), history.len());
        assert_eq!(&searched[0][..4], ["0", "1", "equilibrium", ""]);
        assert_eq!(searched[0][4], "0.000000e0");
        assert_eq!(searched[0][6], history[0][6], "rest level");
        for (a, b) in searched[1..].iter().zip(&history[1..]) {
            assert_eq!(a[..9], b[..9], "{method}");
        }
        // search writes neither summary.json nor the mechanism.
        assert!(!d.join("stage").join("summary.json").exists());
    }
}

/// A ramp segment shorter than the step, FEM, `[stability]` and MPM alike, is named in
/// `summary.json`'s warnings; a segment as long as a step is not.
#[test]
fn a_fast_ramp_is_named_in_the_warnings() {
    // FEM: the footing's surcharge jumps within 1e-4 s of a 1e-2 s step.
    let footing = include_str!("../../../scenes/footing.toml")
        .replacen("steps = 300", "steps = 3", 1)
        .replacen("plots = true", "plots = false", 1);
    let from = "value = [0.0, -20.0e3]   # Pa";
    assert!(footing.contains(from), "test setup");
    let with_ramp = |ramp: &str| {
        let text = footing.replacen(from, &format!("{from}\nramp = {ramp}"), 1);
        let scene = Scene::parse(&text, None).unwrap();
        let d = dir(&format!("ramp_{}", ramp.len()));
        talus::run::fem::run_scene(&scene, &RunOptions::new(&d)).unwrap();
        Summary::read(&d.join("summary.json")).unwrap().warnings
    };
    let warnings = with_ramp("[[0.0, 1.0], [0.015, 1.0], [0.0151, 2.0]]");
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    let w = &warnings[0];
    assert!(w.starts_with("traction[0].ramp: "), "{w}");
    assert!(w.contains("t = 0.015 s") && w.contains("h = 0.01 s"), "{w}");
    // The same change over a step is followed: no warning.
    assert!(with_ramp("[[0.0, 1.0], [0.015, 1.0], [0.03, 2.0]]").is_empty());

    // A [stability] scene's loading: the box's gravity ramped within half a step.
    let text = BOX.replacen("[2.0, 1.0]]", "[0.5, 1.0]]", 1);
    let scene = Scene::parse(&text, None).unwrap();
    let d = dir("ramp_stability");
    stability::run(&scene, &RunOptions::new(&d)).unwrap();
    let warnings = Summary::read(&d.join("summary.json")).unwrap().warnings;
    assert!(
        warnings.iter().any(|w| w.starts_with("gravity_ramp: ")),
        "{warnings:?}"
    );

    // MPM: a prescribed velocity switched on within 0.01 s of a 0.05 s step.
    let mpm = |ramp: &str| {
        let text = CARRIED.replacen(
            "velocity = [0.2, -0.1]",
            &format!("velocity = [0.2, -0.1]\nramp = {ramp}"),
            1,
        );
        let scene = MpmScene::parse(&text, None).unwrap();
        let d = dir(&format!("mpm_ramp_{}", ramp.len()));
        talus::run::mpm::run_mpm_scene(&scene, &RunOptions::new(&d)).unwrap();
        Summary::read(&d.join("summary.json")).unwrap().warnings
    };
    let warnings = mpm("[[0.06, 0.0], [0.07, 1.0]]");
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(
        warnings[0].starts_with("prescribed[0].ramp: "),
        "{warnings:?}"
    );
    assert!(mpm("[[0.0, 0.0], [0.1, 1.0]]").is_empty());
}

const CARRIED: &str = r#"[grid]
origin = [0.0, 0.0]
spacing = 0.1
cells = [12, 12]

[[body]]
rectangle = [[0.3, 0.3], [0.7, 0.6]]
particles_per_cell = 2

[material]
young_modulus = 1.0e7
poisson_ratio = 0.3
friction_angle = 30.0
cohesion = 1.0e4
cone_fit = "plane_strain"
density = 1800.0

[[prescribed]]
name = "carrier"
region = [[-1.0, -1.0], [2.0, 2.0]]
velocity = [0.2, -0.1]

[time]
step = 0.05
steps = 4

[output]
vtu_every = 0
plots = false
"#;
