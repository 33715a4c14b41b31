//! The stepping engine's settings, and the one place where a scene's `[solver]` section
//! becomes them (FEM and MPM alike; the defaults are `SolverSpec::default()`).
use talus_ssn::{Rho, Settings, Stall};

use crate::scene::{RhoScaling, SolverSpec};

/// Where each sub-step's Newton iteration starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PredictorRule {
    /// σₙ + h σ̇ with the last sub-step's stress rate under smooth loading; the elastic
    /// predictor out of rest or after a jump in the loading rate; σₙ if that fails (FEM).
    Extrapolated,
    /// The elastic predictor on every sub-step, σₙ if it fails.
    Elastic,
    /// σₙ (MPM's default: the particles' stresses of the last step).
    Previous,
}

/// How the engine steps: the Newton settings, and what it does when a solve fails.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepSettings {
    pub solver: Settings,
    /// A sub-step whose solve fails is redone as two halves, at most this many times nested.
    pub max_halvings: usize,
    /// Step-size memory: a step that had to be halved starts the next one at the sub-step
    /// size that converged, and after this many steps at that size without a halving tries
    /// twice the size again. 0: every step starts at the full h.
    pub halving_memory: usize,
    pub predictor: PredictorRule,
    /// Later solves of a sub-step (MPM friction passes) keep the first one's Schur analysis
    /// when the pattern is the same (the result is the same bit for bit either way).
    pub reuse_analysis: bool,
}

/// `[solver] stall_window` when the scene does not set it. FEM: the attempts that fail at
/// the footing's mechanism onset stall for 20–40 iterations before `max_iterations`;
/// stopping them (from iteration 25, after 10 iterations without a halving of the merit)
/// cuts the Newton iterations of the 104×48 footing's hardest steps. MPM: the slow but
/// steady first friction passes are better left to run (the a = 2 column: 92.2 → 102.4
/// iterations per step with 10). `docs/solver.md`, "Non-associative Newton at the
/// mechanism's onset".
pub const FEM_STALL_WINDOW: usize = 10;
pub const MPM_STALL_WINDOW: usize = 0;
/// The stall rule applies from this iteration on: slow solves that converge within it (up
/// to 23 iterations on the footing snapshots) keep their step, and so their results.
pub const STALL_AFTER: usize = 25;
/// MPM steps remember a halving for this many steps (`StepSettings::halving_memory`):
/// the a = 2 column's failed attempts at the full step would most likely fail again
/// (`docs/mpm-performance.md`).
pub const MPM_HALVING_MEMORY: usize = 4;

/// The discretization a `[solver]` section drives: its defaults differ where measured.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    Fem,
    Mpm,
}

impl StepSettings {
    /// The settings of a scene's `[solver]` section for `method`.
    pub fn from_spec(s: &SolverSpec, method: Method) -> Self {
        let (stall_window, halving_memory, predictor) = match method {
            Method::Fem => (FEM_STALL_WINDOW, 0, PredictorRule::Extrapolated),
            Method::Mpm => (
                MPM_STALL_WINDOW,
                MPM_HALVING_MEMORY,
                PredictorRule::Previous,
            ),
        };
        Self {
            solver: ssn_settings(s, stall_window),
            max_halvings: s.max_step_halvings,
            halving_memory,
            predictor,
            reuse_analysis: true,
        }
    }
}

/// The talus-ssn settings of a `[solver]` section, with `default_stall_window` when the
/// scene sets none.
pub fn ssn_settings(s: &SolverSpec, default_stall_window: usize) -> Settings {
    let stall_window = s.stall_window.unwrap_or(default_stall_window);
    Settings {
        tolerance: s.tolerance,
        max_iterations: s.max_iterations,
        rho: match s.rho_scaling {
            RhoScaling::Compliance => Rho::PerPointCompliance {
                factor: s.rho_factor,
            },
            RhoScaling::Diagonal => Rho::PerPointDiagonal {
                factor: s.rho_factor,
            },
        },
        line_search: if s.line_search {
            Settings::default().line_search
        } else {
            None
        },
        stall: (stall_window > 0).then_some(Stall {
            after: STALL_AFTER,
            window: stall_window,
            decrease: 0.5,
        }),
        ..Settings::default()
    }
}

impl StepSettings {
    /// A FEM scene's stepping with these Newton settings and halvings.
    pub fn with_solver(solver: Settings, max_halvings: usize) -> Self {
        Self {
            solver,
            max_halvings,
            ..Self::default()
        }
    }
}

impl Default for StepSettings {
    /// A FEM scene's defaults (`SolverSpec::default()`).
    fn default() -> Self {
        Self::from_spec(&SolverSpec::default(), Method::Fem)
    }
}
