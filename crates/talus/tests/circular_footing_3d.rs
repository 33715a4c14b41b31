//! A rigid rough circular footing on undrained clay in 3D (`scenes/circular_footing_3d.toml`,
//! a quarter cylinder of P2 tetrahedra) against Talus' axisymmetric run of the same
//! footing (`scenes/circular_footing_axi.toml`), issue 25; figures in docs/3d.md, 'The
//! circular footing against its axisymmetric run'.
//!
//! The two scenes are one continuum problem: a weightless von Mises body (φ = 0, outer
//! cone) pushed by an axisymmetric footing collapses axisymmetrically, so their limit
//! loads agree as both meshes are refined. Both overestimate it by the mesh's error, of
//! order h and about +19 % on these meshes, and tetrahedra and triangles do not err alike
//! (docs/3d.md: the square footing's tetrahedra overshoot by 11–16 %); so the 3D mesh is
//! the axisymmetric one's meridian triangles revolved a quarter turn (4 layers,
//! `scenes/circular_footing_3d.py`), and the two errors differ by +0.9 % here (+2.4 % on
//! the meridian twice as coarse): within issue 25's 2 %. The 3D load is
//! 4 × the quarter's `footing_fy`; the axisymmetric `footing_fy` is already the whole
//! footing's (2π × per radian, docs/axisymmetry.md).
//!
//! Independent reference: the bearing capacity of a rough circular footing on Tresca
//! clay, `N_c = 6.05` (Eason & Shield 1960, ZAMP 11, 33–43; Shield's 5.69 of 1955 is the
//! smooth one's). The outer cone (`k_d = 2√6/3`) is the von Mises cylinder circumscribed
//! about Tresca's hexagon, the plane-strain fit (`k_d = √2`) the inscribed one, and a
//! weightless φ = 0 limit load scales with `k_d`: so the outer cone's `N_c` lies in
//! `[6.05, 6.05 · 2/√3 = 6.99]`. The test checks that of the mesh-converged axisymmetric
//! load, extrapolated (order 1, as measured: docs/3d.md) from two graded rectangles.
use crate::common;
use std::f64::consts::PI;
use std::path::Path;

use common::replaced;
use talus::run::fem::run_scene;
use talus::run::RunOptions;
use talus::scene::SceneFile;
use talus_fem::ReactionForce;

const R: f64 = 0.5;
const C: f64 = 1.0e4;
/// Eason & Shield (1960): a rough circular footing on Tresca clay.
const N_C_TRESCA: f64 = 6.05;

fn scenes() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

fn options(name: &str) -> RunOptions {
    let dir = common::target_tmp_dir("circular_footing_3d", name);
    let mut options = RunOptions::new(dir.join("out"));
    options.write_fields = false;
    options
}

/// `N_c = Q / (π R² c)` on the plateau, Q the whole footing's load, and the last step's
/// relative rise.
fn bearing_factor(q: &[f64]) -> (f64, f64) {
    let n = q.len();
    (
        q[n - 1] / (PI * R * R * C),
        (q[n - 1] - q[n - 2]) / q[n - 1],
    )
}

/// The axisymmetric scene `text` run; its `N_c` and last rise.
fn axisymmetric(text: &str, name: &str) -> (f64, f64) {
    let path = scenes().join("circular_footing_axi.toml");
    let Ok(SceneFile::Fem(scene)) = SceneFile::parse(text, Some(path)) else {
        panic!("not a 2D scene")
    };
    let run = run_scene(&scene, &options(name)).unwrap_or_else(|e| panic!("{e}"));
    let q: Vec<f64> = run.records.iter().map(|r| r.reaction_force()).collect();
    bearing_factor(&q)
}

#[test]
fn quarter_cylinder_of_tetrahedra_carries_the_axisymmetric_limit_load() {
    let (n3, na) =
        talus::analysis::verification::circular_footing_nc().unwrap_or_else(|e| panic!("{e}"));
    let rise = |n: &[f64]| (n[n.len() - 1] - n[n.len() - 2]) / n[n.len() - 1];
    let (rise3, risea) = (rise(&n3), rise(&na));
    let (n3, na) = (n3[n3.len() - 1], na[na.len() - 1]);
    println!(
        "N_c 3D {n3:.4}, axisymmetric {na:.4}: 3D/axi - 1 = {:+.4}",
        n3 / na - 1.0
    );
    // On the plateau: the last step adds less than 0.1 %.
    assert!(rise3.abs() < 1e-3 && risea.abs() < 1e-3, "{rise3} {risea}");
    // Issue 25: the 3D limit load within 2 % of the axisymmetric one.
    assert!(
        (n3 / na - 1.0).abs() < 0.02,
        "3D {n3} against axisymmetric {na}"
    );
}

/// The axisymmetric run converges into the bracket of Eason & Shield's `N_c`: graded
/// rectangles of 24² and 48² P2 cells, extrapolated with order 1.
#[test]
fn axisymmetric_limit_load_brackets_eason_and_shields_n_c() {
    let axi = std::fs::read_to_string(scenes().join("circular_footing_axi.toml")).unwrap();
    let rectangle = |cells: usize, ratio: f64| {
        let text = replaced(
            &axi,
            "[mesh.gmsh]\npath = \"circular_footing_axi.msh\"",
            &format!(
                "[mesh.rectangle]\nx = [0.0, 1.5]\ny = [-1.5, 0.0]\ncells = [{cells}, {cells}]\n\
                 order = \"P2\"\nfocus = [0.5, 0.0]\nratio = [{ratio}, {ratio}]"
            ),
        );
        let text = replaced(&text, "nodes = \"base\"", "nodes = \"bottom\"");
        let text = replaced(&text, "nodes = \"outer\"", "nodes = \"right\"");
        let text = replaced(
            &text,
            "nodes = \"footing\"",
            "nodes = { box = [[0.0, -1e-9], [0.5, 1e-9]] }",
        );
        axisymmetric(&text, &format!("rectangle_{cells}"))
    };
    // The same grading per unit length: the ratio's square root on twice the cells.
    let (coarse, _) = rectangle(24, 1.15f64.powf(0.5));
    let (fine, rise) = rectangle(48, 1.15f64.powf(0.25));
    let n0 = 2.0 * fine - coarse;
    println!("N_c 24² {coarse:.4}, 48² {fine:.4}, extrapolated {n0:.4}");
    assert!(rise.abs() < 1e-3, "{rise}");
    assert!(fine < coarse, "{fine} !< {coarse}");
    assert!(n0 >= N_C_TRESCA, "circumscribed {n0} < {N_C_TRESCA}");
    assert!(
        n0 * 3f64.sqrt() / 2.0 <= N_C_TRESCA,
        "inscribed {} > {N_C_TRESCA}",
        n0 * 3f64.sqrt() / 2.0
    );
}
