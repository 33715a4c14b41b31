//! The linear system of one Newton step, `J_F d = r` with `J_F = I − D + R G W` (eq. 25
//! generalised in `docs/derivations.md`, 'The Newton matrix': `D`, `G` block diagonal,
//! `R = diag(ρ_i)`).
mod dense;
#[cfg(feature = "mpi")]
mod distributed_factor;
mod owned_assembly;
mod partition;
pub(crate) mod schur;
mod schur_factor;
mod schur_pattern;

mod stress_sized;

pub(crate) use dense::DenseSystem;
pub(crate) use schur::SchurSystem;
pub(crate) use schur_factor::{Factorized, LuChoice};
pub(crate) use stress_sized::StressSizedSystem;
