//! Bad scenes give a clear error naming the field and the line, never a panic.
use talus::model::fem::{FromScene, Model};
use talus::run::fem::run_scene;
use talus::run::RunOptions;
use talus::run::HISTORY_COLUMNS;
use talus::scene::{builtin_footing, Scene};

use crate::common;
use common::line_of;

fn footing_with(from: &str, to: &str) -> String {
    common::replaced(common::FOOTING, from, to)
}

#[test]
fn unknown_key_is_named_with_its_line() {
    let text = footing_with(
        "poisson_ratio = 0.3",
        "poisson_ratio = 0.3\npoisons_ratio = 0.3",
    );
    let err = Scene::parse(&text, None).unwrap_err();
    let msg = err.to_string();
    assert!(msg.contains("poisons_ratio"), "{msg}");
    assert_eq!(err.line, Some(line_of(&text, "poisons_ratio")), "{msg}");
}

#[test]
fn negative_young_modulus_is_named_with_its_line() {
    let text = footing_with("young_modulus = 1.0e9", "young_modulus = -1.0e9");
    let scene = Scene::parse(&text, None).unwrap();
    let err = Model::from_scene(&scene).err().expect("rejected");
    assert_eq!(err.field, "material.young_modulus");
    assert_eq!(err.line, Some(line_of(&text, "young_modulus = -1.0e9")));
    assert!(err.to_string().contains("-1000000000"), "{err}");
}

#[test]
fn empty_node_set_is_named() {
    let text = footing_with(
        "nodes = { box = [[-0.25, -1e-9], [0.25, 1e-9]] }",
        "nodes = { box = [[5.0, 5.0], [6.0, 6.0]] }",
    );
    let scene = Scene::parse(&text, None).unwrap();
    let err = Model::from_scene(&scene).err().expect("rejected");
    assert_eq!(err.field, "boundary[3].nodes");
    assert_eq!(err.line, Some(line_of(&text, "box = [[5.0, 5.0]")));
    let text = footing_with("nodes = \"bottom\"", "nodes = \"botom\"");
    let err = Model::from_scene(&Scene::parse(&text, None).unwrap())
        .err()
        .expect("rejected");
    assert!(
        err.to_string().contains("botom") && err.to_string().contains("bottom"),
        "{err}"
    );
}

#[test]
fn inverted_element_in_msh_names_the_element() {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("bad_scenes");
    std::fs::create_dir_all(&dir).unwrap();
    // Two triangles of the unit square; element 2 is listed clockwise (inverted).
    let msh = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n1 1 \"bottom\"\n2 2 \"domain\"\n$EndPhysicalNames\n\
$Entities\n0 1 1 0\n1 0 0 0 1 0 0 1 1 0\n1 0 0 0 1 1 0 1 2 0\n$EndEntities\n\
$Nodes\n2 4 1 4\n1 1 0 2\n1\n2\n0 0 0\n1 0 0\n2 1 0 2\n3\n4\n1 1 0\n0 1 0\n$EndNodes\n\
$Elements\n2 3 1 3\n1 1 1 1\n1 1 2\n2 1 2 2\n1 1 2 3\n2 1 4 3\n$EndElements\n";
    std::fs::write(dir.join("square.msh"), msh).unwrap();
    let scene_text = "[mesh.gmsh]\npath = \"square.msh\"\n[material]\nyoung_modulus = 1e7\npoisson_ratio = 0.3\n\
friction_angle = 30.0\ncohesion = 1e3\ncone_fit = \"plane_strain\"\ndensity = 1000.0\n[[boundary]]\nnodes = \"bottom\"\nfix = \"xy\"\n\
[time]\nstep = 0.1\nsteps = 1\n";
    let path = dir.join("scene.toml");
    std::fs::write(&path, scene_text).unwrap();
    let scene = Scene::from_path(&path).unwrap();
    let err = Model::from_scene(&scene)
        .err()
        .expect("inverted element rejected");
    let msg = err.to_string();
    assert_eq!(err.field, "mesh.gmsh.path");
    assert!(
        msg.contains('2') && (msg.contains("element") || msg.contains("Element")),
        "{msg}"
    );
    // The .msh file is named, not only the scene's line.
    assert!(
        msg.contains(&dir.join("square.msh").display().to_string()),
        "{msg}"
    );
}

