//! MPM bodies of their own materials (`docs/scenes.md`, 'MPM scenes'): a `[[material]]`
//! list whose materials the `[[body]]`s name. A stiff elastic block beside a sand column
//! on a floor: the column flows, the block never does (its particles' plastic strain stays
//! at round-off, in the particles and in the VTU); each particle weighs its material's
//! density; a checkpoint keeps the particles' materials; bad inputs are errors naming the
//! field.
use crate::common;
use std::ops::ControlFlow;
use std::path::PathBuf;
use std::sync::Arc;

use talus::model::mpm::MpmModel;
use talus::run::mpm::{resume_mpm_scene, run_mpm_scene};
use talus::run::{checkpoint, RunError, RunOptions};
use talus::scene::{MpmScene, SceneError, SceneFile};

// 256 block particles, 72 sand (`common::BLOCK_AND_COLUMN`).
use common::BLOCK_AND_COLUMN;

const N_BLOCK: usize = 16 * 16; // 0.2 m / (0.05 m / 4) per axis
const N_COLUMN: usize = 6 * 12; // 0.15 m / 0.025 m × 0.3 m / 0.025 m

/// `text` without the sand's `[[material]]` table.
fn without_sand(text: &str) -> String {
    let start = text.find("[[material]]\nname = \"sand\"").unwrap();
    let end = text.find("[[wall]]").unwrap();
    format!("{}{}", &text[..start], &text[end..])
}

fn out_dir(name: &str) -> PathBuf {
    let dir = common::target_tmp_dir("mpm_materials", name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn with(from: &str, to: &str) -> String {
    common::replaced(BLOCK_AND_COLUMN, from, to)
}

fn scene(text: &str) -> MpmScene {
    match SceneFile::parse(text, None) {
        Ok(SceneFile::Mpm(scene)) => scene,
        Ok(_) => panic!("parsed as a FEM scene"),
        Err(e) => panic!("{e}"),
    }
}

/// The error building the MPM scene `text` gives (parse or model).
fn build_error(text: &str) -> SceneError {
    let scene = match SceneFile::parse(text, None) {
        Ok(SceneFile::Mpm(scene)) => scene,
        Ok(_) => panic!("parsed as a FEM scene"),
        Err(e) => return e,
    };
    MpmModel::from_scene(&scene)
        .err()
        .expect("the scene must be rejected")
}

fn max(v: &[f64]) -> f64 {
    v.iter().copied().fold(0.0, f64::max)
}

#[test]
fn bodies_take_their_materials_index_and_density() {
    let model = MpmModel::from_scene(&scene(BLOCK_AND_COLUMN)).unwrap();
    let p = &model.particles;
    assert_eq!(p.len(), N_BLOCK + N_COLUMN);
    let mut expected = vec![0; N_BLOCK];
    expected.extend(vec![1; N_COLUMN]);
    assert_eq!(p.material, expected);
    assert_eq!(model.mpm.materials().len(), 2);
    for i in 0..p.len() {
        let density = if i < N_BLOCK { 2400.0 } else { 1800.0 };
        assert!(
            (p.mass[i] / p.volume[i] / density - 1.0).abs() < 1e-12,
            "particle {i}: {} kg/m³",
            p.mass[i] / p.volume[i]
        );
    }
    // A single [material] keeps its particles without indices (all of material 0), the
    // same particles as before there were several; a body may name it.
    let single = MpmScene::from_path(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenes/column_a1.toml"
    )))
    .unwrap();
    let model = MpmModel::from_scene(&single).unwrap();
    assert!(model.particles.material.is_empty());
    assert_eq!(model.mpm.materials().len(), 1);
}

