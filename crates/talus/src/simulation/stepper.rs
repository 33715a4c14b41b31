use std::time::Instant;

use talus_fem::assembly::add_mul_transpose;
use talus_ssn::{Report, Settings, SolveError, Solver};

use super::{Model, State};

/// What one step did (all its sub-steps together).
#[derive(Debug, Clone, PartialEq)]
pub struct StepRecord {
    pub time: f64,
    /// Sub-steps taken (1 unless the step was split after a failed solve). A solve that ends
    /// at its round-off floor is accepted, not split (see `statuses`).
    pub substeps: usize,
    /// Smallest sub-step used (s).
    pub smallest_h: f64,
    /// Newton iterations over all sub-steps.
    pub newton_iterations: usize,
    /// Largest iteration count of a single sub-step.
    pub max_newton_iterations: usize,
    /// Newton iterations of the attempts that failed and were redone as two half steps (not
    /// in `newton_iterations`).
    pub failed_newton_iterations: usize,
    /// Line-search backtracks over all accepted sub-steps.
    pub backtracks: usize,
    /// How each accepted sub-step's solve ended.
    pub statuses: Vec<talus_ssn::Status>,
    /// Where each accepted sub-step's Newton iteration started.
    pub predictors: Vec<Predictor>,
    /// Final `‖F‖∞` of the last sub-step.
    pub residual: f64,
    /// `‖F‖∞ / max(1, ‖σ‖∞)` per iteration, per sub-step (the quantity compared with the
    /// tolerance).
    pub residual_histories: Vec<Vec<f64>>,
    /// `‖F_ρ‖₂ / max(1, ‖σ‖∞)` with the iteration's ρ, per iteration, per sub-step.
    pub merit_histories: Vec<Vec<f64>>,
    /// Reaction on the reported boundary: the force it applies to the body, vertical,
    /// positive downward, N per metre of thickness.
    pub reaction_force: f64,
    /// Force each prescribed dof's condition applies to the body in the last sub-step
    /// (N/m, `reaction_groups::prescribed_forces`).
    pub prescribed_forces: Vec<f64>,
    pub seconds: f64,
}

#[derive(Debug, thiserror::Error)]
pub enum StepError {
    #[error("step to t = {time:.6} s did not converge even with h = {h:e} s ({halvings} halvings): {report_status} after {iterations} Newton iterations, residual {residual:.3e}")]
    NotConverged {
        time: f64,
        h: f64,
        halvings: usize,
        report_status: talus_ssn::Status,
        iterations: usize,
        residual: f64,
    },
    #[error("solver setup: {0}")]
    Solver(SolveError),
}

/// Where a sub-step's Newton iteration starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Predictor {
    /// `σₙ + h σ̇`, the rate of the last accepted sub-step (smooth loading).
    Extrapolated,
    /// The elastic predictor: first step, or right after a jump in the prescribed velocity.
    Elastic,
    /// `σₙ`, when the elastic solve fails.
    Previous,
}

/// Advances a [`State`] step by step. One `Solver` (and one symbolic factorization) per
/// distinct `h`, reused across steps: only `q` changes.
pub struct Stepper<'m> {
    model: &'m Model,
    settings: Settings,
    max_halvings: usize,
    solvers: Vec<(f64, Solver<4>)>,
    /// `(σₙ − σₙ₋₁)/h` of the last sub-step: each solve starts from σₙ + h σ̇, which under
    /// steady loading is second-order close to the answer (warm start).
    stress_rate: Option<Vec<f64>>,
    /// The last sub-step's `StepRecord::prescribed_forces`.
    prescribed_forces: Vec<f64>,
}

impl<'m> Stepper<'m> {
    pub fn new(model: &'m Model, settings: Settings, max_halvings: usize) -> Self {
        Self {
            model,
            settings,
            max_halvings,
            solvers: Vec::new(),
            stress_rate: None,
            prescribed_forces: Vec::new(),
        }
    }

    /// `(σₙ − σₙ₋₁)/h` of the last sub-step, if the next step will extrapolate from it.
    pub fn stress_rate(&self) -> Option<&[f64]> {
        self.stress_rate.as_deref()
    }

    /// Restores a stress rate saved with [`Stepper::stress_rate`] (to resume a run from a
    /// saved state with the same predictor).
    pub fn set_stress_rate(&mut self, rate: Option<Vec<f64>>) {
        self.stress_rate = rate;
    }

