//! A scene's `[solver]` section, and the one place where it becomes the engine's settings:
//! its defaults are the presets of talus-engine and talus-ssn (`StepSettings::fem`,
//! `Settings::fem`), which the scene overrides key by key.
use serde::{Deserialize, Serialize};
use talus_engine::StepSettings;
use talus_ssn::{
    FactorRanks, Krylov, LinearSolver, NewtonSolve, Ordering, Precision, Rho, Settings, Stall,
};

#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct SolverSpec {
    pub tolerance: f64,
    pub max_iterations: usize,
    /// ρ_i = rho_factor / max diag S_i (`compliance`, the return-mapping scale) or
    /// rho_factor / max diag W_i (`diagonal`).
    pub rho_factor: f64,
    pub rho_scaling: RhoScaling,
    /// Halvings of h allowed when a step does not converge.
    pub max_step_halvings: usize,
    /// Armijo backtracking on ‖F‖² (true) or full Newton steps.
    pub line_search: bool,
    /// A solve whose merit has not halved over this many iterations is stopped as stalled
    /// and its step halved (from iteration 25); 0: never. Default: 10 for FEM, 0 for MPM
    /// (`Settings::fem`, `Settings::mpm`, `docs/solver.md`).
    pub stall_window: Option<usize>,
    /// How each Newton direction is solved: `direct`, a factorization per Newton iteration
    /// (the default), `krylov`, GMRES preconditioned by an earlier factorization
    /// (`Krylov::DEFAULT`, `docs/krylov.md`), or `mumps`, MUMPS' factorization over the MPI
    /// ranks (a build with the cargo feature `mpi`; under `mpirun` with more than one rank
    /// every scene uses it, `docs/distributed.md`).
    pub linear_solver: LinearSolverKind,
    /// The factorization's storage precision: `double`, or `single` (f32, only with
    /// `krylov`: the factor is then GMRES's preconditioner, `docs/krylov.md`).
    pub precision: FactorPrecision,
    /// With `krylov`: try GMRES on an earlier Newton iteration's factor first (true, the
    /// default), or factorize every Newton iteration (false: with `single`, GMRES then
    /// only corrects the f32 factor's rounding; `Krylov::reuse`, `docs/krylov.md`).
    pub reuse_factorization: bool,
    /// The fill-reducing ordering of the factorizations: `amd` (the default) or
    /// `nested_dissection` (METIS; a build with the cargo feature `metis`).
    pub ordering: FillOrdering,
    /// Under `mpirun`: MUMPS factorizes on rank 0 alone (true), so that the same number of
    /// ranks gives the same bits on every run, or over all ranks (false, the default),
    /// splitting the factors' memory and flops. One process repeats its bits either way
    /// (`docs/distributed.md`, 'Reproducibility').
    pub reproducible: bool,
}

/// `[solver] linear_solver`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LinearSolverKind {
    #[default]
    Direct,
    Krylov,
    Mumps,
}

/// `[solver] precision`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FactorPrecision {
    #[default]
    Double,
    Single,
}

/// `[solver] ordering`. `nested_dissection` is read in every build and refused by
/// `scene::check::solver` in one without the feature `metis`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FillOrdering {
    #[default]
    Amd,
    NestedDissection,
}

impl FillOrdering {
    /// talus-ssn's ordering; `None` for nested dissection in a build without METIS.
    pub fn ordering(self) -> Option<Ordering> {
        match self {
            FillOrdering::Amd => Some(Ordering::Amd),
            #[cfg(feature = "metis")]
            FillOrdering::NestedDissection => Some(Ordering::NestedDissection),
            #[cfg(not(feature = "metis"))]
            FillOrdering::NestedDissection => None,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RhoScaling {
    Compliance,
    Diagonal,
}

impl Default for SolverSpec {
    /// The FEM preset's values (`StepSettings::fem`); `stall_window` is the method's.
    fn default() -> Self {
        let step = StepSettings::fem();
        let rho_scaling = match step.solver.rho {
            Rho::PerPointDiagonal { .. } => RhoScaling::Diagonal,
            // The presets scale ρ per point; the other variants have no key of their own.
            _ => RhoScaling::Compliance,
        };
        Self {
            tolerance: step.solver.tolerance,
            max_iterations: step.solver.max_iterations,
            rho_factor: step.solver.rho.factor(),
            rho_scaling,
            max_step_halvings: step.max_halvings,
            line_search: step.solver.line_search.is_some(),
            stall_window: None,
            linear_solver: LinearSolverKind::Direct,
            precision: FactorPrecision::Double,
            reuse_factorization: true,
            ordering: FillOrdering::Amd,
            reproducible: false,
        }
    }
}

impl SolverSpec {
    /// The method's preset `base` (`StepSettings::fem()` or `::mpm()`) with this section's
    /// keys (checked by `scene::check::solver`: a nested dissection this build cannot do
    /// keeps the preset's ordering here).
    pub fn step_settings(&self, base: StepSettings) -> StepSettings {
        let distributed =
            self.linear_solver == LinearSolverKind::Mumps || crate::ranks::ranks().distributed();
        // `stall_window = 0` turns off both early ends of a failing solve.
        let fold = match self.stall_window {
            Some(0) => None,
            _ => base.solver.fold,
        };
        let stall = match self.stall_window {
            None => base.solver.stall,
            Some(0) => None,
            Some(window) => Some(Stall {
                window,
                ..base.solver.stall.unwrap_or(Stall::DEFAULT)
            }),
        };
        StepSettings {
            solver: Settings {
                tolerance: self.tolerance,
                max_iterations: self.max_iterations,
                rho: match self.rho_scaling {
                    RhoScaling::Compliance => Rho::PerPointCompliance {
                        factor: self.rho_factor,
                    },
                    RhoScaling::Diagonal => Rho::PerPointDiagonal {
                        factor: self.rho_factor,
                    },
                },
                line_search: if self.line_search {
                    base.solver.line_search.or(Some(Default::default()))
                } else {
                    None
                },
                stall,
                fold,
                ordering: self.ordering.ordering().unwrap_or(base.solver.ordering),
                // Under mpirun every rank must call MUMPS for every factorization: the
                // direct solve, whatever the scene asked (docs/distributed.md).
                linear_solver: if distributed {
                    LinearSolver::Distributed(if self.reproducible {
                        FactorRanks::Host
                    } else {
                        FactorRanks::All
                    })
                } else {
                    base.solver.linear_solver
                },
                newton_solve: match self.linear_solver {
                    _ if distributed => NewtonSolve::Direct,
                    LinearSolverKind::Direct | LinearSolverKind::Mumps => base.solver.newton_solve,
                    LinearSolverKind::Krylov => NewtonSolve::Krylov(Krylov {
                        precision: match self.precision {
                            FactorPrecision::Double => Precision::Double,
                            FactorPrecision::Single => Precision::Single,
                        },
                        reuse: self.reuse_factorization,
                        ..Krylov::DEFAULT
                    }),
                },
                ..base.solver
            },
            max_halvings: self.max_step_halvings,
            ..base
        }
    }

    /// A FEM scene's settings.
    pub fn fem(&self) -> StepSettings {
        self.step_settings(StepSettings::fem())
    }

    /// An MPM scene's settings (before `[mpm] predictor`).
    pub fn mpm(&self) -> StepSettings {
        self.step_settings(StepSettings::mpm())
    }
}
