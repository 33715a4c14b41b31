//! The finite-element model of a scene (`[mesh]`): talus-fem's [`Model`] built from the
//! scene, its initial state, the quasi-static masses, and the named boundaries and
//! monitors a run reports.
mod build;
mod materials;
mod monitors;
mod quasi_static;
mod reaction_groups;
pub mod stages;

pub use build::{warnings, water_table, weight, FromScene};
pub use monitors::NodeMonitors;
pub use quasi_static::{quasi_static_masses, DEFAULT_INERTIA_RATIO};
pub use reaction_groups::ReactionGroups;
pub use talus_fem::{
    prescribed_forces, prescribed_forces_at_rest, FemStats, Loads, Model, RampedForce,
    ReactionForce, State,
};

/// What one FEM step did.
pub type StepRecord = talus_engine::StepReport<FemStats>;
/// Why a FEM step failed.
pub type FemStepError = talus_engine::StepError<std::convert::Infallible>;
