//! 3D scenes run by `talus run` (`docs/3d.md`, 'Next' 1): an elastic block of ground under
//! its own weight (`scenes/block_3d.toml`) against the uniaxial-strain column's closed
//! form, the files a 3D run writes read back, and the 3D refusals naming their fields.
//!
//! The column: rollers on the sides and a fixed base leave only `u_y(y)`, so
//! `ε_xx = ε_zz = 0` and equilibrium `dσ_yy/dy = ρ g` with a free top give
//! `σ_yy = −ρ g (H − y)` and `σ_xx = σ_zz = ν/(1−ν) σ_yy` (Timoshenko & Goodier, *Theory
//! of Elasticity*, the state of uniaxial strain; Jaky's K₀ of an elastic body). `u_y` is
//! quadratic in y, which P2 tetrahedra hold exactly: the Gauss-point stresses are the
//! closed form up to round-off and the quasi-static inertia (`r = 1e-7` of the stiffness).
use crate::common;
use common::{array, replaced, talus_run};
use talus::model::fem::model_3d;
use talus::output::Summary;
use talus::run::fem::run_scene_3d;
use talus::run::RunOptions;
use talus::scene::{Scene3, SceneFile};

const BLOCK: &str = include_str!("../../../scenes/block_3d.toml");
const RHO: f64 = 2000.0;
const G: f64 = 9.81;
const NU: f64 = 0.25;
const HEIGHT: f64 = 2.0;
const VOLUME: f64 = 2.0;

fn scene(text: &str) -> Scene3 {
    match SceneFile::parse(text, None) {
        Ok(SceneFile::Fem3(scene)) => scene,
        Ok(_) => panic!("not read as a 3D scene"),
        Err(e) => panic!("{e}"),
    }
}

/// The error `talus run` stops a 3D scene with: reading it or building its model.
fn error_of(text: &str) -> talus::scene::SceneError {
    match SceneFile::parse(text, None) {
        Ok(SceneFile::Fem3(scene)) => model_3d(&scene).err().expect("the scene must be refused"),
        Ok(_) => panic!("not read as a 3D scene"),
        Err(e) => e,
    }
}

/// The largest errors, in `scale`, of the Gauss points' `σ_yy`, `σ_xx` and `σ_zz`, and
/// shears against a column's closed form `exact(x) = (σ_yy, σ_xx = σ_zz)`, no shear.
fn column_errors(
    points: &[[f64; 3]],
    sigma: &[f64],
    scale: f64,
    exact: impl Fn(&[f64; 3]) -> (f64, f64),
) -> [f64; 3] {
    let mut e = [0.0f64; 3];
    for (p, x) in points.iter().enumerate() {
        let s = &sigma[6 * p..6 * p + 6];
        let (syy, lateral) = exact(x);
        e[0] = e[0].max((s[1] - syy).abs() / scale);
        e[1] = e[1].max((s[0] - lateral).abs().max((s[2] - lateral).abs()) / scale);
        e[2] = e[2].max(s[3..].iter().fold(0.0f64, |m, v| m.max(v.abs())) / scale);
    }
    e
}

#[test]
fn a_block_under_its_own_weight_is_the_uniaxial_strain_column() {
    let scene = scene(BLOCK);
    let dir = common::target_tmp_dir("block_3d", "column");
    let summary = run_scene_3d(&scene, &RunOptions::new(dir.join("out")), None)
        .unwrap_or_else(|e| panic!("{e}"));
    let model = model_3d(&scene).unwrap();
    let sigma = &summary.final_state.sigma;
    let [e_yy, e_lateral, e_shear] =
        column_errors(&model.assembly.gauss_points, sigma, RHO * G * HEIGHT, |x| {
            let syy = -RHO * G * (HEIGHT - x[1]);
            (syy, NU / (1.0 - NU) * syy)
        });
    println!(
        "{} Gauss points: σ_yy {e_yy:.2e}, σ_xx and σ_zz {e_lateral:.2e}, shears {e_shear:.2e} \
         of ρ g H",
        model.n_points()
    );
    assert!(e_yy < 1e-6, "σ_yy off by {e_yy:e} of ρ g H");
    assert!(e_lateral < 1e-6, "σ_xx, σ_zz off by {e_lateral:e} of ρ g H");
    assert!(e_shear < 1e-6, "shears of {e_shear:e} of ρ g H");
    // The base carries the weight: the reported reaction and the named boundary's fy.
    let weight = RHO * G * VOLUME;
    let reaction = summary
        .records
        .last()
        .unwrap()
        .stats
        .as_ref()
        .unwrap()
        .reaction_force;
    let written = Summary::read(&dir.join("out").join("summary.json")).unwrap();
    let base = &written.boundaries["base"];
    println!(
        "weight {weight} N: reaction {reaction:.10e}, base fy {:.10e} (rel. {:.1e})",
        base.last[1],
        (base.last[1] - weight).abs() / weight
    );
    assert!(
        (reaction.abs() - weight).abs() < 1e-9 * weight,
        "{reaction} against {weight}"
    );
    assert!((base.last[1] - weight).abs() < 1e-9 * weight, "{base:?}");
    assert!(base.last[0].abs() < 1e-9 * weight && base.last[2].abs() < 1e-9 * weight);
}

