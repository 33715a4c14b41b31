//! Implicit time stepping of eqs. 15–16 on a finite-element model: each step is one
//! reduced problem `z = Wσ + q` solved by `talus-ssn`, warm-started from the last step.
mod initial_stress;
mod model;
mod quasi_static;
mod state;
mod stepper;

pub use initial_stress::{
    initial_stress, initial_stress_at, k0_bounds, k0_bounds_without_cohesion, k0_stress_at,
    mandel_from_components, uniform_stress,
};
pub use model::{Loads, Model, RampedForce};
pub use quasi_static::{quasi_static_masses, DEFAULT_INERTIA_RATIO};
pub use state::State;
pub use stepper::{Predictor, StepError, StepRecord, Stepper};
