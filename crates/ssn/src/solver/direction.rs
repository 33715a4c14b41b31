//! The Newton direction `J_F d = −F`: through the velocity-sized Schur complement, the
//! stress-sized system, or dense; checked for accuracy (`docs/solver.md`, "The
//! factorization").
use crate::krylov::{Gmres, GmresError, GmresWorkspace, Verdict, PROJECT_AFTER};
use crate::newton::schur::{KrylovRequest, SchurFailure};
use crate::newton::{Factorized, LuChoice};
use crate::operator::{apply, block};
use crate::{Forcing, Krylov, LinearSolver, NewtonSolve, Operator, Report, Status};

use super::{inf_norm, Solver, LINEAR_FORCING};

/// A velocity solve whose normwise backward error (`SchurSystem::backward_error`) is at
/// most this, about 64 units of round-off, is as good as a pivoting LU's. When its
/// direction still fails the accuracy check, the loss is `K`'s conditioning amplified
/// into the stresses through `M⁻¹` (the small masses of a graded mesh's finest cells),
/// which no factorization of `K` removes (`docs/solver.md`, 'The factorization').
const BACKWARD_STABLE: f64 = 1e-14;

impl<const D: usize> Solver<D> {
    /// Solves `J_F d = −F` into `self.direction`. A no-pivot LU direction that fails the
    /// accuracy check is recomputed once with the pivoting LU (`Report::pivoting_fallbacks`),
    /// unless that LU was backward stable (refused: `Report::pivoting_skipped`);
    /// one from GMRES on a reused factorization, with a new factorization. `needed` is the
    /// relative decrease of the stopping test's residual that would end the solve
    /// (`tolerance · scale / residual`; 0 when unknown): the forcing term of a Krylov solve
    /// need not go below it.
    pub(super) fn newton_direction(
        &mut self,
        report: &mut Report,
        needed: f64,
    ) -> Result<(), Status> {
        let owned = self.share.as_ref().map(|s| s.owned());
        for (i, l) in self.lin.iter().enumerate() {
            // Another rank's point: its linearization is stale here, its share of F is 0.
            let mine = owned.is_none_or(|o| o[i]);
            for a in 0..D {
                self.f[D * i + a] = if mine { -l.residual[a] } else { 0.0 };
            }
        }
        let forced = self.settings.linear_solver == LinearSolver::SchurPivoting;
        let mut pivoting = forced;
        let mut krylov = match self.settings.newton_solve {
            NewtonSolve::Direct => None,
            NewtonSolve::Krylov(settings) => {
                let forcing = forcing_term(&settings, &report.merit_history, self.forcing, needed);
                self.forcing = Some(forcing);
                Some(KrylovRequest { settings, forcing })
            }
        };
        loop {
            let used = self.direction_by_schur(pivoting, krylov);
            if let Some(schur) = self.schur.as_mut() {
                let counts = schur.take_counts();
                report.factorizations += counts.factorizations;
                report.krylov_iterations += counts.krylov_iterations;
                report.krylov_failures += counts.krylov_failures;
            }
            // Under MPI every rank would factorize the whole stress-sized system: a singular
            // local block or a failed MUMPS factorization (alike on every rank) halves the
            // step instead (docs/distributed.md, 'When a rank fails').
            if used.is_none() && self.settings.linear_solver.is_distributed() {
                tracing::warn!("no distributed Schur direction: the step is refused");
                return Err(Status::SingularJacobian);
            }
            // The stress-sized system: by GMRES on its last factorization, or factorized.
            let mut stress_reused = false;
            if used.is_none() {
                stress_reused = match krylov {
                    Some(request) => self.direction_stress_sized_krylov(request, report),
                    None => false,
                };
                if !stress_reused {
                    report.factorizations += 1;
                    self.direction_stress_sized()?;
                }
            }
            let accurate = self.direction_is_accurate();
            if !accurate && matches!(used, Some(Factorized::Reused { .. })) {
                tracing::debug!("inaccurate direction from a reused factorization: refactorized");
                if let Some(schur) = self.schur.as_mut() {
                    schur.mark_degraded();
                }
                krylov = None;
                continue;
            }
            if !accurate && stress_reused {
                tracing::debug!("inaccurate direction from a reused factorization: refactorized");
                self.stress_krylov.degraded = true;
                report.krylov_failures += 1;
                krylov = None;
                continue;
            }
            if !accurate && matches!(used, Some(Factorized::NoPivotLu(_))) {
                let blocks = self.blocks.as_ref().expect("a Schur step has point blocks");
                let backward = self
                    .schur
                    .as_ref()
                    .map(|s| s.backward_error(blocks, self.share.as_ref(), self.settings.parallel));
                if backward.is_some_and(|e| e <= BACKWARD_STABLE) {
                    // K's conditioning, not the LU, limits the direction: row exchanges
                    // would cost a second, denser factorization and give the same.
                    tracing::debug!(
                        backward_error = backward,
                        "inaccurate direction from a backward-stable no-pivot LU: refused"
                    );
                    report.pivoting_skipped += 1;
                } else {
                    tracing::warn!(
                        backward_error = backward,
                        "inaccurate no-pivot LU direction: retried with pivoting"
                    );
                    pivoting = true;
                    continue;
                }
            }
            match used {
                Some(f) => {
                    report.schur_steps += 1;
                    match f {
                        Factorized::NoPivotLu(negative) | Factorized::Distributed(negative) => {
                            report.negative_pivots.push(negative)
                        }
                        Factorized::Reused { .. } => report.krylov_solves += 1,
                        Factorized::Cholesky | Factorized::PivotingLu => {}
                    }
                    if f == Factorized::PivotingLu && !forced {
                        report.pivoting_fallbacks += 1;
                    }
                }
                None => {
                    report.stress_sized_steps += 1;
                    if stress_reused {
                        report.krylov_solves += 1;
                    }
                }
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
    pub(super) fn direction_by_schur(
        &mut self,
        pivoting: bool,
        krylov: Option<KrylovRequest>,
    ) -> Option<Factorized> {
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
            krylov,
            self.share.as_ref(),
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
        self.stress_krylov.degraded = false;
        if let (Some(dense), Operator::Dense(w)) = (self.dense.as_mut(), &self.problem.operator) {
            dense.solve(w, &self.lin, &self.rho, &self.f, &mut self.direction);
            return Ok(());
        }
        self.ensure_stress_sized()
            .map_err(|_| Status::SingularJacobian)?;
        let keep = self.settings.newton_solve != NewtonSolve::Direct;
        let sys = self.stress_sized.as_mut().expect("just built");
        sys.solve(&self.lin, &self.rho, &self.f, &mut self.direction, keep)
            .map_err(|e| {
                tracing::warn!(error = %e, "sparse LU failed");
                Status::SingularJacobian
            })
    }

    /// The stress-sized direction by GMRES on `J_F d = −F` (applied as the accuracy check
    /// does: `d − D d + ρ G W d`), preconditioned by the last factorization of `J_F`
    /// (dense or sparse), to `‖J_F d + F‖∞ ≤ η ‖F‖∞`. False (then factorize) without a
    /// fresh factorization or when GMRES misses its tolerance within the cap.
    fn direction_stress_sized_krylov(
        &mut self,
        request: KrylovRequest,
        report: &mut Report,
    ) -> bool {
        let dense = matches!(self.problem.operator, Operator::Dense(_)) && self.dense.is_some();
        let ready = if dense {
            self.dense.as_ref().is_some_and(|s| s.has_factorization())
        } else {
            self.stress_sized
                .as_ref()
                .is_some_and(|s| s.has_factorization())
        };
        if !ready || self.stress_krylov.degraded || !request.settings.reuse {
            return false;
        }
        let clock = std::time::Instant::now();
        let n = self.f.len();
        let settings = request.settings;
        let state = &mut self.stress_krylov;
        if !state
            .workspace
            .as_ref()
            .is_some_and(|w| w.fits(n, settings.restart))
        {
            state.workspace = Some(GmresWorkspace::new(n, settings.restart));
        }
        state.wx.resize(n, 0.0);
        let workspace = state.workspace.as_mut().expect("just built");
        let (op, blocks, lin, rho, parallel) = (
            &self.problem.operator,
            self.blocks.as_ref(),
            &self.lin,
            &self.rho,
            self.settings.parallel,
        );
        let (wx, scratch) = (&mut state.wx, &mut self.scratch);
        let apply_jacobian = |x: &[f64], y: &mut [f64]| {
            apply(op, blocks, x, None, wx, scratch, None, parallel);
            for (i, l) in lin.iter().enumerate() {
                let xi = block::<D>(x, i);
                let v = xi - l.projection_jacobian * xi + l.coupling * block::<D>(wx, i) * rho[i];
                y[D * i..D * i + D].copy_from_slice(v.as_slice());
            }
        };
        let (mut dense_system, sparse_system) = (self.dense.as_mut(), self.stress_sized.as_ref());
        let precondition = |x: &mut [f64]| {
            let done = if dense {
                dense_system
                    .as_deref_mut()
                    .is_some_and(|s| s.precondition(x))
            } else {
                sparse_system.is_some_and(|s| s.precondition(x))
            };
            debug_assert!(done, "checked ready above");
        };
        let allowed = request.forcing * inf_norm(&self.f);
        let two = self.f.iter().map(|v| v * v).sum::<f64>().sqrt();
        // The ∞-norm is what is tested; the 2-norm target starts at its calibrated value.
        let target = if allowed > 0.0 {
            0.5 * allowed * two / inf_norm(&self.f)
        } else {
            0.0
        };
        self.direction.fill(0.0);
        let gmres = Gmres {
            restart: settings.restart,
            max_iterations: settings.max_iterations,
            project_after: PROJECT_AFTER,
        };
        let result = gmres.solve(
            workspace,
            apply_jacobian,
            precondition,
            &self.f,
            &mut self.direction,
            target,
            |_, e| {
                let worst = inf_norm(e);
                if worst <= allowed {
                    Verdict::Accept
                } else {
                    let e_two = e.iter().map(|v| v * v).sum::<f64>().sqrt();
                    Verdict::Continue {
                        target: 0.5 * e_two * allowed / worst,
                    }
                }
            },
        );
        match result {
            Ok(solved) => {
                report.krylov_iterations += solved.iterations;
                self.stress_krylov.degraded = solved.iterations > settings.degraded_iterations;
                tracing::debug!(
                    iterations = solved.iterations,
                    forcing = request.forcing,
                    seconds = clock.elapsed().as_secs_f64(),
                    "GMRES on the last stress-sized factorization"
                );
                true
            }
            Err(error) => {
                let iterations = match error {
                    GmresError::NotConverged { iterations, .. }
                    | GmresError::NonFinite { iterations } => iterations,
                    GmresError::Settings => 0,
                };
                report.krylov_iterations += iterations;
                report.krylov_failures += 1;
                tracing::debug!(%error, "GMRES missed its tolerance: refactorized");
                false
            }
        }
    }

    /// `d` finite and `‖J_F d + F‖∞ ≤ 1e-3 ‖F‖∞`: faer returns finite garbage on a
    /// numerically singular matrix, and a no-pivot LU may lose accuracy to growth.
    pub(super) fn direction_is_accurate(&mut self) -> bool {
        let finite = self.direction.iter().all(|v| v.is_finite());
        let finite = match &self.share {
            Some(share) => share.all(finite),
            None => finite,
        };
        if !finite {
            return false;
        }
        apply(
            &self.problem.operator,
            self.blocks.as_ref(),
            &self.direction,
            None,
            &mut self.check,
            &mut self.scratch,
            self.share.as_ref(),
            self.settings.parallel,
        );
        let owned = self.share.as_ref().map(|s| s.owned());
        let mut worst: f64 = 0.0;
        for (i, l) in self.lin.iter().enumerate() {
            if owned.is_some_and(|o| !o[i]) {
                continue;
            }
            let d = block::<D>(&self.direction, i);
            let wd = block::<D>(&self.check, i);
            let jd = d - l.projection_jacobian * d + l.coupling * wd * self.rho[i];
            worst = worst.max((jd - block::<D>(&self.f, i)).amax());
        }
        if let Some(share) = &self.share {
            worst = share.max(worst);
        }
        let scale = self.norm(&self.f);
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

/// The forcing term `η` of this iteration's Krylov solve (`Forcing`, `docs/krylov.md`):
/// `merits` are `‖F_ρ‖₂` so far (the current one last), `previous` the last `η` of this
/// solve.
fn forcing_term(settings: &Krylov, merits: &[f64], previous: Option<f64>, needed: f64) -> f64 {
    match settings.forcing {
        Forcing::Fixed(eta) => eta,
        Forcing::EisenstatWalker { gamma, alpha, max } => {
            let eta = match merits {
                [.., before, now] if *before > 0.0 => {
                    let mut eta = gamma * (now / before).powf(alpha);
                    // Safeguard (Eisenstat & Walker 1996, §2): do not tighten η faster than
                    // the merit has been falling.
                    if let Some(previous) = previous {
                        let floor = gamma * previous.powf(alpha);
                        if floor > 0.1 {
                            eta = eta.max(floor);
                        }
                    }
                    eta
                }
                _ => max,
            };
            // No tighter than a hundredth of what would end the solve.
            eta.max(0.01 * needed).min(max)
        }
    }
}
