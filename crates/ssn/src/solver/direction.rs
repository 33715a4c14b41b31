//! The Newton direction `J_F d = −F`: through the velocity-sized Schur complement, the
//! stress-sized system, or dense; checked for accuracy (`docs/solver.md`, "The
//! factorization").
use crate::newton::schur::SchurFailure;
use crate::newton::{Factorized, LuChoice};
use crate::operator::{apply, block};
use crate::{LinearSolver, Operator, Report, Status};

use super::{inf_norm, Solver, LINEAR_FORCING};

impl<const D: usize> Solver<D> {
    /// Solves `J_F d = −F` into `self.direction`. A no-pivot LU direction that fails the
    /// accuracy check is recomputed once with the pivoting LU (`Report::pivoting_fallbacks`).
    pub(super) fn newton_direction(&mut self, report: &mut Report) -> Result<(), Status> {
        for (i, l) in self.lin.iter().enumerate() {
            for a in 0..D {
                self.f[D * i + a] = -l.residual[a];
            }
        }
        let forced = self.settings.linear_solver == LinearSolver::SchurPivoting;
        let mut pivoting = forced;
        loop {
            let used = self.direction_by_schur(pivoting);
            if used.is_none() {
                self.direction_stress_sized()?;
            }
            let accurate = self.direction_is_accurate();
            if !accurate && matches!(used, Some(Factorized::NoPivotLu(_))) {
                tracing::warn!("inaccurate no-pivot LU direction: retried with pivoting");
                pivoting = true;
                continue;
            }
            match used {
                Some(f) => {
                    report.schur_steps += 1;
                    if let Factorized::NoPivotLu(negative) = f {
                        report.negative_pivots.push(negative);
                    }
                    if f == Factorized::PivotingLu && !forced {
                        report.pivoting_fallbacks += 1;
                    }
                }
                None => report.stress_sized_steps += 1,
            }
            return if accurate {
                Ok(())
            } else {
                Err(Status::SingularJacobian)
            };
        }
    }

    /// The direction through the velocity-sized Schur system, if the operator is structured
    /// and every local block is regular; `None` sends the step to the stress-sized system.
    pub(super) fn direction_by_schur(&mut self, pivoting: bool) -> Option<Factorized> {
        let (Some(schur), Operator::Structured(s)) = (self.schur.as_mut(), &self.problem.operator)
        else {
            return None;
        };
        let blocks = self
            .blocks
            .as_ref()
            .expect("structured operators carry point blocks");
        match schur.solve(
            s,
            blocks,
            &self.lin,
            &self.rho,
            &self.f,
            &mut self.direction,
            if pivoting {
                LuChoice::Pivoting
            } else {
                LuChoice::NoPivot {
                    pivot_tolerance: self.settings.pivot_tolerance,
                }
            },
            self.settings.parallel,
        ) {
            Ok(used) => Some(used),
            Err(SchurFailure::SingularBlock(i)) => {
                tracing::debug!(point = i, "singular local block: stress-sized step");
                None
            }
            Err(SchurFailure::Factorization(e)) => {
                tracing::debug!(error = %e, "Schur factorization failed: stress-sized step");
                None
            }
        }
    }

    /// The direction through the stress-sized system `J_F d = −F` (dense or sparse).
    pub(super) fn direction_stress_sized(&mut self) -> Result<(), Status> {
        if let (Some(dense), Operator::Dense(w)) = (self.dense.as_mut(), &self.problem.operator) {
            dense.solve(w, &self.lin, &self.rho, &self.f, &mut self.direction);
            return Ok(());
        }
        self.ensure_stress_sized()
            .map_err(|_| Status::SingularJacobian)?;
        let sys = self.stress_sized.as_mut().expect("just built");
        sys.solve(&self.lin, &self.rho, &self.f, &mut self.direction)
            .map_err(|e| {
                tracing::warn!(error = %e, "sparse LU failed");
                Status::SingularJacobian
            })
    }

    /// `d` finite and `‖J_F d + F‖∞ ≤ 1e-3 ‖F‖∞`: faer returns finite garbage on a
    /// numerically singular matrix, and a no-pivot LU may lose accuracy to growth.
    pub(super) fn direction_is_accurate(&mut self) -> bool {
        if !self.direction.iter().all(|v| v.is_finite()) {
            return false;
        }
        apply(
            &self.problem.operator,
            self.blocks.as_ref(),
            &self.direction,
            None,
            &mut self.check,
            &mut self.scratch,
            self.settings.parallel,
        );
        let mut worst: f64 = 0.0;
        for (i, l) in self.lin.iter().enumerate() {
            let d = block::<D>(&self.direction, i);
            let wd = block::<D>(&self.check, i);
            let jd = d - l.projection_jacobian * d + l.coupling * wd * self.rho[i];
            worst = worst.max((jd - block::<D>(&self.f, i)).amax());
        }
        let scale = inf_norm(&self.f);
        // An inexact Newton step with forcing term 1e-3 keeps fast local convergence;
        // beyond it the matrix is numerically singular (or the answer is garbage).
        let accurate = worst <= LINEAR_FORCING * scale;
        if !accurate {
            tracing::warn!(
                linear_residual = worst,
                rhs = scale,
                "inaccurate Newton direction"
            );
        }
        accurate
    }
}
