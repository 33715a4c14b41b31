//! Particle ↔ grid transfers: eq. 11 (mass and momentum to the grid, lumped mass) and
//! eqs. 13–14 (PIC/FLIP velocity and position update), in either dimension.
use crate::dimension::{Dimension, Gradient, Mandel, Vector};
use crate::error::MpmError;
use crate::grid::{Grid, Stencil};
use crate::particles::Particles;

/// Grid quantities from the particles (eq. 11), one entry per grid node, ghosts included.
#[derive(Debug, Clone, PartialEq)]
pub struct GridMomentum<const D: usize = 4>
where
    Mandel<D>: Dimension,
{
    /// Lumped mass `m_i = Σ_p N_i(x_p) m_p` (kg/m in 2D, kg in 3D).
    pub mass: Vec<f64>,
    /// `(Mv)_i = Σ_p N_i(x_p) m_p v_p`.
    pub momentum: Vec<Vector<D>>,
    /// External force `f_i = Σ_p N_i(x_p) (m_p g + f_p)` (N/m in 2D, N in 3D).
    pub force: Vec<Vector<D>>,
}

impl<const D: usize> GridMomentum<D>
where
    Mandel<D>: Dimension,
{
    /// `v_i = (Mv)_i / m_i` where `m_i > 0`, else 0.
    pub fn velocity(&self) -> Vec<Vector<D>> {
        self.mass
            .iter()
            .zip(&self.momentum)
            .map(|(m, p)| {
                let mut v = Vector::<D>::default();
                if *m > 0.0 {
                    for a in 0..Mandel::<D>::AXES {
                        v[a] = p[a] / m;
                    }
                }
                v
            })
            .collect()
    }
}

/// Every particle's stencil, in particle order.
pub fn stencils<const D: usize>(
    grid: &Grid<D>,
    particles: &Particles<D>,
) -> Result<Vec<Stencil<D>>, MpmError>
where
    Mandel<D>: Dimension,
{
    particles
        .position
        .iter()
        .enumerate()
        .map(|(p, x)| grid.stencil(p, *x))
        .collect()
}

/// Eq. 11. Sequential in particle order, so sums do not depend on the thread count.
pub fn particles_to_grid<const D: usize>(
    grid: &Grid<D>,
    particles: &Particles<D>,
    stencils: &[Stencil<D>],
    gravity: Vector<D>,
) -> GridMomentum<D>
where
    Mandel<D>: Dimension,
{
    particles_to_grid_with(
        grid,
        particles,
        stencils,
        gravity,
        &particles.external_force,
    )
}

/// Eq. 11 with the particles' external forces of the sub-step, `external_force` (one per
/// particle), in place of their own.
pub fn particles_to_grid_with<const D: usize>(
    grid: &Grid<D>,
    particles: &Particles<D>,
    stencils: &[Stencil<D>],
    gravity: Vector<D>,
    external_force: &[Vector<D>],
) -> GridMomentum<D>
where
    Mandel<D>: Dimension,
{
    let n = grid.n_nodes();
    let mut g = GridMomentum {
        mass: vec![0.0; n],
        momentum: vec![Vector::<D>::default(); n],
        force: vec![Vector::<D>::default(); n],
    };
    for (p, s) in stencils.iter().enumerate() {
        let (m, v, f) = (particles.mass[p], particles.velocity[p], external_force[p]);
        for (i, w, _) in s.iter() {
            g.mass[i] += w * m;
            for a in 0..Mandel::<D>::AXES {
                g.momentum[i][a] += w * m * v[a];
                g.force[i][a] += w * (m * gravity[a] + f[a]);
            }
        }
    }
    g
}

/// Velocity gradient `L_ab = Σ_i w_i,a ∂_b N_i` at a particle.
pub(crate) fn velocity_gradient<const D: usize>(s: &Stencil<D>, w: &[Vector<D>]) -> Gradient
where
    Mandel<D>: Dimension,
{
    let n = Mandel::<D>::AXES;
    let mut l = [[0.0; 3]; 3];
    for (i, _, g) in s.iter() {
        for a in 0..n {
            for b in 0..n {
                l[a][b] += w[i][a] * g[b];
            }
        }
    }
    l
}

/// Adds `Bᵀσ` (internal force) of every particle to `out` (per node).
pub(crate) fn add_internal_force<const D: usize>(
    stencils: &[Stencil<D>],
    volume: &[f64],
    sigma: &[f64],
    active: &[bool],
    out: &mut [Vector<D>],
) where
    Mandel<D>: Dimension,
{
    for (p, s) in stencils.iter().enumerate() {
        let v = volume[p];
        let t = &sigma[D * p..D * p + D];
        for (i, _, g) in s.iter() {
            if active[i] {
                let f = Mandel::<D>::internal_force(&g, t);
                for a in 0..Mandel::<D>::AXES {
                    out[i][a] += v * f[a];
                }
            }
        }
    }
}

/// Eqs. 13–14 for one particle, with `flip` the FLIP weight α:
/// `v ← α (v + Σ N_i (v_i − v_i,n)) + (1 − α) Σ N_i v_i`, `x ← x + h v`. Eq. 13 prints
/// `h Σ N_i (v_i − v_i,n)` in the FLIP term; that `h` is a typo (a velocity increment needs
/// no time factor; see docs/conventions.md).
pub(crate) fn grid_to_particle<const D: usize>(
    s: &Stencil<D>,
    new: &[Vector<D>],
    old: &[Vector<D>],
    flip: f64,
    h: f64,
    position: &mut Vector<D>,
    velocity: &mut Vector<D>,
) where
    Mandel<D>: Dimension,
{
    let n = Mandel::<D>::AXES;
    let mut pic = [0.0; 3];
    let mut increment = [0.0; 3];
    for (i, w, _) in s.iter() {
        for a in 0..n {
            pic[a] += w * new[i][a];
            increment[a] += w * (new[i][a] - old[i][a]);
        }
    }
    for a in 0..n {
        velocity[a] = flip * (velocity[a] + increment[a]) + (1.0 - flip) * pic[a];
        position[a] += h * velocity[a];
    }
}

/// Linear hats only: a particle exactly on a node line whose gradient reaches a node
/// without mass (outside the active grid) takes it from the cell on the other side; if
/// that node is empty too, the particle has no gradient along that axis. Keeps
/// `Σ_i ∇N_i = 0` over active nodes, so a translation strains nothing.
pub(crate) fn avoid_empty_nodes<const D: usize>(
    grid: &Grid<D>,
    particles: &Particles<D>,
    stencils: &mut [Stencil<D>],
    active: &[bool],
) -> Result<(), MpmError>
where
    Mandel<D>: Dimension,
{
    let n = Mandel::<D>::AXES;
    for (p, s) in stencils.iter_mut().enumerate() {
        let reaches_empty = |s: &Stencil<D>, axis: usize| {
            s.iter()
                .any(|(i, w, g)| w == 0.0 && g[axis] != 0.0 && !active[i])
        };
        let mut below = [false; 3];
        for (a, b) in below.iter_mut().enumerate().take(n) {
            *b = reaches_empty(s, a);
        }
        if !below.contains(&true) {
            continue;
        }
        *s = grid.stencil_with_kinks(p, particles.position[p], below)?;
        for (axis, &flipped) in below.iter().enumerate() {
            if flipped && reaches_empty(s, axis) {
                for k in 0..s.len {
                    s.gradients.as_mut()[k][axis] = 0.0;
                }
            }
        }
    }
    Ok(())
}
