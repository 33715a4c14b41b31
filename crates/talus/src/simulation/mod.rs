//! Implicit time stepping of eqs. 15–16: one engine ([`Stepper`]) over a
//! [`Discretization`]; the finite-element [`Model`] is one, the material point method
//! another (`crate::mpm_run`).
pub mod engine;
mod fem_step;
mod initial_stress;
mod model;
mod monitors;
mod quasi_static;
mod reaction_groups;
mod state;

pub use engine::{
    Discretization, Predictor, PredictorRule, StepError, StepReport, StepSettings, Stepper,
};
pub use fem_step::FemStats;
pub use initial_stress::{
    initial_stress, initial_stress_at, k0_bounds, k0_bounds_without_cohesion, k0_stress_at,
    mandel_from_components, uniform_stress,
};
pub use model::{Loads, Model, RampedForce};
pub use monitors::NodeMonitors;
pub use quasi_static::{quasi_static_masses, DEFAULT_INERTIA_RATIO};
pub use reaction_groups::{prescribed_forces, prescribed_forces_at_rest, ReactionGroups};
pub use state::State;

/// What one FEM step did.
pub type StepRecord = StepReport<FemStats>;
/// Why a FEM step failed.
pub type FemStepError = StepError<std::convert::Infallible>;
