//! The quasi-static scaling's bounds (issue 27, 'Analysis and loads'): `inertia_ratio = 1`
//! doubled the footing's force with a fake limit load, `1e-300` gave NaN and a step of
//! 1e-300 s "lumped_mass: mass 0"; each is now refused naming the field and the value.
//! And the inertia a run leaves in its reported reaction is written out
//! (`history.csv`'s `inertial_share`), a quasi-static run warning when it is not small.
use std::path::{Path, PathBuf};
use std::process::Command;

use talus::model::fem::{FromScene, Model, ReactionForce};
use talus::output::Summary;
use talus::run::fem::run_scene;
use talus::run::{RunError, RunOptions};
use talus::scene::Scene;

use crate::common;
const FOOTING: &str = include_str!("../../../scenes/footing.toml");

/// The paper footing made quasi-static (`[analysis]` before `[time]`), `extra` added to
/// the section, `steps` steps, no plots.
fn footing(extra: &str, steps: usize) -> String {
    assert!(
        FOOTING.contains("[time]\nstep = 1.0e-2\nsteps = 300"),
        "test setup"
    );
    FOOTING
        .replacen(
            "[time]\nstep = 1.0e-2\nsteps = 300",
            &format!("[analysis]\nkind = \"quasi_static\"\n{extra}\n\n[time]\nstep = 1.0e-2\nsteps = {steps}"),
            1,
        )
        .replacen("plots = true", "plots = false", 1)
}

