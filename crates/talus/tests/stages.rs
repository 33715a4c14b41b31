//! Construction in stages (`[[stage]]`, `docs/scenes.md`, 'Stages').
//!
//! - Elastic excavation: removing a region of a block at rest under gravity (K₀ on level
//!   ground, in discrete equilibrium), the staged run ends, once the released force is
//!   fully ramped, at the kept body's direct elastic solve `K_K Δu = −F`, with `F` the force
//!   the removed part exerted, computed independently from the removed elements
//!   (`talus_fem::element_forces`, `docs/derivations.md`), to 1e-8.
//! - A region built on a body at rest carries its weight at the stage's end: the base
//!   reaction grows by the new region's weight `ρ g A`.
//! - One history, one VTU series, summary.json per stage, resume across stages.
//! - Bad inputs name their field and value.
use crate::common;
use nalgebra::{DMatrix, DVector};
use talus::model::fem::stages::Stages;
use talus::model::fem::FromScene;
use talus::run::fem::run_scene;
use talus::run::RunOptions;
use talus::scene::Scene;

const G: f64 = 9.81;
const RHO: f64 = 2000.0;

/// A 4 m × 4 m elastic block on a fixed base with rollers on its sides, K₀ = ν/(1 − ν) at
/// rest under its weight (linear in y: P2's 3-point rule balances it exactly), and
/// `stages`. Inertia ratio 1e-6: what inertia is left after the stages is below 1e-9 of the
/// motion (measured: 1.1e-9 and 6e-10 of it in the excavation test), while a smaller ratio
/// loses digits in `W` (`h² B M⁻¹ Bᵀ` dwarfs `S`: 1e-10 leaves 8e-6).
fn block(stages: &str) -> String {
    format!(
        "gravity = [0.0, -{G}]\n\
         [mesh.rectangle]\nx = [0.0, 4.0]\ny = [0.0, 4.0]\ncells = [4, 4]\norder = \"P2\"\n\n\
         [[region]]\nname = \"top\"\nbox = [[0.0, 3.0], [4.0, 4.0]]\n\n\
         [[region]]\nname = \"corner\"\nbox = [[2.0, 2.0], [4.0, 4.0]]\n\n\
         [material]\nmodel = \"elastic\"\nyoung_modulus = 2.0e7\npoisson_ratio = 0.25\n\
         density = {RHO}\n\n\
         [[boundary]]\nname = \"base\"\nnodes = {{ box = [[0.0, 0.0], [4.0, 0.0]] }}\nfix = \"xy\"\n\n\
         [[boundary]]\nnodes = {{ box = [[0.0, 0.0], [0.0, 4.0]] }}\nfix = \"x\"\n\n\
         [[boundary]]\nnodes = {{ box = [[4.0, 0.0], [4.0, 4.0]] }}\nfix = \"x\"\n\n\
         [initial_stress]\nk0 = {k0:?}\nsurface = 4.0\n\n\
         [analysis]\nkind = \"quasi_static\"\ninertia_ratio = 1e-6\n\n\
         [solver]\ntolerance = 1e-12\n\n\
         [time]\nstep = 1.0\n\n{stages}",
        k0 = 0.25 / 0.75
    )
}

/// The kept body's stiffness on its free dofs, `K = Σ_p V_p B_pᵀ C B_p`, from the
/// assembly's strain operator and the material's compliance (dense; a small mesh).
fn stiffness(model: &talus::model::fem::Model) -> DMatrix<f64> {
    let asm = &model.assembly;
    let n = asm.dofs().n_free();
    let zero = vec![0.0; asm.dofs().n_prescribed()];
    let columns: Vec<Vec<nalgebra::SVector<f64, 4>>> = (0..n)
        .map(|j| {
            let mut e = vec![0.0; n];
            e[j] = 1.0;
            asm.strain(&e, &zero).unwrap()
        })
        .collect();
    let mut k = DMatrix::zeros(n, n);
    for p in 0..asm.n_points() {
        let c = model.compliance_at(p).try_inverse().unwrap();
        let v = asm.gauss_volumes[p];
        for i in 0..n {
            let ci = c * columns[i][p];
            for j in i..n {
                let kij = v * ci.dot(&columns[j][p]);
                k[(i, j)] += kij;
                if j != i {
                    k[(j, i)] += kij;
                }
            }
        }
    }
    k
}

