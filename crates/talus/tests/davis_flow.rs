//! `[material] flow = "davis"` (issue 24, item 3): Davis's (1968) associated equivalent of a
//! non-associative material in any run, `β = cos φ cos ψ / (1 − sin φ sin ψ)`, `c* = β c`,
//! `tan φ* = β tan φ`, `ψ* = φ*` (Davis 1968, in Lee (ed.) *Soil Mechanics: Selected
//! Topics*; Sloan 2013, Géotechnique 63(7), 531–572); `docs/scenes.md`, 'Regions and materials', and
//! `docs/stability.md`, 'Dilatancy'. One transform serves it and `[stability] dilatancy =
//! "davis"`.
use crate::common;
use talus::analysis::stability;
use talus::model::fem::{FromScene, Model};
use talus::model::mpm::MpmModel;
use talus::run::RunOptions;
use talus::scene::{MpmScene, Scene};
use talus_bipotential::{davis_beta, davis_equivalent, Material};

use common::{
    fem, fem_error, footing_soil, footing_two_layers, replaced, with_material_key, FOOTING,
};
const COLUMN: &str = include_str!("../../../scenes/column_a1.toml");
const SLOPE: &str = include_str!("../../../scenes/slope.toml");

/// `text` with `flow = "..."` after its first `cone_fit` line.
fn with_flow(text: &str, flow: &str) -> String {
    with_material_key(text, &format!("flow = \"{flow}\""))
}

fn materials(text: &str) -> Vec<Material> {
    Model::from_scene(&fem(text))
        .unwrap_or_else(|e| panic!("{e}"))
        .materials
}

/// Davis's `(c*, φ*)` (Pa, degrees) of `(c, φ, ψ)` (Pa, degrees), written out here from
/// the formula, not from the library.
fn by_formula(c: f64, phi_deg: f64, psi_deg: f64) -> (f64, f64) {
    let (phi, psi) = (phi_deg.to_radians(), psi_deg.to_radians());
    let beta = phi.cos() * psi.cos() / (1.0 - phi.sin() * psi.sin());
    (beta * c, (beta * phi.tan()).atan().to_degrees())
}

/// The footing's strength keys (`scenes/footing.toml`) replaced by `(c, φ, ψ)`.
fn footing_with_strength(c: f64, phi: f64, psi: f64) -> String {
    let text = replaced(
        FOOTING,
        "friction_angle = 27.0",
        &format!("friction_angle = {phi:?}"),
    );
    let text = replaced(&text, "cohesion = 2.0e3", &format!("cohesion = {c:?}"));
    replaced(
        &text,
        "dilatancy_angle = 14.2906",
        &format!("dilatancy_angle = {psi:?}"),
    )
}

/// Hand values (Davis 1968; the formula as Sloan 2013 writes it): φ = 30°, ψ = 0 gives
/// β = cos 30° = 0.866025, c* = 0.866025 c, φ* = atan(0.866025 · tan 30°) = atan(1/2) =
/// 26.5651°; the footing's φ = 27°, ψ = 14.2906° gives β = 0.891007 · 0.969056 /
/// (1 − 0.453990 · 0.246840) = 0.972406, φ* = 26.3568°.
#[test]
fn beta_and_the_equivalent_strength_by_hand() {
    let rad = f64::to_radians;
    let beta = davis_beta(rad(30.0), 0.0);
    assert!((beta - 0.866_025).abs() < 1e-6, "{beta}");
    let (c, phi) = davis_equivalent(10.0e3, rad(30.0), 0.0);
    assert!((c - 8_660.25).abs() < 1e-2, "{c}");
    assert!(
        (phi.to_degrees() - 26.5651).abs() < 1e-4,
        "{}",
        phi.to_degrees()
    );
    let beta = davis_beta(rad(27.0), rad(14.2906));
    assert!((beta - 0.972_406).abs() < 1e-6, "{beta}");
    let (c, phi) = davis_equivalent(2.0e3, rad(27.0), rad(14.2906));
    assert!((c - 1_944.81).abs() < 1e-2, "{c}");
    assert!(
        (phi.to_degrees() - 26.3568).abs() < 1e-4,
        "{}",
        phi.to_degrees()
    );
    // The stability rule's Davis is the same transform of the reduced strength.
    let s = stability::Strength {
        cohesion: 2.0e3,
        friction: rad(27.0),
        dilatancy: rad(14.2906),
    };
    let r = s.reduced(1.0, talus::scene::DilatancyRule::Davis);
    assert_eq!((r.cohesion, r.friction), (c, phi));
    assert_eq!(r.dilatancy, r.friction);
}

