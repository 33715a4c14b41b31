//! Collapse: a load-controlled body past its capacity accelerates without bound. The run
//! loop reads each accepted step's [`Motion`] and ends the run when the criterion of
//! `docs/scenes.md` ('Collapse') holds, for FEM and MPM alike.

/// A state's motion as the collapse watch reads it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Motion {
    /// `½ Σ m v²` (J/m).
    pub kinetic_energy: f64,
    /// `½ Σ m · v_D²` with `v_D` the largest prescribed speed (J/m): the kinetic energy of
    /// the whole body moving as fast as its fastest boundary. A mechanism driven by its
    /// boundaries moves at a few times their speed; a collapse outgrows it without bound.
    pub prescribed_kinetic_energy: f64,
    /// Small strains (FEM): the largest nodal displacement beyond the largest prescribed
    /// one, over the smallest side of the body's bounding box. `None` for a method made
    /// for large deformations (MPM), whose motion alone never ends a run: there a collapse
    /// is what makes a step fail by leaving the grid
    /// ([`Discretization::left_domain`](crate::Discretization::left_domain)).
    pub free_displacement_ratio: Option<f64>,
}

/// The displacement, as a fraction of the body's smallest side, past which a small-strain
/// body whose kinetic energy keeps rising has collapsed: strains of order 10%, two orders
/// past the elastic range of soils, that no equilibrium of the small-strain model reaches.
pub const COLLAPSE_DISPLACEMENT_RATIO: f64 = 0.1;

/// Consecutive accepted steps over which the kinetic energy must have risen: motion that
/// accelerates, not the transient of a load applied at once (which the implicit steps damp
/// within a step or two) nor motion at a prescribed rate (constant energy).
pub const COLLAPSE_RISING_STEPS: usize = 3;

/// The kinetic energy, over the prescribed one of [`Motion`], past which the motion is no
/// longer the boundaries' doing: the body as a whole ten times faster than its fastest
/// boundary.
pub const COLLAPSE_ENERGY_RATIO: f64 = 100.0;

/// Why the watch called a collapse.
#[derive(Debug, Clone, PartialEq)]
pub struct Collapse {
    pub kinetic_energy: f64,
    /// The displacement ratio of [`Motion`] (`None`: MPM, a step left the grid).
    pub free_displacement_ratio: Option<f64>,
}

impl std::fmt::Display for Collapse {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.free_displacement_ratio {
            Some(r) => write!(
                f,
                "the body moved {:.1}% of its smallest side beyond its prescribed boundaries \
                 (collapse past {:.0}%) with its kinetic energy rising over the last {} steps \
                 to {:.3e} J/m: the loads exceed what the body can carry",
                100.0 * r,
                100.0 * COLLAPSE_DISPLACEMENT_RATIO,
                COLLAPSE_RISING_STEPS,
                self.kinetic_energy
            ),
            None => write!(
                f,
                "material left the grid while its kinetic energy had risen over the last {} \
                 steps to {:.3e} J/m: the loads exceed what the body can carry",
                COLLAPSE_RISING_STEPS, self.kinetic_energy
            ),
        }
    }
}

/// The kinetic energy of the last accepted steps.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CollapseWatch {
    last: Option<f64>,
    /// Accepted steps in a row whose kinetic energy exceeded the one before.
    rising: usize,
}

impl CollapseWatch {
    pub fn new() -> Self {
        Self::default()
    }

    /// After an accepted step: the collapse when the small-strain criterion holds.
    pub fn observe(&mut self, motion: &Motion) -> Option<Collapse> {
        let e = motion.kinetic_energy;
        self.rising = match self.last {
            Some(last) if e > last => self.rising + 1,
            _ => 0,
        };
        self.last = Some(e);
        let ratio = motion.free_displacement_ratio?;
        let driven = e <= COLLAPSE_ENERGY_RATIO * motion.prescribed_kinetic_energy;
        (self.accelerating() && !driven && ratio > COLLAPSE_DISPLACEMENT_RATIO).then_some(
            Collapse {
                kinetic_energy: e,
                free_displacement_ratio: Some(ratio),
            },
        )
    }

    /// Whether the kinetic energy rose over the last [`COLLAPSE_RISING_STEPS`] steps.
    pub fn accelerating(&self) -> bool {
        self.rising >= COLLAPSE_RISING_STEPS
    }

    /// A failed step that left the domain (MPM) during accelerating motion: a collapse.
    pub fn on_leaving_domain(&self) -> Option<Collapse> {
        self.accelerating().then_some(Collapse {
            kinetic_energy: self.last.unwrap_or(0.0),
            free_displacement_ratio: None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn motion(e: f64, r: f64) -> Motion {
        Motion {
            kinetic_energy: e,
            prescribed_kinetic_energy: 0.0,
            free_displacement_ratio: Some(r),
        }
    }

    #[test]
    fn motion_at_the_pace_of_the_boundaries_is_no_collapse() {
        let mut w = CollapseWatch::new();
        for k in 0..15 {
            let m = Motion {
                kinetic_energy: k as f64,
                prescribed_kinetic_energy: 0.1,
                free_displacement_ratio: Some(0.5),
            };
            assert_eq!(w.observe(&m).is_some(), k > 10, "{k}");
        }
    }

    #[test]
    fn rising_energy_and_large_displacement_together_make_a_collapse() {
        let mut w = CollapseWatch::new();
        // Large displacement, energy rising for only 2 steps: not yet.
        assert!(w.observe(&motion(0.0, 0.5)).is_none());
        assert!(w.observe(&motion(1.0, 0.5)).is_none());
        assert!(w.observe(&motion(2.0, 0.5)).is_none());
        assert!(w.observe(&motion(3.0, 0.5)).is_some());
        // Energy falling once resets the count.
        assert!(w.observe(&motion(2.5, 0.5)).is_none());
        assert!(!w.accelerating());
    }

    #[test]
    fn rising_energy_within_small_strains_is_no_collapse() {
        let mut w = CollapseWatch::new();
        for k in 0..10 {
            assert!(w.observe(&motion(k as f64, 0.09)).is_none());
        }
        assert!(w.accelerating());
    }

    #[test]
    fn large_deformation_methods_collapse_only_when_leaving_the_domain() {
        let mut w = CollapseWatch::new();
        for k in 0..5 {
            let m = Motion {
                kinetic_energy: k as f64,
                prescribed_kinetic_energy: 0.0,
                free_displacement_ratio: None,
            };
            assert!(w.observe(&m).is_none());
        }
        assert!(w.on_leaving_domain().is_some());
        let m = Motion {
            kinetic_energy: 0.0,
            prescribed_kinetic_energy: 0.0,
            free_displacement_ratio: None,
        };
        w.observe(&m);
        assert!(w.on_leaving_domain().is_none());
    }
}
