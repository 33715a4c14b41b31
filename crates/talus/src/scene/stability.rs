//! `[stability]`: a factor of safety instead of a run to the end (`docs/stability.md`).
use serde::{Deserialize, Serialize};

/// What a trial factor `F` changes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StabilityMethod {
    /// `c/F`, `tan φ/F` (and the dilatancy by [`DilatancyRule`]).
    StrengthReduction,
    /// Gravity times `F`.
    GravityIncrease,
}

impl StabilityMethod {
    pub fn name(&self) -> &'static str {
        match self {
            Self::StrengthReduction => "strength_reduction",
            Self::GravityIncrease => "gravity_increase",
        }
    }
}

/// How strength reduction treats the dilatancy angle ψ (`docs/stability.md`, 'Dilatancy').
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum DilatancyRule {
    /// `tan ψ_F = tan ψ / F`.
    Scaled,
    /// `ψ_F = min(ψ, φ_F)`.
    Fixed,
    /// Davis (1968) reduced strength with associated flow, β from the reduced angles.
    Davis,
}

impl DilatancyRule {
    pub fn name(&self) -> &'static str {
        match self {
            Self::Scaled => "scaled",
            Self::Fixed => "fixed",
            Self::Davis => "davis",
        }
    }
}

/// `[stability]` as written; checked by `talus::analysis::stability::StabilitySettings`.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct StabilitySpec {
    pub method: StabilityMethod,
    /// Relative width of the final bracket, `(hi − lo)/lo`; default 0.005.
    #[serde(default)]
    pub tolerance: Option<f64>,
    /// Strength reduction only; default `scaled`.
    #[serde(default)]
    pub dilatancy: Option<DilatancyRule>,
    /// A first bracket `[lo, hi]`, each end checked by a trial; default: from `first_guess`.
    #[serde(default)]
    pub bracket: Option<[f64; 2]>,
    /// The first trial factor when no bracket is given; default 1.
    #[serde(default)]
    pub first_guess: Option<f64>,
    /// The name of a `[[monitor]]` whose node the criterion watches; default: the whole body.
    #[serde(default)]
    pub monitor: Option<String>,
    /// Most trials; default 40.
    #[serde(default)]
    pub max_trials: Option<usize>,
    /// Steps of `time.step` each trial runs at most; default 12.
    #[serde(default)]
    pub trial_steps: Option<usize>,
    /// The Newton tolerance of the trials' steps (the loading keeps `[solver] tolerance`);
    /// default 1e-10, or `[solver] tolerance` when that is looser.
    #[serde(default)]
    pub newton_tolerance: Option<f64>,
}
