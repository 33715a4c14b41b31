//! Eqs. 15–16 on the grid: the numbering of the grid velocities, `B` on the free ones, the
//! reduced problem `h z = Wσ + q` of one solve under given wall contacts, and the grid
//! velocities and boundary forces that follow from its stress. One implementation for both
//! dimensions: `D` is the Mandel size (4 in 2D, 6 in 3D), `Mandel::<D>::AXES` the velocity
//! components per node.
use faer::sparse::{SparseColMat, Triplet};
use nalgebra::{SMatrix, SVector};
use talus_bipotential::{FlowRule, Material};
use talus_ssn::{
    reduced_rhs, FreeVelocities, Operator, PrescribedVelocities, ReducedSystem, Structured,
};

use crate::boundary::NodeCondition;
use crate::contact::Contact;
use crate::dimension::{Dimension, Mandel, Vector};
use crate::error::MpmError;
use crate::grid::Stencil;
use crate::loads::SubstepLoads;
use crate::particles::Particles;
use crate::transfer::add_internal_force;

/// Free or prescribed index of a grid velocity component.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Dof {
    Inactive,
    Free(usize),
    Prescribed(f64),
}

/// The grid after P2G (eq. 11), with the sub-step's dof numbering and `B`, shared by the
/// friction passes.
pub(crate) struct Prepared<const D: usize>
where
    Mandel<D>: Dimension,
{
    pub stencils: Vec<Stencil<D>>,
    pub mass: Vec<f64>,
    pub force: Vec<Vector<D>>,
    pub v_old: Vec<Vector<D>>,
    pub active: Vec<bool>,
    /// Every active node's components (the last unused in 2D); a friction node's
    /// tangential components are free velocities in every pass, stick or slide, so that
    /// all passes share one pattern.
    pub dofs: Vec<[Dof; 3]>,
    /// Lumped mass of each free velocity.
    pub mass_free: Vec<f64>,
    /// `B` on the free velocities (eq. 16), stuck tangential columns included.
    pub b: SparseColMat<usize, f64>,
}

/// One pass's view of the grid components: a stuck friction component is prescribed to 0,
/// a sliding one carries the friction force as an external load.
pub(crate) struct PassView<const D: usize>
where
    Mandel<D>: Dimension,
{
    pub dofs: Vec<[Dof; 3]>,
    pub force: Vec<Vector<D>>,
}

/// What a solve gives the grid and the particles.
pub(crate) struct Solved<const D: usize>
where
    Mandel<D>: Dimension,
{
    /// ‖z_p‖ / V_p: the plastic strain increment of each particle.
    pub plastic_increment: Vec<f64>,
    pub v_new: Vec<Vector<D>>,
    /// Force the boundary applies to the body on prescribed components (N/m in 2D, N in
    /// 3D).
    pub reaction: Vec<Vector<D>>,
}

/// Numbers the active nodes' velocity components: prescribed ones keep their velocity (a
/// box's scaled by its multiplier in `loads`); the others, a friction node's tangential
/// component included, are free velocities.
pub(crate) fn numbering<const D: usize>(
    conditions: &[NodeCondition],
    active: &[bool],
    mass: &[f64],
    loads: &SubstepLoads<D>,
) -> (Vec<[Dof; 3]>, Vec<f64>)
where
    Mandel<D>: Dimension,
{
    let n_axes = Mandel::<D>::AXES;
    let mut dofs = vec![[Dof::Inactive; 3]; active.len()];
    let mut mass_free = Vec::new();
    for (i, c) in conditions.iter().enumerate() {
        if !active[i] {
            continue;
        }
        let components = dofs[i].iter_mut().zip(c.velocity).zip(c.source);
        for ((dof, velocity), source) in components.take(n_axes) {
            *dof = match velocity {
                Some(v) => Dof::Prescribed(source.map_or(v, |k| loads.prescribed_velocity(k, v))),
                None => {
                    mass_free.push(mass[i]);
                    Dof::Free(mass_free.len() - 1)
                }
            };
        }
    }
    (dofs, mass_free)
}

