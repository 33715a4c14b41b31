//! What a run reports about the particles besides the solver: the front of a collapsing
//! column and its runout, and the kinetic energy.
use crate::dimension::{Dimension, Mandel};
use crate::Particles;

/// Where runout is measured from: `x_left`, the left wall (or the leftmost body edge when
/// there is no left wall), and `length`, the initial extent `L₀` of the bodies from it (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunoutReference {
    pub x_left: f64,
    pub length: f64,
}

impl RunoutReference {
    /// From the bodies' rectangles and the x of the left wall, if any.
    pub fn of_bodies(
        rectangles: impl Iterator<Item = [[f64; 2]; 2]>,
        left_wall: Option<f64>,
    ) -> Self {
        let (mut x0, mut x1) = (f64::INFINITY, f64::NEG_INFINITY);
        for r in rectangles {
            x0 = x0.min(r[0][0]);
            x1 = x1.max(r[1][0]);
        }
        let x_left = left_wall.map_or(x0, |w| w.min(x0));
        Self {
            x_left,
            length: x1 - x_left,
        }
    }

    /// `(L − L₀)/L₀` with `L = front − x_left`.
    pub fn normalized(&self, front: f64) -> f64 {
        (front - self.x_left - self.length) / self.length
    }
}

/// The largest particle x (m): the front of a flow spreading to the right.
pub fn front<const D: usize>(particles: &Particles<D>) -> f64
where
    Mandel<D>: Dimension,
{
    particles
        .position
        .iter()
        .map(|p| p[0])
        .fold(f64::NEG_INFINITY, f64::max)
}

/// The largest distance of a particle from the vertical axis through `(x_c, z_c)` (m): the
/// front of a 3D flow spreading radially, `R` of Lube et al. (2004). A 2D particle lies in
/// the plane z = 0.
pub fn radial_front<const D: usize>(particles: &Particles<D>, axis: [f64; 2]) -> f64
where
    Mandel<D>: Dimension,
{
    particles
        .position
        .iter()
        .map(|p| {
            let p = p.as_ref();
            (p[0] - axis[0]).hypot(p.get(2).copied().unwrap_or(0.0) - axis[1])
        })
        .fold(f64::NEG_INFINITY, f64::max)
}

/// `½ Σ m v²` (J per metre of thickness in 2D, J in 3D).
pub fn kinetic_energy<const D: usize>(particles: &Particles<D>) -> f64
where
    Mandel<D>: Dimension,
{
    particles
        .mass
        .iter()
        .zip(&particles.velocity)
        .map(|(m, v)| {
            let mut v2 = v[0] * v[0];
            for a in 1..Mandel::<D>::AXES {
                v2 += v[a] * v[a];
            }
            0.5 * m * v2
        })
        .sum()
}