#[test]
fn an_elastic_excavation_ends_at_the_kept_bodys_solve_under_the_released_force() {
    for removed in ["top", "corner"] {
        let text = block(&format!(
            "[[stage]]\nname = \"at rest\"\nsteps = 1\n\n\
             [[stage]]\nname = \"dig\"\nsteps = 4\ndeactivate = [\"{removed}\"]\n\n\
             [[stage]]\nname = \"settle\"\nsteps = 2\n"
        ));
        let scene = Scene::parse(&text, None).unwrap();
        let stages = Stages::<4>::of(&scene).unwrap().unwrap();
        let full = stages.model(&scene, 0).unwrap();
        let kept = stages.model(&scene, 2).unwrap();
        // The removed part's force on the rest at the K₀ state, per node of the full mesh.
        let at_rest = full.model.initial_state(&scene).unwrap();
        let removed_elements: Vec<usize> = (0..full.elements.len())
            .filter(|i| kept.elements.binary_search(&full.elements[*i]).is_err())
            .collect();
        let densities = vec![RHO; full.model.n_points()];
        let f = talus_fem::element_forces(
            &full.model,
            &at_rest,
            &removed_elements,
            [0.0, -G],
            &densities,
        )
        .unwrap();
        let node_map: Vec<Option<usize>> = full
            .nodes
            .iter()
            .map(|n| kept.nodes.binary_search(n).ok())
            .collect();
        let (f_free, _) =
            talus_fem::restrict_forces(&f, &node_map, kept.model.assembly.dofs()).unwrap();
        // Σ F is the removed part's weight (a check of the reference itself).
        let weight: f64 = f.iter().map(|v| v[1]).sum();
        let area = 4.0; // both regions are 4 m²
        assert!(
            (weight + RHO * G * area).abs() < 1e-9 * RHO * G * area,
            "{weight}"
        );
        let k = stiffness(&kept.model);
        let du = k.cholesky().unwrap().solve(&(-DVector::from_vec(f_free)));

        let out = common::target_tmp_dir("stages", &format!("excavation_{removed}"));
        let run = run_scene(&scene, &RunOptions::new(&out)).unwrap();
        let dofs = kept.model.assembly.dofs();
        let reference = dofs
            .scatter(du.as_slice(), &vec![0.0; dofs.n_prescribed()])
            .unwrap();
        let scale = reference
            .iter()
            .flat_map(|u| u.iter())
            .fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(scale > 1e-5, "the excavation moves the body: {scale} m");
        assert_eq!(run.final_state.displacement.len(), reference.len());
        for (n, (u, r)) in run
            .final_state
            .displacement
            .iter()
            .zip(&reference)
            .enumerate()
        {
            for c in 0..2 {
                assert!(
                    (u[c] - r[c]).abs() <= 1e-8 * scale,
                    "{removed}: node {n} component {c}: staged {} against the direct solve {}",
                    u[c],
                    r[c]
                );
            }
        }
    }
}