#[test]
fn an_elastic_block_stays_elastic_while_the_sand_column_beside_it_flows() {
    let scene = scene(BLOCK_AND_COLUMN);
    let out = out_dir("run");
    let options = RunOptions {
        write_fields: true,
        ..RunOptions::new(&out)
    };
    let summary = run_mpm_scene(&scene, &options).unwrap();
    let p = &summary.particles;
    assert_eq!(summary.reports.len(), 20);
    let (block, column) = p.plastic_strain.split_at(N_BLOCK);
    let (block_max, column_max) = (max(block), max(column));
    println!("max plastic strain: block {block_max:.3e}, column {column_max:.3e}");
    assert!(
        column_max > 1e-2,
        "the sand column did not flow: {column_max:.3e}"
    );
    assert!(
        block_max <= 1e-9 * column_max,
        "the elastic block flowed: {block_max:.3e} (column {column_max:.3e})"
    );
    // The block is loaded all the same: it carries its weight to the floor.
    let deepest = (0..N_BLOCK)
        .min_by(|&a, &b| p.position[a][1].total_cmp(&p.position[b][1]))
        .unwrap();
    assert!(p.stress[deepest][1] < -1e3, "{:?}", p.stress[deepest]);
    assert_eq!(&p.material[..N_BLOCK], &[0; N_BLOCK][..]);

    // The last VTU says the same, particle by particle.
    let vtu = std::fs::read_to_string(out.join("vtu/step_00020.vtu")).unwrap();
    let plastic = common::array(&vtu, "plastic_strain");
    assert_eq!(plastic.len(), N_BLOCK + N_COLUMN);
    assert!(max(&plastic[..N_BLOCK]) <= 1e-9 * column_max);
    assert!(max(&plastic[N_BLOCK..]) > 1e-2);

    // The witness: the same block as sand flows (so the block's zero is its material's).
    let sand_block = with("model = \"elastic\"\n", "").replacen(
        "density = 2400.0",
        "friction_angle = 30.0\ncohesion = 0.0\ncone_fit = \"plane_strain\"\ndensity = 2400.0",
        1,
    );
    let witness = run_mpm_scene(
        &self::scene(&sand_block),
        &RunOptions::new(out_dir("witness")),
    )
    .unwrap();
    let witness_max = max(&witness.particles.plastic_strain[..N_BLOCK]);
    println!("the block as sand: max plastic strain {witness_max:.3e}");
    assert!(witness_max > 1e-2, "{witness_max:.3e}");
}

