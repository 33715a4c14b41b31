//! One MPM step of length `h` (eqs. 11–16): P2G, the reduced problem `h z = Wσ + q` on the
//! grid's free velocities solved by talus-ssn, then grid velocities, boundary corrections
//! and G2P.
use std::time::Instant;

use faer::sparse::{SparseColMat, Triplet};
use nalgebra::{SMatrix, SVector};
use talus_bipotential::FlowRule;
use talus_ssn::{Operator, ReducedSystem, Report, SolveError, Solver, Structured};

use crate::boundary::NodeCondition;
use crate::error::MpmError;
use crate::grid::{Grid, Stencil};
use crate::particles::Particles;
use crate::settings::{MpmSettings, Predictor};
use crate::transfer::{
    add_internal_force, avoid_empty_nodes, grid_to_particle, particles_to_grid, stencils,
    strain_rate, velocity_gradient,
};

/// What one sub-step did.
pub(crate) struct SubstepOutcome {
    pub report: Report,
    pub active_nodes: usize,
    pub free_dofs: usize,
    /// Force each boundary group applies to the body (N/m).
    pub group_forces: Vec<[f64; 2]>,
    pub solve_seconds: f64,
    /// Solves taken to settle the friction walls' stick/slide states (1 without them).
    pub contact_passes: usize,
    /// Newton iterations and line-search backtracks of the first friction pass.
    pub first_pass_iterations: usize,
    pub first_pass_backtracks: usize,
    pub backtracks: usize,
    /// Friction passes that reused the first pass's Schur analysis.
    pub reused_analyses: usize,
}

pub(crate) enum SubstepError {
    /// Newton failed: worth retrying with a smaller step.
    NotConverged(Box<Report>),
    Fatal(MpmError),
}

impl From<MpmError> for SubstepError {
    fn from(e: MpmError) -> Self {
        SubstepError::Fatal(e)
    }
}

/// Free or prescribed index of a grid velocity component.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Dof {
    Inactive,
    Free(usize),
    Prescribed(f64),
}

pub(crate) struct StepContext<'a> {
    pub grid: &'a Grid,
    pub conditions: &'a [NodeCondition],
    pub n_groups: usize,
    pub flow_rule: &'a FlowRule<4>,
    pub compliance: &'a SMatrix<f64, 4, 4>,
    pub gravity: [f64; 2],
    pub settings: &'a MpmSettings,
    pub reuse_analysis: bool,
}

/// Stick or slide of a node on a friction wall (Coulomb, solved by an active set: stick
/// first; a node whose tangential reaction exceeds μ times its normal one slides under the
/// force μ R_n; a sliding node whose velocity turns against that force sticks again).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Contact {
    Stick,
    /// Tangential force the wall applies to the body (N/m).
    Slide(f64),
}

/// Passes of the friction active set before the last one is accepted.
const MAX_CONTACT_PASSES: usize = 8;

/// The grid after P2G (eq. 11), with the step's dof numbering and `B`, shared by the
/// friction passes.
struct Prepared {
    stencils: Vec<Stencil>,
    mass: Vec<f64>,
    force: Vec<[f64; 2]>,
    v_old: Vec<[f64; 2]>,
    active: Vec<bool>,
    /// Every active node's components; a friction node's tangential component is a free
    /// velocity in every pass, stick or slide, so that all passes share one pattern.
    dofs: Vec<[Dof; 2]>,
    /// Lumped mass of each free velocity.
    mass_free: Vec<f64>,
    /// `B` on the free velocities (eq. 16), stuck tangential columns included.
    b: SparseColMat<usize, f64>,
}

/// One solve of eqs. 15–16 on a given set of grid conditions.
struct Solved {
    report: Report,
    sigma: Vec<f64>,
    /// ‖z_p‖ / V_p: the plastic strain increment of each particle.
    plastic_increment: Vec<f64>,
    v_new: Vec<[f64; 2]>,
    /// Force the boundary applies to the body on prescribed components (N/m).
    reaction: Vec<[f64; 2]>,
    free_dofs: usize,
    seconds: f64,
    /// Whether the solver kept the previous pass's Schur analysis.
    reused_analysis: bool,
}

