//! Construction in stages in 3D (`[[stage]]` with `[analysis] geometry = "3d"`, as in 2D:
//! `docs/scenes.md`, 'Stages'; `docs/3d.md`).
//!
//! - Digging the top metre of a laterally confined elastic column at rest under K₀ =
//!   ν/(1 − ν) leaves the K₀ state of the shorter column, `σ_yy = −ρ g (H′ − y)`,
//!   `σ_xx = σ_zz = K₀ σ_yy`, and heaves it by the unloading's uniaxial strain, `u_y(y) =
//!   ρ g t y / M` with `M = E (1 − ν) / ((1 + ν)(1 − 2ν))` (one-dimensional consolidation's
//!   constrained modulus, e.g. Lambe & Whitman, Soil Mechanics, 1969, ch. 12): fields linear
//!   in y, which P2 tetrahedra hold exactly, so the staged run meets them to its Newton
//!   tolerance and the quasi-static inertia left.
//! - A region built on a body at rest carries its weight at the stage's end: the base
//!   reaction grows by `ρ g V` (N).
//! - Bad stages name their field, as in 2D.
use crate::common;
use talus::model::fem::stages::{final_model, Stages};
use talus::run::fem::run_scene_3d;
use talus::run::RunOptions;
use talus::scene::{Scene3, SceneFile};

const G: f64 = 9.81;
const RHO: f64 = 2000.0;
const E: f64 = 2.0e7;
const NU: f64 = 0.25;

/// A 2 × 4 × 2 m elastic column of P2 tetrahedra on a fixed base, rollers on its four
/// sides, at rest under its weight by K₀ = ν/(1 − ν), with `stages`.
fn column(stages: &str) -> String {
    format!(
        "gravity = [0.0, -{G}, 0.0]\n\
         [analysis]\ngeometry = \"3d\"\nkind = \"quasi_static\"\ninertia_ratio = 1e-6\n\n\
         [mesh.box]\nx = [0.0, 2.0]\ny = [0.0, 4.0]\nz = [0.0, 2.0]\ncells = [1, 4, 1]\n\
         order = \"P2\"\n\n\
         [[region]]\nname = \"top\"\nbox = [[0.0, 3.0, 0.0], [2.0, 4.0, 2.0]]\n\n\
         [material]\nmodel = \"elastic\"\nyoung_modulus = {E:?}\npoisson_ratio = {NU}\n\
         density = {RHO:?}\n\n\
         [[boundary]]\nname = \"base\"\nnodes = \"bottom\"\nfix = \"xyz\"\n\n\
         [[boundary]]\nnodes = \"left\"\nfix = \"x\"\n\n\
         [[boundary]]\nnodes = \"right\"\nfix = \"x\"\n\n\
         [[boundary]]\nnodes = \"back\"\nfix = \"z\"\n\n\
         [[boundary]]\nnodes = \"front\"\nfix = \"z\"\n\n\
         [initial_stress]\nk0 = {k0:?}\nsurface = 4.0\n\n\
         [solver]\ntolerance = 1e-12\n\n\
         [output]\nreaction = \"base\"\n\n\
         [time]\nstep = 1.0\n\n{stages}",
        k0 = NU / (1.0 - NU)
    )
}

fn scene(text: &str) -> Scene3 {
    match SceneFile::parse(text, None).unwrap() {
        SceneFile::Fem3(scene) => scene,
        _ => panic!("a 3D finite-element scene"),
    }
}

