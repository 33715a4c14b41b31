//! Per-boundary reactions (`NAME_fx`, `NAME_fy` in history.csv): an elastic block on a
//! fixed base with a symmetry side, loaded by a pressure on its top, comes to rest; then
//! the two named boundaries carry the whole load. Summing eq. 15 over every dof,
//! `Σ (M a + Bᵀσ − f) = Σ M a − Σ f` because `Σ_all Bᵀσ = 0` per direction (a rigid
//! translation has no strain): at rest the boundary forces sum to minus the applied force,
//! `(0, p L)`, to rounding. A corner component counted by both boundaries (or by neither)
//! breaks the x balance by the corner's reaction, which is not small (the Poisson
//! expansion presses the block on its symmetry side).
use std::collections::HashMap;
use std::path::PathBuf;

use talus::model::fem::{FromScene, Model, ReactionGroups};
use talus::run::fem::run_scene;
use talus::run::RunOptions;
use talus::scene::Scene;

const PRESSURE: f64 = 1.0e5;
const WIDTH: f64 = 1.0;

/// The block `[0, 1]²`, P2 4×4, base and symmetry side in the order given.
fn block(conditions: &[&str]) -> String {
    let mut text = String::from(
        "[mesh.rectangle]
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
",
    );
    for c in conditions {
        text += match *c {
            "base" => "\n[[boundary]]\nname = \"base\"\nnodes = \"bottom\"\nfix = \"xy\"\n",
            "symmetry" => "\n[[boundary]]\nname = \"symmetry\"\nnodes = \"left\"\nfix = \"x\"\n",
            other => panic!("{other}"),
        };
    }
    // h = 1 s is ~100 times the block's lowest period: backward Euler brings it to rest
    // within a few steps (the kinetic energy falls by ~(ωh)² per step).
    text += &format!(
        "
[[pressure]]
edges = \"top\"
value = {PRESSURE}

[time]
step = 1.0
steps = 8

[output]
reaction = \"base\"
vtu_every = 0
plots = false
"
    );
    text
}

fn out_dir(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("reactions")
        .join(name)
}

/// The last row of history.csv by column name.
fn last_row(out: &std::path::Path) -> HashMap<String, f64> {
    let text = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let last = lines.last().unwrap();
    header
        .into_iter()
        .zip(last.split(',').map(|v| v.parse::<f64>().unwrap()))
        .collect()
}

fn check(order: &[&str], name: &str) {
    let text = block(order);
    let scene = Scene::parse(&text, None).unwrap();
    let out = out_dir(name);
    run_scene(&scene, &RunOptions::new(out.clone())).expect("elastic block runs");
    let row = last_row(&out);
    let load = PRESSURE * WIDTH;
    let sum_x = row["base_fx"] + row["symmetry_fx"];
    let sum_y = row["base_fy"] + row["symmetry_fy"];
    println!(
        "{name}: base ({:.6e}, {:.6e}), symmetry ({:.6e}, {:.6e}), sums ({sum_x:.3e}, {:.3e}) of p L = {load:e}",
        row["base_fx"], row["base_fy"], row["symmetry_fx"], row["symmetry_fy"], sum_y - load
    );
    assert!(sum_x.abs() <= 1e-10 * load, "Σ fx = {sum_x:e}");
    assert!((sum_y - load).abs() <= 1e-10 * load, "Σ fy = {sum_y:e}");
    // A symmetry side carries no vertical force, and it is pressed by the block.
    assert_eq!(row["symmetry_fy"], 0.0);
    assert!(row["symmetry_fx"] > 1e-3 * load, "{}", row["symmetry_fx"]);

    // The reported boundary keeps its columns: reaction_force is the base's push, downward
    // positive (−fy).
    assert!((row["reaction_force"] + row["base_fy"]).abs() <= 1e-9 * load);

    // summary.json holds the same final reactions (full precision).
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["status"], "finished");
    assert_eq!(summary["steps"], 8);
    for (b, c) in [("base", 0), ("base", 1), ("symmetry", 0), ("symmetry", 1)] {
        let v = summary["boundaries"][b]["final"][c].as_f64().unwrap();
        let col = row[&format!("{b}_f{}", ["x", "y"][c])];
        assert!(
            (v - col).abs() <= 1e-9 * load.max(v.abs()),
            "{b} {c}: {v} vs {col}"
        );
    }
}

