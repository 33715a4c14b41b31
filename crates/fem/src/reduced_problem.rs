//! The finite-element method's side of eqs. 15–16 (Guillet et al. 2024), in one file, as
//! `talus-mpm`'s `reduced_problem.rs` is the material point method's:
//! - eq. 16's `W = S + h² B M⁻¹ Bᵀ`, fixed per `h` under small strains, kept in its factors
//!   ([`Model::reduced_system`]), and `q = −(S σₙ + h B vₙ + h² B M⁻¹ f + h B_D v_D)` per
//!   step through talus-ssn's `reduced_rhs` ([`Model::reduced_rhs`]);
//! - eq. 15's update of the velocities from the converged σ (the momentum balance of
//!   eqs. 1–2, discretized by eq. 11's `B` and `M`), the displacements, and the plastic
//!   strain from `z = −h V ε̇ᵖ` (eq. 17's flow rule, eq. 22's natural map per point);
//! - the force each prescribed dof's condition applies: eq. 15 solved for it;
//! - the engine's [`Discretization`] on a [`Model`].
use nalgebra::SVector;
use talus_engine::{Discretization, Loading, Motion, Problem, StepReport};
use talus_ssn::{
    reduced_rhs, FreeVelocities, Operator, PrescribedVelocities, ReducedSystem, SolveError,
    Structured,
};

use crate::assembly::add_mul_transpose;
use crate::dimension::{Dimension, Mandel};
use crate::dofs::Dof;
use crate::model::{Loads, Model};
use crate::state::State;

/// What a FEM sub-step measured.
#[derive(Debug, Clone, PartialEq)]
pub struct FemStats {
    /// Reaction on the reported boundary: the force it applies to the body along the
    /// model's `reaction_direction` (downward positive by default), N per metre of thickness (axisymmetric: N on the whole
    /// circumference, `2π` times the per-radian force; 3D: N).
    pub reaction_force: f64,
    /// Force each prescribed dof's condition applies to the body (N/m, N per radian, or N
    /// in 3D, [`prescribed_forces`]).
    pub prescribed_forces: Vec<f64>,
}

/// The reported boundary's reaction of a FEM step's report.
pub trait ReactionForce {
    /// The reported boundary's reaction at the end of the step (N/m, along the model's
    /// `reaction_direction`: downward positive by default).
    fn reaction_force(&self) -> f64;
}

impl ReactionForce for StepReport<FemStats> {
    fn reaction_force(&self) -> f64 {
        self.stats.as_ref().map_or(0.0, |s| s.reaction_force)
    }
}

