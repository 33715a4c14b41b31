//! One MPM sub-step of length `h` (eqs. 11–16), in the order a stepping engine drives it:
//! [`Mpm::begin_substep`] (P2G and the first reduced problem), [`Substep::after_solve`]
//! after each converged solve (the friction walls' active set may ask for another), and
//! [`Substep::finish`] (grid velocities, G2P). The Newton solves are the caller's.
use talus_ssn::ReducedSystem;

use crate::contact::{self, Contact, MAX_CONTACT_PASSES};
use crate::dimension::{Dimension, Mandel, Vector};
use crate::error::MpmError;
use crate::loads::SubstepLoads;
use crate::particles::Particles;
use crate::reduced_problem::{
    free_strain_operator, numbering, pass_system, solved, Dof, PassView, Prepared, Solved,
};
use crate::transfer::{
    add_internal_force, avoid_empty_nodes, grid_to_particle, particles_to_grid_with, stencils,
    velocity_gradient,
};
use crate::Mpm;

/// A sub-step between its P2G and its G2P.
pub struct Substep<const D: usize = 4>
where
    Mandel<D>: Dimension,
{
    h: f64,
    prep: Prepared<D>,
    friction_nodes: Vec<usize>,
    contact: Vec<Contact>,
    view: PassView<D>,
    passes: usize,
    last: Option<Solved<D>>,
}

/// What a sub-step measured.
#[derive(Debug, Clone, PartialEq)]
pub struct SubstepStats<const D: usize = 4>
where
    Mandel<D>: Dimension,
{
    /// Grid nodes carrying mass, and free velocity components.
    pub active_nodes: usize,
    pub free_dofs: usize,
    /// Force each wall, then each prescribed-velocity box, applies to the material (N/m):
    /// `M a + Bᵀσ − f` on its nodes, friction included.
    pub group_forces: Vec<Vector<D>>,
    /// Solves taken to settle the friction walls' stick/slide states (1 without them).
    pub contact_passes: usize,
}

impl<const D: usize> Mpm<D>
where
    Mandel<D>: Dimension,
{
    /// P2G (eq. 11) and the reduced problem of eq. 16 for a sub-step of `h` from
    /// `particles`, under the constant loads, with the friction nodes in the stick/slide
    /// states the particles' stresses predict (`MpmSettings::contact_predictor`; every node
    /// stuck without it).
    pub fn begin_substep(
        &self,
        particles: &Particles<D>,
        h: f64,
    ) -> Result<(Substep<D>, ReducedSystem<D>), MpmError> {
        self.begin_substep_with(particles, h, &SubstepLoads::default())
    }

    /// As [`Mpm::begin_substep`], under the loads of the sub-step's end `tₙ₊₁` (gravity,
    /// prescribed velocities and particle forces scaled or replaced by `loads`).
    pub fn begin_substep_with(
        &self,
        particles: &Particles<D>,
        h: f64,
        loads: &SubstepLoads<D>,
    ) -> Result<(Substep<D>, ReducedSystem<D>), MpmError> {
        if !(h.is_finite() && h > 0.0) {
            return Err(MpmError::invalid(
                "h",
                format!("{h} s must be finite and > 0"),
            ));
        }
        particles.validate()?;
        self.check_material_indices(particles)?;
        loads.validate(self.boundary().prescribed.len(), particles.len())?;
        let grid = self.grid();
        let conditions = self.conditions();
        let mut stencils = stencils(grid, particles)?;
        let mut gravity = self.gravity();
        for a in 0..Mandel::<D>::AXES {
            gravity[a] *= loads.gravity;
        }
        let external_force = loads
            .external_force
            .as_deref()
            .unwrap_or(&particles.external_force);
        let g = particles_to_grid_with(grid, particles, &stencils, gravity, external_force);
        let active: Vec<bool> = g.mass.iter().map(|m| *m > 0.0).collect();
        avoid_empty_nodes(grid, particles, &mut stencils, &active)?;
        let (dofs, mass_free) = numbering(conditions, &active, &g.mass, loads);
        let b = free_strain_operator(&stencils, &particles.volume, &dofs, mass_free.len())?;
        let prep = Prepared {
            v_old: g.velocity(),
            active,
            stencils,
            mass: g.mass,
            force: g.force,
            dofs,
            mass_free,
            b,
        };
        let friction_nodes: Vec<usize> = (0..prep.mass.len())
            .filter(|&i| prep.active[i] && conditions[i].friction.is_some())
            .collect();
        let mut contact = vec![Contact::Stick; prep.mass.len()];
        if self.settings().contact_predictor && !friction_nodes.is_empty() {
            // The states the last stresses imply: `update` from all stuck, on the reactions
            // that would hold the friction nodes at rest.
            let reaction = stuck_reactions(&prep, particles, &friction_nodes, h);
            contact::update(
                conditions,
                &friction_nodes,
                &reaction,
                &prep.v_old,
                &mut contact,
            );
        }
        let (system, view) = pass_system(
            conditions,
            self.rules(),
            self.materials(),
            particles,
            &prep,
            &contact,
            h,
        )?;
        Ok((
            Substep {
                h,
                prep,
                friction_nodes,
                contact,
                view,
                passes: 0,
                last: None,
            },
            system,
        ))
    }
}

