//! Grid boundary conditions, applied to nodes (ghost layers included) at or beyond a wall,
//! or inside a box.
use crate::dimension::{Dimension, Mandel, Vector};
use crate::error::MpmError;
use crate::grid::Grid;
use crate::side::Side;

/// What a wall does to the grid velocity of its nodes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum WallCondition {
    /// No slip: both components zero.
    Fixed,
    /// Normal component zero, tangential free.
    Slip,
    /// Normal component zero; tangential velocity reduced by Coulomb friction with the
    /// normal force the wall carried (a rough floor). `coefficient` = μ ≥ 0. In 3D the
    /// friction force is a vector of the wall's plane, of length ≤ μ R_n (Coulomb's cone).
    Friction { coefficient: f64 },
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wall {
    pub side: Side,
    pub condition: WallCondition,
}

/// Nodes inside `region` (`[[xmin, ymin], [xmax, ymax]]`, m; 3D: `[[xmin, ymin, zmin],
/// [xmax, ymax, zmax]]`) move with the given velocity components (m/s); `None` leaves a
/// component free. A rigid footing, a moving wall.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PrescribedVelocity<const D: usize = 4>
where
    Mandel<D>: Dimension,
{
    pub region: [Vector<D>; 2],
    pub velocity: <Mandel<D> as Dimension>::Components,
}

/// Every condition of a scene's grid. Later entries win where they overlap: walls first,
/// then prescribed velocities in order. Per velocity component: a component's velocity and
/// the force that enforces it belong to the last condition that prescribes it
/// (`docs/scenes.md`, 'Reactions').
#[derive(Debug, Clone, PartialEq)]
pub struct GridBoundary<const D: usize = 4>
where
    Mandel<D>: Dimension,
{
    pub walls: Vec<Wall>,
    pub prescribed: Vec<PrescribedVelocity<D>>,
}

impl<const D: usize> Default for GridBoundary<D>
where
    Mandel<D>: Dimension,
{
    fn default() -> Self {
        Self {
            walls: Vec::new(),
            prescribed: Vec::new(),
        }
    }
}

/// A friction wall's hold on a node: the normal axis, the inward normal's sign, μ, and the
/// tangential components it acts on (those no earlier condition prescribed).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct Friction {
    pub axis: usize,
    pub sign: f64,
    pub mu: f64,
    pub tangential: [bool; 3],
}

impl Friction {
    /// The tangential components it acts on.
    pub fn components(&self) -> impl Iterator<Item = usize> + '_ {
        (0..3).filter(|&a| self.tangential[a])
    }
}

/// Per node: prescribed velocity per component (3 entries, the last unused in 2D), and the
/// friction wall it lies on.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct NodeCondition {
    pub velocity: [Option<f64>; 3],
    /// The prescribed box that set each component's velocity (`None`: a wall's zero), whose
    /// multiplier scales it in a sub-step (`crate::SubstepLoads`).
    pub source: [Option<usize>; 3],
    pub friction: Option<Friction>,
    /// Per component, the wall or box (index in walls, then prescribed) whose velocity it
    /// follows, for the force it applies: the last one that prescribes it; the tangential
    /// component of a friction node that nothing prescribes belongs to its friction wall
    /// (the friction force).
    pub owner: [Option<usize>; 3],
}

