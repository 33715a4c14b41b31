//! Euclidean projection onto second-order cones and von Mises cylinders, with one element
//! of the Clarke Jacobian of each projection (paper eqs. 23–24).
//!
//! Every set lives in `R^D` (3 for the Siconos problems, 4 for plane strain and 6 for 3D in
//! Mandel notation) and is described by a unit axis `n`:
//! - [`SecondOrderCone`]: `apex + {x : ‖x_t‖ ≤ η x_n}`, with `x_n = x·n`, `x_t = x − x_n n`;
//! - [`VonMisesCylinder`]: `{x : ‖x_t‖ ≤ R}` (no apex: the Drucker-Prager cone at φ = 0).
//!
//! ```
//! use talus_cone::{Projector, Region, SecondOrderCone};
//! use nalgebra::vector;
//! let cone = SecondOrderCone::try_new(vector![1.0, 0.0, 0.0], vector![0.0, 0.0, 0.0], 0.5)?;
//! let p = cone.project(&vector![0.0, 2.0, 0.0]);
//! assert_eq!(p.region, Region::Boundary);
//! assert!(cone.contains(&p.point, 1e-12));
//! # Ok::<(), talus_cone::ConeError>(())
//! ```
//! Projections of many points go through [`project_batch`], whose results are bitwise the
//! same for any thread count (points are independent; nothing is reduced).

mod batch;
mod cylinder;
mod error;
mod projection;
mod second_order_cone;

pub use batch::{project_batch, Parallelism};
pub use cylinder::VonMisesCylinder;
pub use error::ConeError;
pub use projection::{Projection, Projector, Region};
pub use second_order_cone::SecondOrderCone;

/// Re-exported so that callers name the same vector and matrix types.
pub use nalgebra::{SMatrix, SVector};

// The README's example, compiled and run as a doctest (`cargo test --doc`).
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