impl StepContext<'_> {
    /// Advances `particles` by `h`. On error `particles` may be partly updated: the caller
    /// passes a copy.
    pub fn substep(
        &self,
        particles: &mut Particles,
        h: f64,
    ) -> Result<SubstepOutcome, SubstepError> {
        let mut stencils = stencils(self.grid, particles)?;
        let g = particles_to_grid(self.grid, particles, &stencils, self.gravity);
        let active: Vec<bool> = g.mass.iter().map(|m| *m > 0.0).collect();
        avoid_empty_nodes(self.grid, particles, &mut stencils, &active)?;
        let (dofs, mass_free) = self.numbering(&active, &g.mass);
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
            .filter(|&i| prep.active[i] && self.conditions[i].friction.is_some())
            .collect();
        let mut contact = vec![Contact::Stick; prep.mass.len()];
        let mut start: Vec<f64> = particles.stress.iter().flatten().copied().collect();
        let mut solver = None;
        let mut iterations = 0;
        let mut backtracks = 0;
        let mut first_pass = (0, 0);
        let mut reused_analyses = 0;
        let mut solve_seconds = 0.0;
        let mut pass = 0;
        let solved = loop {
            pass += 1;
            let mut solved = self.solve(particles, &prep, &contact, &start, h, &mut solver)?;
            iterations += solved.report.iterations;
            backtracks += solved.report.backtracks;
            if pass == 1 {
                first_pass = (solved.report.iterations, solved.report.backtracks);
            }
            reused_analyses += solved.reused_analysis as usize;
            solve_seconds += solved.seconds;
            solved.report.iterations = iterations;
            // Slide forces are settled to 1% of the largest friction force the floor can
            // carry: below the uncertainty of μ itself. The fixed point f = μ R_n(f)
            // contracts by about 3 per pass.
            let force_scale = friction_nodes
                .iter()
                .filter_map(|&i| {
                    let (axis, sign, mu) = self.conditions[i].friction?;
                    Some(mu * (sign * solved.reaction[i][axis]).max(0.0))
                })
                .fold(0.0, f64::max);
            let mut changed = false;
            for &i in &friction_nodes {
                let Some((axis, sign, mu)) = self.conditions[i].friction else {
                    continue;
                };
                let t = 1 - axis;
                let normal = (sign * solved.reaction[i][axis]).max(0.0);
                let next = match contact[i] {
                    Contact::Stick if solved.reaction[i][t].abs() > mu * normal => {
                        Contact::Slide(mu * normal * solved.reaction[i][t].signum())
                    }
                    Contact::Stick => Contact::Stick,
                    // Friction opposes sliding: a velocity along the force means stick.
                    Contact::Slide(f) if solved.v_new[i][t] * f > 0.0 => Contact::Stick,
                    Contact::Slide(f) => Contact::Slide(mu * normal * f.signum()),
                };
                changed |= match (contact[i], next) {
                    (Contact::Slide(a), Contact::Slide(b)) => (a - b).abs() > 1e-2 * force_scale,
                    (a, b) => a != b,
                };
                contact[i] = next;
            }
            if !changed || pass >= MAX_CONTACT_PASSES {
                if changed {
                    tracing::debug!(pass, "friction active set not settled; last pass kept");
                }
                tracing::trace!(pass, iterations, "friction active set");
                break solved;
            }
            start.copy_from_slice(&solved.sigma);
        };

        for (p, dp) in solved.plastic_increment.iter().enumerate() {
            particles.plastic_strain[p] += dp;
        }
        let mut group_forces = vec![[0.0; 2]; self.n_groups];
        for (i, c) in self.conditions.iter().enumerate() {
            for (a, owner) in c.owner.iter().enumerate() {
                if let (true, Some(k)) = (prep.active[i], *owner) {
                    group_forces[k][a] += solved.reaction[i][a];
                }
            }
        }

        // G2P (eqs. 13–14), volume and objective stress update.
        let flip = self.settings.flip_weight(h);
        for (p, s) in prep.stencils.iter().enumerate() {
            let l = velocity_gradient(s, &solved.v_new);
            let jacobian = (1.0 + h * l[0][0]) * (1.0 + h * l[1][1]) - h * h * l[0][1] * l[1][0];
            if !(jacobian > 0.0 && jacobian.is_finite()) {
                return Err(MpmError::Inverted {
                    particle: p,
                    jacobian,
                    h,
                }
                .into());
            }
            particles.volume[p] *= jacobian;
            let mut t = [0.0; 4];
            t.copy_from_slice(&solved.sigma[4 * p..4 * p + 4]);
            if self.settings.rotate_stress {
                t = rotate(t, 0.5 * h * (l[1][0] - l[0][1]));
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
            particles.position[p] = self.grid.keep_inside(particles.position[p]);
        }
        Ok(SubstepOutcome {
            report: solved.report,
            active_nodes: prep.active.iter().filter(|a| **a).count(),
            free_dofs: solved.free_dofs,
            group_forces,
            solve_seconds,
            contact_passes: pass,
            first_pass_iterations: first_pass.0,
            first_pass_backtracks: first_pass.1,
            backtracks,
            reused_analyses,
        })
    }

    /// Numbers the active nodes' velocity components: prescribed ones keep their velocity;
    /// the others, a friction node's tangential component included, are free velocities.
    fn numbering(&self, active: &[bool], mass: &[f64]) -> (Vec<[Dof; 2]>, Vec<f64>) {
        let mut dofs = vec![[Dof::Inactive; 2]; active.len()];
        let mut mass_free = Vec::new();
        for (i, c) in self.conditions.iter().enumerate() {
            if !active[i] {
                continue;
            }
            for (dof, velocity) in dofs[i].iter_mut().zip(c.velocity) {
                *dof = match velocity {
                    Some(v) => Dof::Prescribed(v),
                    None => {
                        mass_free.push(mass[i]);
                        Dof::Free(mass_free.len() - 1)
                    }
                };
            }
        }
        (dofs, mass_free)
    }

    /// Eqs. 15–16 with the walls' conditions and the friction nodes' contact states. A
    /// stuck tangential velocity stays a free velocity of the numbering but its column of
    /// `B` is zeroed: it then strains nothing, exactly as the prescribed velocity 0 it is,
    /// and the Newton matrix keeps the pattern of the step (`solver` is reused by
    /// `Solver::replace_problem`).
    fn solve(
        &self,
        particles: &Particles,
        prep: &Prepared,
        contact: &[Contact],
        start: &[f64],
        h: f64,
        solver: &mut Option<Solver<4>>,
    ) -> Result<Solved, SubstepError> {
        let n_p = particles.len();
        let n_nodes = prep.mass.len();
        // The pass's view of each component: a stuck friction component is prescribed to 0,
        // a sliding one carries the friction force as an external load.
        let mut dofs = prep.dofs.clone();
        let mut force = prep.force.clone();
        let mut b = prep.b.clone();
        for (i, c) in self.conditions.iter().enumerate() {
            let Some((axis, _, _)) = c.friction else {
                continue;
            };
            if !prep.active[i] {
                continue;
            }
            let t = 1 - axis;
            match contact[i] {
                Contact::Stick => {
                    if let Dof::Free(j) = dofs[i][t] {
                        let range = b.symbolic().col_range(j);
                        b.val_mut()[range].fill(0.0);
                    }
                    dofs[i][t] = Dof::Prescribed(0.0);
                }
                Contact::Slide(f) => force[i][t] += f,
            }
        }
        let n_free = prep.mass_free.len();

        // q of eq. 16 (`docs/derivations.md`, 'The reduced system'): −(S σₙ + B w) with
        // w = h vₙ + h² M⁻¹ f on free components and h v_D on prescribed ones.
        let w: Vec<[f64; 2]> = (0..n_nodes)
            .map(|i| {
                let mut wi = [0.0; 2];
                for a in 0..2 {
                    wi[a] = match dofs[i][a] {
                        Dof::Inactive => 0.0,
                        Dof::Free(_) => h * prep.v_old[i][a] + h * h * force[i][a] / prep.mass[i],
                        Dof::Prescribed(v) => h * v,
                    };
                }
                wi
            })
            .collect();
        let mut q = vec![0.0; 4 * n_p];
        let mut compliance = Vec::with_capacity(n_p);
        for (p, s) in prep.stencils.iter().enumerate() {
            let vol = particles.volume[p];
            let s_p = self.compliance * vol;
            let e = strain_rate(s, &w, &prep.active);
            let s_sigma = s_p * SVector::<f64, 4>::from(particles.stress[p]);
            for k in 0..4 {
                q[4 * p + k] = -(s_sigma[k] + vol * e[k]);
            }
            compliance.push(s_p);
        }

        let rules = vec![*self.flow_rule; n_p];
        let operator = Operator::Structured(Structured {
            compliance,
            b,
            lumped_mass: prep.mass_free.clone(),
            h,
        });
        let clock = Instant::now();
        let system = ReducedSystem::try_new(operator, q, rules).map_err(MpmError::Solver)?;
        let first = solver.is_none();
        let reused_analysis = match solver {
            Some(s) if self.reuse_analysis => {
                s.replace_problem(system).map_err(MpmError::Solver)?
            }
            _ => {
                *solver =
                    Some(Solver::new(system, self.settings.solver).map_err(MpmError::Solver)?);
                false
            }
        };
        let solver = solver.as_mut().expect("just set");
        let mut sigma = start.to_vec();
        if first
            && self.settings.predictor == Predictor::Elastic
            && solver.elastic_predictor(&mut sigma).is_err()
        {
            sigma.copy_from_slice(start);
        }
        let report = match solver.solve(&mut sigma) {
            Ok(r) => r,
            Err(SolveError::NotConverged(r)) => return Err(SubstepError::NotConverged(r)),
            Err(e) => return Err(MpmError::Solver(e).into()),
        };
        let seconds = clock.elapsed().as_secs_f64();

        // z = Wσ + q is h·(−V ε̇ᵖ) per particle (eq. 16).
        let z = solver.z();
        let plastic_increment = (0..n_p)
            .map(|p| {
                z[4 * p..4 * p + 4]
                    .iter()
                    .map(|v| v * v)
                    .sum::<f64>()
                    .sqrt()
                    / particles.volume[p]
            })
            .collect();

        // Grid velocities from eq. 15: v = vₙ + h M⁻¹ (f − Bᵀσ); on prescribed components
        // the boundary's force M a + Bᵀσ − f (friction included: it is part of f there).
        let mut internal = vec![[0.0; 2]; n_nodes];
        add_internal_force(
            &prep.stencils,
            &particles.volume,
            &sigma,
            &prep.active,
            &mut internal,
        );
        let mut v_new = vec![[0.0; 2]; n_nodes];
        let mut reaction = vec![[0.0; 2]; n_nodes];
        for i in 0..n_nodes {
            if !prep.active[i] {
                continue;
            }
            let m = prep.mass[i];
            for a in 0..2 {
                match dofs[i][a] {
                    Dof::Prescribed(v) => {
                        v_new[i][a] = v;
                        reaction[i][a] =
                            m * (v - prep.v_old[i][a]) / h + internal[i][a] - prep.force[i][a];
                    }
                    _ => {
                        v_new[i][a] = prep.v_old[i][a] + h * (force[i][a] - internal[i][a]) / m;
                        reaction[i][a] = force[i][a] - prep.force[i][a];
                    }
                }
            }
        }
        Ok(Solved {
            report,
            sigma,
            plastic_increment,
            v_new,
            reaction,
            free_dofs: n_free,
            seconds,
            reused_analysis,
        })
    }
}

