//! The implicit MPM's fixed data: a grid with its boundary conditions, the materials
//! (Drucker-Prager or elastic; each particle names its own), gravity, and the settings of
//! the transfers.
use nalgebra::SMatrix;
use talus_bipotential::{DruckerPrager, FlowRule, Material};

use crate::boundary::{GridBoundary, NodeCondition};
use crate::dimension::{Dimension, Mandel, Vector};
use crate::error::MpmError;
use crate::grid::Grid;
use crate::settings::MpmSettings;
use crate::side::Side;

/// The implicit MPM: [`Mpm::begin_substep`] starts a sub-step of a [`Particles`] set
/// (`crate::Particles`); a stepping engine solves its reduced problems.
#[derive(Debug, Clone)]
pub struct Mpm<const D: usize = 4>
where
    Mandel<D>: Dimension,
{
    grid: Grid<D>,
    boundary: GridBoundary<D>,
    conditions: Vec<NodeCondition>,
    materials: Vec<Material>,
    /// Each material's flow rule and compliance `S₀` (1/Pa), built once.
    rules: Vec<(FlowRule<D>, SMatrix<f64, D, D>)>,
    gravity: Vector<D>,
    settings: MpmSettings,
}

impl<const D: usize> Mpm<D>
where
    Mandel<D>: Dimension,
{
    /// One Drucker-Prager material for every particle; `gravity` in m/s².
    pub fn try_new(
        grid: Grid<D>,
        boundary: GridBoundary<D>,
        material: &DruckerPrager,
        gravity: Vector<D>,
        settings: MpmSettings,
    ) -> Result<Self, MpmError> {
        Self::with_materials(
            grid,
            boundary,
            &[Material::DruckerPrager(*material)],
            gravity,
            settings,
        )
    }

    /// Several materials: particle `p` is of `materials[particles.material[p]]`
    /// ([`Particles::material`](crate::Particles::material)); `gravity` in m/s².
    pub fn with_materials(
        grid: Grid<D>,
        boundary: GridBoundary<D>,
        materials: &[Material],
        gravity: Vector<D>,
        settings: MpmSettings,
    ) -> Result<Self, MpmError> {
        if materials.is_empty() {
            return Err(MpmError::invalid(
                "materials",
                "none given: a material point model needs at least one",
            ));
        }
        boundary.validate()?;
        if !gravity.as_ref().iter().all(|g| g.is_finite()) {
            return Err(MpmError::invalid(
                "gravity",
                format!("{gravity:?} must be finite"),
            ));
        }
        let a = settings.flip_ratio;
        if !(0.0..=1.0).contains(&a) {
            return Err(MpmError::invalid(
                "flip_ratio",
                format!("{a} must be in [0, 1] (0 = PIC, 1 = FLIP)"),
            ));
        }
        if let Some(t) = settings.flip_reference_time {
            if !(t.is_finite() && t > 0.0) {
                return Err(MpmError::invalid(
                    "flip_reference_time",
                    format!("{t} s must be finite and > 0"),
                ));
            }
        }
        let sides: Vec<Side> = boundary.walls.iter().map(|w| w.side).collect();
        let grid = grid.with_walls(&sides);
        Ok(Self {
            conditions: boundary.node_conditions(&grid),
            grid,
            boundary,
            rules: materials
                .iter()
                .map(|m| (m.flow_rule::<D>(0.0), m.compliance::<D>()))
                .collect(),
            materials: materials.to_vec(),
            gravity,
            settings,
        })
    }

    pub fn grid(&self) -> &Grid<D> {
        &self.grid
    }

    pub fn boundary(&self) -> &GridBoundary<D> {
        &self.boundary
    }

    pub fn settings(&self) -> &MpmSettings {
        &self.settings
    }

    pub fn gravity(&self) -> Vector<D> {
        self.gravity
    }

    pub(crate) fn conditions(&self) -> &[NodeCondition] {
        &self.conditions
    }

    /// The materials, indexed by [`Particles::material`](crate::Particles::material).
    pub fn materials(&self) -> &[Material] {
        &self.materials
    }

    /// Each material's rate-independent flow rule and compliance `S₀`, in the order of
    /// [`Mpm::materials`].
    pub(crate) fn rules(&self) -> &[(FlowRule<D>, SMatrix<f64, D, D>)] {
        &self.rules
    }

    /// Every particle's material index within [`Mpm::materials`]: an error names the
    /// first particle that is out of range and its index.
    pub(crate) fn check_material_indices(
        &self,
        particles: &crate::Particles<D>,
    ) -> Result<(), MpmError> {
        let n = self.materials.len();
        match particles.material.iter().position(|&m| m >= n) {
            None => Ok(()),
            Some(p) => Err(MpmError::invalid(
                format!("particles.material[{p}]"),
                format!(
                    "particle {p} is of material {}, but the model has {n} material{} \
                     (indices 0..{n})",
                    particles.material[p],
                    if n == 1 { "" } else { "s" }
                ),
            )),
        }
    }
}