/// `flow = "davis"` builds the material a scene writing `(c*, φ*, ψ* = φ*)` as given builds,
/// bit for bit: in a single `[material]`, in one of a `[[material]]` list (the other as
/// given), and in an MPM scene.
#[test]
fn davis_builds_the_as_given_material_of_the_equivalent_strength() {
    let (c, phi) = by_formula(2.0e3, 27.0, 14.2906);
    assert!(phi < 27.0 && c < 2.0e3);
    let davis = materials(&with_flow(FOOTING, "davis"));
    let written = materials(&footing_with_strength(c, phi, phi));
    assert_eq!(davis, written);
    let Material::DruckerPrager(dp) = davis[0] else {
        panic!("Drucker-Prager")
    };
    assert_eq!(
        dp.parameters().dilatancy_angle,
        dp.parameters().friction_angle
    );
    // "as_given" is the default.
    assert_eq!(
        materials(&with_flow(FOOTING, "as_given")),
        materials(FOOTING)
    );
    assert_ne!(materials(FOOTING), written);

    // A [[material]] list: the upper layer Davis, the lower one as given.
    let soil = footing_soil();
    let layered = |upper: &str| footing_two_layers(upper, soil);
    let list = materials(&layered(&with_flow(soil, "davis")));
    assert_eq!(list[0], written[0]);
    assert_eq!(list[1], materials(FOOTING)[0]);

    // MPM shares the material spec: the column of sand (φ = 30°, ψ = 0, c = 0).
    let mpm = |text: &str| {
        let scene = MpmScene::parse(text, None).unwrap_or_else(|e| panic!("{e}"));
        let model = MpmModel::from_scene(&scene).unwrap_or_else(|e| panic!("{e}"));
        model.mpm.materials().to_vec()
    };
    let (c0, phi0) = by_formula(0.0, 30.0, 0.0);
    assert_eq!(c0, 0.0);
    let column_written = replaced(
        &replaced(
            COLUMN,
            "friction_angle = 30.0",
            &format!("friction_angle = {phi0:?}"),
        ),
        "dilatancy_angle = 0.0",
        &format!("dilatancy_angle = {phi0:?}"),
    );
    assert_eq!(mpm(&with_flow(COLUMN, "davis")), mpm(&column_written));
    assert_ne!(mpm(COLUMN), mpm(&column_written));
}

/// `flow = "davis"` on an associative material (ψ = φ, β = 1) changes nothing: the same
/// material and the same flow rules at every Gauss point, so the same steps bit for bit (a
/// run is a function of the model). At φ = 30° `atan(tan φ)` and the degrees' round trip
/// are not exact in floating point: the transform must not be applied there.
#[test]
fn davis_on_an_associative_material_changes_nothing() {
    for phi in ["27.0", "30.0"] {
        let associative = replaced(
            &replaced(
                FOOTING,
                "friction_angle = 27.0",
                &format!("friction_angle = {phi}"),
            ),
            "dilatancy_angle = 14.2906",
            &format!("dilatancy_angle = {phi}"),
        );
        let davis = with_flow(&associative, "davis");
        assert_eq!(materials(&davis), materials(&associative), "φ = {phi}°");
        let rules = |text: &str| Model::from_scene(&fem(text)).unwrap().flow_rules();
        assert_eq!(rules(&davis), rules(&associative), "φ = {phi}°");
    }
    // A φ = 0 (Tresca) material is associative too: unchanged.
    let tresca = replaced(
        &replaced(FOOTING, "friction_angle = 27.0", "friction_angle = 0.0"),
        "dilatancy_angle = 14.2906",
        "dilatancy_angle = 0.0",
    );
    assert_eq!(materials(&with_flow(&tresca, "davis")), materials(&tresca));
}

/// The Newton system of a Davis run is symmetric: the solver factorizes it by Cholesky when
/// every point's flow rule is associative, `ReducedSystem::is_associative`
/// (`crates/ssn/src/solver/mod.rs`, `Solver::new`: `symmetric = problem.is_associative()`;
/// `docs/solver.md`, 'The factorization'). No report says which factorization ran, so the
/// predicate is tested on the system the step solves.
#[test]
fn a_davis_run_takes_the_symmetric_cholesky_path() {
    let symmetric = |text: &str| {
        let scene = fem(text);
        let model = Model::from_scene(&scene).unwrap();
        let system = model.reduced_system(scene.spec.time.step).unwrap();
        let solver = talus_ssn::Solver::new(system, talus_ssn::Settings::default()).unwrap();
        solver.problem().is_associative()
    };
    assert!(
        !symmetric(FOOTING),
        "the footing as given is non-associative"
    );
    assert!(symmetric(&with_flow(FOOTING, "davis")));
    // Every Gauss point's rule, each with κ = 0 exactly.
    let scene = fem(&with_flow(FOOTING, "davis"));
    let model = Model::from_scene(&scene).unwrap();
    for rule in model.flow_rules() {
        assert_eq!(rule.kappa(), 0.0);
    }
}

