//! Simulation output: ParaView files (`.vtu` per step, `.pvd` collection) and PNG plots
//! for reports (force–displacement, Newton convergence, a field on the mesh).
//! Material points (MPM) have their own VTU (one vertex per particle) and PNG map.
//!
//! ```ignore
//! talus::output::write_vtu(Path::new("out/step_0010.vtu"), &snapshot)?;
//! ```
//! Inputs are plain slices (no dependency on the FEM crate); every writer checks lengths
//! and finiteness first and returns `OutputError::Invalid` naming the field, so no NaN
//! reaches a file.
mod atomic;
mod canvas;
mod colormap;
mod error;
mod map_frame;
mod mesh;
mod particles_vtu;
mod plateau;
mod plot_curves;
mod plot_field;
mod plot_particles;
mod pvd;
mod pvtu;
mod results;
mod spacing;
mod stage_summary;
mod summary;
mod vtu;

pub(crate) use atomic::write as write_atomically;
pub(crate) use canvas::significant;
pub use error::OutputError;
pub use map_frame::ColourScale;
pub use mesh::MeshView;
pub use particles_vtu::{
    write_particle_vtu, write_particle_vtu_piece, write_particle_vtu_with, ParticleExtras,
    ParticleSnapshot,
};
pub use plateau::{plateau, Plateau, PlateauCriterion};
pub use plot_curves::{
    force_axis_label, plot_force_displacement, plot_force_displacement_with_unit,
    plot_newton_residuals,
};
pub use plot_field::{plot_field_map, plot_field_on_mesh, FieldMap};
pub use plot_particles::{plot_particles, ParticlePlot};
pub use pvd::write_pvd;
pub use pvtu::{piece_range, write_pvtu};
pub use results::{BadColumn, Results, ResultsProgress};
pub use stage_summary::StageSummary;
pub use summary::{
    BoundaryReaction, CollapseTime, FactorOfSafety, Limit, MonitorValues, ReportedReaction,
    RunStatus, Summary,
};
pub use vtu::{
    pressure, principal_stresses, von_mises, write_vtu, write_vtu_piece, write_vtu_with,
    FieldExtras, FieldSnapshot,
};