#[test]
fn run_reports_a_non_convergent_step_and_keeps_the_history() {
    // One Newton iteration allowed and no halving: the first plastic step cannot converge.
    let text = footing_with(
        "[output]",
        "[solver]\nmax_iterations = 1\nmax_step_halvings = 0\n\n[output]",
    );
    let scene = Scene::parse(&text, None).unwrap();
    let out = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("non_convergent");
    let err = run_scene(&scene, &RunOptions::new(out.clone())).expect_err("the run must stop");
    let msg = err.to_string();
    assert!(
        msg.contains("step 1") && msg.contains("did not converge"),
        "{msg}"
    );
    let history = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let mut lines = history.lines();
    assert_eq!(
        lines.next(),
        // The footing is a named boundary: its reaction columns follow.
        Some(
            format!(
                "{HISTORY_COLUMNS},reaction_force,footing_displacement,footing_fx,footing_fy,\
                 inertial_share"
            )
            .as_str()
        )
    );
    assert!(
        lines.next().is_some_and(|l| l.starts_with("0,")),
        "the initial state's row is kept: {history}"
    );
    // summary.json names what to try, with the knobs' values.
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    for knob in [
        "[time] step (now 1e-2 s)",
        "max_step_halvings (now 0)",
        "max_iterations (now 1)",
        "[solver] tolerance (now",
    ] {
        assert!(summary.contains(knob), "{knob}: {summary}");
    }
    let _ = builtin_footing();
}

#[test]
fn traction_box_cutting_a_boundary_edge_is_an_error() {
    // 30 cells over [-1, 1]: no node at x = ±0.25, where the surcharge box ends.
    let text = footing_with("cells = [32, 14]", "cells = [30, 14]");
    let err = Model::from_scene(&Scene::parse(&text, None).unwrap())
        .err()
        .expect("rejected");
    assert_eq!(err.field, "traction[0].edges");
    assert!(err.to_string().contains("cuts the boundary edge"), "{err}");
    assert_eq!(err.line, Some(line_of(&text, "edges = { box = [[-1.0")));
}

#[test]
fn k0_outside_the_cone_reports_the_admissible_interval() {
    // φ = 45°, c = 0: Jaky's K₀ = 1 − sin φ = 0.293 lies outside the plane-strain cone.
    let text = footing_with("friction_angle = 27.0", "friction_angle = 45.0")
        .replacen("cohesion = 2.0e3", "cohesion = 0.0", 1)
        .replacen("dilatancy_angle = 14.2906", "dilatancy_angle = 10.0", 1)
        .replacen("k0 = 0.546", "k0 = 0.2929", 1);
    let scene = Scene::parse(&text, None).unwrap();
    let model = Model::from_scene(&scene).unwrap();
    let (lo, hi) = talus::model::k0_bounds_without_cohesion(&model);
    assert!(lo > 0.2929 && lo < hi, "bounds {lo} {hi}");
    let err =
        talus::model::initial_stress(&scene, &model, scene.spec.initial_stress.as_ref().unwrap())
            .unwrap_err();
    assert_eq!(err.field, "initial_stress.k0");
    assert!(err.to_string().contains(&format!("{lo:.4} ≤ K₀")), "{err}");
    // Just inside the interval the K0 state is accepted, just outside it is not.
    for (k0, ok) in [(lo * 1.001, true), (lo * 0.999, false), (hi * 0.999, true)] {
        let mut spec = *scene.spec.initial_stress.as_ref().unwrap();
        spec.k0 = Some(k0);
        assert_eq!(
            talus::model::initial_stress(&scene, &model, &spec).is_ok(),
            ok,
            "K0 = {k0}"
        );
    }
}
