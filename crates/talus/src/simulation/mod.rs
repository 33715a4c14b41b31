//! Implicit time stepping of eqs. 15–16 on a finite-element model: each step is one
//! reduced problem `z = Wσ + q` solved by `talus-ssn`, warm-started from the last step.
mod initial_stress;
mod model;
mod monitors;
mod reaction_groups;
mod state;
mod stepper;

pub use initial_stress::{k0_bounds, k0_bounds_without_cohesion, k0_stress, k0_stress_at};
pub use model::{Loads, Model, RampedForce};
pub use monitors::NodeMonitors;
pub use reaction_groups::{prescribed_forces, prescribed_forces_at_rest, ReactionGroups};
pub use state::State;
pub use stepper::{Predictor, StepError, StepRecord, Stepper};
