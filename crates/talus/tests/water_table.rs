//! A drained water table (`docs/scenes.md`, 'Water'): hydrostatic pore pressure under the
//! phreatic line, effective stress for yield, saturated weight below the line, the water's
//! push on the free boundary. Checked against Terzaghi's geostatic closed form, against
//! equilibrium at rest, and against the dry slope of buoyant unit weight (Archimedes:
//! hydrostatic water is in equilibrium on its own).
use crate::common;
use talus::analysis::stability;
use talus::model::fem::{FromScene, Model};
use talus::run::RunOptions;
use talus::scene::Scene;
use talus_engine::Stepper;

const G: f64 = 9.81;
const GAMMA_W: f64 = 9810.0;

/// Level ground 2 m wide and 2 m deep on rollers, K₀ = 0.5 from the surface y = 0 under a
/// surcharge of 10 kPa, ρ = 1800 kg/m³, ρ_sat = 2100 kg/m³, `water` as given; quasi-static.
fn level_ground(water: &str) -> String {
    format!(
        "gravity = [0.0, -{G}]\n\
         [mesh.rectangle]\nx = [0.0, 2.0]\ny = [-2.0, 0.0]\ncells = [4, 8]\norder = \"P2\"\n\n\
         [material]\nyoung_modulus = 5.0e7\npoisson_ratio = 0.3\nfriction_angle = 30.0\n\
         cohesion = 5.0e3\ncone_fit = \"plane_strain\"\ndensity = 1800.0\nsaturated_density = 2100.0\n\n\
         {water}\n\
         [[boundary]]\nnodes = \"bottom\"\nfix = \"xy\"\n\n\
         [[boundary]]\nnodes = \"left\"\nfix = \"x\"\n\n\
         [[boundary]]\nnodes = \"right\"\nfix = \"x\"\n\n\
         [[traction]]\nedges = \"top\"\nvalue = [0.0, -1.0e4]\n\n\
         [initial_stress]\nk0 = 0.5\nsurface = 0.0\nsurcharge = 1.0e4\n\n\
         [analysis]\nkind = \"quasi_static\"\n\n[time]\nstep = 1.0\nsteps = 3\n"
    )
}

/// `σ'_v`, `σ'_h = K₀ σ'_v` and `p_w` at every Gauss point against the closed form with the
/// table at `y_w` (below the surface: the soil above it dry; above: flooded, the surface
/// loaded by the water): `σ'_v = −(q + γ (0 − max(y, y_w))⁺ + (γ_sat − γ_w)(min(0, y_w) − y)⁺)`,
/// `p_w = γ_w (y_w − y)⁺`, total `σ = σ' − p_w I`; then three steps at rest move nothing.
fn check_level_ground(y_w: f64) {
    let water_key = format!("[water]\nlevel = {y_w:?}\n");
    let mut text = level_ground(&water_key);
    if y_w > 0.0 {
        // A flooded surface: the surcharge is the water's, on the top as the water load.
        text = text
            .replace(
                "[[traction]]\nedges = \"top\"\nvalue = [0.0, -1.0e4]\n\n",
                "",
            )
            .replace("surcharge = 1.0e4", &format!("surcharge = {:?}", 0.0));
    }
    let scene = Scene::parse(&text, None).unwrap();
    let model = Model::from_scene(&scene).unwrap();
    let mut state = model.initial_state(&scene).unwrap();
    let q = if y_w > 0.0 { 0.0 } else { 1.0e4 };
    let (gamma, gamma_sat) = (1800.0 * G, 2100.0 * G);
    for (p, &[_, y]) in model.assembly.gauss_points.iter().enumerate() {
        let dry = (0.0 - y.max(y_w)).max(0.0);
        let wet = (y_w.min(0.0) - y).max(0.0);
        let sv = -(q + gamma * dry + (gamma_sat - GAMMA_W) * wet);
        let p_w = GAMMA_W * (y_w - y).max(0.0);
        let s = &state.sigma[4 * p..4 * p + 4];
        let tol = 1e-10 * sv.abs().max(p_w);
        assert!(
            (model.pore_pressure[p] - p_w).abs() <= tol,
            "p_w at y = {y}"
        );
        assert!(
            (s[1] + p_w - sv).abs() <= tol,
            "σ'_v at y = {y}: {} vs {sv}",
            s[1] + p_w
        );
        assert!((s[0] + p_w - 0.5 * sv).abs() <= tol, "σ'_h at y = {y}");
        assert!((s[2] + p_w - 0.5 * sv).abs() <= tol, "σ'_zz at y = {y}");
        assert_eq!(s[3], 0.0);
    }
    // At rest: the weight (saturated below the table), the water's push and the K₀ state
    // are in equilibrium, so the steps move nothing but round-off.
    let mut stepper = Stepper::new(&model, scene.spec.solver.fem());
    for _ in 0..3 {
        stepper.advance(&mut state, scene.spec.time.step).unwrap();
    }
    let moved = state
        .displacement
        .iter()
        .fold(0.0f64, |m, u| m.max(u[0].abs()).max(u[1].abs()));
    // The settlement a 10% load imbalance would give: 0.1 σ_v H / E ≈ 2e-4 m.
    assert!(moved < 1e-9, "the ground at rest moved {moved:e} m");
}

#[test]
fn level_ground_under_a_water_table_is_geostatic() {
    check_level_ground(-0.5);
}

#[test]
fn flooded_level_ground_is_geostatic() {
    check_level_ground(1.0);
}

