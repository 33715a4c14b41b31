//! Grid boundary conditions, applied to nodes (ghost layers included) at or beyond a wall,
//! or inside a box.
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
    /// normal force the wall carried (a rough floor). `coefficient` = μ ≥ 0.
    Friction { coefficient: f64 },
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wall {
    pub side: Side,
    pub condition: WallCondition,
}

/// Nodes inside `region` (`[[xmin, ymin], [xmax, ymax]]`, m) move with the given velocity
/// components (m/s); `None` leaves a component free. A rigid footing, a moving wall.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PrescribedVelocity {
    pub region: [[f64; 2]; 2],
    pub velocity: [Option<f64>; 2],
}

/// Every condition of a scene's grid. Later entries win where they overlap: walls first,
/// then prescribed velocities in order. Per velocity component: a component's velocity and
/// the force that enforces it belong to the last condition that prescribes it
/// (`docs/scenes.md`, 'Reactions').
#[derive(Debug, Clone, PartialEq, Default)]
pub struct GridBoundary {
    pub walls: Vec<Wall>,
    pub prescribed: Vec<PrescribedVelocity>,
}

/// Per node: prescribed velocity per component, and the friction wall it lies on.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct NodeCondition {
    pub velocity: [Option<f64>; 2],
    /// The prescribed box that set each component's velocity (`None`: a wall's zero), whose
    /// multiplier scales it in a sub-step (`crate::SubstepLoads`).
    pub source: [Option<usize>; 2],
    /// (normal axis, inward normal sign, μ).
    pub friction: Option<(usize, f64, f64)>,
    /// Per component, the wall or box (index in walls, then prescribed) whose velocity it
    /// follows, for the force it applies: the last one that prescribes it; the tangential
    /// component of a friction node that nothing prescribes belongs to its friction wall
    /// (the friction force).
    pub owner: [Option<usize>; 2],
}

impl GridBoundary {
    pub(crate) fn validate(&self) -> Result<(), MpmError> {
        for (k, w) in self.walls.iter().enumerate() {
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
            let [[x0, y0], [x1, y1]] = p.region;
            if !(p.region.iter().flatten().all(|v| v.is_finite()) && x1 >= x0 && y1 >= y0) {
                return Err(MpmError::invalid(
                    format!("prescribed[{k}].region"),
                    format!("{:?} must be finite with max ≥ min", p.region),
                ));
            }
            if !p.velocity.iter().flatten().all(|v| v.is_finite()) {
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
    pub(crate) fn node_conditions(&self, grid: &Grid) -> Vec<NodeCondition> {
        (0..grid.n_nodes())
            .map(|n| {
                let [i, j] = grid.node_coordinates(n);
                let x = grid.node_position(n);
                let mut c = NodeCondition::default();
                for (k, w) in self.walls.iter().enumerate() {
                    let line = grid.wall_node(w.side);
                    let on_wall = match w.side {
                        Side::Left => i <= line,
                        Side::Right => i >= line,
                        Side::Bottom => j <= line,
                        Side::Top => j >= line,
                    };
                    if !on_wall {
                        continue;
                    }
                    let (axis, sign) = w.side.normal();
                    match w.condition {
                        WallCondition::Fixed => {
                            c.velocity = [Some(0.0); 2];
                            c.owner = [Some(k); 2];
                            c.source = [None; 2];
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
                            if c.velocity[1 - axis].is_none() {
                                c.friction = Some((axis, sign, coefficient));
                                c.owner[1 - axis] = Some(k);
                            }
                        }
                    }
                }
                // A tolerance of 1e-9 dx so that a box edge on a grid line includes it.
                let eps = 1e-9 * grid.spacing();
                for (k, p) in self.prescribed.iter().enumerate() {
                    let [[x0, y0], [x1, y1]] = p.region;
                    let inside = x[0] >= x0 - eps
                        && x[0] <= x1 + eps
                        && x[1] >= y0 - eps
                        && x[1] <= y1 + eps;
                    if inside {
                        for a in 0..2 {
                            if let Some(v) = p.velocity[a] {
                                c.velocity[a] = Some(v);
                                c.owner[a] = Some(self.walls.len() + k);
                                c.source[a] = Some(k);
                            }
                        }
                        if c.velocity.iter().all(Option::is_some) {
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
        assert_eq!(at(0, 0).owner, [Some(1), Some(3)]);
        // Bottom-right corner: the friction wall prescribes x; y stays the floor's.
        assert_eq!(at(4, 0).owner, [Some(2), Some(0)]);
        // The friction wall's free tangential component carries its friction force.
        assert_eq!(at(4, 2).owner, [Some(2), Some(2)]);
        assert!(at(4, 2).friction.is_some());
        // A slip side alone: only its normal component.
        assert_eq!(at(0, 3).owner, [Some(1), Some(3)]);
        assert_eq!(at(0, 4).owner[0], Some(1));
        assert_eq!(at(2, 2).owner, [None, None]);
    }
}
