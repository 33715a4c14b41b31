//! Talus: implicit elasto-plasticity of geomaterials by the semi-smooth Newton method on
//! the bi-potential formulation (Guillet, Acary, Bourrier & Goury 2024). This crate is the
//! application over the lower layers (talus-cone, talus-bipotential, talus-ssn,
//! talus-engine, talus-fem, talus-mpm), its folders in the order the data travels:
//!
//! - [`scene`]: scene files read and checked, every error naming its field and line; the
//!   one place where `[solver]` becomes the engine's settings (`SolverSpec::step_settings`);
//! - [`model`]: a method's model from a scene, finite elements ([`model::fem`]) or material
//!   points ([`model::mpm`]), with its initial stress and its size in memory;
//! - [`run`]: a scene stepped to its end by the engine, with `history.csv`, checkpoints and
//!   resume, one run loop for both methods;
//! - [`output`]: VTU, `summary.json` and PNG pictures;
//! - [`analysis`]: studies built on runs: factors of safety and the verification cases;
//! - [`ranks`]: the MPI ranks of a distributed run (cargo feature `mpi`).
//!
//! ```no_run
//! use talus::run::{fem::run_scene, RunOptions};
//! let scene = talus::scene::builtin_footing();
//! let summary = run_scene(&scene, &RunOptions::new("out"))?;
//! println!("{} steps in {:.1} s", summary.records.len(), summary.seconds);
//! # Ok::<(), talus::run::RunError>(())
//! ```
pub mod analysis;
pub mod model;
pub mod output;
pub mod ranks;
pub mod run;
pub mod scene;
