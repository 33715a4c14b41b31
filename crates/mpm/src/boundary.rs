//! Grid boundary conditions, applied to nodes (ghost layers included) at or beyond a wall,
//! or inside a box.
use crate::error::MpmError;
use crate::grid::Grid;

/// A side of the grid.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    Left,
    Right,
    Bottom,
    Top,
}

impl Side {
    /// Axis of the normal, and 0 for the low end, 1 for the high end.
    pub(crate) fn axis_and_end(&self) -> (usize, usize) {
        match self {
            Side::Left => (0, 0),
            Side::Right => (0, 1),
            Side::Bottom => (1, 0),
            Side::Top => (1, 1),
        }
    }

    /// Axis of the wall normal and the sign of the normal pointing into the domain.
    fn normal(&self) -> (usize, f64) {
        match self {
            Side::Left => (0, 1.0),
            Side::Right => (0, -1.0),
            Side::Bottom => (1, 1.0),
            Side::Top => (1, -1.0),
        }
    }
}

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
/// then prescribed velocities in order.
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
    /// Which wall or box fixed the node last (index in walls, then prescribed), for the
    /// force it applies.
    pub owner: Option<usize>,
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
                    c.owner = Some(k);
                    match w.condition {
                        WallCondition::Fixed => {
                            c.velocity = [Some(0.0); 2];
                            c.source = [None; 2];
                            c.friction = None;
                        }
                        WallCondition::Slip => {
                            c.velocity[axis] = Some(0.0);
                            c.source[axis] = None;
                        }
                        WallCondition::Friction { coefficient } => {
                            c.velocity[axis] = Some(0.0);
                            c.source[axis] = None;
                            if c.velocity[1 - axis].is_none() {
                                c.friction = Some((axis, sign, coefficient));
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
                        c.owner = Some(self.walls.len() + k);
                        for a in 0..2 {
                            if let Some(v) = p.velocity[a] {
                                c.velocity[a] = Some(v);
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
