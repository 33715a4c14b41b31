//! MPM scenes (`[grid]`): every shipped one builds, a tiny column collapse runs through the
//! `talus run` command and writes its files, and bad scenes are errors naming the field.
use std::path::{Path, PathBuf};
use std::process::Command;

use talus::model::mpm::{MpmModel, Reaction};
use talus::run::mpm::run_mpm_scene;
use talus::run::RunOptions;
use talus::run::HISTORY_COLUMNS;
use talus::scene::{MpmScene, SceneError, SceneFile};

use crate::common;
use common::line_of;

const SCENES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes");

/// A 4 cm square column of sand, 16 particles, on a rough floor against a smooth wall.
const TINY_COLUMN: &str = r#"title = "tiny column"
gravity = [0.0, -9.81]

[grid]
origin = [0.0, 0.0]
spacing = 0.02
cells = [10, 4]

[[body]]
rectangle = [[0.0, 0.0], [0.04, 0.04]]
particles_per_cell = 2

[material]
young_modulus = 1.0e7
poisson_ratio = 0.3
friction_angle = 30.0
cohesion = 0.0
dilatancy_angle = 0.0
cone_fit = "plane_strain"
density = 1800.0

[[wall]]
side = "left"
condition = "slip"

[[wall]]
side = "bottom"
condition = "friction"
friction = 0.6

[time]
step = 2.0e-3
steps = 5

[output]
runout = true
vtu_every = 2
snapshot_every = 2
"#;

fn out_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("mpm_scenes")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn tiny_with(from: &str, to: &str) -> String {
    common::replaced(TINY_COLUMN, from, to)
}

/// The error building the MPM scene `text` gives (parse or model).
fn build_error(text: &str) -> SceneError {
    let scene = match SceneFile::parse(text, None) {
        Ok(SceneFile::Mpm(scene)) => scene,
        Ok(_) => panic!("parsed as a FEM scene"),
        Err(e) => return e,
    };
    MpmModel::from_scene(&scene)
        .err()
        .expect("the scene must be rejected")
}

#[test]
fn every_shipped_mpm_scene_parses_and_builds() {
    let mut names = Vec::new();
    for entry in std::fs::read_dir(SCENES).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("toml") {
            continue;
        }
        match SceneFile::from_path(&path).unwrap_or_else(|e| panic!("{e}")) {
            SceneFile::Mpm(scene) => {
                let model = MpmModel::from_scene(&scene).unwrap_or_else(|e| panic!("{e}"));
                assert!(!model.particles.is_empty(), "{}", path.display());
                names.push(path.file_name().unwrap().to_string_lossy().into_owned());
            }
            SceneFile::Mpm3(scene) => {
                let model = MpmModel::from_scene_3d(&scene).unwrap_or_else(|e| panic!("{e}"));
                assert!(!model.particles.is_empty(), "{}", path.display());
                names.push(path.file_name().unwrap().to_string_lossy().into_owned());
            }
            SceneFile::Fem(scene) => assert!(scene.path.is_some()),
            SceneFile::Fem3(scene) => assert!(scene.path.is_some()),
        }
    }
    names.sort();
    assert_eq!(
        names,
        [
            "column_3d.toml",
            "column_3d_a1.toml",
            "column_a0.5.toml",
            "column_a1.toml",
            "column_a2.toml",
            "column_a4.toml",
            "column_newton.toml",
            "column_newton_fine.toml",
            "mpm_footing.toml"
        ]
    );
}

#[test]
fn footing_scene_loads_the_surface_and_reports_the_footing() {
    let scene = MpmScene::from_path(&Path::new(SCENES).join("mpm_footing.toml")).unwrap();
    let model = MpmModel::from_scene(&scene).unwrap();
    // Walls bottom, left, right, then the footing box.
    assert_eq!(
        model.reaction,
        Some(Reaction {
            group: 3,
            velocity_y: Some(-1.0e-3)
        })
    );
    // The surcharge: 20 kPa over the 1.5 m of surface beside the footing, downward.
    let load: f64 = model.particles.external_force.iter().map(|f| f[1]).sum();
    assert!((load + 20.0e3 * 1.5).abs() < 1e-6, "{load}");
    // K0 stress: every particle compressed, the deepest most.
    assert!(model.particles.stress.iter().all(|s| s[1] < 0.0));
}