/// The force each friction node's wall would apply to hold it at its prescribed normal
/// velocity and at rest tangentially under the particles' stresses `σₙ`:
/// `M (v − vₙ)/h + Bᵀσₙ − f`, the reaction of `reduced_problem::solved` at the start of the
/// sub-step (zero on other nodes).
fn stuck_reactions<const D: usize>(
    prep: &Prepared<D>,
    particles: &Particles<D>,
    friction_nodes: &[usize],
    h: f64,
) -> Vec<Vector<D>>
where
    Mandel<D>: Dimension,
{
    let n_nodes = prep.mass.len();
    let mut internal = vec![Vector::<D>::default(); n_nodes];
    add_internal_force(
        &prep.stencils,
        &particles.volume,
        particles.stress.as_flattened(),
        &prep.active,
        &mut internal,
    );
    let mut reaction = vec![Vector::<D>::default(); n_nodes];
    for &i in friction_nodes {
        for a in 0..Mandel::<D>::AXES {
            let v = match prep.dofs[i][a] {
                Dof::Prescribed(v) => v,
                _ => 0.0,
            };
            reaction[i][a] =
                prep.mass[i] * (v - prep.v_old[i][a]) / h + internal[i][a] - prep.force[i][a];
        }
    }
    reaction
}

impl<const D: usize> Substep<D>
where
    Mandel<D>: Dimension,
{
    /// After a converged solve of the current problem (`sigma`, `z = Wσ + q`): updates the
    /// friction walls' stick/slide states; `Some` is the next problem to solve (from
    /// `sigma`) while they change, `None` once they settle (or after
    /// `MAX_CONTACT_PASSES`, keeping the last pass).
    pub fn after_solve(
        &mut self,
        mpm: &Mpm<D>,
        particles: &Particles<D>,
        sigma: &[f64],
        z: &[f64],
    ) -> Result<Option<ReducedSystem<D>>, MpmError> {
        self.passes += 1;
        let s = solved(particles, &self.prep, &self.view, sigma, z, self.h);
        let changes = contact::update(
            mpm.conditions(),
            &self.friction_nodes,
            &s.reaction,
            &s.v_new,
            &mut self.contact,
        );
        tracing::debug!(pass = self.passes, ?changes, "friction pass");
        let changed = changes.any();
        self.last = Some(s);
        if !changed || self.passes >= MAX_CONTACT_PASSES {
            if changed {
                tracing::debug!(
                    passes = self.passes,
                    "friction active set not settled; last pass kept"
                );
            }
            return Ok(None);
        }
        let (system, view) = pass_system(
            mpm.conditions(),
            mpm.rules(),
            mpm.materials(),
            particles,
            &self.prep,
            &self.contact,
            self.h,
        )?;
        self.view = view;
        Ok(Some(system))
    }

    /// G2P (eqs. 13–14) from the last solve's stress `sigma`: plastic strain, volumes,
    /// objective stresses, velocities and positions. On error `particles` may be partly
    /// updated: the caller passes a copy.
    pub fn finish(
        self,
        mpm: &Mpm<D>,
        particles: &mut Particles<D>,
        sigma: Vec<f64>,
    ) -> Result<SubstepStats<D>, MpmError> {
        let h = self.h;
        let Some(solved) = self.last else {
            return Err(MpmError::invalid(
                "substep",
                "finished before a solve was accepted",
            ));
        };
        let prep = &self.prep;
        for (p, dp) in solved.plastic_increment.iter().enumerate() {
            particles.plastic_strain[p] += dp;
        }
        let mut group_forces = vec![Vector::<D>::default(); mpm.boundary().n_groups()];
        // Each component's force goes to the condition that prescribes it
        // (`NodeCondition::owner`, `docs/scenes.md`, 'Reactions').
        for (i, c) in mpm.conditions().iter().enumerate() {
            for (a, owner) in c.owner.iter().enumerate().take(Mandel::<D>::AXES) {
                if let (true, Some(k)) = (prep.active[i], *owner) {
                    group_forces[k][a] += solved.reaction[i][a];
                }
            }
        }
        let settings = mpm.settings();
        let flip = settings.flip_weight(h);
        for (p, s) in prep.stencils.iter().enumerate() {
            let l = velocity_gradient(s, &solved.v_new);
            let jacobian = Mandel::<D>::jacobian(&l, h);
            if !(jacobian > 0.0 && jacobian.is_finite()) {
                return Err(MpmError::Inverted {
                    particle: p,
                    jacobian,
                    h,
                });
            }
            particles.volume[p] *= jacobian;
            let mut t = [0.0; D];
            t.copy_from_slice(&sigma[D * p..D * p + D]);
            if settings.rotate_stress {
                Mandel::<D>::rotate(&mut t, &l, h);
            }
            particles.stress[p] = t;
            grid_to_particle(
                s,
                &solved.v_new,
                &prep.v_old,
                flip,
                h,
                &mut particles.position[p],
                &mut particles.velocity[p],
            );
            particles.position[p] = mpm.grid().keep_inside(particles.position[p]);
        }
        Ok(SubstepStats {
            active_nodes: prep.active.iter().filter(|a| **a).count(),
            free_dofs: prep.mass_free.len(),
            group_forces,
            contact_passes: self.passes,
        })
    }
}
