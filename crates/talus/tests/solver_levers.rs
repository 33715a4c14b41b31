//! The `[solver]` levers of the Newton system (`docs/scenes.md`, `docs/krylov.md`):
//! `linear_solver = "direct" | "krylov"`, `precision = "double" | "single"`,
//! `ordering = "amd" | "nested_dissection"`. Unset, they are the presets' settings bit for
//! bit; set, a Krylov solve (GMRES on a reused factorization, checked to the Newton
//! tolerance like every direction) must find the factor of safety the direct solve finds;
//! bad values are refused naming the field and value.
use crate::common;
use talus::analysis::stability::{self, StabilityRun};
use talus::run::RunOptions;
use talus::scene::{Scene, SolverSpec};
use talus_engine::StepSettings;
use talus_ssn::{Krylov, NewtonSolve, Ordering, Precision};

fn scenes() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

/// `scenes/<name>` with `[solver]` keys appended (none: as shipped).
fn scene(name: &str, solver: &str, edit: impl Fn(String) -> String) -> Result<Scene, String> {
    let path = scenes().join(name);
    let text = edit(std::fs::read_to_string(&path).unwrap());
    let text = if solver.is_empty() {
        text
    } else {
        format!("{text}\n[solver]\n{solver}\n")
    };
    Scene::parse(&text, Some(path)).map_err(|e| e.to_string())
}

fn factor_of_safety(scene: &Scene, name: &str) -> StabilityRun {
    let out = RunOptions::new(common::target_tmp_dir("solver_levers", name));
    stability::run(scene, &out).unwrap()
}

fn bracket(run: &StabilityRun) -> [f64; 2] {
    let [lo, hi] = run.factor_of_safety.bracket;
    [lo.expect("lo"), hi.expect("hi")]
}

/// The keys unset, or set to their defaults, give the presets' settings exactly (so every
/// existing scene's results stay bit-identical); `krylov` is `Krylov::DEFAULT`, `single`
/// its f32 factor.
#[test]
fn unset_levers_are_the_presets_and_set_ones_reach_the_solver() {
    assert_eq!(SolverSpec::default().fem(), StepSettings::fem());
    assert_eq!(SolverSpec::default().mpm(), StepSettings::mpm());
    let spelled = scene(
        "slope.toml",
        "linear_solver = \"direct\"\nprecision = \"double\"\nordering = \"amd\"",
        |t| t,
    )
    .unwrap();
    assert_eq!(spelled.spec.solver.fem(), StepSettings::fem());
    let krylov = scene("slope.toml", "linear_solver = \"krylov\"", |t| t).unwrap();
    let single = scene(
        "slope.toml",
        "linear_solver = \"krylov\"\nprecision = \"single\"",
        |t| t,
    )
    .unwrap();
    assert_eq!(
        krylov.spec.solver.fem().solver.newton_solve,
        NewtonSolve::Krylov(Krylov::DEFAULT)
    );
    assert_eq!(
        single.spec.solver.fem().solver.newton_solve,
        NewtonSolve::Krylov(Krylov {
            precision: Precision::Single,
            ..Krylov::DEFAULT
        })
    );
    let fresh = scene(
        "slope.toml",
        "linear_solver = \"krylov\"\nprecision = \"single\"\nreuse_factorization = false",
        |t| t,
    )
    .unwrap();
    assert_eq!(
        fresh.spec.solver.fem().solver.newton_solve,
        NewtonSolve::Krylov(Krylov {
            precision: Precision::Single,
            reuse: false,
            ..Krylov::DEFAULT
        })
    );
    // Only the Newton system changes.
    let settings = StepSettings {
        solver: talus_ssn::Settings {
            newton_solve: NewtonSolve::Direct,
            ..krylov.spec.solver.fem().solver
        },
        ..krylov.spec.solver.fem()
    };
    assert_eq!(settings, StepSettings::fem());
    assert_eq!(krylov.spec.solver.fem().solver.ordering, Ordering::Amd);
}