#[test]
fn tiny_column_runs_from_the_command_line() {
    let dir = out_dir("tiny_column");
    let scene_path = dir.join("tiny_column.toml");
    std::fs::write(&scene_path, TINY_COLUMN).unwrap();
    let out = dir.join("out");
    let run = Command::new(env!("CARGO_BIN_EXE_talus"))
        .arg("run")
        .arg(&scene_path)
        .arg("--out")
        .arg(&out)
        .env("TALUS_LOG", "warn")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        run.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(stdout.starts_with("5 steps"), "{stdout}");
    assert!(stdout.contains("runout"), "{stdout}");

    let history = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let mut lines = history.lines();
    assert_eq!(
        lines.next(),
        Some("step,time,h,substeps,newton_iterations,failed_newton_iterations,max_newton_iterations,backtracks,residual,relative_residual,seconds,contact_passes,reaction_force_x,reaction_force_y,front,runout_normalized,kinetic_energy")
    );
    assert!(
        history.starts_with(HISTORY_COLUMNS),
        "the columns FEM runs share"
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 6, "step 0 and 5 steps");
    for (step, row) in rows.iter().enumerate() {
        assert_eq!(row.len(), 17);
        assert_eq!(row[0], step as f64);
        assert!(row.iter().all(|v| v.is_finite()));
    }
    // The column starts at rest and falls: it gains kinetic energy.
    assert_eq!(rows[0][16], 0.0);
    assert!(rows[5][16] > 0.0);
    assert!(rows[1..].iter().all(|r| r[4] >= 1.0), "Newton iterations");

    let vtus: Vec<_> = std::fs::read_dir(out.join("vtu"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(vtus.contains(&"step_00005.vtu".to_string()), "{vtus:?}");
    let vtu = std::fs::read_to_string(out.join("vtu/step_00005.vtu")).unwrap();
    assert!(vtu.contains(r#"NumberOfPoints="16""#));
    let pvd = std::fs::read_to_string(out.join("solution.pvd")).unwrap();
    assert!(pvd.contains("vtu/step_00005.vtu"));
    for png in [
        "plastic_strain.png",
        "snapshots/step_00000.png",
        "snapshots/step_00005.png",
    ] {
        let bytes = std::fs::read(out.join(png)).unwrap_or_else(|e| panic!("{png}: {e}"));
        assert!(bytes.starts_with(b"\x89PNG"), "{png}");
    }
}

#[test]
fn a_failing_step_is_named_and_the_history_is_kept() {
    // One Newton iteration and no halving: the first step of the collapse cannot converge.
    let text = tiny_with(
        "[output]",
        "[solver]\nmax_iterations = 1\nmax_step_halvings = 0\n\n[output]",
    );
    let scene = MpmScene::parse(&text, None).unwrap();
    let out = out_dir("failing_step");
    let err = run_mpm_scene(&scene, &RunOptions::new(out.clone())).expect_err("the run must stop");
    let msg = err.to_string();
    assert!(
        msg.contains("step 1 ") && msg.contains("did not converge"),
        "{msg}"
    );
    let history = std::fs::read_to_string(out.join("history.csv")).unwrap();
    assert_eq!(history.lines().count(), 2, "header and step 0: {history}");
}

#[test]
fn friction_wall_without_friction_is_named() {
    let text = tiny_with("friction = 0.6\n", "");
    let err = build_error(&text);
    assert_eq!(err.field, "wall[1].friction", "{err}");
    assert!(err.to_string().contains("missing"), "{err}");
    assert!(err.line.is_some(), "{err}");

    let text = tiny_with("friction = 0.6", "friction = -0.2");
    let err = build_error(&text);
    assert_eq!(err.field, "wall[1].friction");
    assert_eq!(err.line, Some(line_of(&text, "friction = -0.2")));
    assert!(err.to_string().contains("-0.2"), "{err}");

    let text = tiny_with(
        "condition = \"slip\"",
        "condition = \"slip\"\nfriction = 0.3",
    );
    let err = build_error(&text);
    assert_eq!(err.field, "wall[0].friction");
    assert!(err.to_string().contains("slip"), "{err}");
}

#[test]
fn body_outside_the_grid_or_inverted_is_named() {
    let text = tiny_with("[[0.0, 0.0], [0.04, 0.04]]", "[[0.0, 0.0], [0.04, 0.5]]");
    let err = build_error(&text);
    assert_eq!(err.field, "body[0].rectangle");
    assert_eq!(err.line, Some(line_of(&text, "rectangle =")));
    assert!(
        err.to_string().contains("0.5") && err.to_string().contains("outside the grid"),
        "{err}"
    );

    let text = tiny_with("[[0.0, 0.0], [0.04, 0.04]]", "[[0.04, 0.0], [0.0, 0.04]]");
    let err = build_error(&text);
    assert_eq!(err.field, "body[0].rectangle");
    assert!(
        err.to_string().contains("[[0.04, 0.0], [0.0, 0.04]]"),
        "{err}"
    );
}

#[test]
fn flip_ratio_outside_the_unit_interval_is_named() {
    let text = tiny_with("[output]", "[mpm]\nflip_ratio = 1.5\n\n[output]");
    let err = build_error(&text);
    assert_eq!(err.field, "mpm.flip_ratio");
    assert_eq!(err.line, Some(line_of(&text, "flip_ratio = 1.5")));
    assert!(err.to_string().contains("1.5"), "{err}");
}

#[test]
fn a_scene_needs_exactly_one_of_mesh_and_grid() {
    let both = tiny_with(
        "[grid]",
        "[mesh.rectangle]\nx = [0.0, 1.0]\ny = [0.0, 1.0]\ncells = [2, 2]\norder = \"P1\"\n\n[grid]",
    );
    let err = build_error(&both);
    let msg = err.to_string();
    assert!(msg.contains("mesh") && msg.contains("grid"), "{msg}");
    assert_eq!(err.line, Some(line_of(&both, "[grid]")));

    let neither = TINY_COLUMN.replace("[grid]", "[gird]");
    let msg = build_error(&neither).to_string();
    assert!(msg.contains("mesh") && msg.contains("grid"), "{msg}");
}

#[test]
fn other_bad_inputs_are_named() {
    // An unknown key, with its line.
    let text = tiny_with("spacing = 0.02", "spacing = 0.02\nspaceing = 0.02");
    let err = build_error(&text);
    assert!(err.to_string().contains("spaceing"), "{err}");
    assert_eq!(err.line, Some(line_of(&text, "spaceing")));
    // A reaction naming no prescribed box.
    let err = build_error(&tiny_with("runout = true", "reaction = \"footing\""));
    assert_eq!(err.field, "output.reaction");
    assert!(err.to_string().contains("footing"), "{err}");
    // A prescribed box with no velocity, one with both forms.
    let err = build_error(&tiny_with(
        "[time]",
        "[[prescribed]]\nregion = [[0.0, 0.0], [0.1, 0.1]]\n\n[time]",
    ));
    assert_eq!(err.field, "prescribed[0]");
    let err = build_error(&tiny_with(
        "[time]",
        "[[prescribed]]\nregion = [[0.0, 0.0], [0.1, 0.1]]\nvelocity = [0.0, 0.0]\nvelocity_y = 1.0\n\n[time]",
    ));
    assert_eq!(err.field, "prescribed[0].velocity");
    // A surface load that holds two rows of particles.
    let err = build_error(&tiny_with(
        "[time]",
        "[[surface_load]]\nregion = [[0.0, 0.0], [0.04, 0.04]]\npressure = 1e3\n\n[time]",
    ));
    assert_eq!(err.field, "surface_load[0].region");
    assert!(err.to_string().contains("more than one particle"), "{err}");
    // A material parameter, through the checks FEM scenes use.
    let err = build_error(&tiny_with("poisson_ratio = 0.3", "poisson_ratio = 0.7"));
    assert_eq!(err.field, "material.poisson_ratio");
    // No bodies.
    let text = TINY_COLUMN.replace(
        "[[body]]\nrectangle = [[0.0, 0.0], [0.04, 0.04]]\nparticles_per_cell = 2\n",
        "",
    );
    assert_eq!(build_error(&text).field, "body");
}
