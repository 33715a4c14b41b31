//! Layered ground (`docs/scenes.md`, 'Regions and materials'): `[[region]]` boxes and
//! `[[material]]` lists, each Gauss point with its material; an elastic material that never
//! flows; the K₀ procedure through layers of different unit weights; and every bad input
//! named by its field and value.
use crate::common;
use talus::model::fem::{FromScene, Model, ReactionForce};
use talus::run::fem::run_scene;
use talus::run::RunOptions;
use talus::scene::Scene;
use talus_engine::Stepper;

const FOOTING: &str = include_str!("../../../scenes/footing.toml");

/// The paper footing with its `[material]` table replaced by `materials` (TOML) and the
/// `regions` added before it.
fn footing_with_materials(regions: &str, materials: &str) -> String {
    let start = FOOTING
        .find("[material]")
        .expect("[material] in the footing");
    let end = FOOTING[start..]
        .find("\n\n")
        .expect("a blank line after it")
        + start;
    format!(
        "{}{regions}\n{materials}{}",
        &FOOTING[..start],
        &FOOTING[end..]
    )
}

/// The footing's own material keys, as in `scenes/footing.toml`.
const SOIL: &str = "young_modulus = 1.0e9\npoisson_ratio = 0.3\nfriction_angle = 27.0\n\
                    cohesion = 2.0e3\ndilatancy_angle = 14.2906\ncone_fit = \"plane_strain\"\n\
                    density = 2.0e3\n";

const TWO_LAYERS: &str = "[[region]]\nname = \"upper\"\nbox = [[-1.0, -0.4], [1.0, 0.0]]\n\n\
                          [[region]]\nname = \"lower\"\nbox = [[-1.0, -1.0], [1.0, -0.4]]\n";