#[test]
fn digging_the_top_of_a_confined_column_leaves_its_k0_state_and_heaves_it_by_uniaxial_strain() {
    let text = column(
        "[[stage]]\nname = \"at rest\"\nsteps = 1\n\n\
         [[stage]]\nname = \"dig\"\nsteps = 4\ndeactivate = [\"top\"]\n\n\
         [[stage]]\nname = \"settle\"\nsteps = 2\n",
    );
    let scene = scene(&text);
    let out = common::target_tmp_dir("stages_3d", "dig");
    let run = run_scene_3d(&scene, &RunOptions::new(&out), None).unwrap();
    assert_eq!(run.records.len(), 7);
    let model = final_model::<3, 6>(&scene).unwrap();
    let (t, h) = (1.0, 3.0);
    let k0 = NU / (1.0 - NU);
    let m = E * (1.0 - NU) / ((1.0 + NU) * (1.0 - 2.0 * NU));
    let heave = RHO * G * t * h / m;
    assert!(heave > 1e-3, "the dig moves the column: {heave} m");
    let positions = &model.mesh.nodes;
    assert_eq!(run.final_state.displacement.len(), positions.len());
    assert!(
        positions.iter().all(|p| p[1] <= h + 1e-12),
        "the top is gone"
    );
    let mut worst_u = 0.0f64;
    for (u, p) in run.final_state.displacement.iter().zip(positions) {
        let expected = [0.0, RHO * G * t * p[1] / m, 0.0];
        for c in 0..3 {
            worst_u = worst_u.max((u[c] - expected[c]).abs() / heave);
        }
    }
    let scale = RHO * G * h;
    let mut worst_s = 0.0f64;
    for (s, x) in run
        .final_state
        .sigma
        .chunks_exact(6)
        .zip(&model.assembly.gauss_points)
    {
        let syy = -RHO * G * (h - x[1]);
        let expected = [k0 * syy, syy, k0 * syy, 0.0, 0.0, 0.0];
        for c in 0..6 {
            worst_s = worst_s.max((s[c] - expected[c]).abs() / scale);
        }
    }
    // Measured: heave 2.4525e-3 m, errors 9.5e-10 and 4.1e-10.
    println!("heave {heave:.6e} m; worst displacement error {worst_u:.2e} of it, stress {worst_s:.2e} of ρgH′");
    assert!(
        worst_u < 1e-8,
        "displacement off the uniaxial-strain heave by {worst_u:e} of it"
    );
    assert!(
        worst_s < 1e-8,
        "stress off the K₀ state of the dug column by {worst_s:e} of ρgH′"
    );
    // The base carries the shorter column: ρ g V′ (N).
    let base = common::history_column(&out, "base_fy");
    let weight = RHO * G * 2.0 * 2.0 * h;
    let last = base[base.len() - 1];
    assert!(
        (last - weight).abs() < 1e-7 * weight,
        "base {last} N against ρgV′ = {weight}"
    );
}

#[test]
fn a_region_built_on_the_column_carries_its_weight_at_the_stages_end() {
    // The top metre is absent at first: the base carries 2 × 3 × 2 m³, then 2 × 4 × 2 m³.
    let text = column(
        "[[stage]]\nname = \"ground\"\nsteps = 1\n\n\
         [[stage]]\nname = \"fill\"\nsteps = 4\nactivate = [\"top\"]\n",
    )
    .replace("surface = 4.0", "surface = 3.0");
    let scene = scene(&text);
    let stages = Stages::<6>::of(&scene).unwrap().unwrap();
    assert_eq!(
        stages.plans[0].elements.len(),
        18,
        "three of the four cells' 6 tetrahedra"
    );
    let out = common::target_tmp_dir("stages_3d", "fill");
    run_scene_3d(&scene, &RunOptions::new(&out), None).unwrap();
    let stage = common::history_column(&out, "stage");
    assert_eq!(stage, [0.0, 0.0, 1.0, 1.0, 1.0, 1.0]);
    let base = common::history_column(&out, "base_fy");
    let w = |v: f64| RHO * G * v;
    for (step, expected) in [(1, w(12.0)), (5, w(16.0))] {
        assert!(
            (base[step] - expected).abs() < 1e-6 * expected,
            "step {step}: base reaction {} N against ρ g V = {expected}",
            base[step]
        );
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let stages = summary["stages"].as_array().unwrap();
    assert_eq!(stages[1]["activated"][0], "top");
    assert_eq!(
        (
            stages[0]["elements"].as_u64(),
            stages[1]["elements"].as_u64()
        ),
        (Some(18), Some(24))
    );
    assert_eq!(summary["status"], "finished");
}

#[test]
fn bad_3d_stages_are_refused_naming_the_field_and_the_value() {
    let cases = [
        (
            column("[[stage]]\nname = \"dig\"\nsteps = 2\ndeactivate = [\"roof\"]\n"),
            "stage[0].deactivate[0]",
            "roof",
        ),
        (
            column(
                "[[stage]]\nname = \"a\"\nsteps = 1\ndeactivate = [\"top\"]\n\n\
                 [[stage]]\nname = \"b\"\nsteps = 1\ndeactivate = [\"top\"]\n",
            ),
            "stage[1].deactivate[0]",
            "removed already",
        ),
        (
            column("[[stage]]\nname = \"a\"\nsteps = 1\nactivate = [\"top\"]\n")
                .replace("nodes = \"left\"", "nodes = \"left\"\nstages = [\"b\"]"),
            "boundary[1].stages[0]",
            "\"b\"",
        ),
    ];
    for (text, field, needle) in cases {
        let scene = scene(&text);
        let e = match Stages::<6>::of(&scene) {
            Err(e) => e,
            Ok(Some(stages)) => {
                match (0..stages.plans.len()).find_map(|k| stages.model(&scene, k).err()) {
                    Some(e) => e,
                    None => panic!("{field}: accepted"),
                }
            }
            Ok(None) => panic!("{field}: no stages"),
        };
        let message = e.to_string();
        assert!(
            message.contains(field) && message.contains(needle),
            "{field}: {message}"
        );
    }
}
