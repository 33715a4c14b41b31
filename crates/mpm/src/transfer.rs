//! Particle ↔ grid transfers: eq. 11 (mass and momentum to the grid, lumped mass) and
//! eqs. 13–14 (PIC/FLIP velocity and position update).
use std::f64::consts::FRAC_1_SQRT_2;

use crate::error::MpmError;
use crate::grid::{Grid, Stencil};
use crate::particles::Particles;

/// Grid quantities from the particles (eq. 11), one entry per grid node, ghosts included.
#[derive(Debug, Clone, PartialEq)]
pub struct GridMomentum {
    /// Lumped mass `m_i = Σ_p N_i(x_p) m_p` (kg/m).
    pub mass: Vec<f64>,
    /// `(Mv)_i = Σ_p N_i(x_p) m_p v_p`.
    pub momentum: Vec<[f64; 2]>,
    /// External force `f_i = Σ_p N_i(x_p) (m_p g + f_p)` (N/m).
    pub force: Vec<[f64; 2]>,
}

impl GridMomentum {
    /// `v_i = (Mv)_i / m_i` where `m_i > 0`, else 0.
    pub fn velocity(&self) -> Vec<[f64; 2]> {
        self.mass
            .iter()
            .zip(&self.momentum)
            .map(|(m, p)| {
                if *m > 0.0 {
                    [p[0] / m, p[1] / m]
                } else {
                    [0.0; 2]
                }
            })
            .collect()
    }
}

/// Every particle's stencil, in particle order.
pub fn stencils(grid: &Grid, particles: &Particles) -> Result<Vec<Stencil>, MpmError> {
    particles
        .position
        .iter()
        .enumerate()
        .map(|(p, x)| grid.stencil(p, *x))
        .collect()
}

/// Eq. 11. Sequential in particle order, so sums do not depend on the thread count.
pub fn particles_to_grid(
    grid: &Grid,
    particles: &Particles,
    stencils: &[Stencil],
    gravity: [f64; 2],
) -> GridMomentum {
    particles_to_grid_with(
        grid,
        particles,
        stencils,
        gravity,
        &particles.external_force,
    )
}

/// Eq. 11 with the particles' external forces of the sub-step, `external_force` (N/m, one
/// per particle), in place of their own.
pub fn particles_to_grid_with(
    grid: &Grid,
    particles: &Particles,
    stencils: &[Stencil],
    gravity: [f64; 2],
    external_force: &[[f64; 2]],
) -> GridMomentum {
    let n = grid.n_nodes();
    let mut g = GridMomentum {
        mass: vec![0.0; n],
        momentum: vec![[0.0; 2]; n],
        force: vec![[0.0; 2]; n],
    };
    for (p, s) in stencils.iter().enumerate() {
        let (m, v, f) = (particles.mass[p], particles.velocity[p], external_force[p]);
        for (i, w, _) in s.iter() {
            g.mass[i] += w * m;
            for a in 0..2 {
                g.momentum[i][a] += w * m * v[a];
                g.force[i][a] += w * (m * gravity[a] + f[a]);
            }
        }
    }
    g
}

/// Velocity gradient `L_ab = Σ_i w_i,a ∂_b N_i` at a particle.
pub(crate) fn velocity_gradient(s: &Stencil, w: &[[f64; 2]]) -> [[f64; 2]; 2] {
    let mut l = [[0.0; 2]; 2];
    for (i, _, g) in s.iter() {
        for a in 0..2 {
            for b in 0..2 {
                l[a][b] += w[i][a] * g[b];
            }
        }
    }
    l
}

/// Adds `Bᵀσ` (internal force, N/m) of every particle to `out` (per node).
pub(crate) fn add_internal_force(
    stencils: &[Stencil],
    volume: &[f64],
    sigma: &[f64],
    active: &[bool],
    out: &mut [[f64; 2]],
) {
    for (p, s) in stencils.iter().enumerate() {
        let v = volume[p];
        let t = &sigma[4 * p..4 * p + 4];
        let sxy = FRAC_1_SQRT_2 * t[3];
        for (i, _, g) in s.iter() {
            if active[i] {
                out[i][0] += v * (g[0] * t[0] + g[1] * sxy);
                out[i][1] += v * (g[1] * t[1] + g[0] * sxy);
            }
        }
    }
}

/// Eqs. 13–14 for one particle, with `flip` the FLIP weight α:
/// `v ← α (v + Σ N_i (v_i − v_i,n)) + (1 − α) Σ N_i v_i`, `x ← x + h v`. Eq. 13 prints
/// `h Σ N_i (v_i − v_i,n)` in the FLIP term; that `h` is a typo (a velocity increment needs
/// no time factor; see docs/conventions.md).
pub(crate) fn grid_to_particle(
    s: &Stencil,
    new: &[[f64; 2]],
    old: &[[f64; 2]],
    flip: f64,
    h: f64,
    position: &mut [f64; 2],
    velocity: &mut [f64; 2],
) {
    let mut pic = [0.0; 2];
    let mut increment = [0.0; 2];
    for (i, w, _) in s.iter() {
        for a in 0..2 {
            pic[a] += w * new[i][a];
            increment[a] += w * (new[i][a] - old[i][a]);
        }
    }
    for a in 0..2 {
        velocity[a] = flip * (velocity[a] + increment[a]) + (1.0 - flip) * pic[a];
        position[a] += h * velocity[a];
    }
}

/// Linear hats only: a particle exactly on a node line whose gradient reaches a node
/// without mass (outside the active grid) takes it from the cell on the other side; if
/// that node is empty too, the particle has no gradient along that axis. Keeps
/// `Σ_i ∇N_i = 0` over active nodes, so a translation strains nothing.
pub(crate) fn avoid_empty_nodes(
    grid: &Grid,
    particles: &Particles,
    stencils: &mut [Stencil],
    active: &[bool],
) -> Result<(), MpmError> {
    for (p, s) in stencils.iter_mut().enumerate() {
        let reaches_empty = |s: &Stencil, axis: usize| {
            s.iter()
                .any(|(i, w, g)| w == 0.0 && g[axis] != 0.0 && !active[i])
        };
        let below = [reaches_empty(s, 0), reaches_empty(s, 1)];
        if !below.contains(&true) {
            continue;
        }
        *s = grid.stencil_with_kinks(p, particles.position[p], below)?;
        for (axis, &flipped) in below.iter().enumerate() {
            if flipped && reaches_empty(s, axis) {
                for k in 0..s.len {
                    s.gradients[k][axis] = 0.0;
                }
            }
        }
    }
    Ok(())
}