    /// The reaction of the reported boundary in a state at rest (`M a = 0`): `Bᵀσ − f` on
    /// its vertical prescribed dofs, positive downward (N/m), `f` at the state's time.
    pub fn reaction(&self, state: &State) -> f64 {
        let asm = &self.model.assembly;
        let mut internal = vec![0.0; asm.lumped_mass_prescribed.len()];
        add_mul_transpose(&asm.b_prescribed, &state.sigma, &mut internal);
        let force_prescribed = self.model.loads_at(state.time).force_prescribed;
        self.model
            .reaction_dofs
            .iter()
            .filter(|(_, comp)| *comp == 1)
            .map(|&(j, _)| -(internal[j] - force_prescribed[j]))
            .sum()
    }

    /// One step of `h`. A sub-step that does not converge is redone as two of half the
    /// length, down to `h / 2^max_halvings`; past that the step fails and `state` is left
    /// as it was before the failing sub-step.
    pub fn advance(&mut self, state: &mut State, h: f64) -> Result<StepRecord, StepError> {
        let start = Instant::now();
        let mut record = StepRecord {
            time: state.time,
            substeps: 0,
            smallest_h: h,
            newton_iterations: 0,
            max_newton_iterations: 0,
            failed_newton_iterations: 0,
            backtracks: 0,
            statuses: Vec::new(),
            predictors: Vec::new(),
            residual: 0.0,
            residual_histories: Vec::new(),
            merit_histories: Vec::new(),
            reaction_force: 0.0,
            prescribed_forces: Vec::new(),
            seconds: 0.0,
        };
        self.advance_level(state, h, 0, &mut record)?;
        record.time = state.time;
        record.seconds = start.elapsed().as_secs_f64();
        Ok(record)
    }

    fn advance_level(
        &mut self,
        state: &mut State,
        h: f64,
        level: usize,
        record: &mut StepRecord,
    ) -> Result<(), StepError> {
        let mut trial = state.clone();
        match self.substep(&mut trial, h) {
            Ok((report, reaction, predictor)) => {
                if let Some(floor) = report.round_off_floor {
                    tracing::warn!(
                        time = state.time,
                        h,
                        residual = floor.reached / report.scale,
                        floor_estimate = floor.estimate / report.scale,
                        "step accepted at the round-off floor, above the tolerance"
                    );
                }
                *state = trial;
                record.substeps += 1;
                record.smallest_h = record.smallest_h.min(h);
                record.newton_iterations += report.iterations;
                record.max_newton_iterations = record.max_newton_iterations.max(report.iterations);
                record.residual = report.residual;
                record.backtracks += report.backtracks;
                record.statuses.push(report.status);
                record.predictors.push(predictor);
                record.merit_histories.push(
                    report
                        .merit_history
                        .iter()
                        .map(|r| r / report.scale)
                        .collect(),
                );
                record.residual_histories.push(
                    report
                        .residual_history
                        .iter()
                        .map(|r| r / report.scale)
                        .collect(),
                );
                record.reaction_force = reaction;
                record.prescribed_forces = std::mem::take(&mut self.prescribed_forces);
                Ok(())
            }
            Err(SolveError::NotConverged(report)) => {
                if level >= self.max_halvings {
                    return Err(StepError::NotConverged {
                        time: state.time + h,
                        h,
                        halvings: level,
                        report_status: report.status,
                        iterations: report.iterations,
                        residual: report.residual,
                    });
                }
                record.failed_newton_iterations += report.iterations;
                tracing::warn!(time = state.time, h, status = %report.status, "step did not converge: halving h");
                self.advance_level(state, 0.5 * h, level + 1, record)?;
                self.advance_level(state, 0.5 * h, level + 1, record)
            }
            Err(e) => Err(StepError::Solver(e)),
        }
    }

    fn solver(&mut self, h: f64) -> Result<&mut Solver<4>, SolveError> {
        let pos = match self.solvers.iter().position(|(hh, _)| *hh == h) {
            Some(p) => p,
            None => {
                let system = self.model.reduced_system(h)?;
                self.solvers.push((h, Solver::new(system, self.settings)?));
                self.solvers.len() - 1
            }
        };
        Ok(&mut self.solvers[pos].1)
    }

