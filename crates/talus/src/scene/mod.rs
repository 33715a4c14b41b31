//! Scene files: TOML holding only what a simulation needs (mesh or grid, material, boundary
//! conditions and loads, time stepping, solver settings, outputs). Unknown keys are
//! rejected; every error names the field and, when it is in the file, the line.
//! [`SceneFile`] tells the kinds apart: `[mesh]` is a finite-element [`Scene`], `[grid]`
//! a material-point [`MpmScene`].
pub mod check;
pub mod dimension;
mod error;
mod file;
mod load;
mod material;
mod monitor;
mod mpm_load;
mod mpm_types;
pub mod scales;
mod solver;
mod source;
mod stability;
pub mod stage;
mod types;
mod water;

pub use error::SceneError;
pub use file::SceneFile;
pub use load::{
    builtin_footing, builtin_footing_with_cells, paper_grading, Scene, Scene3, SceneOf,
    BUILTIN_FOOTING,
};
pub use material::{Flow, MaterialModel, MaterialSpec, Materials, RegionSpec};
pub use monitor::{
    bad_name, first_duplicate, monitor_columns, MonitorSpec, MONITOR_COLUMNS, MONITOR_COLUMNS_3D,
    REACTION_COLUMNS,
};
pub use mpm_load::{check_dimension as check_mpm_dimension, MpmScene, MpmScene3};
pub use mpm_types::*;
pub use solver::{FactorPrecision, FillOrdering, LinearSolverKind, RhoScaling, SolverSpec};
pub use source::{Locate, SceneDocument};
pub use stability::{DilatancyRule, StabilityMethod, StabilitySpec};
pub use stage::StageSpec;
pub use talus_engine::{Ramp, RampError};
pub use types::*;
pub use water::{WaterSpec, WaterTable, WATER_UNIT_WEIGHT};