#[test]
fn a_region_built_carries_its_weight_at_the_stages_end() {
    // The top metre is absent at first (a later stage builds it): the base carries the
    // lower 4 × 3 m², then the whole 4 × 4 m² block, `ρ g A` per metre.
    let text = block(
        "[[stage]]\nname = \"ground\"\nsteps = 1\n\n\
         [[stage]]\nname = \"fill\"\nsteps = 4\nactivate = [\"top\"]\n",
    )
    .replace("surface = 4.0", "surface = 3.0")
    .replace("[time]", "[output]\nreaction = \"base\"\n\n[time]");
    let scene = Scene::parse(&text, None).unwrap();
    let out = common::target_tmp_dir("stages", "construction");
    let run = run_scene(&scene, &RunOptions::new(&out)).unwrap();
    assert_eq!(run.records.len(), 5);
    let stage = common::history_column(&out, "stage");
    assert_eq!(stage.len(), 6, "step 0 and five steps, numbered on");
    assert_eq!(stage, [0.0, 0.0, 1.0, 1.0, 1.0, 1.0]);
    let base_fy = common::history_column(&out, "base_fy");
    let w = |a: f64| RHO * G * a;
    for (step, expected) in [(1, w(12.0)), (5, w(16.0))] {
        assert!(
            (base_fy[step] - expected).abs() < 1e-6 * expected,
            "step {step}: base reaction {} N/m against ρ g A = {expected}",
            base_fy[step]
        );
    }
    // Half-way through the ramp, half the new weight.
    assert!(
        (base_fy[3] - w(14.0)).abs() < 1e-3 * w(14.0),
        "{}",
        base_fy[3]
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let stages = summary["stages"].as_array().unwrap();
    assert_eq!(stages.len(), 2);
    assert_eq!(stages[1]["name"], "fill");
    assert_eq!(stages[1]["activated"][0], "top");
    assert_eq!(
        (
            stages[1]["first_step"].as_u64(),
            stages[1]["last_step"].as_u64()
        ),
        (Some(2), Some(5))
    );
    assert_eq!(
        (
            stages[0]["elements"].as_u64(),
            stages[1]["elements"].as_u64()
        ),
        (Some(24), Some(32))
    );
    assert_eq!(summary["status"], "finished");
    assert_eq!(summary["steps"], 5);
}

#[test]
fn the_vtu_series_runs_on_across_stages_each_file_on_its_stages_mesh() {
    let text = block(
        "[[stage]]\nname = \"at rest\"\nsteps = 2\n\n\
         [[stage]]\nname = \"dig\"\nsteps = 3\ndeactivate = [\"corner\"]\n",
    )
    .replace("[time]", "[output]\nvtu_every = 2\n\n[time]");
    let scene = Scene::parse(&text, None).unwrap();
    let out = common::target_tmp_dir("stages", "vtu_series");
    run_scene(
        &scene,
        &RunOptions {
            write_fields: true,
            ..RunOptions::new(&out)
        },
    )
    .unwrap();
    let pvd = std::fs::read_to_string(out.join("solution.pvd")).unwrap();
    // Step 0, 2 (also the first stage's end), 4, and 5 (the last).
    let files: Vec<&str> = pvd
        .lines()
        .filter_map(|l| l.split("file=\"").nth(1))
        .map(|f| f.split('"').next().unwrap())
        .collect();
    assert_eq!(
        files,
        [
            "vtu/step_00000.vtu",
            "vtu/step_00002.vtu",
            "vtu/step_00004.vtu",
            "vtu/step_00005.vtu"
        ]
    );
    let cells = |f: &str| {
        let xml = std::fs::read_to_string(out.join(f)).unwrap();
        common::attr(&xml, "NumberOfCells")
            .parse::<usize>()
            .unwrap()
    };
    assert_eq!(cells(files[1]), 32);
    assert_eq!(cells(files[3]), 24, "the corner's 8 triangles are gone");
}

#[test]
fn a_staged_run_resumed_in_its_second_stage_ends_as_the_run_never_stopped() {
    use std::ops::ControlFlow;
    use talus::run::checkpoint;
    use talus::run::fem::resume_scene;
    let text = block(
        "[[stage]]\nname = \"at rest\"\nsteps = 2\n\n\
         [[stage]]\nname = \"dig\"\nsteps = 4\ndeactivate = [\"corner\"]\n\n\
         [[stage]]\nname = \"settle\"\nsteps = 2\n",
    );
    let scene = Scene::parse(&text, None).unwrap();
    let whole = common::target_tmp_dir("stages", "resume_whole");
    let whole_run = run_scene(&scene, &RunOptions::new(&whole)).unwrap();
    let cut = common::target_tmp_dir("stages", "resume_cut");
    let stop: talus::run::Observer = std::sync::Arc::new(|p| {
        if p.step == 4 {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    });
    let options = RunOptions {
        checkpoint_every: 3,
        observer: Some(stop),
        ..RunOptions::new(&cut)
    };
    let err = run_scene(&scene, &options).unwrap_err();
    assert!(
        matches!(err, talus::run::RunError::Interrupted { step: 4, .. }),
        "{err}"
    );
    let saved = checkpoint::read(&cut).unwrap();
    assert_eq!(saved.step, 4);
    let resumed = resume_scene(&scene, saved, &RunOptions::new(&cut)).unwrap();
    assert_eq!(
        resumed.final_state.displacement,
        whole_run.final_state.displacement
    );
    assert_eq!(resumed.final_state.sigma, whole_run.final_state.sigma);
    // The same history, the seconds column aside.
    assert_eq!(
        common::history_without_seconds(&cut),
        common::history_without_seconds(&whole)
    );
    let summary = |dir: &std::path::Path| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
    };
    assert_eq!(summary(&cut)["stages"], summary(&whole)["stages"]);
}

/// The error of the scene `text`'s stages or model, by field and message.
fn refused(text: &str) -> (String, String) {
    let scene = match Scene::parse(text, None) {
        Ok(s) => s,
        Err(e) => return (e.field, e.message),
    };
    let e = match Stages::<4>::of(&scene) {
        Err(e) => e,
        Ok(Some(stages)) => (0..stages.plans.len())
            .find_map(|k| stages.model(&scene, k).err())
            .expect("refused"),
        Ok(None) => match talus::model::fem::Model::from_scene(&scene) {
            Err(e) => e,
            Ok(_) => panic!("refused"),
        },
    };
    (e.field, e.message)
}

#[test]
fn bad_stages_are_refused_naming_the_field_and_the_value() {
    let one = "[[stage]]\nname = \"a\"\nsteps = 1\n";
    let two = |second: &str| {
        block(&format!(
            "{one}\n[[stage]]\nname = \"b\"\nsteps = 1\n{second}"
        ))
    };
    let left_side = "[[boundary]]\nnodes = { box = [[0.0, 0.0], [0.0, 4.0]] }\nfix = \"x\"";
    let cases: Vec<(String, &str, &str)> = vec![
        (
            two("deactivate = [\"top\", \"corner\", \"base\"]\n"),
            "stage[1].deactivate[2]",
            "\"base\" is no region of the scene (regions: corner, top)",
        ),
        (
            two("deactivate = [\"top\"]\n\n[[stage]]\nname = \"c\"\nsteps = 1\ndeactivate = [\"top\"]\n"),
            "stage[2].deactivate[0]",
            "region \"top\" was removed already, by stage[1] (\"b\")",
        ),
        (
            two("deactivate = [\"everything\"]\n").replace(
                "[material]",
                "[[region]]\nname = \"everything\"\nbox = [[0.0, 0.0], [4.0, 4.0]]\n\n[material]",
            ),
            "stage[1].deactivate",
            "[\"everything\"] leaves stage \"b\" without any element",
        ),
        (
            two("activate = [\"top\"]\n\n[[stage]]\nname = \"c\"\nsteps = 1\nactivate = [\"top\"]\n"),
            "stage[2].activate[0]",
            "region \"top\" is there already",
        ),
        (
            block(&format!("{one}\n{one}")),
            "stage[1].name",
            "\"a\" is already the name of stage[0]",
        ),
        (block(&one.replace("steps = 1", "steps = 0")), "stage[0].steps", "at least 1"),
        (
            block(one).replace("[time]\nstep = 1.0", "[time]\nstep = 1.0\nsteps = 3"),
            "time.steps",
            "3 with [[stage]]: each stage gives its own `steps`",
        ),
        (
            block(&format!("{one}factor_of_safety = true\n")),
            "stage[0].factor_of_safety",
            "needs a [stability] section",
        ),
        (
            block(one).replace(left_side, &format!("{left_side}\nstages = [\"z\"]")),
            "boundary[1].stages[0]",
            "\"z\" is no stage of the scene (stages: a)",
        ),
        (
            block("[[traction]]\nedges = \"top\"\nvalue = [0.0, -1.0]\nstages = [\"a\"]\n")
                .replace("step = 1.0", "step = 1.0\nsteps = 1"),
            "traction[0].stages",
            "the scene has no [[stage]]",
        ),
        (
            two("water = { phreatic = [[0.0, 3.0], [0.0, 2.0]] }\n"),
            "stage[1].water.phreatic",
            "increase",
        ),
        (
            two("water = { level = 2.0, unit_weight = -1.0 }\n"),
            "stage[1].water.unit_weight",
            "-1",
        ),
    ];
    for (text, field, message) in cases {
        let (f, m) = refused(&text);
        assert_eq!(f, field, "{m}");
        assert!(m.contains(message), "{field}: {m}");
    }
    // A value of the wrong type is a TOML error: it names the value and the key's line.
    for (key, value) in [
        ("reset_displacements", "\"yes\""),
        ("factor_of_safety", "1"),
    ] {
        let text = two(&format!("{key} = {value}\n"));
        let err = Scene::parse(&text, None).unwrap_err();
        let line = common::line_of(&text, &format!("{key} = {value}"));
        assert_eq!(err.line, Some(line), "{err}");
        assert!(err.message.contains("expected a boolean"), "{err}");
    }
}

#[test]
fn a_cut_dug_in_lifts_and_dug_at_once_have_one_factor_of_safety() {
    // Associative perfect plasticity has a unique limit load (the bound theorems), so the
    // factor of safety cannot depend on the path: three lifts from K₀, or the final
    // geometry loaded by gravity in one stage, give one factor to the bracket's tolerance.
    use talus::analysis::verification::{cut_scenes, staged_factor, CUT_IN_LIFTS};
    assert!(CUT_IN_LIFTS.contains("dilatancy_angle = 20.0      # associative"));
    let (lifts, once) = cut_scenes().unwrap();
    assert_eq!(lifts.spec.stage.len(), 4);
    assert_eq!(once.spec.stage.len(), 1);
    assert!(once.spec.initial_stress.is_none());
    let a = common::target_tmp_dir("stages", "cut_lifts");
    let (fa, ba) = staged_factor(&lifts, &a).unwrap();
    assert!(a.join("trials_lift_3.csv").exists());
    let b = common::target_tmp_dir("stages", "cut_once");
    let (fb, bb) = staged_factor(&once, &b).unwrap();
    let tolerance = 0.005;
    assert!(
        (fa - fb).abs() <= tolerance * fa.min(fb),
        "in lifts F = {fa} {ba:?}, at once F = {fb} {bb:?}"
    );
    assert!(
        ba[0] < bb[1] && bb[0] < ba[1],
        "the brackets overlap: {ba:?} {bb:?}"
    );
    // The cut stood through its lifts: 1 < F.
    assert!(fa > 1.0, "{fa}");
}

#[test]
fn a_stage_factor_of_safety_stopped_by_the_observer_stops_the_run_as_interrupted() {
    use std::ops::ControlFlow;
    let (lifts, _) = talus::analysis::verification::cut_scenes().unwrap();
    let out = common::target_tmp_dir("stages", "fos_interrupted");
    // Trials report `F = …` (docs/stability.md): stop at the first.
    let stop: talus::run::Observer = std::sync::Arc::new(|p| {
        if p.message.starts_with("F = ") {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    });
    let options = RunOptions {
        observer: Some(stop),
        ..RunOptions::new(&out)
    };
    let err = run_scene(&lifts, &options).unwrap_err();
    assert!(
        matches!(err, talus::run::RunError::Interrupted { step: 13, .. }),
        "{err}"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["status"], "interrupted");
    let last = summary["stages"].as_array().unwrap().last().unwrap();
    assert_eq!(last["name"], "lift 3");
    assert_eq!(last["factor_of_safety"]["status"], "interrupted");
    assert!(last["factor_of_safety"]["value"].is_null());
}

#[test]
fn a_stage_that_raises_the_water_table_loads_the_base_with_the_saturated_weight() {
    // The block dry at rest, then a table at y = 2 m: below it the soil weighs ρ_sat; the
    // base carries the total weight, ρ g 4·2 + ρ_sat g 4·2 per metre, once the stage has
    // released the change (the rollers and base hold the water's push on the sides).
    let rho_sat = 2300.0;
    let text = block(
        "[[stage]]\nname = \"dry\"\nsteps = 1\n\n\
         [[stage]]\nname = \"wet\"\nsteps = 4\nwater = { level = 2.0 }\n",
    )
    .replace(
        &format!("density = {RHO}\n"),
        &format!("density = {RHO}\nsaturated_density = {rho_sat:?}\n"),
    )
    .replace("[time]", "[output]\nreaction = \"base\"\n\n[time]");
    let scene = Scene::parse(&text, None).unwrap();
    let out = common::target_tmp_dir("stages", "water");
    run_scene(&scene, &RunOptions::new(&out)).unwrap();
    let base = common::history_column(&out, "base_fy");
    let dry = RHO * G * 16.0;
    let wet = RHO * G * 8.0 + rho_sat * G * 8.0;
    assert!(
        (base[1] - dry).abs() < 1e-6 * dry,
        "{} against {dry}",
        base[1]
    );
    assert!(
        (base[5] - wet).abs() < 1e-6 * wet,
        "{} against {wet}",
        base[5]
    );
}

#[test]
fn reset_displacements_starts_the_stage_from_zero_displacement() {
    // The fill's weight settles the block; a last stage that changes nothing ends with that
    // settlement, or, with reset_displacements, with none (the stresses carry on).
    let run = |reset: bool| {
        let text = block(&format!(
            "[[stage]]\nname = \"ground\"\nsteps = 1\n\n\
             [[stage]]\nname = \"fill\"\nsteps = 4\nactivate = [\"top\"]\n\n\
             [[stage]]\nname = \"after\"\nsteps = 2\nreset_displacements = {reset}\n"
        ))
        .replace("surface = 4.0", "surface = 3.0");
        let scene = Scene::parse(&text, None).unwrap();
        let out = common::target_tmp_dir("stages", &format!("reset_{reset}"));
        run_scene(&scene, &RunOptions::new(&out))
            .unwrap()
            .final_state
    };
    let largest = |s: &talus::model::fem::State| {
        s.displacement
            .iter()
            .flat_map(|u| u.iter())
            .fold(0.0f64, |m, v| m.max(v.abs()))
    };
    let (kept, reset) = (run(false), run(true));
    assert!(
        largest(&kept) > 1e-4,
        "the fill settles the block: {}",
        largest(&kept)
    );
    assert!(
        largest(&reset) < 1e-8 * largest(&kept),
        "{} after the reset",
        largest(&reset)
    );
    assert_eq!(kept.sigma, reset.sigma, "the stresses carry on either way");
}

#[test]
fn a_load_switched_on_by_stage_is_carried_at_that_stages_end() {
    // A surcharge q = 10 kPa on the top that acts in the second stage only: the base
    // carries the weight, then the weight and q over the 4 m width.
    let q = 1.0e4;
    let text = block(
        "[[stage]]\nname = \"weight\"\nsteps = 1\n\n\
         [[stage]]\nname = \"surcharge\"\nsteps = 4\n\n\
         [[stage]]\nname = \"removed\"\nsteps = 4\n",
    )
    .replace(
        "[initial_stress]",
        &format!(
            "[[traction]]\nedges = \"top\"\nvalue = [0.0, -{q:?}]\nstages = [\"surcharge\"]\n\n\
             [initial_stress]"
        ),
    )
    .replace("[time]", "[output]\nreaction = \"base\"\n\n[time]");
    let scene = Scene::parse(&text, None).unwrap();
    let out = common::target_tmp_dir("stages", "surcharge");
    run_scene(&scene, &RunOptions::new(&out)).unwrap();
    let base = common::history_column(&out, "base_fy");
    let weight = RHO * G * 16.0;
    for (step, expected) in [(1, weight), (5, weight + 4.0 * q), (9, weight)] {
        assert!(
            (base[step] - expected).abs() < 1e-6 * expected,
            "step {step}: {} against {expected}",
            base[step]
        );
    }
}
