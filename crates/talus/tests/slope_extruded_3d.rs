//! Factors of safety in 3D (`docs/stability.md`, 'Factors of safety in 3D'): the slope of
//! Griffiths & Lane (1999, example 1; `scenes/slope.toml`) extruded along z into P2
//! tetrahedra with rollers on both z faces (`scenes/slope_extruded.toml`) is in plane
//! strain, so its factor of safety is the 2D one. Both run on the same 2D mesh
//! (`scenes/slope_3d_section.msh`, `slope.geo` at twice its element size, for a test's
//! time), with the same cone (`cone_fit = "plane_strain"`), dilatancy rule and bracket
//! tolerance (0.005): the factors agree within 1%.
//!
//! The 3D search is the 2D one (one implementation over the Mandel size): its files are
//! the same (history.csv, summary.json) and its mechanism a VTU of tetrahedra.
use crate::common;
use std::path::{Path, PathBuf};

use talus::analysis::stability;
use talus::run::RunOptions;
use talus::scene::{Scene, Scene3, SceneFile};

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

fn read(name: &str) -> String {
    std::fs::read_to_string(scenes().join(name)).unwrap()
}

/// The 3D scene `text`, parsed as a file in `scenes/` (its mesh path relative there).
fn scene3(text: &str) -> Scene3 {
    match SceneFile::parse(text, Some(scenes().join("slope_extruded.toml"))) {
        Ok(SceneFile::Fem3(s)) => s,
        Ok(_) => panic!("not read as a 3D scene"),
        Err(e) => panic!("{e}"),
    }
}

const SECTION: &str = "path = \"slope_3d_section.msh\"";

#[test]
fn extruded_slope_has_the_plane_strain_factor_of_safety() {
    let text2 = common::replaced(&read("slope.toml"), "path = \"slope.msh\"", SECTION);
    let text2 = common::replaced(&text2, "plots = true", "plots = false");
    let s2 = Scene::parse(&text2, Some(scenes().join("slope.toml"))).unwrap();
    let out2 = common::target_tmp_dir("slope_extruded_3d", "2d");
    let run2 = stability::run(&s2, &RunOptions::new(&out2)).unwrap();

    let text3 = common::replaced(
        &read("slope_extruded.toml"),
        "path = \"slope.msh\"",
        SECTION,
    );
    let s3 = scene3(&text3);
    let out3 = common::target_tmp_dir("slope_extruded_3d", "3d");
    let options = RunOptions {
        write_fields: true,
        ..RunOptions::new(&out3)
    };
    let run3 = stability::run(&s3, &options).unwrap();

    let (f2, f3) = (
        run2.factor_of_safety.value.unwrap(),
        run3.factor_of_safety.value.unwrap(),
    );
    let iterations =
        |r: &[stability::Trial<4>]| r.iter().map(|t| t.newton_iterations).sum::<usize>();
    let iterations3: usize = run3.trials.iter().map(|t| t.newton_iterations).sum();
    println!(
        "2D: F = {f2:.4} in {:?}, {} trials, {} Newton iterations, {:.1} s",
        run2.factor_of_safety.bracket,
        run2.trials.len(),
        iterations(&run2.trials),
        run2.seconds
    );
    println!(
        "3D: F = {f3:.4} in {:?}, {} trials, {iterations3} Newton iterations, {:.1} s",
        run3.factor_of_safety.bracket,
        run3.trials.len(),
        run3.seconds
    );
    assert!((f3 / f2 - 1.0).abs() < 0.01, "3D {f3} against 2D {f2}");
    // Both are the slope's: Griffiths & Lane's 1.38–1.4 within the coarse mesh's 3%.
    for f in [f2, f3] {
        assert!((1.34..1.45).contains(&f), "{f}");
    }
    // The same tolerance reached in both.
    for run in [&run2.factor_of_safety, &run3.factor_of_safety] {
        let [lo, hi] = run.bracket;
        assert!(hi.unwrap() / lo.unwrap() - 1.0 <= 0.005 * (1.0 + 1e-12));
        assert_eq!(run.status, "found");
    }

    // The 3D files: a history row per trial after the loading's, summary.json's factor
    // and force unit, the mechanism as tetrahedra.
    let summary = talus::output::Summary::read(&out3.join("summary.json")).unwrap();
    assert_eq!(summary.factor_of_safety.unwrap().value, Some(f3));
    assert_eq!(summary.force_unit, "N");
    let history = std::fs::read_to_string(out3.join("history.csv")).unwrap();
    assert_eq!(history.lines().count(), 2 + run3.trials.len());
    assert!(history.starts_with(stability::TRIAL_COLUMNS));
    let vtu = std::fs::read_to_string(out3.join("mechanism.vtu")).unwrap();
    let types = common::array(&vtu, "types");
    assert!(
        !types.is_empty() && types.iter().all(|t| *t == 24.0),
        "P2 tetrahedra (VTK 24)"
    );
    assert!(!out3.join("mechanism.png").exists());
}

