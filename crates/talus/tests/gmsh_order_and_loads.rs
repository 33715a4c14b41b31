//! `[mesh.gmsh] order = "P2"` turns a linear Gmsh mesh into P2 (and a plastic run on P1
//! warns, in the log and in `summary.json`); `[[pressure]]` with a `gradient` gives a
//! hydrostatic load; `[[point_load]]` a force at the node nearest a point. Checked by
//! equilibrium: at rest, the supports carry exactly the load (½ γ_w H² for water on a wall).
use crate::common;
#[allow(dead_code)]
#[path = "../../fem/tests/common/gmsh_square.rs"]
mod gmsh_square;

use talus::model::fem::{FromScene, Model};
use talus::output::Summary;
use talus::run::fem::run_scene;
use talus::run::RunOptions;
use talus::scene::Scene;
use talus_fem::ElementOrder;

/// A scene on the unit square of `gmsh_square.rs` (physical curve "bottom", surface
/// "domain"), its `.msh` written to `dir`, with `mesh_keys` added to `[mesh.gmsh]` and
/// `material` as the material table.
fn square_scene(dir: &std::path::Path, msh: &str, mesh_keys: &str, material: &str) -> Scene {
    std::fs::write(dir.join("square.msh"), msh).unwrap();
    let text = format!(
        "[mesh.gmsh]\npath = \"square.msh\"\n{mesh_keys}\n\n{material}\n\
         [[boundary]]\nnodes = \"bottom\"\nfix = \"xy\"\n\n\
         [[point_load]]\npoint = [1.0, 1.0]\nforce = [0.0, -1.0e4]\n\n\
         [analysis]\nkind = \"quasi_static\"\n\n[time]\nstep = 1.0\nsteps = 2\n"
    );
    let path = dir.join("square.toml");
    std::fs::write(&path, &text).unwrap();
    Scene::from_path(&path).unwrap()
}

const PLASTIC: &str = "[material]\nyoung_modulus = 1e7\npoisson_ratio = 0.3\n\
                       friction_angle = 30.0\ncohesion = 1e5\ncone_fit = \"plane_strain\"\n";
const ELASTIC: &str = "[material]\nmodel = \"elastic\"\nyoung_modulus = 1e7\npoisson_ratio = 0.3\n";

#[test]
fn order_p2_turns_a_linear_gmsh_mesh_into_p2() {
    let dir = common::target_tmp_dir("gmsh_order_and_loads", "p2");
    let p1 = gmsh_square::p1_file(gmsh_square::P1_TRIANGLES);
    let scene = square_scene(&dir, &p1, "order = \"P2\"", PLASTIC);
    let model = Model::from_scene(&scene).unwrap();
    assert_eq!(model.mesh.order, ElementOrder::P2);
    // Without the key, the mesh stays P1.
    let linear = Model::from_scene(&square_scene(&dir, &p1, "", PLASTIC)).unwrap();
    assert_eq!(linear.mesh.order, ElementOrder::P1);
    // One new node per distinct edge of the linear mesh.
    let mut edges: Vec<[usize; 2]> = linear
        .mesh
        .triangles
        .iter()
        .flat_map(|t| [[t[0], t[1]], [t[1], t[2]], [t[2], t[0]]])
        .map(|[a, b]| [a.min(b), a.max(b)])
        .collect();
    edges.sort();
    edges.dedup();
    assert_eq!(
        model.mesh.nodes.len(),
        linear.mesh.nodes.len() + edges.len()
    );
    assert_eq!(
        model.mesh.node_sets["bottom"].len(),
        2 * linear.mesh.node_sets["bottom"].len() - 1,
        "the bottom gains the mid nodes of its edges"
    );
    // A P2 mesh is not lowered.
    let scene = square_scene(&dir, &gmsh_square::p2_file(), "order = \"P1\"", PLASTIC);
    let err = Model::from_scene(&scene).err().expect("refused");
    assert_eq!(err.field, "mesh.gmsh.order");
}