#[test]
fn a_3d_run_writes_history_summary_and_tetrahedral_vtus() {
    let (out, stdout, _) = talus_run("block_3d", "files", BLOCK);
    assert!(stdout.contains("3 steps"), "{stdout}");
    let history = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let header = history.lines().next().unwrap();
    assert!(
        header.ends_with(
            ",reaction_force,footing_displacement,base_fx,base_fy,base_fz,inertial_share"
        ),
        "{header}"
    );
    assert_eq!(history.lines().count(), 1 + 4, "a row per step from step 0");
    // Quasi-static: inertia carries a negligible share of the base's reaction (2D's
    // `inertial_share`, the same function).
    let share: f64 = (history.lines().last().unwrap().rsplit(',').next().unwrap())
        .parse()
        .unwrap();
    println!("inertial share {share:e}");
    assert!(share < talus::run::fem::INERTIAL_SHARE_WARNING, "{share}");
    let summary = Summary::read(&out.join("summary.json")).unwrap();
    assert_eq!(summary.steps, 3);
    assert_eq!(summary.force_unit, "N");
    assert_eq!(summary.boundaries["base"].last.len(), 3);
    let pvd = std::fs::read_to_string(out.join("solution.pvd")).unwrap();
    for step in 0..=3 {
        let name = format!("vtu/step_{step:05}.vtu");
        assert!(pvd.contains(&name), "{pvd}");
        let xml = std::fs::read_to_string(out.join(&name)).unwrap();
        let types = array(&xml, "types");
        // 2 × 4 × 2 cells of 6 tetrahedra, P2: VTK's quadratic tetrahedron.
        assert_eq!(types, vec![24.0; 96], "{name}");
        assert_eq!(
            array(&xml, "displacement").len(),
            3 * 225,
            "{name}: 3 per node"
        );
    }
    assert!(out.join("force_displacement.png").exists());
    assert!(
        !out.join("plastic_strain.png").exists(),
        "no field map in 3D"
    );
}

#[test]
fn bad_3d_inputs_are_refused_naming_their_field() {
    let cases = [
        (
            "[output]",
            "[initial_stress]\nstress = [-1.0, -1.0, 0.0, -1.0]\n\n[output]",
            "initial_stress.stress",
        ),
        ("cells = [2, 4, 2]", "cells = [2, 0, 2]", "mesh.box.cells"),
        ("z = [0.0, 1.0]", "z = [1.0, 1.0]", "mesh.box.z"),
        ("nodes = \"left\"", "nodes = \"west\"", "boundary[1].nodes"),
        (
            "nodes = \"left\"",
            "nodes = { box = [[5.0, 0.0, 0.0], [6.0, 1.0, 1.0]] }",
            "boundary[1].nodes",
        ),
    ];
    for (from, to, field) in cases {
        let err = error_of(&replaced(BLOCK, from, to));
        assert_eq!(err.field, field, "{to}: {err}");
        println!("{field}: {err}");
    }
    // A face load on a box of no boundary face, and on a face set the mesh lacks.
    let loaded = format!(
        "{BLOCK}\n[[pressure]]\nfaces = {{ box = [[0.2, 0.5, 0.2], [0.8, 1.5, 0.8]] }}\nvalue = 1e3\n"
    );
    assert_eq!(error_of(&loaded).field, "pressure[0].faces");
    // The checks 2D's loads share (`scene::check::{pressure, point_load}`).
    let bad_gradient =
        format!("{BLOCK}\n[[pressure]]\nfaces = \"top\"\nvalue = 1e3\ngradient = inf\n");
    assert_eq!(error_of(&bad_gradient).field, "pressure[0].gradient");
    let bad_force =
        format!("{BLOCK}\n[[point_load]]\npoint = [0.5, 2.0, 0.5]\nforce = [0.0, nan, 0.0]\n");
    let err = error_of(&bad_force);
    assert_eq!(err.field, "point_load[0].force", "{err}");
    let named = format!("{BLOCK}\n[[traction]]\nfaces = \"roof\"\nvalue = [0.0, -1e3, 0.0]\n");
    let err = error_of(&named);
    assert_eq!(err.field, "traction[0].faces", "{err}");
    assert!(err.message.contains("top"), "lists the face sets: {err}");
}

