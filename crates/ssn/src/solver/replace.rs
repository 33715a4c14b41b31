//! A new problem on the same pattern (a new time step, a new friction pass) keeps the
//! Schur system's analysis.
use super::rho::{choose_rho, RESIDUAL_RHO};
use super::Solver;
use crate::operator::PointBlocks;
use crate::{Operator, ReducedSystem, SolveError};

impl<const D: usize> Solver<D> {
    /// Replaces the problem (operator, `q`, flow rules), keeping the Schur system's
    /// pattern and symbolic analysis when the new operator is structured with the same `B`
    /// sparsity pattern (rows, velocity columns, stored entries) and the same symmetry as
    /// the old one: a new time step, or a new friction pass, on the same particles, or
    /// another sub-step size of a fixed operator. ρ is chosen anew; with another `h`, a
    /// Krylov solve's next direction factorizes afresh. Otherwise the solver is rebuilt as
    /// by [`Solver::new`]. Returns whether the analysis was reused; on error the solver is
    /// left unchanged.
    pub fn replace_problem(&mut self, problem: ReducedSystem<D>) -> Result<bool, SolveError> {
        let (reusable, new_h) = match (&self.problem.operator, &problem.operator, &self.schur) {
            (Operator::Structured(old), Operator::Structured(new), Some(_)) => (
                old.lumped_mass.len() == new.lumped_mass.len()
                    && Self::same_pattern(&old.b, &new.b)
                    && self.problem.is_associative() == problem.is_associative(),
                old.h != new.h,
            ),
            _ => (false, false),
        };
        if !reusable {
            *self = Self::new(problem, self.settings)?;
            return Ok(false);
        }
        let diagonal = problem.operator.diagonal();
        let rho = choose_rho::<D>(&self.settings.rho, &diagonal, &problem.operator)?;
        let residual_rho = choose_rho::<D>(&RESIDUAL_RHO, &diagonal, &problem.operator)?;
        if let Operator::Structured(s) = &problem.operator {
            let mut blocks = PointBlocks::new(&s.b, problem.n_points());
            // The same pattern, the same groups: this rank keeps its points.
            if let Some(share) = &self.share {
                blocks.keep_points(share.owned());
            }
            self.blocks = Some(blocks);
        }
        if new_h {
            // Another sub-step size: its K differs by the factor h² on the plastic part,
            // so GMRES starts from a factor of its own, as a new solver would.
            if let Some(schur) = self.schur.as_mut() {
                schur.forget_factor();
            }
        }
        self.rho = rho;
        self.residual_rho = residual_rho;
        // Built from W's values: stale with the new operator.
        self.stress_sized = None;
        self.problem = problem;
        Ok(true)
    }

    /// Same shape and the same stored entries, column by column (values may differ).
    pub(super) fn same_pattern(
        a: &faer::sparse::SparseColMat<usize, f64>,
        b: &faer::sparse::SparseColMat<usize, f64>,
    ) -> bool {
        let (a, b) = (a.symbolic(), b.symbolic());
        a.nrows() == b.nrows()
            && a.ncols() == b.ncols()
            && (0..a.ncols()).all(|j| a.row_idx_of_col_raw(j) == b.row_idx_of_col_raw(j))
    }
}