/// The y (m) of the footing mesh's grid line nearest −0.4 m (`[mesh.rectangle]`: 14 cells
/// in y graded by 1.1 toward the surface): where the two layers of [`TWO_LAYERS`] meet.
fn interface() -> f64 {
    let ys = talus_fem::graded_coordinates(-1.0, 0.0, 14, 0.0, 1.1).unwrap();
    ys.into_iter()
        .min_by(|a, b| (a + 0.4).abs().total_cmp(&(b + 0.4).abs()))
        .unwrap()
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

fn steps(scene: &Scene, n: usize) -> (Vec<f64>, Vec<f64>) {
    let model = Model::from_scene(scene).unwrap();
    let mut state = model.initial_state(scene).unwrap();
    let mut stepper = Stepper::new(&model, scene.spec.solver.fem());
    let mut reactions = Vec::new();
    for _ in 0..n {
        let r = stepper.advance(&mut state, scene.spec.time.step).unwrap();
        reactions.push(r.reaction_force());
    }
    (reactions, state.sigma)
}

#[test]
fn two_regions_with_one_material_give_the_one_material_run_bit_for_bit() {
    let one = Scene::parse(FOOTING, None).unwrap();
    let layered = footing_with_materials(
        TWO_LAYERS,
        &format!("[[material]]\nname = \"soil\"\nregions = [\"upper\", \"lower\"]\n{SOIL}"),
    );
    let two = Scene::parse(&layered, None).unwrap();
    let (ra, sa) = steps(&one, 8);
    let (rb, sb) = steps(&two, 8);
    assert_eq!(bits(&ra), bits(&rb));
    assert_eq!(bits(&sa), bits(&sb));
    // Two materials with the same parameters are the same ground too.
    let split = footing_with_materials(
        TWO_LAYERS,
        &format!(
            "[[material]]\nname = \"a\"\nregions = [\"upper\"]\n{SOIL}\n\
             [[material]]\nname = \"b\"\nregions = [\"lower\"]\n{SOIL}"
        ),
    );
    let (rc, sc) = steps(&Scene::parse(&split, None).unwrap(), 8);
    assert_eq!(bits(&ra), bits(&rc));
    assert_eq!(bits(&sa), bits(&sc));
}

/// An elastic lower layer never flows, while the same layer as Drucker-Prager soil does
/// (the witness that the check can fail); the upper soil flows in both.
#[test]
fn an_elastic_layer_has_no_plastic_strain() {
    let run = |lower: &str| {
        let text = footing_with_materials(
            TWO_LAYERS,
            &format!(
                "[[material]]\nname = \"soil\"\nregions = [\"upper\"]\n{SOIL}\n\
                 [[material]]\nname = \"base\"\nregions = [\"lower\"]\n{lower}"
            ),
        );
        let scene = Scene::parse(&text, None).unwrap();
        let model = Model::from_scene(&scene).unwrap();
        let mut state = model.initial_state(&scene).unwrap();
        let mut stepper = Stepper::new(&model, scene.spec.solver.fem());
        for _ in 0..60 {
            stepper.advance(&mut state, scene.spec.time.step).unwrap();
        }
        let largest = |m: usize| {
            (0..model.n_points())
                .filter(|&p| model.point_material[p] == m)
                .map(|p| state.plastic_strain[p])
                .fold(0.0, f64::max)
        };
        (largest(0), largest(1))
    };
    let elastic =
        "model = \"elastic\"\nyoung_modulus = 1.0e9\npoisson_ratio = 0.3\ndensity = 2.0e3\n";
    let (upper, lower) = run(elastic);
    eprintln!("elastic layer: upper {upper:e}, lower {lower:e}");
    assert!(upper > 1e-4, "the footing yields the upper soil: {upper:e}");
    // z = 0 at the root; a converged solve leaves it at the tolerance's round-off.
    assert!(
        lower < 1e-9 * upper,
        "the elastic layer does not flow: {lower:e}"
    );
    // The same layer of a weak Drucker-Prager soil flows.
    let weak = SOIL.replace("cohesion = 2.0e3", "cohesion = 1.0e2");
    let (_, lower) = run(&weak);
    eprintln!("weak layer: lower {lower:e}");
    assert!(
        lower > 1e-6 * upper,
        "a plastic lower layer flows: the check can fail"
    );
}

/// Level ground of two layers, γ₁ = 20 kN/m³ over γ₂ = 18 kN/m³ below the grid line `y_i`
/// nearest −0.4 m, surcharge q: `σ_yy = −(q + γ₁ (0 − y))` above,
/// `−(q + γ₁ (0 − y_i) + γ₂ (y_i − y))` below, `σ_xx = σ_zz = K₀ σ_yy`, at every Gauss point
/// (the geostatic stress of layered ground).
#[test]
fn k0_in_layers_sums_the_weight_of_each_layer_above() {
    let lower = SOIL.replace("density = 2.0e3", "density = 1.8e3");
    let yi = interface();
    let layers = TWO_LAYERS.replace("-0.4]", &format!("{yi:?}]"));
    let text = footing_with_materials(
        &layers,
        &format!(
            "[[material]]\nname = \"upper\"\nregions = [\"upper\"]\n{SOIL}\n\
             [[material]]\nname = \"lower\"\nregions = [\"lower\"]\n{lower}"
        ),
    );
    let scene = Scene::parse(&text, None).unwrap();
    let model = Model::from_scene(&scene).unwrap();
    let state = model.initial_state(&scene).unwrap();
    let (q, k0, g) = (20.0e3, 0.546, 9.81);
    let (g1, g2) = (2.0e3 * g, 1.8e3 * g);
    let yi = interface();
    let mut below = 0;
    for (p, x) in model.assembly.gauss_points.iter().enumerate() {
        let y = x[1];
        let weight = if y >= yi {
            g1 * -y
        } else {
            below += 1;
            g1 * -yi + g2 * (yi - y)
        };
        let syy = -(q + weight);
        let s = &state.sigma[4 * p..4 * p + 4];
        assert!(
            (s[1] - syy).abs() <= 1e-10 * syy.abs(),
            "point {p} at y = {y}: {} vs {syy}",
            s[1]
        );
        assert!((s[0] - k0 * syy).abs() <= 1e-10 * syy.abs());
        assert!((s[2] - k0 * syy).abs() <= 1e-10 * syy.abs());
    }
    assert!(below > 0, "points in the lower layer");
}

fn refused(regions: &str, materials: &str) -> talus::scene::SceneError {
    let text = footing_with_materials(regions, materials);
    let scene = Scene::parse(&text, None).expect("parses");
    Model::from_scene(&scene).err().expect("refused")
}

#[test]
fn overlapping_materials_are_named_with_the_element() {
    let err = refused(
        TWO_LAYERS,
        &format!(
            "[[material]]\nname = \"a\"\nregions = [\"upper\", \"lower\"]\n{SOIL}\n\
             [[material]]\nname = \"b\"\nregions = [\"lower\"]\n{SOIL}"
        ),
    );
    assert_eq!(err.field, "material[1].regions");
    let msg = err.to_string();
    assert!(
        msg.contains("\"a\"") && msg.contains("\"b\"") && msg.contains("centroid"),
        "{msg}"
    );
}

#[test]
fn an_element_of_no_material_is_named_by_its_centroid() {
    let err = refused(
        TWO_LAYERS,
        &format!("[[material]]\nname = \"a\"\nregions = [\"upper\"]\n{SOIL}"),
    );
    assert_eq!(err.field, "material");
    assert!(err.to_string().contains("claimed by no material"), "{err}");
    assert!(err.to_string().contains("centroid ("), "{err}");
}

#[test]
fn a_region_that_does_not_exist_is_named_with_the_known_ones() {
    let err = refused(
        TWO_LAYERS,
        &format!("[[material]]\nname = \"a\"\nregions = [\"upper\", \"clay\"]\n{SOIL}"),
    );
    assert_eq!(err.field, "material[0].regions[1]");
    let msg = err.to_string();
    assert!(
        msg.contains("\"clay\"") && msg.contains("lower, upper"),
        "{msg}"
    );
}

#[test]
fn bad_regions_are_named() {
    let one = format!("[[material]]\nname = \"a\"\nregions = [\"upper\"]\n{SOIL}");
    let err = refused(
        "[[region]]\nname = \"upper\"\nbox = [[1.0, 0.0], [-1.0, 1.0]]\n",
        &one,
    );
    assert_eq!(err.field, "region[0].box");
    let err = refused(
        "[[region]]\nname = \"upper\"\nbox = [[5.0, 5.0], [6.0, 6.0]]\n",
        &one,
    );
    assert_eq!(err.field, "region[0].box");
    assert!(err.to_string().contains("no element"), "{err}");
    let twice =
        format!("{TWO_LAYERS}\n[[region]]\nname = \"upper\"\nbox = [[-1.0, -1.0], [1.0, 0.0]]\n");
    let err = refused(&twice, &one);
    assert_eq!(err.field, "region[2].name");
}

#[test]
fn bad_materials_are_named() {
    // A list entry without a name.
    let err = refused(
        TWO_LAYERS,
        &format!("[[material]]\nregions = [\"upper\", \"lower\"]\n{SOIL}"),
    );
    assert_eq!(err.field, "material[0].name");
    // Two materials of one name.
    let err = refused(
        TWO_LAYERS,
        &format!(
            "[[material]]\nname = \"a\"\nregions = [\"upper\"]\n{SOIL}\n\
             [[material]]\nname = \"a\"\nregions = [\"lower\"]\n{SOIL}"
        ),
    );
    assert_eq!(err.field, "material[1].name");
    // A Drucker-Prager key on an elastic material.
    let err = refused(
        TWO_LAYERS,
        "[[material]]\nname = \"a\"\nregions = [\"upper\", \"lower\"]\nmodel = \"elastic\"\n\
         young_modulus = 1e9\npoisson_ratio = 0.3\nfriction_angle = 30.0\ndensity = 2e3\n",
    );
    assert_eq!(err.field, "material[0].friction_angle");
    // A missing cone fit lists the choices.
    let err = refused(
        "",
        &SOIL
            .replace("cone_fit = \"plane_strain\"\n", "")
            .replace("young", "[material]\nyoung"),
    );
    assert_eq!(err.field, "material.cone_fit");
    assert!(err.to_string().contains("\"outer_cone\""), "{err}");
    // A bad saturated density.
    let err = refused("", &format!("[material]\n{SOIL}saturated_density = -1.0\n"));
    assert_eq!(err.field, "material.saturated_density");
    assert!(err.to_string().contains("-1"), "{err}");
    // A list entry out of range names its index.
    let err = refused(
        TWO_LAYERS,
        &format!(
            "[[material]]\nname = \"a\"\nregions = [\"upper\", \"lower\"]\n{}",
            SOIL.replace("poisson_ratio = 0.3", "poisson_ratio = 0.7")
        ),
    );
    assert_eq!(err.field, "material[0].poisson_ratio");
}

/// The VTU's `material` cell field holds each element's material: 0 (the upper layer, the
/// first `[[material]]`) for the elements whose centroid lies above the interface, else 1.
#[test]
fn the_vtu_has_each_elements_material() {
    let yi = interface();
    let layers = TWO_LAYERS.replace("-0.4]", &format!("{yi:?}]"));
    let text = footing_with_materials(
        &layers,
        &format!(
            "[[material]]\nname = \"soil\"\nregions = [\"upper\"]\n{SOIL}\n\
             [[material]]\nname = \"base\"\nregions = [\"lower\"]\n{SOIL}"
        ),
    )
    .replace("steps = 300", "steps = 2");
    let scene = Scene::parse(&text, None).unwrap();
    let out = common::target_tmp_dir("regions_and_materials", "vtu");
    let options = RunOptions {
        write_fields: true,
        ..RunOptions::new(&out)
    };
    run_scene(&scene, &options).unwrap();
    let xml = std::fs::read_to_string(out.join("vtu/step_00002.vtu")).unwrap();
    let material = common::array(&xml, "material");
    let model = Model::from_scene(&scene).unwrap();
    assert_eq!(material.len(), model.mesh.triangles.len());
    for (e, t) in model.mesh.triangles.iter().enumerate() {
        let y = (model.mesh.nodes[t[0]][1] + model.mesh.nodes[t[1]][1] + model.mesh.nodes[t[2]][1])
            / 3.0;
        let expected = if y > yi { 0.0 } else { 1.0 };
        assert_eq!(material[e], expected, "element {e} at y = {y}");
    }
}