/// A monitor at the top of the block records the column's settlement: `u_y(H) = −ρ g H² /
/// (2M)`, `M = E (1 − ν) / ((1 + ν)(1 − 2ν))` the constrained modulus (the integral of
/// `ε_yy = σ_yy / M` over the height; quadratic in y, held exactly by P2 tetrahedra), and
/// no horizontal motion; its six columns and `summary.json`'s `uz`, `vz`. A point outside
/// the mesh is refused naming `monitor[0].point`.
#[test]
fn a_3d_monitor_records_the_settlement_of_the_column() {
    const E: f64 = 2.0e7;
    let text = replaced(
        BLOCK,
        "[output]",
        "[[monitor]]\nname = \"top\"\npoint = [0.5, 2.0, 0.5]\n\n[output]",
    );
    let (out, _, _) = talus_run("block_3d", "monitor", &text);
    let history = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let mut lines = history.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let last: Vec<f64> = (lines.last().unwrap().split(','))
        .map(|v| v.parse().unwrap())
        .collect();
    let column = |name: &str| {
        let k = header.iter().position(|h| *h == name);
        last[k.unwrap_or_else(|| panic!("no column {name} in {header:?}"))]
    };
    let m = E * (1.0 - NU) / ((1.0 + NU) * (1.0 - 2.0 * NU));
    let exact = -RHO * G * HEIGHT * HEIGHT / (2.0 * m);
    let uy = column("top_uy");
    println!(
        "top u_y {uy:.10e} m against {exact:.10e} (rel. {:.1e}); u_x {:.1e}, u_z {:.1e}",
        (uy - exact).abs() / exact.abs(),
        column("top_ux"),
        column("top_uz")
    );
    assert!(
        (uy - exact).abs() < 1e-6 * exact.abs(),
        "{uy} against {exact}"
    );
    // No horizontal motion: measured 9.2e-12 m (5.6e-9 of the settlement), the round-off
    // of the quasi-static solve; a monitor on the wrong node or component is far off.
    for c in ["top_ux", "top_uz", "top_vx", "top_vz"] {
        assert!(column(c).abs() < 1e-7 * exact.abs(), "{c} = {}", column(c));
    }
    let summary = Summary::read(&out.join("summary.json")).unwrap();
    let top = summary.monitors["top"].unwrap();
    // history.csv keeps 11 significant digits.
    assert!(
        (top.uy - uy).abs() < 1e-9 * uy.abs(),
        "{top:?} against {uy}"
    );
    assert!(top.uz.is_some() && top.vz.is_some(), "{top:?}");
    let outside = replaced(&text, "point = [0.5, 2.0, 0.5]", "point = [0.5, 2.5, 0.5]");
    let err = error_of_run(&outside);
    assert_eq!(err.field, "monitor[0].point", "{err}");
}

/// The block half under water (`[water] level = 1`, saturated density 2200 kg/m³ below
/// it), started from the K₀ procedure (K₀ = 0.5, surface y = 2): the uniaxial-strain column
/// with the water of `docs/water.md`. The effective vertical stress is the buoyant weight
/// above the point, `σ'_yy = −ρ g (2 − y)` above the table and `−(ρ g + γ' (1 − y))` below
/// it, `γ' = ρ_sat g − γ_w`; the pore pressure `p = γ_w (1 − y)`; the total stress
/// `σ = σ' − p I`, `σ_xx = σ_zz = K₀ σ'_yy − p`. That state balances the saturated weight
/// exactly, so the steps keep it: the final Gauss-point stresses are the closed form, and the
/// base carries the whole weight, `ρ g V_dry + ρ_sat g V_wet` (Terzaghi's effective stress;
/// Craig's Soil Mechanics, ch. 3).
#[test]
fn a_block_half_under_water_keeps_the_effective_stress_of_its_k0_state() {
    const RHO_SAT: f64 = 2200.0;
    const GAMMA_W: f64 = 9810.0;
    const K0: f64 = 0.5;
    let text = replaced(
        &replaced(BLOCK, "density = 2000.0", "density = 2000.0\nsaturated_density = 2200.0"),
        "[output]",
        "[water]\nlevel = 1.0\nunit_weight = 9810.0\n\n[initial_stress]\nk0 = 0.5\nsurface = 2.0\n\n[output]",
    );
    let scene = scene(&text);
    let dir = common::target_tmp_dir("block_3d", "water");
    let summary = run_scene_3d(&scene, &RunOptions::new(dir.join("out")), None)
        .unwrap_or_else(|e| panic!("{e}"));
    let model = model_3d(&scene).unwrap();
    let sigma = &summary.final_state.sigma;
    let buoyant = RHO_SAT * G - GAMMA_W;
    let points = &model.assembly.gauss_points;
    let wet = points.iter().filter(|x| x[1] < 1.0).count();
    let [e_yy, e_lateral, e_shear] = column_errors(points, sigma, RHO_SAT * G * HEIGHT, |x| {
        let y = x[1];
        let (effective, pore) = if y >= 1.0 {
            (-RHO * G * (HEIGHT - y), 0.0)
        } else {
            (-(RHO * G + buoyant * (1.0 - y)), GAMMA_W * (1.0 - y))
        };
        (effective - pore, K0 * effective - pore)
    });
    println!(
        "{} Gauss points ({wet} under water): σ_yy {e_yy:.2e}, σ_xx and σ_zz {e_lateral:.2e}, \
         shears {e_shear:.2e} of ρ_sat g H",
        model.n_points()
    );
    assert!(wet > 0 && wet < model.n_points());
    assert!(e_yy < 1e-6, "σ_yy off by {e_yy:e}");
    assert!(e_lateral < 1e-6, "σ_xx, σ_zz off by {e_lateral:e}");
    assert!(e_shear < 1e-6, "shears of {e_shear:e}");
    // Each point's pore pressure is the table's, and the base carries the saturated weight.
    for (p, x) in model.assembly.gauss_points.iter().enumerate() {
        let exact = GAMMA_W * (1.0 - x[1]).max(0.0);
        assert!(
            (model.pore_pressure[p] - exact).abs() <= 1e-9 * GAMMA_W,
            "point {p}"
        );
    }
    let weight = (RHO * G + RHO_SAT * G) * VOLUME / 2.0;
    let reaction = summary
        .records
        .last()
        .unwrap()
        .stats
        .as_ref()
        .unwrap()
        .reaction_force;
    println!("weight {weight} N: reaction {reaction:.10e}");
    assert!(
        (reaction.abs() - weight).abs() < 1e-9 * weight,
        "{reaction} against {weight}"
    );
}

