//! Semi-smooth Newton for the reduced elasto-plastic problem of Guillet et al. (2024),
//! eqs. 16–25: find σ with `z = Wσ + q` and, at every point, the non-associative
//! Drucker-Prager flow rule in natural-map form `σ_i = P_K(σ_i − ρ_i y_i(z_i))`.
//!
//! `W` is given dense, sparse, or structured as `S + h² B M⁻¹ Bᵀ` ([`Structured`]); the
//! structured form takes each Newton step through a velocity-sized Schur complement
//! (sparse Cholesky when associative, LU otherwise; symbolic analysis done once).
//!
//! Call it from a worker of rayon's pool ([`on_pool`]): its per-point loops fork from there
//! at a fraction of the cost.
//!
//! ```no_run
//! # use talus_ssn::{ReducedSystem, Settings, Solver};
//! # fn demo(problem: ReducedSystem<3>) -> Result<(), talus_ssn::SolveError> {
//! let mut solver = Solver::new(problem, Settings::default())?;
//! let mut sigma = vec![0.0; solver.problem().operator().size()];
//! let report = solver.solve(&mut sigma)?; // Err(NotConverged) must be handled
//! println!("{} iterations, residual {:e}", report.iterations, report.residual);
//! # Ok(()) }
//! ```

mod error;
pub mod factorization;
pub mod krylov;
mod local_lu;
mod newton;
mod norm;
mod operator;
mod point_share;
mod pool;
mod problem;
mod reduced_rhs;
mod report;
mod settings;
pub mod siconos;
mod siconos_system;
mod solver;
mod stopping;

pub use error::SolveError;
pub use factorization::Ordering;
pub use operator::{Operator, Structured};
pub use pool::{on_pool, on_pool_polling};
pub use problem::ReducedSystem;
pub use reduced_rhs::{reduced_rhs, FreeVelocities, PrescribedVelocities};
pub use report::{Report, RoundOffFloor, Status};
pub use settings::{
    FactorRanks, Fold, Forcing, Krylov, LineSearch, LinearSolver, NewtonSolve, Precision, Rho,
    Settings, Stall,
};
pub use siconos_system::reduced_system_from_siconos;
pub use solver::Solver;

pub use faer;

// The README's example, compiled and run as a doctest (`cargo test --doc`).
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
