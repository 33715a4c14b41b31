//! A method's model from a scene: the finite elements ([`fem`]) or the material point
//! method ([`mpm`]), their initial stress, and the size a model will take in memory.
pub mod fem;
mod initial_stress;
mod layered_weight;
pub mod mpm;
pub mod size;

pub use initial_stress::{
    initial_stress, initial_stress_at, k0_bounds, k0_bounds_without_cohesion, k0_stress_at,
    mandel_from_components, uniform_stress,
};
pub use layered_weight::layered_weight;