    /// Eqs. 15–16: `h z = Wσ + q` with `q = −(S σ_n + h B v_n + h² B M⁻¹ f + h B_D v_D)`
    /// (`docs/derivations.md`, 'The reduced system': `B v` is the strain rate; prescribed
    /// velocities enter through `B_D`), `f` and `v_D` taken at the end of the sub-step.
    /// Returns the report, the reaction force and where the iteration started.
    fn substep(
        &mut self,
        state: &mut State,
        h: f64,
    ) -> Result<(Report, f64, Predictor), SolveError> {
        let model = self.model;
        let asm = &model.assembly;
        let loads = model.loads_at(state.time + h);
        let q = model.reduced_rhs_with(state, h, &loads);

        let solver = self.solver(h)?;
        solver.set_q(q)?;
        // Starting point: σₙ + h σ̇ when the last step's loading was smooth (steady flow is
        // then predicted to second order); otherwise, out of rest or right after a jump in
        // the prescribed velocity, the elastic predictor (one elastic solve). A jump: the
        // velocity applied over the last step is not the programme's at the step's start
        // (the start from rest; with constant loads, the only jump), or the loading rate
        // changes (`Model::loading_rate_changes_from`, `docs/scenes.md`, 'Load
        // programmes'). This step's rate predicts the next unless it changes inside.
        let (t0, t1) = (state.time, state.time + h);
        let velocity_jumps = state.velocity_prescribed != model.prescribed_velocity_at(t0);
        let loading_jumps = velocity_jumps || model.loading_rate_changes_from(t0, t1);
        let smooth_within = !velocity_jumps && !model.loading_rate_changes_inside(t0, t1);
        let mut sigma = state.sigma.clone();
        let rate = if loading_jumps {
            None
        } else {
            self.stress_rate.take()
        };
        let solver = self.solver(h)?;
        let predictor = match &rate {
            Some(rate) => {
                for (s, r) in sigma.iter_mut().zip(rate) {
                    *s += h * r;
                }
                Predictor::Extrapolated
            }
            None => match solver.elastic_predictor(&mut sigma) {
                Ok(()) => Predictor::Elastic,
                Err(_) => {
                    sigma.copy_from_slice(&state.sigma);
                    Predictor::Previous
                }
            },
        };
        tracing::trace!(?predictor, "start of step");
        let solver = self.solver(h)?;
        let report = match solver.solve(&mut sigma) {
            Ok(report) => report,
            Err(e) => {
                // The halved retries start from the same rate: after a failure the
                // elastic predictor is much further from the solution (`docs/solver.md`,
                // "Non-associative Newton at the mechanism's onset").
                self.stress_rate = rate;
                return Err(e);
            }
        };
        // z = Wσ + q is h·(−V ε̇ᵖ) per point: the plastic strain increment is ‖z_p‖ / V_p.
        let z = solver.z();
        for (p, v) in asm.gauss_volumes.iter().enumerate() {
            let dz = (0..4)
                .map(|k| z[4 * p + k] * z[4 * p + k])
                .sum::<f64>()
                .sqrt();
            state.plastic_strain[p] += dz / v;
        }
        let mut internal_free = vec![0.0; asm.lumped_mass_free.len()];
        let mut internal_prescribed = vec![0.0; asm.lumped_mass_prescribed.len()];
        add_mul_transpose(&asm.b_free, &sigma, &mut internal_free);
        add_mul_transpose(&asm.b_prescribed, &sigma, &mut internal_prescribed);
        for (j, v) in state.velocity_free.iter_mut().enumerate() {
            *v += h * (loads.force_free[j] - internal_free[j]) / asm.lumped_mass_free[j];
        }
        // The force the boundary applies: M a + Bᵀσ − f on its prescribed dofs.
        let mut reaction = 0.0;
        for &(j, comp) in &model.reaction_dofs {
            if comp == 1 {
                let inertia = asm.lumped_mass_prescribed[j]
                    * (loads.prescribed_velocity[j] - state.velocity_prescribed[j])
                    / h;
                reaction -= inertia + internal_prescribed[j] - loads.force_prescribed[j];
            }
        }
        self.prescribed_forces = super::prescribed_forces(
            model,
            &loads,
            &state.velocity_prescribed,
            &internal_prescribed,
            h,
        );
        state
            .velocity_prescribed
            .copy_from_slice(&loads.prescribed_velocity);
        if let Ok(v) = asm
            .dofs()
            .scatter(&state.velocity_free, &state.velocity_prescribed)
        {
            for (u, vn) in state.displacement.iter_mut().zip(v) {
                u[0] += h * vn[0];
                u[1] += h * vn[1];
            }
        }
        // A rate is worth extrapolating only if this step's loading was smooth.
        self.stress_rate = smooth_within.then(|| {
            sigma
                .iter()
                .zip(&state.sigma)
                .map(|(a, b)| (a - b) / h)
                .collect()
        });
        state.sigma = sigma;
        state.time += h;
        Ok((report, reaction, predictor))
    }
}
