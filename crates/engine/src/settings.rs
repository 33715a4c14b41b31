//! The stepping engine's settings, with one preset per method ([`StepSettings::fem`],
//! [`StepSettings::mpm`]) over talus-ssn's ([`Settings::fem`], [`Settings::mpm`]): the one
//! place of the defaults, which a scene's `[solver]` section overrides.
use talus_ssn::Settings;

use crate::Growth;

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
    /// The elastic predictor when the sub-step's problem is associative
    /// (`ReducedSystem::is_associative`), σₙ otherwise.
    ElasticIfAssociative,
}

/// How the engine steps: the Newton settings, and what it does when a solve fails.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepSettings {
    pub solver: Settings,
    /// A sub-step whose solve fails is retried at half its size; the smallest sub-step is
    /// `h / 2^max_halvings`.
    pub max_halvings: usize,
    /// When the step control doubles a halved sub-step again ([`Growth`]).
    pub growth: Growth,
    pub predictor: PredictorRule,
    /// Later solves of a sub-step (MPM friction passes) keep the first one's Schur analysis
    /// when the pattern is the same (the result is the same bit for bit either way).
    pub reuse_analysis: bool,
}

impl StepSettings {
    /// A finite-element model: talus-ssn's [`Settings::fem`], 8 halvings, a halved
    /// sub-step doubled again after 2 sub-steps of at most 12 iterations
    /// (`docs/solver.md`, 'The step control'), predicted from the last stress rate.
    pub const fn fem() -> Self {
        Self {
            solver: Settings::fem(),
            max_halvings: 8,
            growth: Growth {
                after: 2,
                cheap_iterations: 12,
            },
            predictor: PredictorRule::Extrapolated,
            reuse_analysis: true,
        }
    }

    /// The material point method: talus-ssn's [`Settings::mpm`], a halved sub-step doubled
    /// again after 16 sub-steps whatever their cost, about the 4 steps at h/4 of the
    /// halving memory it replaces (the matched a = 2 column: growth after 4 sub-steps took
    /// 2.6 sub-steps per step and moved the runout from 3.26 to 3.11, against 3.49 at
    /// h = 1e-3 s, `docs/mpm-performance.md`), each solve from the particles' last
    /// stresses.
    pub const fn mpm() -> Self {
        Self {
            solver: Settings::mpm(),
            growth: Growth {
                after: 16,
                cheap_iterations: usize::MAX,
            },
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