/// The error the run of a 3D scene stops with, after its model is built.
fn error_of_run(text: &str) -> talus::scene::SceneError {
    let scene = scene(text);
    let dir = common::target_tmp_dir("block_3d", "refused_run");
    match run_scene_3d(&scene, &RunOptions::new(dir.join("out")), None) {
        Err(talus::run::RunError::Scene(e)) => e,
        Err(e) => panic!("not a scene error: {e}"),
        Ok(_) => panic!("the scene must be refused"),
    }
}

/// A uniform pressure on the top of the block, selected by a 3D box, adds `q A` to the
/// base's reaction (the faces whose nodes all lie in the box, turned outward).
#[test]
fn a_pressure_on_faces_in_a_box_adds_its_resultant_to_the_base() {
    let q = 1.0e4;
    let text = format!(
        "{BLOCK}\n[[pressure]]\nfaces = {{ box = [[0.0, 2.0, 0.0], [1.0, 2.0, 1.0]] }}\nvalue = {q}\n"
    );
    let scene = scene(&text);
    let dir = common::target_tmp_dir("block_3d", "pressure");
    let summary = run_scene_3d(&scene, &RunOptions::new(dir.join("out")), None)
        .unwrap_or_else(|e| panic!("{e}"));
    let reaction = summary
        .records
        .last()
        .unwrap()
        .stats
        .as_ref()
        .unwrap()
        .reaction_force;
    let expected = RHO * G * VOLUME + q * 1.0;
    println!("reaction {reaction:.10e} N, expected {expected} N");
    assert!(
        (reaction.abs() - expected).abs() < 1e-9 * expected,
        "{reaction}"
    );
}

/// A 3D mesh whose Newton factorization cannot fit the machine is refused before its
/// nodes are allocated, naming `mesh.box.cells` with the estimate; the block itself is
/// not. 200³ P2 cells are 6.4e7 nodes: the estimate (`model::fem::memory`, the peaks
/// measured in docs/3d.md) is terabytes, beyond any machine this runs on. Refused in
/// well under a second (allocating the mesh alone would take 4 GB).
#[test]
fn a_3d_mesh_too_large_for_the_memory_is_refused_with_the_estimate() {
    assert!(model_3d(&scene(BLOCK)).is_ok());
    let start = std::time::Instant::now();
    let err = error_of(&replaced(
        BLOCK,
        "cells = [2, 4, 2]",
        "cells = [200, 200, 200]",
    ));
    assert_eq!(err.field, "mesh.box.cells", "{err}");
    assert!(
        err.message.contains("GiB") && err.message.contains("64481201"),
        "{err}"
    );
    assert!(
        start.elapsed().as_secs_f64() < 1.0,
        "refused before allocating"
    );
    // Associative flow (the elastic block) is estimated on the Cholesky curve: smaller.
    use talus::model::fem::memory::peak_mib;
    assert!(peak_mib(1e6, true) < peak_mib(1e6, false));
    println!("{err}");
}
