//! The loads of one sub-step when they vary in time: eq. 16 is implicit, so a sub-step from
//! `tₙ` to `tₙ₊₁` takes the gravity, prescribed velocities and particle forces of `tₙ₊₁`.
//! The caller evaluates its load programme there; this crate only applies the values.
use crate::dimension::{Dimension, Mandel, Vector};
use crate::error::MpmError;

/// What multiplies or replaces the constant loads of an [`crate::Mpm`] in one sub-step.
/// [`SubstepLoads::default`] is the constant loading: every multiplier 1.
#[derive(Debug, Clone, PartialEq)]
pub struct SubstepLoads<const D: usize = 4>
where
    Mandel<D>: Dimension,
{
    /// Multiplier of [`crate::Mpm::gravity`].
    pub gravity: f64,
    /// Multiplier of each prescribed box's velocity, in the order of
    /// [`crate::GridBoundary::prescribed`]; empty: all 1.
    pub prescribed: Vec<f64>,
    /// Each particle's external force in this sub-step (N/m in 2D, N in 3D), in place of
    /// [`crate::Particles::external_force`]; `None`: the particles' own.
    pub external_force: Option<Vec<Vector<D>>>,
}

impl<const D: usize> Default for SubstepLoads<D>
where
    Mandel<D>: Dimension,
{
    fn default() -> Self {
        Self {
            gravity: 1.0,
            prescribed: Vec::new(),
            external_force: None,
        }
    }
}

impl<const D: usize> SubstepLoads<D>
where
    Mandel<D>: Dimension,
{
    pub(crate) fn validate(&self, n_boxes: usize, n_particles: usize) -> Result<(), MpmError> {
        if !self.gravity.is_finite() {
            return Err(MpmError::invalid(
                "loads.gravity",
                format!("multiplier {} must be finite", self.gravity),
            ));
        }
        if !(self.prescribed.is_empty() || self.prescribed.len() == n_boxes) {
            return Err(MpmError::invalid(
                "loads.prescribed",
                format!(
                    "{} multipliers for {n_boxes} prescribed boxes",
                    self.prescribed.len()
                ),
            ));
        }
        if let Some(k) = self.prescribed.iter().position(|f| !f.is_finite()) {
            return Err(MpmError::invalid(
                format!("loads.prescribed[{k}]"),
                format!("multiplier {} must be finite", self.prescribed[k]),
            ));
        }
        if let Some(force) = &self.external_force {
            if force.len() != n_particles {
                return Err(MpmError::invalid(
                    "loads.external_force",
                    format!("{} forces for {n_particles} particles", force.len()),
                ));
            }
            if let Some(p) = force
                .iter()
                .position(|f| !f.as_ref().iter().all(|v| v.is_finite()))
            {
                return Err(MpmError::invalid(
                    format!("loads.external_force[{p}]"),
                    format!("{:?} N/m must be finite", force[p]),
                ));
            }
        }
        Ok(())
    }

    /// The velocity `v` that prescribed box `k` gives a component in this sub-step.
    pub(crate) fn prescribed_velocity(&self, k: usize, v: f64) -> f64 {
        // Without multipliers, `v` itself (not `1 · v`): constant loads stay as they were.
        self.prescribed.get(k).map_or(v, |f| f * v)
    }
}
