//! `[[monitor]]`: the FEM monitor records its nearest node, the same values the VTU and
//! the final state hold; the MPM monitor interpolates through the grid, and on a body
//! carried in rigid translation by a prescribed velocity it follows the prescribed motion
//! `u = v t` exactly (and the box's force is the impulse `m Δv / h` of the first step).
//! Bad monitors are refused naming the field.
use crate::common;
use std::path::PathBuf;

use talus::model::fem::{FromScene, Model};
use talus::run::fem::FemResults;
use talus::run::fem::{run_scene, FEM_COLUMNS};
use talus::run::mpm::run_mpm_scene;
use talus::run::HISTORY_COLUMNS;
use talus::run::{RunError, RunOptions};
use talus::scene::{MpmScene, Scene};

const BLOCK: &str = "[mesh.rectangle]
x = [0.0, 1.0]
y = [0.0, 1.0]
cells = [4, 4]
order = \"P2\"

[material]
young_modulus = 1.0e7
poisson_ratio = 0.3
friction_angle = 30.0
cohesion = 1.0e9
cone_fit = \"plane_strain\"
density = 2.0e3

[[boundary]]
name = \"base\"
nodes = \"bottom\"
fix = \"xy\"

[[pressure]]
edges = \"top\"
value = 1.0e5

[time]
step = 0.01
steps = 5

[output]
vtu_every = 0
plots = false
";

fn out_dir(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("monitors")
        .join(name)
}

fn options(out: &std::path::Path) -> RunOptions {
    RunOptions {
        write_fields: true,
        ..RunOptions::new(out.to_path_buf())
    }
}

fn summary(out: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap()
}

/// Rows of history.csv as `(header, rows)`.
fn history(out: &std::path::Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    (header, rows)
}