/// The slope with a water table (`scenes/slope_water.toml`: the phreatic line through the
/// slope, saturated weight below it, pore pressure in the cone, the water's push on the
/// submerged face) extruded along z with rollers on both z faces is in plane strain too:
/// its factor of safety is the 2D one within 1%, on the same section mesh. The water's
/// pieces in 3D are 2D's functions (`model::fem::build`: densities, `free_below` on faces,
/// the pore pressure along the extruded phreatic surface). A `[stability] monitor` names a
/// 3D `[[monitor]]` (the crest) as in 2D.
#[test]
fn extruded_slope_with_water_has_the_plane_strain_factor_of_safety() {
    let (run2, run3) = talus::analysis::verification::extruded_slope_runs("slope_water.toml", true)
        .unwrap_or_else(|e| panic!("{e}"));
    let (f2, f3) = (
        run2.factor_of_safety.value.unwrap(),
        run3.factor_of_safety.value.unwrap(),
    );
    println!(
        "with water: 2D F = {f2:.4} {:?} in {:.1} s, 3D F = {f3:.4} {:?} in {:.1} s",
        run2.factor_of_safety.bracket, run2.seconds, run3.factor_of_safety.bracket, run3.seconds
    );
    assert!((f3 / f2 - 1.0).abs() < 0.01, "3D {f3} against 2D {f2}");
    // The water matters: the dry section's factor is 1.4151 (the test above), so a 3D run
    // that ignored it would miss the 2D one by far more than 1%.
    assert!(f2 < 1.3 && f3 < 1.3, "{f2} {f3}");
}

/// The keys of an extrusion and of a 3D `[stability]` name themselves when wrong.
#[test]
fn extrusion_and_3d_stability_errors_name_their_field() {
    let text3 = read("slope_extruded.toml");
    let refused = |text: &str| match SceneFile::parse(text, Some(scenes().join("x.toml"))) {
        Ok(SceneFile::Fem3(s)) => stability::Analysis::new(&s)
            .err()
            .expect("refused")
            .to_string(),
        Ok(_) => panic!("not 3D"),
        Err(e) => e.to_string(),
    };
    let cases = [
        (
            common::replaced(&text3, "extrude = [0.0, 1.0]", "extrude = [1.0, 1.0]"),
            "mesh.gmsh.extrude",
        ),
        (
            common::replaced(&text3, "layers = 1 ", "layers = 0 "),
            "mesh.gmsh.layers",
        ),
        (
            common::replaced(&text3, "extrude = [0.0, 1.0]", ""),
            "mesh.gmsh.layers",
        ),
        (
            common::replaced(
                &text3,
                "tolerance = 0.005",
                "tolerance = 0.005\nmonitor = \"crest\"",
            ),
            "stability.monitor",
        ),
        (
            common::replaced(&text3, "tolerance = 0.005", "tolerance = 2.0"),
            "stability.tolerance",
        ),
        (
            common::replaced(
                &common::replaced(&text3, "inertia_ratio = 1e-6", ""),
                "kind = \"quasi_static\"",
                "kind = \"dynamic\"",
            ),
            "analysis.kind",
        ),
    ];
    for (text, field) in cases {
        let e = refused(&text);
        assert!(e.contains(field), "{field}: {e}");
    }
    // A 2D scene has no extrusion.
    let text2 = common::replaced(
        &read("slope.toml"),
        "path = \"slope.msh\"",
        "path = \"slope.msh\"\nextrude = [0.0, 1.0]",
    );
    let e = Scene::parse(&text2, Some(scenes().join("slope.toml")))
        .map(|s| {
            use talus::model::fem::FromScene;
            talus::model::fem::Model::from_scene(&s)
                .err()
                .expect("refused")
                .to_string()
        })
        .unwrap_or_else(|e| e.to_string());
    assert!(e.contains("mesh.gmsh.extrude"), "{e}");
}

/// Gravity increase in 3D: the same slab and section, its weight multiplied by the trial
/// factor (`model::fem::weight_3d`), against the 2D search of the same scene.
#[test]
fn extruded_slope_gravity_increase_matches_plane_strain() {
    let method = |text: &str| {
        let text = common::replaced(text, "path = \"slope.msh\"", SECTION);
        let text = common::replaced(
            &text,
            "method = \"strength_reduction\"",
            "method = \"gravity_increase\"",
        );
        common::replaced(&text, "dilatancy = \"fixed\"\n", "")
    };
    let text2 = common::replaced(
        &method(&read("slope.toml")),
        "plots = true",
        "plots = false",
    );
    let s2 = Scene::parse(&text2, Some(scenes().join("slope.toml"))).unwrap();
    let out2 = common::target_tmp_dir("slope_extruded_3d", "gravity_2d");
    let run2 = stability::run(&s2, &RunOptions::new(&out2)).unwrap();
    let s3 = scene3(&method(&read("slope_extruded.toml")));
    let out3 = common::target_tmp_dir("slope_extruded_3d", "gravity_3d");
    let run3 = stability::run(&s3, &RunOptions::new(&out3)).unwrap();
    let (f2, f3) = (
        run2.factor_of_safety.value.unwrap(),
        run3.factor_of_safety.value.unwrap(),
    );
    println!(
        "gravity increase: 2D F = {f2:.4} ({} trials, {:.1} s), 3D F = {f3:.4} ({} trials, {:.1} s)",
        run2.trials.len(),
        run2.seconds,
        run3.trials.len(),
        run3.seconds
    );
    assert_eq!(run3.factor_of_safety.method, "gravity_increase");
    assert!((f3 / f2 - 1.0).abs() < 0.01, "3D {f3} against 2D {f2}");
    assert_eq!(run3.factor_of_safety.status, "found");
}