/// Eqs. 15–16 with the walls' conditions and the friction nodes' contact states. A stuck
/// tangential velocity stays a free velocity of the numbering but its column of `B` is
/// zeroed: it then strains nothing, exactly as the prescribed velocity 0 it is, and the
/// Newton matrix keeps the pattern of the sub-step (the engine keeps its analysis). Each
/// particle takes the flow rule and `S_p = V_p S₀` of its material (`rules`, indexed by
/// `Particles::material`, checked when the sub-step began), with the material's Duvaut–Lions
/// relaxation `N = (τ/h) S_p⁻¹` if it has one (`Material::relaxation`).
pub(crate) fn pass_system<const D: usize>(
    conditions: &[NodeCondition],
    rules: &[(FlowRule<D>, SMatrix<f64, D, D>)],
    materials: &[Material],
    particles: &Particles<D>,
    prep: &Prepared<D>,
    contact: &[Contact],
    h: f64,
) -> Result<(ReducedSystem<D>, PassView<D>), MpmError>
where
    Mandel<D>: Dimension,
{
    let n_axes = Mandel::<D>::AXES;
    let n_p = particles.len();
    let n_nodes = prep.mass.len();
    let mut dofs = prep.dofs.clone();
    let mut force = prep.force.clone();
    let mut b = prep.b.clone();
    for (i, c) in conditions.iter().enumerate() {
        let Some(friction) = c.friction else {
            continue;
        };
        if !prep.active[i] {
            continue;
        }
        for t in friction.components() {
            match contact[i] {
                Contact::Stick => {
                    if let Dof::Free(j) = dofs[i][t] {
                        let range = b.symbolic().col_range(j);
                        b.val_mut()[range].fill(0.0);
                    }
                    dofs[i][t] = Dof::Prescribed(0.0);
                }
                Contact::Slide(f) => force[i][t] += f[t],
            }
        }
    }

    // q of eq. 16, with `B_D` on the prescribed components that move (a component at
    // rest adds nothing).
    let mut s_sigma = vec![0.0; D * n_p];
    let mut compliance_blocks = Vec::with_capacity(n_p);
    let mut flow_rules = Vec::with_capacity(n_p);
    for p in 0..n_p {
        let m = particles.material_of(p);
        let (flow_rule, compliance) = &rules[m];
        let s_p = compliance * particles.volume[p];
        let s = s_p * SVector::<f64, D>::from(particles.stress[p]);
        s_sigma[D * p..D * p + D].copy_from_slice(s.as_slice());
        compliance_blocks.push(s_p);
        let relaxation = materials[m]
            .relaxation(h, particles.volume[p])
            .map_err(|e| MpmError::invalid("relaxation_time", e.to_string()))?;
        flow_rules.push(flow_rule.with_relaxation(relaxation));
    }
    let mut v_free = vec![0.0; prep.mass_free.len()];
    let mut f_free = vec![0.0; prep.mass_free.len()];
    let mut moving = Vec::new();
    let mut column = vec![[None; 3]; n_nodes];
    for i in 0..n_nodes {
        for a in 0..n_axes {
            match dofs[i][a] {
                Dof::Free(j) => {
                    v_free[j] = prep.v_old[i][a];
                    f_free[j] = force[i][a];
                }
                Dof::Prescribed(v) if v != 0.0 => {
                    column[i][a] = Some(moving.len());
                    moving.push(v);
                }
                _ => {}
            }
        }
    }
    let b_prescribed = strain_operator::<D>(
        &prep.stencils,
        &particles.volume,
        |i, a| column[i][a],
        moving.len(),
    )?;
    let q = reduced_rhs(
        h,
        &s_sigma,
        &FreeVelocities {
            b: &b,
            velocity: &v_free,
            force: &f_free,
            lumped_mass: &prep.mass_free,
        },
        &PrescribedVelocities {
            b: &b_prescribed,
            velocity: &moving,
        },
    )
    .map_err(MpmError::Solver)?;
    let operator = Operator::Structured(Structured {
        compliance: compliance_blocks,
        b,
        lumped_mass: prep.mass_free.clone(),
        h,
    });
    let system = ReducedSystem::try_new(operator, q, flow_rules).map_err(MpmError::Solver)?;
    Ok((system, PassView { dofs, force }))
}