impl<const D: usize> Model<D>
where
    Mandel<D>: Dimension,
{
    /// The reduced problem of eq. 16 for steps of length `h`: `W = S + h² B M⁻¹ Bᵀ` kept in
    /// factors, `q = 0` until [`Solver::set_q`](talus_ssn::Solver::set_q) with
    /// [`reduced_rhs`](Self::reduced_rhs).
    pub fn reduced_system(&self, h: f64) -> Result<ReducedSystem<D>, SolveError> {
        let asm = &self.assembly;
        let operator = Operator::Structured(Structured {
            compliance: self.compliance_blocks(),
            b: asm.b_free.clone(),
            lumped_mass: asm.lumped_mass_free.clone(),
            h,
        });
        let rules = self
            .step_flow_rules(h)
            .map_err(|e| SolveError::InvalidInput {
                field: "rules",
                reason: e.to_string(),
            })?;
        ReducedSystem::try_new(operator, vec![0.0; D * asm.n_points()], rules)
    }

    /// `S_p = V_p S₀` of each Gauss point with its material's compliance: the `S` of
    /// eq. 15 (one material: [`Assembly::compliance_blocks`](crate::Assembly::compliance_blocks)).
    pub fn compliance_blocks(&self) -> Vec<nalgebra::SMatrix<f64, D, D>> {
        let volumes = &self.assembly.gauss_volumes;
        (0..volumes.len())
            .map(|p| self.compliance_at(p) * volumes[p])
            .collect()
    }

    /// `q` of eq. 16 for the step of length `h` after `state`:
    /// `q = −(S σₙ + h B vₙ + h² B M⁻¹ f + h B_D v_D)` (`docs/derivations.md`, 'The reduced
    /// system': `B v` is the strain rate; prescribed velocities enter through `B_D`), with
    /// `f` and `v_D` those of the end of the step, `tₙ + h` (implicit).
    pub fn reduced_rhs(&self, state: &State<D>, h: f64) -> Vec<f64> {
        self.reduced_rhs_with(state, h, &self.loads_at(state.time + h))
    }

    /// [`reduced_rhs`](Self::reduced_rhs) with the step's loads already evaluated.
    pub fn reduced_rhs_with(&self, state: &State<D>, h: f64, loads: &Loads) -> Vec<f64> {
        let asm = &self.assembly;
        let mut s_sigma = vec![0.0; D * asm.n_points()];
        for (p, v) in asm.gauss_volumes.iter().enumerate() {
            let s = self.compliance_at(p)
                * SVector::<f64, D>::from_column_slice(&state.sigma[D * p..D * p + D])
                * *v;
            s_sigma[D * p..D * p + D].copy_from_slice(s.as_slice());
        }
        let free = FreeVelocities {
            b: &asm.b_free,
            velocity: &state.velocity_free,
            force: &loads.force_free,
            lumped_mass: &asm.lumped_mass_free,
        };
        let prescribed = PrescribedVelocities {
            b: &asm.b_prescribed,
            velocity: &loads.prescribed_velocity,
        };
        // The lengths come from the same assembly: they agree by construction.
        reduced_rhs(h, &s_sigma, &free, &prescribed)
            .expect("the assembly's operators and velocities have matching sizes")
    }

    /// The reaction of the reported boundary in a state at rest (`M a = 0`): `Bᵀσ − f` on
    /// its prescribed dofs along `reaction_direction` (N/m; N in 3D), `f` at the state's
    /// time.
    pub fn reaction(&self, state: &State<D>) -> f64 {
        self.reported_reaction(&prescribed_forces_at_rest(self, state))
    }

    /// The reported boundary's push on the body along `reaction_direction` (downward
    /// positive by default), from the force of every prescribed dof; axisymmetric: on the
    /// whole circumference (`2π` times).
    fn reported_reaction(&self, prescribed_forces: &[f64]) -> f64 {
        let (axis, sign) = self.reaction_direction;
        self.reaction_dofs
            .iter()
            .filter(|(_, comp)| *comp == axis)
            .fold(0.0, |r, &(j, _)| r + sign * prescribed_forces[j])
            * self.assembly.geometry().whole_body_factor()
    }
}

/// The force each prescribed dof's condition applies to the body over a step of `h`
/// (N/m): `M a + Bᵀσ − f` (eq. 15 solved for the boundary force), with `Bᵀσ` the internal
/// force `internal` of the step's stress, `f` and the new velocities those of `loads`,
/// `velocity_before` the prescribed velocities at the step's start.
pub fn prescribed_forces<const D: usize>(
    model: &Model<D>,
    loads: &Loads,
    velocity_before: &[f64],
    internal: &[f64],
    h: f64,
) -> Vec<f64>
where
    Mandel<D>: Dimension,
{
    let mass = &model.assembly.lumped_mass_prescribed;
    (0..mass.len())
        .map(|j| {
            mass[j] * (loads.prescribed_velocity[j] - velocity_before[j]) / h + internal[j]
                - loads.force_prescribed[j]
        })
        .collect()
}

/// The same in a state at rest (`M a = 0`): `Bᵀσ − f` at the state's time.
pub fn prescribed_forces_at_rest<const D: usize>(model: &Model<D>, state: &State<D>) -> Vec<f64>
where
    Mandel<D>: Dimension,
{
    let asm = &model.assembly;
    let mut internal = vec![0.0; asm.lumped_mass_prescribed.len()];
    add_mul_transpose(&asm.b_prescribed, &state.sigma, &mut internal);
    let f = model.loads_at(state.time).force_prescribed;
    internal.iter().zip(&f).map(|(i, f)| i - f).collect()
}

