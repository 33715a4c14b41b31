//! Plane-strain and axisymmetric finite elements for Talus (plane strain: thickness 1 m;
//! axisymmetric: per radian, [`Geometry`]; SI units, tension positive):
//! P1 / P2 triangle meshes (structured or Gmsh), Dirichlet dof maps, and the operators of
//! Guillet et al. (2024), eq. 11–16: the volume-weighted strain operator `B` (Mandel rows),
//! the lumped mass `M`, the compliance blocks `S` and the nodal loads `f`.
//!
//! ```
//! use talus_fem::{Assembly, Constraint, DofMap, ElementOrder, Mesh};
//! let mesh = Mesh::rectangle(&[0.0, 1.0, 2.0], &[0.0, 1.0], ElementOrder::P2)?;
//! let dofs = DofMap::new(mesh.nodes.len(), &[(mesh.node_sets["bottom"].clone(), Constraint::Fixed)])?;
//! let asm = Assembly::new(&mesh, &dofs, 2000.0)?;
//! assert_eq!(asm.b_free.nrows(), 4 * asm.n_points());
//! # Ok::<(), talus_fem::FemError>(())
//! ```
pub mod assembly;
mod dimension;
pub mod dofs;
pub mod element;
mod error;
mod excavation;
pub mod geometry;
pub mod mesh;
pub mod mesh3;
mod model;
pub mod quadrature;
mod quasi_static;
mod reduced_problem;
mod state;

pub use assembly::Assembly;
pub use dimension::{Dimension, ElementMesh, Mandel, StressPoint};
pub use dofs::{Constraint, Dof, DofMap};
pub use element::ElementOrder;
pub use error::{FemError, MeshError};
pub use excavation::{
    element_forces, kept_points, restrict_forces, restrict_state, transfer_state, Part,
};
pub use geometry::Geometry;
pub use mesh::{graded_coordinates, BoundaryEdge, Mesh};
pub use mesh3::{BoundaryFace, TetrahedralMesh};
pub use model::{bounding_box, Loads, Model, RampedForce};
pub use reduced_problem::{prescribed_forces, prescribed_forces_at_rest, FemStats, ReactionForce};
pub use state::State;

// The README's example, compiled and run as a doctest (`cargo test --doc`).
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