#[test]
fn a_checkpoint_keeps_the_particles_materials() {
    let scene = scene(BLOCK_AND_COLUMN);
    let reference = run_mpm_scene(&scene, &RunOptions::new(out_dir("reference"))).unwrap();
    let out = out_dir("interrupted");
    let options = RunOptions {
        checkpoint_every: 3,
        observer: Some(Arc::new(|p: &talus::run::StepProgress| {
            if p.step == 7 {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        })),
        ..RunOptions::new(&out)
    };
    match run_mpm_scene(&scene, &options) {
        Err(RunError::Interrupted { step: 7, .. }) => {}
        Err(e) => panic!("{e}"),
        Ok(_) => panic!("the run was not interrupted"),
    }
    let saved = checkpoint::read(&out).unwrap();
    let resumed = resume_mpm_scene(&scene, saved, &RunOptions::new(&out)).unwrap();
    assert_eq!(resumed.particles.material, reference.particles.material);
    assert!(
        resumed.particles == reference.particles,
        "the resumed run differs from the uninterrupted one"
    );
}

#[test]
fn a_list_needs_every_body_to_name_a_known_material() {
    // Missing.
    let text = with("material = \"sand\"\n", "");
    let err = build_error(&text);
    assert_eq!(err.field, "body[1].material", "{err}");
    let msg = err.to_string();
    assert!(msg.contains("missing"), "{msg}");
    assert!(msg.contains("\"block\", \"sand\""), "{msg}");
    // Unknown.
    let text = with("material = \"sand\"", "material = \"gravel\"");
    let err = build_error(&text);
    assert_eq!(err.field, "body[1].material", "{err}");
    assert_eq!(
        err.line,
        Some(common::line_of(&text, "material = \"gravel\""))
    );
    let msg = err.to_string();
    assert!(
        msg.contains("gravel") && msg.contains("\"block\", \"sand\""),
        "{msg}"
    );
}

#[test]
fn list_materials_need_a_name_used_by_a_body_and_no_regions() {
    // No name.
    let err = build_error(&with("name = \"sand\"\n", ""));
    assert_eq!(err.field, "material[1].name", "{err}");
    // The same name twice.
    let err = build_error(&with("name = \"sand\"", "name = \"block\""));
    assert_eq!(err.field, "material[1].name", "{err}");
    assert!(err.to_string().contains("material[0]"), "{err}");
    // A material no body uses.
    let text = with(
        "[[wall]]",
        "[[material]]\nname = \"clay\"\nmodel = \"elastic\"\nyoung_modulus = 1.0e7\n\
         poisson_ratio = 0.3\ndensity = 1900.0\n\n[[wall]]",
    );
    let err = build_error(&text);
    assert_eq!(err.field, "material[2].name", "{err}");
    assert_eq!(err.line, Some(common::line_of(&text, "name = \"clay\"")));
    assert!(err.to_string().contains("clay"), "{err}");
    // Regions, in a list and in a single [material].
    let text = with("name = \"sand\"", "name = \"sand\"\nregions = [\"right\"]");
    let err = build_error(&text);
    assert_eq!(err.field, "material[1].regions", "{err}");
    assert_eq!(err.line, Some(common::line_of(&text, "regions = ")));
    assert!(err.to_string().contains("[[body]]"), "{err}");
    let err = build_error(&single_material("regions = [\"all\"]\n", ""));
    assert_eq!(err.field, "material.regions", "{err}");
    // Each density is required.
    let err = build_error(&with("density = 1800.0\n", ""));
    assert_eq!(err.field, "material[1].density", "{err}");
    assert!(err.to_string().contains("required"), "{err}");
}

/// The sand column alone, of a single `[material]` (with `material_key` added to it) and
/// `body_key` added to its body.
fn single_material(material_key: &str, body_key: &str) -> String {
    let text = with(
        "[[body]]\nrectangle = [[0.1, 0.0], [0.3, 0.2]]\nparticles_per_cell = 4\nmaterial = \"block\"\n\n",
        "",
    );
    let block = "[[material]]\nname = \"block\"\nmodel = \"elastic\"\nyoung_modulus = 1.0e8\n\
                 poisson_ratio = 0.25\ndensity = 2400.0\n\n";
    let text = text.replacen(block, "", 1).replacen(
        "[[material]]\nname = \"sand\"\n",
        &format!("[material]\n{material_key}"),
        1,
    );
    text.replacen("material = \"sand\"\n", body_key, 1)
}

#[test]
fn a_single_material_needs_no_body_key_and_may_be_named() {
    let model = MpmModel::from_scene(&scene(&single_material("", ""))).unwrap();
    assert_eq!(model.particles.len(), N_COLUMN);
    assert!(model.particles.material.is_empty());
    let named = single_material("name = \"sand\"\n", "material = \"sand\"\n");
    let model = MpmModel::from_scene(&scene(&named)).unwrap();
    assert_eq!(model.particles.len(), N_COLUMN);
    // A name the single material does not have.
    let err = build_error(&single_material("", "material = \"sand\"\n"));
    assert_eq!(err.field, "body[0].material", "{err}");
    assert!(err.to_string().contains("no name"), "{err}");
    // An elastic single material runs the material point method too.
    let elastic = without_sand(
        &with(
            "[[body]]\nrectangle = [[0.6, 0.0], [0.75, 0.3]]\nmaterial = \"sand\"\n\n",
            "",
        )
        .replacen(
            "[[material]]\nname = \"block\"",
            "[material]\nname = \"block\"",
            1,
        ),
    );
    let summary = run_mpm_scene(&scene(&elastic), &RunOptions::new(out_dir("elastic"))).unwrap();
    assert_eq!(summary.particles.len(), N_BLOCK);
    assert!(max(&summary.particles.plastic_strain) < 1e-12);
}

#[test]
fn initial_stress_is_checked_against_each_particles_material() {
    // K₀ of bodies of different densities: refused, naming the densities.
    let k0 = "[initial_stress]\nk0 = 0.5\nsurface = 0.3\n\n[time]";
    let text = with("[time]", k0);
    let err = build_error(&text);
    assert_eq!(err.field, "initial_stress.k0", "{err}");
    assert_eq!(err.line, Some(common::line_of(&text, "k0 = 0.5")));
    let msg = err.to_string();
    assert!(msg.contains("2400") && msg.contains("1800"), "{msg}");
    // The form comes first, no material's: both forms given.
    let both = with(
        "[time]",
        "[initial_stress]\nk0 = 0.5\nsurface = 0.3\nstress = [-1.0e3, -1.0e3, 0.0, -1.0e3]\n\n[time]",
    );
    let err = build_error(&both);
    assert_eq!(err.field, "initial_stress.stress", "{err}");
    assert!(!err.to_string().contains("material["), "{err}");
    // Equal densities: each particle of its own height under the one unit weight.
    let text = with("[time]", k0).replacen("density = 2400.0", "density = 1800.0", 1);
    let model = MpmModel::from_scene(&scene(&text)).unwrap();
    let p = &model.particles;
    for i in 0..p.len() {
        let syy = -1800.0 * 9.81 * (0.3 - p.position[i][1]);
        assert!(
            (p.stress[i][1] - syy).abs() <= 1e-9 * syy.abs(),
            "particle {i}"
        );
        assert!(
            (p.stress[i][0] - 0.5 * syy).abs() <= 1e-9 * syy.abs(),
            "particle {i}"
        );
    }
    // A uniform tension: outside the sand's cone, refused at the sand's particles; an
    // elastic material has no cone.
    let tension = "[initial_stress]\nstress = [1.0e3, 1.0e3, 0.0, 1.0e3]\n\n[time]";
    let err = build_error(&with("[time]", tension));
    assert_eq!(err.field, "initial_stress.stress", "{err}");
    assert!(err.to_string().contains("material[1] \"sand\""), "{err}");
    let elastic_only = without_sand(&with("[time]", tension).replacen(
        "material = \"sand\"",
        "material = \"block\"",
        1,
    ));
    let model = MpmModel::from_scene(&scene(&elastic_only)).unwrap();
    assert_eq!(model.particles.len(), N_BLOCK + N_COLUMN);
    assert!(model.particles.material.iter().all(|m| *m == 0));
    assert!(model
        .particles
        .stress
        .iter()
        .all(|s| *s == [1.0e3, 1.0e3, 1.0e3, 0.0]));
}