/// A table below the mesh changes nothing: the K₀ state (here summed element by element
/// through the column, a different order of the same arithmetic) and a step agree with the
/// dry scene's to round-off.
#[test]
fn a_table_below_the_ground_changes_nothing() {
    let dry = Scene::parse(&level_ground(""), None).unwrap();
    let deep = Scene::parse(&level_ground("[water]\nlevel = -5.0\n"), None).unwrap();
    let run = |scene: &Scene| {
        let model = Model::from_scene(scene).unwrap();
        let mut state = model.initial_state(scene).unwrap();
        let initial = state.sigma.clone();
        let mut stepper = Stepper::new(&model, scene.spec.solver.fem());
        stepper.advance(&mut state, 1.0).unwrap();
        (initial, state.sigma)
    };
    let relative = |a: &[f64], b: &[f64]| {
        let scale = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        a.iter()
            .zip(b)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
            / scale
    };
    let ((a0, a1), (b0, b1)) = (run(&dry), run(&deep));
    assert!(
        relative(&a0, &b0) <= 1e-14,
        "K₀ states differ by {:e}",
        relative(&a0, &b0)
    );
    // After a solve to the tolerance 1e-12 (relative residual): the solutions agree to
    // what that tolerance resolves.
    assert!(
        relative(&a1, &b1) <= 1e-9,
        "steps differ by {:e}",
        relative(&a1, &b1)
    );
}

/// Griffiths & Lane's slope (`scenes/slope.toml`) fully submerged (level 20 m, above its
/// 10 m crest), γ_sat = 20 kN/m³, has the factor of safety of the same dry slope of buoyant
/// unit weight γ_sat − γ_w: the two brackets overlap.
#[test]
fn a_submerged_slope_has_the_factor_of_safety_of_the_buoyant_dry_slope() {
    let (dry, wet) = talus::analysis::verification::submerged_slope_scenes().unwrap();
    let factor = |scene: &Scene, name: &str| {
        let out = common::target_tmp_dir("water_table", name);
        let run = stability::run(scene, &RunOptions::new(&out)).unwrap();
        let [lo, hi] = run.factor_of_safety.bracket;
        (lo.unwrap(), hi.unwrap())
    };
    let (dl, du) = factor(&dry, "dry");
    let (wl, wu) = factor(&wet, "submerged");
    assert!(
        dl <= wu && wl <= du,
        "brackets [{dl}, {du}] and [{wl}, {wu}] must overlap"
    );
    // And differ from the dry slope of full weight, whose factor is lower (the witness).
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/slope.toml");
    let full = Scene::from_path(&path).unwrap();
    let (fl, _) = factor(&full, "full_weight");
    assert!(fl < dl, "full weight {fl} below buoyant {dl}");
}

#[test]
fn bad_water_tables_are_named() {
    let refused = |water: &str| {
        let scene = Scene::parse(&level_ground(water), None).unwrap();
        Model::from_scene(&scene).err().expect("refused")
    };
    let err = refused("[water]\nphreatic = [[0.0, -1.0], [1.0, -1.2], [0.5, -1.1]]\n");
    assert_eq!(err.field, "water.phreatic");
    assert!(err.to_string().contains("increase"), "{err}");
    let err = refused("[water]\nlevel = -1.0\nphreatic = [[0.0, -1.0]]\n");
    assert_eq!(err.field, "water.phreatic");
    let err = refused("[water]\nlevel = -1.0\nunit_weight = -9810.0\n");
    assert_eq!(err.field, "water.unit_weight");
    assert!(err.to_string().contains("-9810"), "{err}");
    let err = refused("[water]\nunit_weight = 9810.0\n");
    assert_eq!(err.field, "water");
}

/// The VTU holds `pore_pressure` (the element's points' mean) and `effective_stress =
/// stress + p_w I`.
#[test]
fn the_vtu_has_pore_pressure_and_effective_stress() {
    let scene = Scene::parse(&level_ground("[water]\nlevel = -0.5\n"), None).unwrap();
    let out = common::target_tmp_dir("water_table", "vtu");
    let options = RunOptions {
        write_fields: true,
        ..RunOptions::new(&out)
    };
    talus::run::fem::run_scene(&scene, &options).unwrap();
    let xml = std::fs::read_to_string(out.join("vtu/step_00003.vtu")).unwrap();
    let p_w = common::array(&xml, "pore_pressure");
    let stress = common::array(&xml, "stress");
    let effective = common::array(&xml, "effective_stress");
    let model = Model::from_scene(&scene).unwrap();
    let n = model.mesh.triangles.len();
    assert_eq!(p_w.len(), n);
    for e in 0..n {
        let points: Vec<usize> = (0..model.n_points())
            .filter(|&p| model.assembly.gauss_element[p] == e)
            .collect();
        let mean =
            points.iter().map(|&p| model.pore_pressure[p]).sum::<f64>() / points.len() as f64;
        assert!(
            (p_w[e] - mean).abs() <= 1e-12 * mean.max(1.0),
            "element {e}"
        );
        for c in 0..3 {
            let (s, eff) = (stress[6 * e + c], effective[6 * e + c]);
            assert!(
                (eff - (s + p_w[e])).abs() <= 1e-9 * s.abs().max(1.0),
                "element {e}"
            );
        }
        assert_eq!(effective[6 * e + 3], stress[6 * e + 3]);
    }
    assert!(p_w.iter().any(|p| *p > 0.0) && p_w.contains(&0.0));
}
