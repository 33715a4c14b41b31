//! The finite-element model as the stepping engine's [`Discretization`]: `W` fixed per `h`
//! (small strains), `q` of eq. 16 per sub-step, then velocities, displacements and the
//! reaction from eq. 15.
use talus_fem::assembly::add_mul_transpose;
use talus_ssn::{ReducedSystem, SolveError};

use super::engine::{Discretization, Loading, Motion, Problem};
use super::{Loads, Model, State};

/// What a FEM sub-step measured.
#[derive(Debug, Clone, PartialEq)]
pub struct FemStats {
    /// Reaction on the reported boundary: the force it applies to the body, vertical,
    /// positive downward, N per metre of thickness (axisymmetric: N on the whole
    /// circumference, `2π` times the per-radian force).
    pub reaction_force: f64,
    /// Force each prescribed dof's condition applies to the body (N/m, or N per radian,
    /// `reaction_groups::prescribed_forces`).
    pub prescribed_forces: Vec<f64>,
}

impl super::StepReport<FemStats> {
    /// The reported boundary's reaction at the end of the step (N/m, downward positive).
    pub fn reaction_force(&self) -> f64 {
        self.stats.as_ref().map_or(0.0, |s| s.reaction_force)
    }
}

impl Model {
    /// The reaction of the reported boundary in a state at rest (`M a = 0`): `Bᵀσ − f` on
    /// its vertical prescribed dofs, positive downward (N/m), `f` at the state's time.
    pub fn reaction(&self, state: &State) -> f64 {
        self.reported_reaction(&super::prescribed_forces_at_rest(self, state))
    }

    /// The reported boundary's vertical push on the body, downward positive, from the force
    /// of every prescribed dof; axisymmetric: on the whole circumference (`2π` times).
    fn reported_reaction(&self, prescribed_forces: &[f64]) -> f64 {
        self.reaction_dofs
            .iter()
            .filter(|(_, comp)| *comp == 1)
            .fold(0.0, |r, &(j, _)| r - prescribed_forces[j])
            * self.assembly.geometry().whole_body_factor()
    }
}

impl Discretization for Model {
    type State = State;
    /// The loads at the end of the sub-step.
    type Substep = Loads;
    type Stats = FemStats;
    type Error = std::convert::Infallible;

    fn fixed_system(&self, h: f64) -> Option<Result<ReducedSystem<4>, SolveError>> {
        Some(self.reduced_system(h))
    }

    fn time(&self, state: &State) -> f64 {
        state.time
    }

    fn stress<'s>(&self, state: &'s State) -> &'s [f64] {
        &state.sigma
    }

    /// A jump: the velocity applied over the last step is not the programme's at the
    /// step's start (the start from rest; with constant loads, the only jump), or the
    /// loading rate changes (`Model::loading_rate_changes_from`, `docs/scenes.md`, 'Load
    /// programmes').
    fn loading(&self, state: &State, h: f64) -> Loading {
        let (t0, t1) = (state.time, state.time + h);
        let velocity_jumps = state.velocity_prescribed != self.prescribed_velocity_at(t0);
        Loading {
            jumps: velocity_jumps || self.loading_rate_changes_from(t0, t1),
            changes_inside: velocity_jumps || self.loading_rate_changes_inside(t0, t1),
        }
    }

    /// Eqs. 15–16: `q = −(S σ_n + h B v_n + h² B M⁻¹ f + h B_D v_D)` with `f` and `v_D`
    /// taken at the end of the sub-step.
    fn begin(&self, state: &State, h: f64) -> Result<(Loads, Problem), Self::Error> {
        let loads = self.loads_at(state.time + h);
        let q = self.reduced_rhs_with(state, h, &loads);
        Ok((loads, Problem::Rhs(q)))
    }

    fn after_solve(
        &self,
        _: &mut Loads,
        _: &State,
        _: &[f64],
        _: &[f64],
    ) -> Result<Option<Problem>, Self::Error> {
        Ok(None)
    }

    fn finish(
        &self,
        loads: Loads,
        state: &mut State,
        sigma: Vec<f64>,
        z: &[f64],
        h: f64,
    ) -> Result<FemStats, Self::Error> {
        let asm = &self.assembly;
        // z = Wσ + q is h·(−V ε̇ᵖ) per point: the plastic strain increment is ‖z_p‖ / V_p.
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
        // The force each boundary applies: M a + Bᵀσ − f on its prescribed dofs.
        let prescribed_forces = super::prescribed_forces(
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
        if let Ok(v) = asm
            .dofs()
            .scatter(&state.velocity_free, &state.velocity_prescribed)
        {
            for (u, vn) in state.displacement.iter_mut().zip(v) {
                u[0] += h * vn[0];
                u[1] += h * vn[1];
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
    fn motion(&self, state: &State) -> Option<Motion> {
        let asm = &self.assembly;
        let energy =
            |m: &[f64], v: &[f64]| -> f64 { m.iter().zip(v).map(|(m, v)| 0.5 * m * v * v).sum() };
        let kinetic_energy = energy(&asm.lumped_mass_free, &state.velocity_free)
            + energy(&asm.lumped_mass_prescribed, &state.velocity_prescribed);
        let largest = state
            .displacement
            .iter()
            .map(|u| u[0].hypot(u[1]))
            .fold(0.0, f64::max);
        let prescribed = asm
            .dofs()
            .prescribed_dofs()
            .iter()
            .map(|&(n, comp)| state.displacement[n][comp].abs())
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
