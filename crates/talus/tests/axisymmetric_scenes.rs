//! `[analysis] geometry`: bad values and meshes are named errors; the shipped
//! axisymmetric scenes report whole-circumference forces (`docs/axisymmetry.md`).
use std::path::Path;

use talus::model::fem::ReactionForce;
use talus::model::fem::{FromScene, Model};
use talus::model::mpm::MpmModel;
use talus::run::fem::solver_settings;
use talus::scene::{MpmScene, Scene};
use talus_engine::{StepSettings, Stepper};

fn scene_text(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../scenes/{name}"));
    std::fs::read_to_string(path).expect("scene file")
}

fn line_of(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.contains(needle))
        .expect("needle in text")
        + 1
}

#[test]
fn unknown_geometry_is_named_with_its_value_and_line() {
    let text = scene_text("triaxial.toml").replacen(
        "geometry = \"axisymmetric\"",
        "geometry = \"axisymetric\"",
        1,
    );
    let err = Scene::parse(&text, None).unwrap_err();
    let msg = err.to_string();
    assert!(
        msg.contains("axisymetric") && msg.contains("geometry"),
        "{msg}"
    );
    assert_eq!(err.line, Some(line_of(&text, "axisymetric")), "{msg}");
}

/// The plane-strain footing spans x ∈ [−1, 1]: as an axisymmetric mesh it crosses the axis.
#[test]
fn a_mesh_at_negative_radius_is_refused() {
    let text = scene_text("footing.toml").replacen(
        "[material]",
        "[analysis]\ngeometry = \"axisymmetric\"\n\n[material]",
        1,
    );
    let scene = Scene::parse(&text, None).unwrap();
    let err = Model::from_scene(&scene).err().expect("rejected");
    assert_eq!(err.field, "analysis.geometry");
    let msg = err.to_string();
    assert!(msg.contains("r ≥ 0") && msg.contains("-1e0"), "{msg}");
}

#[test]
fn material_point_scenes_refuse_axisymmetry() {
    let text = scene_text("mpm_footing.toml") + "\n[analysis]\ngeometry = \"axisymmetric\"\n";
    let scene = MpmScene::parse(&text, None).unwrap();
    let err = MpmModel::from_scene(&scene).err().expect("rejected");
    assert_eq!(err.field, "analysis.geometry", "{err}");
}

/// At rest the footing carries the K₀ stress of the 20 kPa surcharge on its area: a load
/// of `20 kPa · π a²` on the whole circumference (a = 0.25 m), 2π times the per-radian
/// integral `20 kPa · a²/2`. Weightless, the stress is uniform and the P2 rule integrates
/// `Bᵀσ` exactly; with gravity the stress is linear in depth and `∂N/∂y σ r` (degree 3)
/// is integrated by the degree-2 rule: 3.9e-6 of the load on this mesh.
#[test]
fn circular_footing_reports_the_whole_footing_load() {
    let exact = 20.0e3 * std::f64::consts::PI * 0.25 * 0.25;
    let weightless =
        scene_text("circular_footing.toml").replacen("gravity = [0.0, -9.81]\n", "", 1);
    let scene = Scene::parse(&weightless, None).unwrap();
    let model = Model::from_scene(&scene).unwrap();
    let at_rest = model.reaction(&model.initial_state(&scene).unwrap());
    assert!(
        (at_rest - exact).abs() < 1e-12 * exact,
        "{at_rest} vs {exact}"
    );

    let scene = Scene::parse(&scene_text("circular_footing.toml"), None).unwrap();
    let model = Model::from_scene(&scene).unwrap();
    let mut state = model.initial_state(&scene).unwrap();
    let at_rest = model.reaction(&state);
    assert!(
        (at_rest - exact).abs() < 1e-5 * exact,
        "{at_rest} vs {exact}"
    );
    // A few steps load it further, converging.
    let mut stepper = Stepper::new(
        &model,
        StepSettings::with_solver(solver_settings(&scene), scene.spec.solver.max_step_halvings),
    );
    let mut last = at_rest;
    for _ in 0..5 {
        let r = stepper.advance(&mut state, scene.spec.time.step).unwrap();
        assert!(r.reaction_force() > last);
        last = r.reaction_force();
    }
}

/// The summary and the last line give the whole-circumference force in N (not N/m), and
/// its value is the `reaction_force` of history.csv's last row.
#[test]
fn axisymmetric_summary_reports_forces_in_newtons() {
    let text = scene_text("circular_footing.toml").replacen("steps = 300", "steps = 3", 1);
    let scene = Scene::parse(&text, None).unwrap();
    let out = std::env::temp_dir().join("talus-axisym-summary-unit");
    let _ = std::fs::remove_dir_all(&out);
    let options = talus::run::RunOptions::new(out.clone());
    let run = talus::run::fem::run_scene(&scene, &options).unwrap();
    let summary = talus::output::Summary::read(&out.join("summary.json")).unwrap();
    assert_eq!(summary.force_unit, "N");
    let reaction = summary.reaction.as_ref().unwrap();
    let last = run.records.last().unwrap().reaction_force();
    assert_eq!(reaction.force, last);
    let sentence = summary.sentence();
    assert!(
        sentence.contains(" N at ") && !sentence.contains("N/m"),
        "{sentence}"
    );
}

/// A radial velocity prescribed on axis nodes is refused, naming the boundary's velocity;
/// the same velocity on a boundary off the axis (r = 1 m) is a legitimate radial push.
#[test]
fn radial_velocity_on_the_axis_is_refused() {
    let base = scene_text("circular_footing.toml");
    let footing = "fix = \"y\"                # smooth: u_r free under the footing\nvelocity = [0.0, -1.0e-3]";
    assert!(base.contains(footing), "circular_footing.toml changed");
    let text = base.replacen(footing, "fix = \"xy\"\nvelocity = [1.0e-4, -1.0e-3]", 1);
    let scene = Scene::parse(&text, None).unwrap();
    let err = Model::from_scene(&scene).err().expect("refused");
    assert_eq!(err.field, "boundary[2].velocity", "{err}");
    assert!(
        err.to_string().contains("on the axis r = 0 radially"),
        "{err}"
    );
    assert_eq!(
        err.line,
        Some(line_of(&text, "velocity = [1.0e-4")),
        "{err}"
    );

    let right = "nodes = \"right\"          # r = 1 m\nfix = \"x\"";
    assert!(base.contains(right), "circular_footing.toml changed");
    let text = base.replacen(right, &format!("{right}\nvelocity = [1.0e-4, 0.0]"), 1);
    let scene = Scene::parse(&text, None).unwrap();
    assert!(Model::from_scene(&scene).is_ok());
}