#[test]
fn a_plastic_run_on_p1_warns_in_its_summary() {
    let p1 = gmsh_square::p1_file(gmsh_square::P1_TRIANGLES);
    let warnings = |keys: &str, material: &str, name: &str| {
        let dir = common::target_tmp_dir("gmsh_order_and_loads", name);
        let scene = square_scene(&dir, &p1, keys, material);
        let out = dir.join("out");
        run_scene(&scene, &RunOptions::new(&out)).unwrap();
        Summary::read(&out.join("summary.json")).unwrap().warnings
    };
    let w = warnings("", PLASTIC, "p1_plastic");
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("P1") && w[0].contains("order = \"P2\""),
        "{}",
        w[0]
    );
    assert!(warnings("order = \"P2\"", PLASTIC, "p2_plastic").is_empty());
    assert!(
        warnings("", ELASTIC, "p1_elastic").is_empty(),
        "no flow, no locking"
    );
}

/// An elastic 1 m × 1 m block on rollers (left: x fixed, bottom: y fixed), quasi-static.
fn block(loads: &str) -> String {
    format!(
        "[mesh.rectangle]\nx = [0.0, 1.0]\ny = [0.0, 1.0]\ncells = [4, 4]\norder = \"P2\"\n\n\
         {ELASTIC}\n\
         [[boundary]]\nname = \"left\"\nnodes = \"left\"\nfix = \"x\"\n\n\
         [[boundary]]\nname = \"bottom\"\nnodes = \"bottom\"\nfix = \"y\"\n\n\
         {loads}\n[analysis]\nkind = \"quasi_static\"\n\n[time]\nstep = 1.0\nsteps = 3\n"
    )
}

fn run_block(loads: &str, name: &str) -> Summary {
    let scene = Scene::parse(&block(loads), None).unwrap();
    let out = common::target_tmp_dir("gmsh_order_and_loads", name);
    run_scene(&scene, &RunOptions::new(&out)).unwrap();
    Summary::read(&out.join("summary.json")).unwrap()
}

/// Water standing 1 m deep against the right side, `p = γ_w (1 − y)`: the left rollers
/// carry its whole thrust `½ γ_w H² = 4905 N/m`, acting toward +x on the body.
#[test]
fn a_hydrostatic_pressure_is_carried_by_the_supports() {
    let gamma = 9810.0;
    let s = run_block(
        &format!(
            "[[pressure]]\nedges = \"right\"\nvalue = {gamma:?}\ngradient = {:?}\n",
            -gamma
        ),
        "water",
    );
    let fx = s.boundaries["left"].last[0];
    let exact = 0.5 * gamma;
    assert!((fx - exact).abs() <= 1e-6 * exact, "{fx} against {exact}");
    assert!(s.boundaries["bottom"].last[1].abs() <= 1e-6 * exact);
    // Without the gradient the same value is a uniform pressure: twice the thrust.
    let s = run_block(
        &format!("[[pressure]]\nedges = \"right\"\nvalue = {gamma:?}\n"),
        "uniform",
    );
    assert!((s.boundaries["left"].last[0] - 2.0 * exact).abs() <= 1e-6 * exact);
}

#[test]
fn a_point_load_is_carried_by_the_supports() {
    let s = run_block(
        "[[point_load]]\npoint = [0.9, 1.05]\nforce = [0.0, -1.0e3]\n",
        "point",
    );
    let fy = s.boundaries["bottom"].last[1];
    assert!((fy - 1.0e3).abs() <= 1e-6 * 1.0e3, "{fy}");
}

#[test]
fn bad_loads_are_named() {
    let refused = |loads: &str| {
        let scene = Scene::parse(&block(loads), None).unwrap();
        Model::from_scene(&scene).err().expect("refused")
    };
    let err = refused("[[pressure]]\nedges = \"right\"\nvalue = 1.0\ngradient = nan\n");
    assert_eq!(err.field, "pressure[0].gradient");
    let err = refused("[[point_load]]\npoint = [0.5, 0.5]\nforce = [inf, 0.0]\n");
    assert_eq!(err.field, "point_load[0].force");
    let err = refused("[[point_load]]\npoint = [nan, 0.5]\nforce = [0.0, 1.0]\n");
    assert_eq!(err.field, "point_load[0].point");
}
