//! The implicit MPM's fixed data: a grid with its boundary conditions, one Drucker-Prager
//! material, gravity, and the settings of the transfers.
use nalgebra::SMatrix;
use talus_bipotential::{DruckerPrager, FlowRule};

use crate::boundary::{GridBoundary, NodeCondition};
use crate::error::MpmError;
use crate::grid::Grid;
use crate::settings::MpmSettings;
use crate::side::Side;

/// The implicit MPM: [`Mpm::begin_substep`] starts a sub-step of a [`Particles`] set
/// (`crate::Particles`); a stepping engine solves its reduced problems.
#[derive(Debug, Clone)]
pub struct Mpm {
    grid: Grid,
    boundary: GridBoundary,
    conditions: Vec<NodeCondition>,
    flow_rule: FlowRule<4>,
    compliance: SMatrix<f64, 4, 4>,
    gravity: [f64; 2],
    settings: MpmSettings,
}

impl Mpm {
    /// `gravity` in m/s².
    pub fn try_new(
        grid: Grid,
        boundary: GridBoundary,
        material: &DruckerPrager,
        gravity: [f64; 2],
        settings: MpmSettings,
    ) -> Result<Self, MpmError> {
        boundary.validate()?;
        if !gravity.iter().all(|g| g.is_finite()) {
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
            flow_rule: material.flow_rule::<4>(),
            compliance: material.compliance::<4>(),
            gravity,
            settings,
        })
    }

    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    pub fn boundary(&self) -> &GridBoundary {
        &self.boundary
    }

    pub fn settings(&self) -> &MpmSettings {
        &self.settings
    }

    pub fn gravity(&self) -> [f64; 2] {
        self.gravity
    }

    pub(crate) fn conditions(&self) -> &[NodeCondition] {
        &self.conditions
    }

    pub(crate) fn flow_rule(&self) -> &FlowRule<4> {
        &self.flow_rule
    }

    pub(crate) fn compliance(&self) -> &SMatrix<f64, 4, 4> {
        &self.compliance
    }
}