impl<const D: usize> Discretization<D> for Model<D>
where
    Mandel<D>: Dimension,
{
    type State = State<D>;
    /// The loads at the end of the sub-step.
    type Substep = Loads;
    type Stats = FemStats;
    type Error = std::convert::Infallible;

    fn fixed_system(&self, h: f64) -> Option<Result<ReducedSystem<D>, SolveError>> {
        Some(self.reduced_system(h))
    }

    fn time(&self, state: &State<D>) -> f64 {
        state.time
    }

    fn stress<'s>(&self, state: &'s State<D>) -> &'s [f64] {
        &state.sigma
    }

    /// A jump: the velocity applied over the last step is not the programme's at the
    /// step's start (the start from rest; with constant loads, the only jump), or the
    /// loading rate changes (`Model::loading_rate_changes_from`, `docs/scenes.md`, 'Load
    /// programmes').
    fn loading(&self, state: &State<D>, h: f64) -> Loading {
        let (t0, t1) = (state.time, state.time + h);
        let velocity_jumps = state.velocity_prescribed != self.prescribed_velocity_at(t0);
        Loading {
            jumps: velocity_jumps || self.loading_rate_changes_from(t0, t1),
            changes_inside: velocity_jumps || self.loading_rate_changes_inside(t0, t1),
        }
    }

    /// Eqs. 15–16: `q = −(S σ_n + h B v_n + h² B M⁻¹ f + h B_D v_D)` with `f` and `v_D`
    /// taken at the end of the sub-step.
    fn begin(&self, state: &State<D>, h: f64) -> Result<(Loads, Problem<D>), Self::Error> {
        let loads = self.loads_at(state.time + h);
        let q = self.reduced_rhs_with(state, h, &loads);
        let problem = match self.flow_rules_at(state.time + h, h) {
            Some(Ok(rules)) => Problem::RhsAndRules(q, rules),
            // Only a relaxation can fail, and it does not depend on the pore pressure: the
            // fixed system of this `h` fails the same way and the engine reports it.
            Some(Err(_)) | None => Problem::Rhs(q),
        };
        Ok((loads, problem))
    }

    fn after_solve(
        &self,
        _: &mut Loads,
        _: &State<D>,
        _: &[f64],
        _: &[f64],
    ) -> Result<Option<Problem<D>>, Self::Error> {
        Ok(None)
    }

    fn finish(
        &self,
        loads: Loads,
        state: &mut State<D>,
        sigma: Vec<f64>,
        z: &[f64],
        h: f64,
    ) -> Result<FemStats, Self::Error> {
        let asm = &self.assembly;
        // z = Wσ + q is h·(−V ε̇ᵖ) per point: the plastic strain increment is ‖z_p‖ / V_p.
        for (p, v) in asm.gauss_volumes.iter().enumerate() {
            let dz = (0..D)
                .map(|k| z[D * p + k] * z[D * p + k])
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
        // The force each boundary applies: M a + Bᵀσ − f on its prescribed dofs.
        let prescribed_forces = prescribed_forces(
            self,
            &loads,
            &state.velocity_prescribed,
            &internal_prescribed,
            h,
        );
        let reaction = self.reported_reaction(&prescribed_forces);
        state
            .velocity_prescribed
            .copy_from_slice(&loads.prescribed_velocity);
        let dofs = asm.dofs();
        for (node, u) in state.displacement.iter_mut().enumerate() {
            for (comp, uc) in u.as_mut().iter_mut().enumerate() {
                match dofs.dof(node, comp) {
                    Some(Dof::Free(i)) => *uc += h * state.velocity_free[i],
                    Some(Dof::Prescribed(j)) => *uc += h * state.velocity_prescribed[j],
                    None => {}
                }
            }
        }
        state.sigma = sigma;
        state.time += h;
        Ok(FemStats {
            reaction_force: reaction,
            prescribed_forces,
        })
    }

    /// The lumped kinetic energy, and the largest nodal displacement beyond the largest
    /// prescribed one over the smallest side of the mesh's bounding box.
    fn motion(&self, state: &State<D>) -> Option<Motion> {
        let asm = &self.assembly;
        let energy =
            |m: &[f64], v: &[f64]| -> f64 { m.iter().zip(v).map(|(m, v)| 0.5 * m * v * v).sum() };
        let kinetic_energy = energy(&asm.lumped_mass_free, &state.velocity_free)
            + energy(&asm.lumped_mass_prescribed, &state.velocity_prescribed);
        let largest = state
            .displacement
            .iter()
            .map(|u| u.as_ref().iter().map(|c| c * c).sum::<f64>().sqrt())
            .fold(0.0, f64::max);
        let prescribed = asm
            .dofs()
            .prescribed_dofs()
            .iter()
            .map(|&(n, comp)| state.displacement[n].as_ref()[comp].abs())
            .fold(0.0, f64::max);
        let mass: f64 = asm.lumped_mass_free.iter().sum::<f64>()
            + asm.lumped_mass_prescribed.iter().sum::<f64>();
        let v_d = state
            .velocity_prescribed
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()));
        Some(Motion {
            kinetic_energy,
            prescribed_kinetic_energy: 0.5 * mass * v_d * v_d,
            free_displacement_ratio: Some((largest - prescribed).max(0.0) / self.size),
        })
    }
}