#[test]
fn fem_monitor_is_its_nearest_node_in_the_vtu_and_the_final_state() {
    // (0.97, 0.99) is nearest to the top-right corner (1, 1) (P2 node spacing 0.125), which
    // moves right (Poisson expansion, free side) and down, and is still moving after 5
    // short steps: every component is non-zero.
    let text = format!("{BLOCK}\n[[monitor]]\nname = \"corner\"\npoint = [0.97, 0.99]\n");
    let scene = Scene::parse(&text, None).unwrap();
    let out = out_dir("fem");
    let run = run_scene(&scene, &options(&out)).unwrap();
    let model = Model::from_scene(&scene).unwrap();
    let node = model
        .mesh
        .nodes
        .iter()
        .position(|p| *p == [1.0, 1.0])
        .unwrap();
    let u = run.final_state.displacement[node];
    let vtu = std::fs::read_to_string(out.join("vtu/step_00005.vtu")).unwrap();
    let (du, dv) = (
        common::array(&vtu, "displacement"),
        common::array(&vtu, "velocity"),
    );
    let m = &summary(&out)["monitors"]["corner"];
    let got = ["ux", "uy", "vx", "vy"].map(|k| m[k].as_f64().unwrap());
    println!("corner node {node}: monitor {got:?}, final state u {u:?}");
    assert_eq!([got[0], got[1]], u);
    assert_eq!([got[0], got[1]], [du[3 * node], du[3 * node + 1]]);
    assert_eq!([got[2], got[3]], [dv[3 * node], dv[3 * node + 1]]);
    assert!(got[0] > 0.0 && got[1] < 0.0, "{got:?}");
    assert!(got.iter().all(|v| *v != 0.0), "{got:?}");
    // history.csv holds the same, to its 11 significant digits.
    let (header, rows) = history(&out);
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    let last = rows.last().unwrap();
    for (k, name) in ["corner_ux", "corner_uy", "corner_vx", "corner_vy"]
        .iter()
        .enumerate()
    {
        assert!(
            (last[col(name)] - got[k]).abs() <= 1e-10 * got[k].abs(),
            "{name}"
        );
    }
    // Step 0 is written too (t = 0, at rest) and listed first in solution.pvd.
    let vtu0 = std::fs::read_to_string(out.join("vtu/step_00000.vtu")).unwrap();
    assert!(common::array(&vtu0, "displacement")
        .iter()
        .all(|v| *v == 0.0));
    let pvd = std::fs::read_to_string(out.join("solution.pvd")).unwrap();
    let first = pvd.lines().find(|l| l.contains("<DataSet")).unwrap();
    assert!(
        first.contains(r#"timestep="0e0""#) && first.contains("vtu/step_00000.vtu"),
        "{first}"
    );
    assert_eq!(rows[0][col("corner_uy")], 0.0);
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

[[monitor]]
name = "centre"
point = [0.5, 0.45]

[[monitor]]
name = "edge"
point = [0.3, 0.6]

[time]
step = 0.05
steps = 4

[output]
vtu_every = 0
plots = false
"#;

#[test]
fn mpm_monitor_follows_a_rigid_translation() {
    let scene = MpmScene::parse(CARRIED, None).unwrap();
    let out = out_dir("mpm_rigid");
    run_mpm_scene(&scene, &options(&out)).unwrap();
    let (v, h) = ([0.2, -0.1], 0.05);
    let (header, rows) = history(&out);
    let col = |name: &str| header.iter().position(|c| c == name).unwrap();
    assert_eq!(rows.len(), 5);
    for (step, row) in rows.iter().enumerate() {
        let t = step as f64 * h;
        for m in ["centre", "edge"] {
            let got = [
                row[col(&format!("{m}_ux"))],
                row[col(&format!("{m}_uy"))],
                row[col(&format!("{m}_vx"))],
                row[col(&format!("{m}_vy"))],
            ];
            let want = if step == 0 {
                [0.0; 4]
            } else {
                [v[0] * t, v[1] * t, v[0], v[1]]
            };
            for k in 0..4 {
                assert!(
                    (got[k] - want[k]).abs() <= 1e-10 * want[k].abs(),
                    "step {step} {m}: {got:?} vs {want:?}"
                );
            }
        }
    }
    let s = summary(&out);
    let centre = &s["monitors"]["centre"];
    assert!((centre["ux"].as_f64().unwrap() - 4.0 * h * v[0]).abs() < 1e-15);
    assert!((centre["vy"].as_f64().unwrap() - v[1]).abs() < 1e-15);
    // The box accelerates the whole body (m = ρ A = 1800 × 0.12 kg/m) from rest to v in
    // the first step: it applies m v / h; then nothing.
    let m = 1800.0 * 0.4 * 0.3;
    let (fx, fy) = (rows[1][col("carrier_fx")], rows[1][col("carrier_fy")]);
    assert!((fx - m * v[0] / h).abs() <= 1e-9 * fx.abs(), "{fx}");
    assert!((fy - m * v[1] / h).abs() <= 1e-9 * fy.abs(), "{fy}");
    assert!(rows[4][col("carrier_fx")].abs() < 1e-9 * fx.abs());
    assert_eq!(s["boundaries"]["carrier"]["peak_step"], 1);
}

fn fem_error(extra: &str) -> talus::scene::SceneError {
    let scene = Scene::parse(&format!("{BLOCK}{extra}"), None).unwrap();
    let model = Model::from_scene(&scene).unwrap();
    FemResults::new(
        &scene,
        &model,
        &format!("{HISTORY_COLUMNS},{}", FEM_COLUMNS.join(",")),
    )
    .err()
    .expect("refused")
}

fn mpm_error(extra: &str) -> talus::scene::SceneError {
    let scene = MpmScene::parse(&format!("{CARRIED}{extra}"), None).unwrap();
    match run_mpm_scene(&scene, &options(&out_dir("mpm_error"))) {
        Err(RunError::Scene(e)) => e,
        other => panic!("expected a scene error, got {:?}", other.err()),
    }
}

#[test]
fn bad_monitors_and_names_are_refused_naming_the_field() {
    let e = fem_error("\n[[monitor]]\nname = \"far\"\npoint = [1.5, 0.5]\n");
    assert_eq!(e.field, "monitor[0].point");
    assert!(e.message.contains("outside the mesh"), "{e}");
    let e = fem_error(
        "\n[[monitor]]\nname = \"a\"\npoint = [0.5, 0.5]\n[[monitor]]\nname = \"a\"\npoint = [0.2, 0.5]\n",
    );
    assert_eq!(e.field, "monitor[1].name");
    assert!(e.message.contains("a_ux"), "{e}");
    let e = fem_error("\n[[monitor]]\nname = \"a b\"\npoint = [0.5, 0.5]\n");
    assert_eq!(e.field, "monitor[0].name");

    let e = mpm_error("\n[[monitor]]\nname = \"out\"\npoint = [1.3, 0.5]\n");
    assert_eq!(e.field, "monitor[2].point");
    assert!(e.message.contains("outside the grid"), "{e}");
    let e = mpm_error("\n[[monitor]]\nname = \"air\"\npoint = [1.1, 1.1]\n");
    assert_eq!(e.field, "monitor[2].point");
    assert!(e.message.contains("no material"), "{e}");
    let e = mpm_error("\n[[wall]]\nname = \"carrier\"\nside = \"bottom\"\ncondition = \"slip\"\n");
    assert_eq!(e.field, "prescribed[0].name");
    assert!(e.message.contains("carrier_fx"), "{e}");
}