impl<const D: usize> GridBoundary<D>
where
    Mandel<D>: Dimension,
{
    pub(crate) fn validate(&self) -> Result<(), MpmError> {
        let n = Mandel::<D>::AXES;
        for (k, w) in self.walls.iter().enumerate() {
            if w.side.axis_and_end().0 >= n {
                return Err(MpmError::invalid(
                    format!("walls[{k}].side"),
                    format!("{:?} is a z side: a 2D grid has none", w.side),
                ));
            }
            if let WallCondition::Friction { coefficient } = w.condition {
                if !(coefficient.is_finite() && coefficient >= 0.0) {
                    return Err(MpmError::invalid(
                        format!("walls[{k}].friction"),
                        format!("{coefficient} must be finite and ≥ 0"),
                    ));
                }
            }
        }
        for (k, p) in self.prescribed.iter().enumerate() {
            let [lo, hi] = p.region;
            let finite = p
                .region
                .iter()
                .all(|x| x.as_ref().iter().all(|v| v.is_finite()));
            if !(finite && (0..n).all(|a| hi[a] >= lo[a])) {
                return Err(MpmError::invalid(
                    format!("prescribed[{k}].region"),
                    format!("{:?} must be finite with max ≥ min", p.region),
                ));
            }
            if !p.velocity.as_ref().iter().flatten().all(|v| v.is_finite()) {
                return Err(MpmError::invalid(
                    format!("prescribed[{k}].velocity"),
                    format!("{:?} must be finite", p.velocity),
                ));
            }
        }
        Ok(())
    }

    /// Number of groups whose force is reported: walls, then prescribed boxes.
    pub fn n_groups(&self) -> usize {
        self.walls.len() + self.prescribed.len()
    }

    /// The condition of every node of `grid`.
    pub(crate) fn node_conditions(&self, grid: &Grid<D>) -> Vec<NodeCondition> {
        let n_axes = Mandel::<D>::AXES;
        (0..grid.n_nodes())
            .map(|n| {
                let ij = grid.node_coordinates(n);
                let x = grid.node_position(n);
                let mut c = NodeCondition::default();
                for (k, w) in self.walls.iter().enumerate() {
                    let line = grid.wall_node(w.side);
                    let (normal_axis, end) = w.side.axis_and_end();
                    let on_wall = match end {
                        0 => ij[normal_axis] <= line,
                        _ => ij[normal_axis] >= line,
                    };
                    if !on_wall {
                        continue;
                    }
                    let (axis, sign) = w.side.normal();
                    match w.condition {
                        WallCondition::Fixed => {
                            for a in 0..n_axes {
                                c.velocity[a] = Some(0.0);
                                c.owner[a] = Some(k);
                                c.source[a] = None;
                            }
                            c.friction = None;
                        }
                        WallCondition::Slip => {
                            c.velocity[axis] = Some(0.0);
                            c.owner[axis] = Some(k);
                            c.source[axis] = None;
                        }
                        WallCondition::Friction { coefficient } => {
                            c.velocity[axis] = Some(0.0);
                            c.owner[axis] = Some(k);
                            c.source[axis] = None;
                            let mut tangential = [false; 3];
                            for t in (0..n_axes).filter(|&t| t != axis) {
                                tangential[t] = c.velocity[t].is_none();
                            }
                            if tangential.contains(&true) {
                                c.friction = Some(Friction {
                                    axis,
                                    sign,
                                    mu: coefficient,
                                    tangential,
                                });
                                for t in (0..3).filter(|&t| tangential[t]) {
                                    c.owner[t] = Some(k);
                                }
                            }
                        }
                    }
                }
                // A tolerance of 1e-9 dx so that a box edge on a grid line includes it.
                let eps = 1e-9 * grid.spacing();
                for (k, p) in self.prescribed.iter().enumerate() {
                    let [lo, hi] = p.region;
                    let inside = (0..n_axes).all(|a| x[a] >= lo[a] - eps && x[a] <= hi[a] + eps);
                    if inside {
                        for a in 0..n_axes {
                            if let Some(v) = p.velocity.as_ref()[a] {
                                c.velocity[a] = Some(v);
                                c.owner[a] = Some(self.walls.len() + k);
                                c.source[a] = Some(k);
                            }
                        }
                        if c.velocity[..n_axes].iter().all(Option::is_some) {
                            c.friction = None;
                        }
                    }
                }
                c
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shape::ShapeFunction;

    #[test]
    fn each_component_belongs_to_the_last_condition_that_prescribes_it() {
        let boundary = GridBoundary {
            walls: vec![
                Wall {
                    side: Side::Bottom,
                    condition: WallCondition::Fixed,
                },
                Wall {
                    side: Side::Left,
                    condition: WallCondition::Slip,
                },
                Wall {
                    side: Side::Right,
                    condition: WallCondition::Friction { coefficient: 0.5 },
                },
            ],
            prescribed: vec![PrescribedVelocity {
                region: [[0.0, 0.0], [0.1, 0.4]],
                velocity: [None, Some(-1.0)],
            }],
        };
        let grid = Grid::try_new([0.0, 0.0], 0.1, [4, 4], ShapeFunction::Linear)
            .unwrap()
            .with_walls(&[Side::Bottom, Side::Left, Side::Right]);
        let conditions = boundary.node_conditions(&grid);
        let at = |i: i64, j: i64| {
            let n = (0..grid.n_nodes())
                .find(|&n| grid.node_coordinates(n) == [i, j])
                .unwrap();
            conditions[n]
        };
        // Bottom-left corner: x from the slip side (later), y from the box (latest).
        assert_eq!(at(0, 0).owner, [Some(1), Some(3), None]);
        // Bottom-right corner: the friction wall prescribes x; y stays the floor's.
        assert_eq!(at(4, 0).owner, [Some(2), Some(0), None]);
        // The friction wall's free tangential component carries its friction force.
        assert_eq!(at(4, 2).owner, [Some(2), Some(2), None]);
        assert!(at(4, 2).friction.is_some());
        // A slip side alone: only its normal component.
        assert_eq!(at(0, 3).owner, [Some(1), Some(3), None]);
        assert_eq!(at(0, 4).owner[0], Some(1));
        assert_eq!(at(2, 2).owner, [None, None, None]);
    }
}