/// The corner (0, 0) is fixed in x by both conditions and in y by the base: its x
/// belongs to the later condition only, its y to the base.
fn corner_owners(order: &[&str]) -> (Vec<&'static str>, Vec<&'static str>) {
    let scene = Scene::parse(&block(order), None).unwrap();
    let model = Model::from_scene(&scene).unwrap();
    let names: Vec<Option<String>> = scene.spec.boundary.iter().map(|b| b.name.clone()).collect();
    let groups = ReactionGroups::of_model(&model, &names);
    let corner = model
        .mesh
        .nodes
        .iter()
        .position(|p| p[0] == 0.0 && p[1] == 0.0)
        .unwrap();
    let dofs = model.assembly.dofs();
    let mut owners = (Vec::new(), Vec::new());
    for (comp, list) in [(0, &mut owners.0), (1, &mut owners.1)] {
        let j = dofs.prescribed(corner, comp).unwrap();
        for (g, (_, name)) in groups.names.iter().enumerate() {
            if groups.dofs[g].contains(&(j, comp)) {
                list.push(if name == "base" { "base" } else { "symmetry" });
            }
        }
    }
    // Every prescribed dof is in exactly one group (both conditions are named).
    let mut count = vec![0; dofs.n_prescribed()];
    for g in &groups.dofs {
        for &(j, _) in g {
            count[j] += 1;
        }
    }
    assert!(count.iter().all(|&c| c == 1), "{count:?}");
    owners
}

#[test]
fn base_then_symmetry_side_carry_the_pressure_once() {
    check(&["base", "symmetry"], "base_then_symmetry");
    assert_eq!(
        corner_owners(&["base", "symmetry"]),
        (vec!["symmetry"], vec!["base"])
    );
}

#[test]
fn symmetry_side_then_base_carry_the_pressure_once() {
    assert_eq!(
        corner_owners(&["symmetry", "base"]),
        (vec!["base"], vec!["base"])
    );
    check(&["symmetry", "base"], "symmetry_then_base");
}

/// MPM walls follow the same rule: a slip side written after a fixed floor owns only the
/// x of the corner nodes, so it never reports a vertical force, while the floor carries
/// the weight. (Owning whole nodes, the side would report the corner's share of the
/// weight.)
#[test]
fn an_mpm_slip_side_reports_no_vertical_force_at_the_floor_corner() {
    let text = r#"gravity = [0.0, -9.81]
[grid]
origin = [0.0, 0.0]
spacing = 0.02
cells = [10, 4]

[[body]]
rectangle = [[0.0, 0.0], [0.04, 0.04]]

[material]
young_modulus = 1.0e7
poisson_ratio = 0.3
friction_angle = 30.0
cohesion = 0.0
dilatancy_angle = 0.0
cone_fit = "plane_strain"
density = 1800.0

[[wall]]
name = "floor"
side = "bottom"
condition = "fixed"

[[wall]]
name = "side"
side = "left"
condition = "slip"

[time]
step = 2.0e-3
steps = 3

[output]
vtu_every = 0
plots = false
"#;
    let scene = talus::scene::MpmScene::parse(text, None).unwrap();
    let out = out_dir("mpm_corner");
    talus::run::mpm::run_mpm_scene(&scene, &RunOptions::new(out.clone())).unwrap();
    let row = last_row(&out);
    println!(
        "floor ({:.4e}, {:.4e}), side ({:.4e}, {:.4e})",
        row["floor_fx"], row["floor_fy"], row["side_fx"], row["side_fy"]
    );
    assert_eq!(row["side_fy"], 0.0);
    assert!(row["side_fx"] > 0.0, "the column presses on its side");
    let weight = 1800.0 * 0.04 * 0.04 * 9.81;
    assert!(row["floor_fy"] > 0.5 * weight, "{}", row["floor_fy"]);
}