/// Two searches' brackets must overlap: each `lo` came to rest and each `hi` failed, and
/// the collapse factor is one (the criterion's, whatever the load path: `docs/stability.md`,
/// 'Why the path does not change the factor'), so a stable `lo` above a failing `hi`
/// would be a contradiction. Both searches must have closed their bracket to the
/// tolerance (a search stopped at its trial cap with a wide bracket would overlap anything).
fn assert_same_factor(direct: &StabilityRun, other: &StabilityRun) {
    let ([dl, dh], [ol, oh]) = (bracket(direct), bracket(other));
    println!(
        "direct [{dl}, {dh}] ({} trials), other [{ol}, {oh}] ({} trials)",
        direct.trials.len(),
        other.trials.len()
    );
    assert!(dl < oh && ol < dh, "disjoint: [{dl}, {dh}] [{ol}, {oh}]");
    for r in [direct, other] {
        let f = &r.factor_of_safety;
        assert!(f.within_tolerance && f.status == "found", "{f:?}");
    }
}

/// Griffiths & Lane's slope (`scenes/slope.toml`, ψ = 0: a non-symmetric Newton system,
/// no-pivot LU) with `krylov`: every direction is checked to the same accuracy and every
/// solve stops at the same tolerance, so the factor is the direct one's. Not the same
/// trials bit for bit: near collapse the tangent is nearly singular, the displacement
/// `D(F)` the extrapolation steers by differs beyond the stress tolerance, and the trials
/// land elsewhere (measured with the trials at 1e-10: direct [1.38477, 1.39033], Krylov
/// [1.38590, 1.39033], 8 trials each).
#[test]
fn krylov_finds_the_direct_factor_on_the_slope() {
    let off = |t: String| t.replacen("plots = true", "plots = false", 1);
    let direct = factor_of_safety(&scene("slope.toml", "", off).unwrap(), "slope_direct");
    let krylov = factor_of_safety(
        &scene("slope.toml", "linear_solver = \"krylov\"", off).unwrap(),
        "slope_krylov",
    );
    assert_same_factor(&direct, &krylov);
    // Griffiths & Lane's 1.38 within 3% (the verification case's tolerance).
    let f = krylov.factor_of_safety.value.unwrap();
    assert!((f / 1.38 - 1.0).abs() < 0.03, "{f}");
}

/// The vertical cut (`scenes/vertical_cut.toml` on 16 × 8 cells, Tresca: associative, a
/// Cholesky factor) by strength reduction with the f32 factor as GMRES's preconditioner
/// (`precision = "single"`), reused or fresh every Newton iteration
/// (`reuse_factorization = false`): the direct f64 solve's factor (measured: direct
/// [1.17259, 1.17807], single [1.17210, 1.17756]).
#[test]
fn a_single_precision_factor_finds_the_direct_bracket_on_the_cut() {
    let cut = |t: String| {
        assert!(t.contains("cells = [32, 16]"), "test setup");
        t.replacen("cells = [32, 16]", "cells = [16, 8]", 1)
            .replacen("plots = true", "plots = false", 1)
            .replacen(
                "method = \"gravity_increase\"",
                "method = \"strength_reduction\"",
                1,
            )
    };
    let direct = factor_of_safety(&scene("vertical_cut.toml", "", cut).unwrap(), "cut_direct");
    let single = factor_of_safety(
        &scene(
            "vertical_cut.toml",
            "linear_solver = \"krylov\"\nprecision = \"single\"",
            cut,
        )
        .unwrap(),
        "cut_single",
    );
    assert_same_factor(&direct, &single);
    let fresh = factor_of_safety(
        &scene(
            "vertical_cut.toml",
            "linear_solver = \"krylov\"\nprecision = \"single\"\nreuse_factorization = false",
            cut,
        )
        .unwrap(),
        "cut_fresh",
    );
    assert_same_factor(&direct, &fresh);
}