/// A misspelt flow is refused naming `material.flow` (`material[k].flow` in a list), its
/// line and the choices; an elastic material refuses the key.
#[test]
fn a_bad_flow_is_refused_naming_the_field_and_the_choices() {
    let text = with_flow(FOOTING, "davies");
    let e = fem_error(&text);
    let m = e.to_string();
    assert_eq!(e.field, "material.flow", "{m}");
    assert_eq!(
        e.line,
        Some(common::line_of(&text, "flow = \"davies\"")),
        "{m}"
    );
    for needle in ["\"davies\"", "\"as_given\"", "\"davis\"", "default"] {
        assert!(m.contains(needle), "`{needle}` not in: {m}");
    }
    // In a list: the second material.
    let list = footing_two_layers(footing_soil(), &with_flow(footing_soil(), "Davis"));
    let e = fem_error(&list);
    assert_eq!(e.field, "material[1].flow", "{e}");
    assert!(e.to_string().contains("\"Davis\""), "{e}");
    // MPM: the same check.
    let scene = MpmScene::parse(&with_flow(COLUMN, "davies"), None).unwrap();
    let e = MpmModel::from_scene(&scene).err().expect("refused");
    assert_eq!(e.field, "material.flow", "{e}");
    // Elastic: a Drucker-Prager key.
    let elastic = "[material]\nmodel = \"elastic\"\nyoung_modulus = 1.0e9\npoisson_ratio = 0.3\n\
                   density = 2.0e3\nflow = \"davis\"\n";
    let e = fem_error(&replaced(
        FOOTING,
        &format!("[material]\n{}", footing_soil()),
        elastic,
    ));
    assert_eq!(e.field, "material.flow", "{e}");
    assert!(e.to_string().contains("Drucker-Prager key"), "{e}");
}

/// `scenes/slope.toml`'s path (its mesh file is beside it).
fn slope_path() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/slope.toml")
}

fn factor_of_safety(text: &str, name: &str) -> (f64, [Option<f64>; 2]) {
    let path = slope_path();
    let text = replaced(text, "plots = true", "plots = false");
    let scene = Scene::parse(&text, Some(path)).unwrap_or_else(|e| panic!("{e}"));
    let out = common::target_tmp_dir("davis_flow", name);
    // The blind search of those measurements (`stability::run_blind`): the guided search
    // brackets the same factor with other trials.
    let run = stability::run_blind(&scene, &RunOptions::new(out)).unwrap_or_else(|e| panic!("{e}"));
    let fos = run.factor_of_safety;
    (fos.value.expect("a factor"), fos.bracket)
}

/// `[stability] dilatancy = "davis"` gives the factors it gave before the transform moved
/// to `talus_bipotential::davis_equivalent` (measured 2026-11-26 on `scenes/slope.toml`
/// with `dilatancy = "davis"`: 1.3691 in [1.3672, 1.3711], `docs/stability.md`; and with
/// `dilatancy_angle = 10.0`: 1.4043 in [1.4023, 1.4062]). With `flow = "davis"` the material
/// is associative before any reduction, so every dilatancy rule gives the same trials
/// (F ≥ 1).
#[test]
fn stability_davis_gives_the_factor_it_gave_before() {
    let davis = replaced(SLOPE, "dilatancy = \"fixed\"", "dilatancy = \"davis\"");
    let (f, bracket) = factor_of_safety(&davis, "slope_davis");
    assert_eq!(f, 1.369140625);
    assert_eq!(bracket, [Some(1.3671875), Some(1.37109375)]);
    let psi10 = replaced(&davis, "dilatancy_angle = 0.0 ", "dilatancy_angle = 10.0");
    let (f, bracket) = factor_of_safety(&psi10, "slope_davis_psi10");
    assert_eq!(f, 1.404296875);
    assert_eq!(bracket, [Some(1.40234375), Some(1.40625)]);
    // flow = "davis": β of the unreduced angles, then c*/F, tan φ*/F. For F ≥ 1 (a
    // search tries F = 1 first and none below: the slope's history.csv) the rule is moot:
    // each builds the same reduced materials (`Analysis::set_factor`, the reduction every
    // trial runs with), so the searches' trials are the same. Below 1, "fixed" keeps
    // ψ_F = min(ψ*, φ*_F) = φ* < φ*_F (`stability/strength.rs`, `Strength::reduced`).
    let flow = with_flow(SLOPE, "davis");
    let reduced = |rule: &str, f: f64| {
        let text = replaced(
            &flow,
            "dilatancy = \"fixed\"",
            &format!("dilatancy = \"{rule}\""),
        );
        let scene = Scene::parse(&text, Some(slope_path())).unwrap_or_else(|e| panic!("{e}"));
        let mut analysis = stability::Analysis::new(&scene)
            .unwrap()
            .expect("[stability]");
        analysis.set_factor(f).unwrap();
        analysis.model.materials.clone()
    };
    let unreduced = reduced("fixed", 1.0);
    for f in [0.5, 1.0, 1.37, 2.0] {
        let fixed = reduced("fixed", f);
        if f != 1.0 {
            assert_ne!(fixed, unreduced, "F = {f} reduces");
        }
        let davis = reduced("davis", f);
        assert_eq!(reduced("scaled", f), davis, "F = {f}, dilatancy = scaled");
        if f >= 1.0 {
            assert_eq!(fixed, davis, "F = {f}, dilatancy = fixed");
        } else {
            assert_ne!(fixed, davis, "F = {f}: fixed keeps ψ below φ_F");
        }
    }
}