fn dir(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("quasi_static_bounds")
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn refused(text: &str) -> talus::scene::SceneError {
    let scene = Scene::parse(text, None).unwrap();
    match Model::from_scene(&scene) {
        Err(e) => e,
        Ok(_) => panic!("accepted"),
    }
}

#[test]
fn inertia_ratio_is_bounded_where_inertia_starts_to_matter() {
    for (r, shown) in [("1.0", "1e0"), ("2e-4", "2e-4"), ("1e-300", "1e-300")] {
        let e = refused(&footing(&format!("inertia_ratio = {r}"), 3));
        assert_eq!(e.field, "analysis.inertia_ratio", "{r}");
        assert!(e.message.starts_with(shown), "{r}: {e}");
        assert!(e.message.contains("[1e-12, 1e-4]"), "{e}");
        assert!(e.line.is_some(), "{e}");
    }
    // The bounds themselves are accepted.
    for r in ["1e-4", "1e-12"] {
        let scene = Scene::parse(&footing(&format!("inertia_ratio = {r}"), 3), None).unwrap();
        assert!(Model::from_scene(&scene).is_ok(), "{r}");
    }
    // `talus run`: invalid input, nothing written.
    let d = dir("cli_inertia");
    let scene = d.join("footing.toml");
    std::fs::write(&scene, footing("inertia_ratio = 1.0", 3)).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_talus"))
        .arg("run")
        .arg(&scene)
        .arg("--out")
        .arg(d.join("out"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("analysis.inertia_ratio: 1e0 must be within"),
        "{stderr}"
    );
    assert!(!d.join("out").join("history.csv").exists());
    assert!(!d.join("out").join("summary.json").exists());
}

#[test]
fn a_quasi_static_step_whose_square_underflows_is_refused() {
    for h in ["1e-300", "1e-160", "1e160"] {
        let text = footing("", 3).replacen("step = 1.0e-2", &format!("step = {h}"), 1);
        let e = refused(&text);
        assert_eq!(e.field, "time.step", "{h}: {e}");
        assert!(e.message.starts_with(&format!("{h} s")), "{e}");
        // run_scene says the same before writing anything.
        let scene = Scene::parse(&text, None).unwrap();
        let d = dir(&format!("step_{h}"));
        match run_scene(&scene, &RunOptions::new(d.join("out"))) {
            Err(RunError::Scene(e)) => assert_eq!(e.field, "time.step"),
            other => panic!("{h}: {:?}", other.err()),
        }
        assert!(!d.join("out").join("history.csv").exists());
    }
    // A small step that squares to a normal number runs (time is a load parameter): at
    // 1e95 m/s it settles 1e-5 m a step as the h = 1e-2 s run at 1e-3 m/s does, and gives
    // its reactions: the masses are `r h² K_jj` (`model/fem/quasi_static.rs`), so the
    // inertia is the same share of the stiffness at either h and the step problems differ
    // by the rounding of the scaling alone. Measured 2026-11-26: 7.8e-13 and 5.3e-13 relative
    // at steps 1 and 2; bound 1e-11.
    let reactions = |h: &str, velocity: &str, name: &str| -> Vec<f64> {
        let text = footing("", 2)
            .replacen("step = 1.0e-2", &format!("step = {h}"), 1)
            .replacen(
                "velocity = [0.0, -1.0e-3]",
                &format!("velocity = [0.0, {velocity}]"),
                1,
            );
        let scene = Scene::parse(&text, None).unwrap();
        let ran = run_scene(&scene, &RunOptions::new(dir(name))).unwrap();
        assert!(ran.records.iter().all(|r| r.residual.is_finite()));
        ran.records.iter().map(|r| r.reaction_force()).collect()
    };
    let tiny = reactions("1e-100", "-1.0e95", "step_1e-100");
    let plain = reactions("1.0e-2", "-1.0e-3", "step_1e-2");
    assert_eq!(tiny.len(), 2);
    for (k, (a, b)) in tiny.iter().zip(&plain).enumerate() {
        let diff = (a / b - 1.0).abs();
        eprintln!("step {}: {a:e} against {b:e} N/m, relative {diff:e}", k + 1);
        assert!(
            b.abs() > 0.0 && diff < 1e-11,
            "step {}: {a} against {b}",
            k + 1
        );
    }
}

/// `history.csv`'s last column: the reported reaction's inertial share. Quasi-static at
/// the default ratio it is round-off after the start; a dynamic footing stepped at
/// 1e-4 s (inertia up to 0.11 of the stiffness, 25% off the quasi-static reaction,
/// `tests/quasi_static_footing.rs`) shows it.
#[test]
fn the_inertial_share_of_the_reaction_is_written() {
    let share = |text: &str, name: &str| -> (Vec<Option<f64>>, Summary) {
        let scene = Scene::parse(text, None).unwrap();
        let d = dir(name);
        run_scene(&scene, &RunOptions::new(&d)).unwrap();
        let history = std::fs::read_to_string(d.join("history.csv")).unwrap();
        let header = history.lines().next().unwrap();
        assert!(header.ends_with(",inertial_share"), "{name}: {header}");
        let values = common::history_column(&d, "inertial_share")
            .into_iter()
            .map(|v| Some(v).filter(|v| !v.is_nan()))
            .collect();
        (values, Summary::read(&d.join("summary.json")).unwrap())
    };
    let (quasi, summary) = share(&footing("", 20), "quasi_static");
    assert_eq!(quasi.len(), 21);
    assert_eq!(quasi[0], Some(0.0), "at rest");
    let after_start = quasi[2..].iter().map(|s| s.unwrap()).fold(0.0, f64::max);
    assert!(after_start < 1e-5, "{after_start:e}");
    assert!(summary.warnings.is_empty(), "{:?}", summary.warnings);

    let dynamic = FOOTING
        .replacen("step = 1.0e-2\nsteps = 300", "step = 1.0e-4\nsteps = 20", 1)
        .replacen("velocity = [0.0, -1.0e-3]", "velocity = [0.0, -1.0e-1]", 1)
        .replacen("plots = true", "plots = false", 1);
    let (dynamic, summary) = share(&dynamic, "dynamic");
    let largest = dynamic[2..].iter().map(|s| s.unwrap()).fold(0.0, f64::max);
    assert!(largest > 0.1, "{largest:e}");
    // Inertia is physical in a dynamic run: no warning.
    assert!(summary.warnings.is_empty(), "{:?}", summary.warnings);
}

/// A quasi-static run whose reaction is more than 1% inertia after its first step says so:
/// the Lamé cylinder at the largest ratio allowed, its ramp's breakpoints each a change of
/// rate (`docs/derivations.md`, 'The quasi-static limit'), reported on its base.
#[test]
fn a_quasi_static_run_carried_by_inertia_warns() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/lame_cylinder.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let edit = |ratio: &str| {
        text.replacen(
            "kind = \"quasi_static\"",
            &format!("kind = \"quasi_static\"\n{ratio}"),
            1,
        )
        .replacen(
            "nodes = \"bottom\"",
            "nodes = \"bottom\"\nname = \"base\"",
            1,
        )
        .replacen("[output]", "[output]\nreaction = \"base\"", 1)
    };
    let warnings = |ratio: &str, name: &str| {
        let scene = Scene::parse(&edit(ratio), Some(path.clone())).unwrap();
        let options = RunOptions::new(dir(name));
        run_scene(&scene, &options).unwrap();
        Summary::read(&options.out_dir.join("summary.json"))
            .unwrap()
            .warnings
    };
    let w = warnings("inertia_ratio = 1e-4", "lame_1e-4");
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].starts_with("inertia carries 8.6% of the reported reaction at step 2"),
        "{w:?}"
    );
    assert!(w[0].contains("analysis.inertia_ratio (now 1e-4)"), "{w:?}");
    // The default ratio: no warning.
    assert!(warnings("", "lame_default").is_empty());
}
