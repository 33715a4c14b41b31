//! Sparse factorizations of the Newton (Schur) matrix `M + h² Σ Bᵢᵀ Cᵢ Bᵢ`.
//!
//! [`SupernodalCholesky`] for associative flow rules (symmetric `K`): the supernodal
//! [`SymmetricPatternLlt`] on the LU's structure and thread schedule, in f64 or (a
//! preconditioner's) f32, [`Real`]; storage reused across factorizations.
//!
//! Both take their fill-reducing [`Ordering`]: AMD by default, METIS' nested dissection
//! with the cargo feature `metis`.
//!
//! [`SymmetricPatternLu`] is the LU without pivoting on the Cholesky structure of its
//! symmetric pattern: the default for non-associative flow rules, guarded by a pivot test
//! with a pivoting LU as fallback (`docs/solver.md`, "The factorization").
//!
//! ```
//! use std::sync::Arc;
//! use talus_ssn::factorization::{SymbolicSymmetricPatternLu, SymmetricPatternLu, DEFAULT_PIVOT_TOLERANCE};
//! use talus_ssn::faer::sparse::{SparseColMat, Triplet};
//! // [[4, 1], [2, 3]]
//! let a = SparseColMat::<usize, f64>::try_new_from_triplets(2, 2, &[
//!     Triplet::new(0, 0, 4.0), Triplet::new(1, 0, 2.0),
//!     Triplet::new(0, 1, 1.0), Triplet::new(1, 1, 3.0),
//! ]).unwrap();
//! let symbolic = Arc::new(SymbolicSymmetricPatternLu::try_new(a.symbolic()).unwrap());
//! let mut lu = SymmetricPatternLu::new(symbolic);
//! lu.factorize(a.val(), DEFAULT_PIVOT_TOLERANCE).unwrap();
//! let mut x = vec![5.0, 5.0];
//! lu.solve_in_place(&mut x);
//! assert!((x[0] - 1.0).abs() < 1e-15 && (x[1] - 1.0).abs() < 1e-15);
//! ```
mod cholesky;
mod dense_llt;
mod dense_lu;
#[cfg(feature = "metis")]
pub(crate) mod metis_graph;
mod ordering;
mod real;
mod subtrees;
mod supernodal_llt;
mod symbolic_error;
mod symmetric_pattern_lu;

#[cfg(feature = "metis")]
pub use ordering::nested_dissection;
pub use ordering::{Ordering, SymbolicError};
pub use real::Real;

pub use cholesky::SupernodalCholesky;
pub use supernodal_llt::{NotPositiveDefinite, SymmetricPatternLlt};
pub use symmetric_pattern_lu::{
    PivotBreakdown, SymbolicSymmetricPatternLu, SymmetricPatternLu, DEFAULT_PIVOT_TOLERANCE,
};