/// The plastic strain increments, grid velocities (eq. 15: v = vₙ + h M⁻¹ (f − Bᵀσ)) and,
/// on prescribed components, the boundary's force M a + Bᵀσ − f (friction included: it is
/// part of f there) of a solve's `sigma` and `z = Wσ + q`.
pub(crate) fn solved<const D: usize>(
    particles: &Particles<D>,
    prep: &Prepared<D>,
    view: &PassView<D>,
    sigma: &[f64],
    z: &[f64],
    h: f64,
) -> Solved<D>
where
    Mandel<D>: Dimension,
{
    // z = Wσ + q is h·(−V ε̇ᵖ) per particle (eq. 16).
    let plastic_increment = (0..particles.len())
        .map(|p| {
            z[D * p..D * p + D]
                .iter()
                .map(|v| v * v)
                .sum::<f64>()
                .sqrt()
                / particles.volume[p]
        })
        .collect();
    let n_nodes = prep.mass.len();
    let mut internal = vec![Vector::<D>::default(); n_nodes];
    add_internal_force(
        &prep.stencils,
        &particles.volume,
        sigma,
        &prep.active,
        &mut internal,
    );
    let mut v_new = vec![Vector::<D>::default(); n_nodes];
    let mut reaction = vec![Vector::<D>::default(); n_nodes];
    for i in 0..n_nodes {
        if !prep.active[i] {
            continue;
        }
        let m = prep.mass[i];
        for a in 0..Mandel::<D>::AXES {
            match view.dofs[i][a] {
                Dof::Prescribed(v) => {
                    v_new[i][a] = v;
                    reaction[i][a] =
                        m * (v - prep.v_old[i][a]) / h + internal[i][a] - prep.force[i][a];
                }
                _ => {
                    v_new[i][a] = prep.v_old[i][a] + h * (view.force[i][a] - internal[i][a]) / m;
                    reaction[i][a] = view.force[i][a] - prep.force[i][a];
                }
            }
        }
    }
    Solved {
        plastic_increment,
        v_new,
        reaction,
    }
}

/// `B` on the free velocity components: row block `p` is `V_p · ε̇(x_p)` in Mandel form
/// (as in talus-fem), so that `Bᵀσ` is the internal force and `W` is symmetric.
pub(crate) fn free_strain_operator<const D: usize>(
    stencils: &[Stencil<D>],
    volume: &[f64],
    dofs: &[[Dof; 3]],
    n_free: usize,
) -> Result<SparseColMat<usize, f64>, MpmError>
where
    Mandel<D>: Dimension,
{
    let free = |i: usize, a: usize| match dofs[i][a] {
        Dof::Free(j) => Some(j),
        _ => None,
    };
    strain_operator(stencils, volume, free, n_free)
}

/// `B` on the grid velocity components `column` numbers (node, component → column).
fn strain_operator<const D: usize>(
    stencils: &[Stencil<D>],
    volume: &[f64],
    column: impl Fn(usize, usize) -> Option<usize>,
    n_columns: usize,
) -> Result<SparseColMat<usize, f64>, MpmError>
where
    Mandel<D>: Dimension,
{
    let n_axes = Mandel::<D>::AXES;
    let width = stencils.first().map_or(0, |s| s.len);
    let mut triplets = Vec::with_capacity(stencils.len() * width * 2 * n_axes);
    for (p, s) in stencils.iter().enumerate() {
        let (v, r) = (volume[p], D * p);
        for (i, _, g) in s.iter() {
            for a in 0..n_axes {
                if let Some(j) = column(i, a) {
                    for (row, value) in Mandel::<D>::strain_rows(&g, a) {
                        if value != 0.0 {
                            triplets.push(Triplet::new(r + row, j, v * value));
                        }
                    }
                }
            }
        }
    }
    SparseColMat::try_new_from_triplets(D * stencils.len(), n_columns, &triplets)
        .map_err(|e| MpmError::invalid("B", format!("sparse assembly failed: {e:?}")))
}
