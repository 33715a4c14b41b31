//! The stepping engine's settings, with one preset per method ([`StepSettings::fem`],
//! [`StepSettings::mpm`]) over talus-ssn's ([`Settings::fem`], [`Settings::mpm`]): the one
//! place of the defaults, which a scene's `[solver]` section overrides.
use talus_ssn::Settings;

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

/// MPM steps remember a halving for this many steps (`StepSettings::halving_memory`):
/// the a = 2 column's failed attempts at the full step would most likely fail again
/// (`docs/mpm-performance.md`).
pub const MPM_HALVING_MEMORY: usize = 4;

impl StepSettings {
    /// A finite-element model: talus-ssn's [`Settings::fem`], 4 halvings, every step from
    /// the full `h`, predicted from the last stress rate.
    pub const fn fem() -> Self {
        Self {
            solver: Settings::fem(),
            max_halvings: 4,
            halving_memory: 0,
            predictor: PredictorRule::Extrapolated,
            reuse_analysis: true,
        }
    }

    /// The material point method: talus-ssn's [`Settings::mpm`], 4 halvings remembered for
    /// [`MPM_HALVING_MEMORY`] steps, each solve from the particles' last stresses.
    pub const fn mpm() -> Self {
        Self {
            solver: Settings::mpm(),
            halving_memory: MPM_HALVING_MEMORY,
            predictor: PredictorRule::Previous,
            ..Self::fem()
        }
    }

    /// [`StepSettings::fem`] with these Newton settings and halvings.
    pub fn with_solver(solver: Settings, max_halvings: usize) -> Self {
        Self {
            solver,
            max_halvings,
            ..Self::fem()
        }
    }
}

impl Default for StepSettings {
    /// [`StepSettings::fem`].
    fn default() -> Self {
        Self::fem()
    }
}
