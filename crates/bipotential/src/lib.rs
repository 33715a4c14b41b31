//! Drucker-Prager flow rules, associative or not, in the bi-potential form of
//! Guillet et al. (2024): the yield cone (eq. 7), the flow rule (eq. 8), the bipotential
//! (eq. 10) and, per material point, the natural-map residual of eq. 20 with its
//! generalized Jacobian blocks.
//!
//! Stresses and strains are Mandel vectors, tension positive: `(xx, yy, zz, √2 xy)` in
//! plane strain (`D = 4`), `(xx, yy, zz, √2 yz, √2 xz, √2 xy)` in 3D (`D = 6`).
//!
//! ```
//! use talus_bipotential::{ConeFit, DruckerPrager, DruckerPragerParameters};
//! let soil = DruckerPrager::try_new(DruckerPragerParameters {
//!     young_modulus: 1e9, poisson_ratio: 0.3, friction_angle: 27.0,
//!     cohesion: 2e3, dilatancy_angle: 14.3, cone_fit: ConeFit::PlaneStrain,
//! })?;
//! let rule = soil.flow_rule::<4>();
//! # Ok::<(), talus_bipotential::MaterialError>(())
//! ```

mod cone_fit;
mod davis;
mod drucker_prager;
mod error;
mod flow_rule;
pub mod mandel;
mod material;
mod relaxation;

pub use cone_fit::ConeFit;
pub use davis::{davis_beta, davis_equivalent};
pub use drucker_prager::{DruckerPrager, DruckerPragerParameters};
pub use error::MaterialError;
pub use flow_rule::{FlowRule, NaturalMapLinearization, YieldSet};
pub use material::{Elastic, Material};
pub(crate) use relaxation::check_relaxation_time;
pub use relaxation::Relaxation;
pub use talus_cone::{Projector, Region, SMatrix, SVector};

// The README's example, compiled and run as a doctest (`cargo test --doc`).
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
