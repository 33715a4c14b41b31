//! Scene files: TOML holding only what a simulation needs (mesh, material, boundary
//! conditions and loads, time stepping, solver settings, outputs). Unknown keys are
//! rejected; every error names the field and, when it is in the file, the line.
mod error;
mod load;
mod types;

pub use error::SceneError;
pub use load::{builtin_footing, Scene};
pub use types::*;
