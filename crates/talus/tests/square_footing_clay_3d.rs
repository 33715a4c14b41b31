//! A rigid rough square footing on undrained clay (φ = 0) in 3D
//! (`scenes/square_footing_clay_3d.toml`), bracketing Tresca's bearing capacity factor.
//!
//! Tresca's `N_c` for a rough square footing is 5.78 (Salgado, Lyamin, Sloan & Yu 2004,
//! Géotechnique 54(5), their bounds' mean) to 5.90 (Gourvenec, Randolph & Kingsnorth
//! 2006). Drucker-Prager at φ = 0 is a von Mises cylinder `‖dev σ‖ ≤ k_d c`: with
//! `k_d = √2` (`cone_fit = "plane_strain"`) it is inscribed in Tresca's hexagon, with
//! `k_d = 2√6/3` (`"outer_cone"`) circumscribed about it, so by the limit theorems their
//! limit loads bound Tresca's from below and above. Displacement elements overestimate
//! a limit load, by the mesh's error: the test runs two meshes, extrapolates
//! `N(h) = N₀ + C h^p` to h → 0 with p = 1 and with the p = 1.14 of a three-mesh fit
//! (6×5×6, 9×7×9, 12×10×12 cells: 6.721, 6.224, 5.987; `docs/3d.md`), and requires
//! the inscribed `N₀ ≤ 5.78`, the circumscribed `N₀ ≥ 5.90`. A weightless φ = 0 body's
//! limit load is proportional to the cylinder's radius, so the circumscribed load is the
//! inscribed one times `(2√6/3)/√2 = 2/√3`, which the coarse mesh checks to 1e-3 (the
//! elastic part does not scale; the plateau does).
mod common;

use common::replaced;
use talus::run::fem::run_scene_3d;
use talus::run::RunOptions;
use talus::scene::SceneFile;
use talus_fem::ReactionForce;

const SCENE: &str = include_str!("../../../scenes/square_footing_clay_3d.toml");
const C: f64 = 1.0e4;
/// The quarter footing's area, (B/2)², m².
const QUARTER: f64 = 0.25;

/// `N_c = F / ((B/2)² c)` on the plateau and its last relative rise per step.
fn bearing_factor(cells: &str, fit: &str, name: &str) -> (f64, f64) {
    let text = replaced(
        &replaced(SCENE, "cells = [9, 7, 9]", &format!("cells = [{cells}]")),
        "cone_fit = \"plane_strain\"",
        &format!("cone_fit = \"{fit}\""),
    );
    let Ok(SceneFile::Fem3(scene)) = SceneFile::parse(&text, None) else {
        panic!("not a 3D scene")
    };
    let dir = common::target_tmp_dir("square_footing_clay_3d", name);
    let mut options = RunOptions::new(dir.join("out"));
    options.write_fields = false;
    let run = run_scene_3d(&scene, &options, None).unwrap_or_else(|e| panic!("{e}"));
    let f: Vec<f64> = run.records.iter().map(|r| r.reaction_force()).collect();
    let n = f.len();
    let rise = (f[n - 1] - f[n - 2]) / f[n - 1];
    (f[n - 1] / (QUARTER * C), rise)
}

#[test]
fn von_mises_cylinders_inscribed_and_circumscribed_bracket_tresca_n_c() {
    let (coarse, rise_c) = bearing_factor("6, 5, 6", "plane_strain", "inscribed_6");
    let (fine, rise_f) = bearing_factor("9, 7, 9", "plane_strain", "inscribed_9");
    let (outer, _) = bearing_factor("6, 5, 6", "outer_cone", "circumscribed_6");
    println!("N_c inscribed: 6x5x6 {coarse:.4}, 9x7x9 {fine:.4}; circumscribed 6x5x6 {outer:.4}");
    // On the plateau: the last step adds less than 0.1 %.
    assert!(
        rise_c.abs() < 1e-3 && rise_f.abs() < 1e-3,
        "{rise_c} {rise_f}"
    );
    // The circumscribed cylinder's load is the inscribed one's times 2/√3.
    let ratio = outer / coarse;
    assert!((ratio / (2.0 / 3f64.sqrt()) - 1.0).abs() < 1e-3, "{ratio}");
    // Displacement elements converge from above.
    assert!(fine < coarse, "{fine} !< {coarse}");
    let (h_c, h_f): (f64, f64) = (1.0 / 6.0, 1.0 / 9.0);
    for p in [1.0f64, 1.14] {
        let c = (coarse - fine) / (h_c.powf(p) - h_f.powf(p));
        let inscribed = fine - c * h_f.powf(p);
        let circumscribed = inscribed * 2.0 / 3f64.sqrt();
        println!("p = {p}: N0 inscribed {inscribed:.3}, circumscribed {circumscribed:.3}");
        assert!(inscribed <= 5.78, "p = {p}: inscribed {inscribed} > 5.78");
        assert!(
            circumscribed >= 5.90,
            "p = {p}: circumscribed {circumscribed} < 5.90"
        );
        // And the bracket is not vacuous: within 15 % of the range it brackets.
        assert!(inscribed > 5.78 / 1.15 && circumscribed < 5.90 * 1.15);
    }
}
