//! `scenes/slope_3d.toml`, the homogeneous 3D slope of Sysala et al. (docs/stability.md,
//! 'Factors of safety in 3D'), as the search sets it up, without the search (a minute or
//! more; `benches/slope_3d.rs` runs it): the Gmsh file's P2 tetrahedra fill the slab's
//! 3000 m³ (40 × 10 × 5 below the toe, and the 15 × 10 + 10 × 10 / 2 m² section of the
//! slope above it, 5 m deep), so the weight the search holds is γV = 60 MN; gravity
//! increase adds that weight once per unit of factor (`Analysis::set_factor`,
//! `model::fem::weight_3d`); the rollers hold every side but the toe, face and crest.
use std::path::{Path, PathBuf};

use talus::analysis::stability::Analysis;
use talus::scene::{Scene3, SceneFile};

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

fn scene(text: &str) -> Scene3 {
    match SceneFile::parse(text, Some(scenes().join("slope_3d.toml"))) {
        Ok(SceneFile::Fem3(s)) => s,
        Ok(_) => panic!("not read as a 3D scene"),
        Err(e) => panic!("{e}"),
    }
}

/// γV of the slab (N): 20 kN/m³ over 3000 m³.
const WEIGHT: f64 = 20e3 * 3000.0;

/// The y-components of the model's forces at the end of the loading (t = 2 s, where the
/// gravity ramp is at 1), free and prescribed dofs, summed.
fn sum_y(analysis: &Analysis<6>) -> f64 {
    let model = &analysis.model;
    let dofs = model.assembly.dofs();
    let mut sum = 0.0;
    let forces = std::iter::once((1.0, &model.force_free, &model.force_prescribed))
        .chain((model.ramped_forces.iter()).map(|r| (r.ramp.at(2.0), &r.free, &r.prescribed)));
    for (m, free, prescribed) in forces {
        for n in 0..model.mesh.nodes.len() {
            if let Some(k) = dofs.free(n, 1) {
                sum += m * free[k];
            }
            if let Some(k) = dofs.prescribed(n, 1) {
                sum += m * prescribed[k];
            }
        }
    }
    sum
}

#[test]
fn sysala_slope_scene_holds_its_weight_on_rollers() {
    let text = std::fs::read_to_string(scenes().join("slope_3d.toml")).unwrap();
    let s = scene(&text);
    let analysis = Analysis::new(&s).unwrap().expect("[stability]");
    let model = &analysis.model;
    assert_eq!(model.mesh.order, talus_fem::ElementOrder::P2);
    let free = model.assembly.dofs().n_free();
    assert!((15_000..30_000).contains(&free), "{free} free dofs");
    // The weight at the end of the loading (the ramp has reached 1).
    let w = sum_y(&analysis);
    assert!(
        (w + WEIGHT).abs() < 1e-9 * WEIGHT,
        "{w} N against −γV = {}",
        -WEIGHT
    );
    // The free surface is free: a node of the face moves in x, y and z; a node of the
    // bottom is held in y only.
    let dofs = model.assembly.dofs();
    let on = |n: usize, f: fn([f64; 3]) -> bool| f(model.mesh.nodes[n]);
    let face = (0..model.mesh.nodes.len())
        .find(|&n| {
            on(n, |p| {
                (p[0] + p[1] - 5.0).abs() < 1e-9 && p[1] > 12.0 && p[2] > 1.0 && p[2] < 4.0
            })
        })
        .expect("a node inside the face");
    assert!((0..3).all(|c| dofs.free(face, c).is_some()));
    let bottom = (0..model.mesh.nodes.len())
        .find(|&n| {
            on(n, |p| {
                p[1] == 0.0 && p[0] > -25.0 && p[0] < 5.0 && p[2] > 1.0 && p[2] < 4.0
            })
        })
        .expect("a node inside the bottom");
    assert!(dofs.prescribed(bottom, 1).is_some());
    assert!(dofs.free(bottom, 0).is_some() && dofs.free(bottom, 2).is_some());

    // Gravity increase: each unit of factor adds the weight once more.
    let text = text
        .replacen(
            "method = \"strength_reduction\"",
            "method = \"gravity_increase\"",
            1,
        )
        .replacen("\ndilatancy = \"davis\"\n", "\n", 1);
    let mut analysis = Analysis::new(&scene(&text)).unwrap().expect("[stability]");
    analysis.set_factor(2.5).unwrap();
    let w = sum_y(&analysis);
    assert!((w + 2.5 * WEIGHT).abs() < 1e-9 * WEIGHT, "{w}");
    analysis.set_factor(1.0).unwrap();
    assert!((sum_y(&analysis) + WEIGHT).abs() < 1e-9 * WEIGHT);
}