/// `B` on the free velocity components: row block `p` is `V_p · ε̇(x_p)` in Mandel form
/// (as in talus-fem), so that `Bᵀσ` is the internal force and `W` is symmetric.
fn free_strain_operator(
    stencils: &[Stencil],
    volume: &[f64],
    dofs: &[[Dof; 2]],
    n_free: usize,
) -> Result<SparseColMat<usize, f64>, MpmError> {
    let r2 = std::f64::consts::FRAC_1_SQRT_2;
    let mut triplets = Vec::with_capacity(stencils.len() * 9 * 4);
    for (p, s) in stencils.iter().enumerate() {
        let (v, r) = (volume[p], 4 * p);
        for (i, _, g) in s.iter() {
            let entries = [
                (0, [(r, g[0]), (r + 3, r2 * g[1])]),
                (1, [(r + 1, g[1]), (r + 3, r2 * g[0])]),
            ];
            for (a, rows) in entries {
                if let Dof::Free(j) = dofs[i][a] {
                    for (row, value) in rows {
                        if value != 0.0 {
                            triplets.push(Triplet::new(row, j, v * value));
                        }
                    }
                }
            }
        }
    }
    SparseColMat::try_new_from_triplets(4 * stencils.len(), n_free, &triplets)
        .map_err(|e| MpmError::invalid("B", format!("sparse assembly failed: {e:?}")))
}

/// `R σ Rᵀ` for a rotation by `angle` in the xy plane (Mandel, σzz unchanged).
fn rotate(t: [f64; 4], angle: f64) -> [f64; 4] {
    let (s, c) = angle.sin_cos();
    let sxy = t[3] * std::f64::consts::FRAC_1_SQRT_2;
    let xx = c * c * t[0] - 2.0 * s * c * sxy + s * s * t[1];
    let yy = s * s * t[0] + 2.0 * s * c * sxy + c * c * t[1];
    let xy = s * c * (t[0] - t[1]) + (c * c - s * s) * sxy;
    [xx, yy, t[2], std::f64::consts::SQRT_2 * xy]
}
