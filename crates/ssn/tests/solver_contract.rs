//! What callers rely on: bad input is rejected naming the field, and a solve that does not
//! converge is an `Err` carrying its report, never a result that looks fine.
use std::path::PathBuf;

use talus_ssn::faer::Mat;
use talus_ssn::siconos::SiconosProblem;
use talus_ssn::{
    reduced_system_from_siconos, Operator, ReducedSystem, Rho, Settings, SolveError, Solver, Stall,
    Status,
};

fn footing_100() -> ReducedSystem<3> {
    let path = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../data/siconos-plasticity/plasticity_2d_footing_100.dat"
    ));
    reduced_system_from_siconos::<3>(&SiconosProblem::from_path(&path).unwrap()).unwrap()
}

fn with_stall(after: usize, window: usize, decrease: f64) -> Settings {
    Settings {
        stall: Some(Stall {
            after,
            window,
            decrease,
        }),
        ..Settings::default()
    }
}

fn field_of(e: SolveError) -> &'static str {
    match e {
        SolveError::InvalidInput { field, .. } => field,
        other => panic!("expected InvalidInput, got {other}"),
    }
}

#[test]
fn non_convergence_is_an_error_with_its_report() {
    let mut solver = Solver::new(
        footing_100(),
        Settings {
            max_iterations: 2,
            ..Settings::default()
        },
    )
    .unwrap();
    let mut sigma = vec![0.0; 300];
    match solver.solve(&mut sigma) {
        Err(SolveError::NotConverged(report)) => {
            assert_eq!(report.status, Status::MaxIterations);
            assert_eq!(report.iterations, 2);
            assert!(report.residual > 1e-12);
            assert!(!report.is_converged());
        }
        other => panic!("expected NotConverged, got {other:?}"),
    }
}

#[test]
fn a_stalled_solve_ends_early_with_its_own_status() {
    // No Newton step of footing_100 lowers the merit by a factor 1e12: a window of one
    // iteration with that decrease stalls after the first step, while the same rule from
    // iteration 100 on, or a window longer than the solve, lets it converge (`Stall`,
    // docs/solver.md).
    let solve = |settings: Settings| {
        let mut sigma = vec![0.0; 300];
        Solver::new(footing_100(), settings)
            .unwrap()
            .solve(&mut sigma)
    };
    match solve(with_stall(0, 1, 1e-12)) {
        Err(SolveError::NotConverged(report)) => {
            assert_eq!(report.status, Status::Stalled);
            assert_eq!(report.iterations, 1);
            let h = &report.merit_history;
            assert!(h[1] >= 1e-12 * h[0], "{h:?}");
        }
        other => panic!("expected a stalled solve, got {other:?}"),
    }
    for (after, window, decrease) in [(100, 1, 1e-12), (0, 100, 0.5)] {
        let report = solve(with_stall(after, window, decrease)).unwrap();
        assert_eq!(report.status, Status::Converged);
    }
}

#[test]
fn stall_settings_are_validated() {
    for (window, decrease) in [(0, 0.5), (5, 1.0), (5, f64::NAN)] {
        let e = Solver::new(footing_100(), with_stall(0, window, decrease))
            .err()
            .expect("rejected");
        assert_eq!(field_of(e), "settings.stall");
    }
}

#[test]
fn warm_start_from_the_solution_takes_no_step() {
    let mut solver = Solver::new(footing_100(), Settings::default()).unwrap();
    let mut sigma = vec![0.0; 300];
    let cold = solver.solve(&mut sigma).unwrap();
    assert!(cold.iterations > 3);
    let warm = solver.solve(&mut sigma).unwrap();
    assert_eq!(warm.iterations, 0);
    // Without warm start the given σ is ignored.
    let mut solver = Solver::new(
        footing_100(),
        Settings {
            warm_start: false,
            ..Settings::default()
        },
    )
    .unwrap();
    let again = solver.solve(&mut sigma).unwrap();
    assert_eq!(again.iterations, cold.iterations);
}

#[test]
fn bad_input_names_the_field() {
    let bad = |s: Settings| field_of(Solver::new(footing_100(), s).err().expect("rejected"));
    assert_eq!(
        bad(Settings {
            tolerance: 0.0,
            ..Settings::default()
        }),
        "settings.tolerance"
    );
    assert_eq!(
        bad(Settings {
            tolerance: f64::NAN,
            ..Settings::default()
        }),
        "settings.tolerance"
    );
    assert_eq!(
        bad(Settings {
            max_iterations: 0,
            ..Settings::default()
        }),
        "settings.max_iterations"
    );
    assert_eq!(
        bad(Settings {
            rho: Rho::Fixed(-1.0),
            ..Settings::default()
        }),
        "settings.rho"
    );
    assert_eq!(
        bad(Settings {
            rho: Rho::PerPointDiagonal {
                factor: f64::INFINITY
            },
            ..Settings::default()
        }),
        "settings.rho"
    );

    let system = footing_100();
    let rules = system.rules().to_vec();
    let mut q = system.q().to_vec();
    q[7] = f64::NAN;
    assert_eq!(
        field_of(ReducedSystem::try_new(system.operator().clone(), q, rules.clone()).unwrap_err()),
        "q"
    );
    assert_eq!(
        field_of(
            ReducedSystem::try_new(system.operator().clone(), vec![0.0; 299], rules.clone())
                .unwrap_err()
        ),
        "q"
    );
    assert_eq!(
        field_of(
            ReducedSystem::try_new(
                system.operator().clone(),
                vec![0.0; 300],
                rules[..99].to_vec()
            )
            .unwrap_err()
        ),
        "rules"
    );
    let mut w = Mat::<f64>::identity(300, 300);
    w[(3, 4)] = f64::INFINITY;
    assert_eq!(
        field_of(
            ReducedSystem::try_new(Operator::Dense(w), vec![0.0; 300], rules.clone()).unwrap_err()
        ),
        "W"
    );
    // A zero diagonal block leaves ρ undefined.
    let w = Mat::<f64>::zeros(300, 300);
    let system = ReducedSystem::try_new(Operator::Dense(w), vec![0.0; 300], rules).unwrap();
    assert_eq!(
        field_of(Solver::new(system, Settings::default()).err().unwrap()),
        "W"
    );

    let mut solver = Solver::new(footing_100(), Settings::default()).unwrap();
    assert_eq!(field_of(solver.solve(&mut [0.0; 12]).unwrap_err()), "sigma");
    let mut sigma = vec![0.0; 300];
    sigma[0] = f64::NAN;
    assert_eq!(field_of(solver.solve(&mut sigma).unwrap_err()), "sigma");
}