/// Bad values name the value and its line (the TOML reader's message for every key of
/// fixed values, as `stability.dilatancy`'s) and the values allowed; `single` or
/// `reuse_factorization = false` without `krylov` and, in a build
/// without METIS, `nested_dissection` are refused by `scene::check::solver` before any
/// step, saying what would make them valid.
#[test]
fn bad_levers_name_the_field_and_value() {
    let error = |solver: &str| -> String {
        match scene("slope.toml", solver, |t| t) {
            Err(e) => e,
            Ok(s) => match stability::Analysis::new(&s) {
                Err(e) => e.to_string(),
                Ok(_) => "accepted".into(),
            },
        }
    };
    // The appended key's line: after the scene, an empty line and `[solver]`.
    let shipped = std::fs::read_to_string(scenes().join("slope.toml")).unwrap();
    let at = format!("slope.toml:{}", shipped.lines().count() + 3);
    let cases: Vec<(String, Vec<&str>)> = vec![
        (
            error("linear_solver = \"cg\""),
            vec![at.as_str(), "`cg`", "krylov"],
        ),
        (
            error("precision = \"half\""),
            vec![at.as_str(), "`half`", "single"],
        ),
        (
            error("ordering = \"rcm\""),
            vec![at.as_str(), "`rcm`", "nested_dissection"],
        ),
        (
            error("precision = \"single\""),
            vec![
                "solver.precision",
                "\"single\"",
                "linear_solver = \"krylov\"",
            ],
        ),
        (
            error("reuse_factorization = false"),
            vec![
                "solver.reuse_factorization",
                "false",
                "linear_solver = \"krylov\"",
            ],
        ),
        (
            error("reuse_factorization = 0"),
            vec![at.as_str(), "`0`", "boolean"],
        ),
        (
            error("reproducible = \"yes\""),
            vec![at.as_str(), "\"yes\"", "boolean"],
        ),
    ];
    for (message, needles) in cases {
        for n in needles {
            assert!(message.contains(n), "`{n}` not in: {message}");
        }
    }
    // The slope's ψ = 0 makes a non-symmetric (LU) Newton system, which has no f32
    // factor: the run stops at its first step with talus-ssn's reason.
    let non_associative = scene(
        "slope.toml",
        "linear_solver = \"krylov\"\nprecision = \"single\"",
        |t| t,
    )
    .unwrap();
    let out = RunOptions::new(common::target_tmp_dir("solver_levers", "single_lu"));
    let message = match stability::run(&non_associative, &out) {
        Err(e) => e.to_string(),
        Ok(_) => "accepted".into(),
    };
    assert!(
        message.contains("single-precision factor needs an associative flow"),
        "{message}"
    );
    let nd = error("ordering = \"nested_dissection\"");
    if cfg!(feature = "metis") {
        assert_eq!(nd, "accepted");
    } else {
        for n in [
            "solver.ordering",
            "\"nested_dissection\"",
            "--features metis",
        ] {
            assert!(nd.contains(n), "`{n}` not in: {nd}");
        }
    }
    // MUMPS: refused in a build without MPI, naming what would make it valid; with MPI, the
    // distributed factorization reaches the solver with a direct Newton solve.
    // This test runs outside mpirun: with MPI, `mumps` is refused there, naming mpirun.
    let mumps = error("linear_solver = \"mumps\"");
    if cfg!(feature = "mpi") {
        for n in ["solver.linear_solver", "\"mumps\"", "mpirun -np N"] {
            assert!(mumps.contains(n), "`{n}` not in: {mumps}");
        }
        let s = scene("slope.toml", "linear_solver = \"mumps\"", |t| t).unwrap();
        let solver = s.spec.solver.fem().solver;
        let all = talus_ssn::LinearSolver::Distributed(talus_ssn::FactorRanks::All);
        assert_eq!(solver.linear_solver, all);
        assert_eq!(solver.newton_solve, NewtonSolve::Direct);
        // `reproducible`: MUMPS on rank 0 alone.
        let s = scene(
            "slope.toml",
            "linear_solver = \"mumps\"\nreproducible = true",
            |t| t,
        )
        .unwrap();
        let host = talus_ssn::LinearSolver::Distributed(talus_ssn::FactorRanks::Host);
        assert_eq!(s.spec.solver.fem().solver.linear_solver, host);
    } else {
        for n in ["solver.linear_solver", "\"mumps\"", "--features mpi"] {
            assert!(mumps.contains(n), "`{n}` not in: {mumps}");
        }
    }
}
