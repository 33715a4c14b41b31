//! The background grid: square cells of side `dx` over `[x0, x0 + nx dx] × [y0, y0 + ny dx]`,
//! plus ghost node layers outside it (see [`ShapeFunction`]).
use crate::error::MpmError;
use crate::shape::ShapeFunction;
use crate::side::Side;

/// Up to 9 nodes a particle touches, with `N_i(x_p)` and `∇N_i(x_p)` (1/m).
#[derive(Debug, Clone, Copy)]
pub struct Stencil {
    pub nodes: [usize; 9],
    pub weights: [f64; 9],
    pub gradients: [[f64; 2]; 9],
    pub len: usize,
}

impl Stencil {
    pub fn iter(&self) -> impl Iterator<Item = (usize, f64, [f64; 2])> + '_ {
        (0..self.len).map(|k| (self.nodes[k], self.weights[k], self.gradients[k]))
    }
}

/// A uniform background grid. Nodes are numbered row by row, ghosts included.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    origin: [f64; 2],
    spacing: f64,
    cells: [usize; 2],
    shape: ShapeFunction,
    /// Walled sides, `[axis][low, high]`: shape functions conform to them and particles
    /// cannot cross them.
    walls: [[bool; 2]; 2],
}

impl Grid {
    /// `origin` (m) is the lower-left corner, `spacing` the cell side `dx` (m), `cells`
    /// the number of cells per axis.
    pub fn try_new(
        origin: [f64; 2],
        spacing: f64,
        cells: [usize; 2],
        shape: ShapeFunction,
    ) -> Result<Self, MpmError> {
        if !origin.iter().all(|v| v.is_finite()) {
            return Err(MpmError::invalid(
                "grid.origin",
                format!("{origin:?} must be finite"),
            ));
        }
        if !(spacing.is_finite() && spacing > 0.0) {
            return Err(MpmError::invalid(
                "grid.spacing",
                format!("{spacing} m must be finite and > 0"),
            ));
        }
        if cells.contains(&0) || cells.iter().any(|&c| c > 1 << 20) {
            return Err(MpmError::invalid(
                "grid.cells",
                format!("{cells:?} must be between 1 and 2^20 per axis"),
            ));
        }
        Ok(Self {
            origin,
            spacing,
            cells,
            shape,
            walls: [[false; 2]; 2],
        })
    }

    /// The same grid with walls on `sides`: quadratic B-splines take the open knot vector
    /// there ([`ShapeFunction::weights_1d_walled`]) and particles are kept inside.
    pub fn with_walls(mut self, sides: &[Side]) -> Self {
        for side in sides {
            let (axis, end) = side.axis_and_end();
            self.walls[axis][end] = true;
        }
        self
    }

    /// Index along the wall's normal of the nodes that carry a wall's velocity: the wall's
    /// node line for linear hats, the first ghost line for wall-conforming B-splines.
    pub fn wall_node(&self, side: Side) -> i64 {
        let (axis, end) = side.axis_and_end();
        let offset = match self.shape {
            ShapeFunction::Linear => 0,
            ShapeFunction::QuadraticBSpline => 1,
        };
        if end == 0 {
            -offset
        } else {
            self.cells[axis] as i64 + offset
        }
    }

    /// `x` moved back inside the walled sides (m).
    pub fn keep_inside(&self, mut x: [f64; 2]) -> [f64; 2] {
        let end = self.end();
        for a in 0..2 {
            if self.walls[a][0] {
                x[a] = x[a].max(self.origin[a]);
            }
            if self.walls[a][1] {
                x[a] = x[a].min(end[a]);
            }
        }
        x
    }

    pub fn origin(&self) -> [f64; 2] {
        self.origin
    }

    pub fn spacing(&self) -> f64 {
        self.spacing
    }

    pub fn cells(&self) -> [usize; 2] {
        self.cells
    }

    pub fn shape(&self) -> ShapeFunction {
        self.shape
    }

    /// Upper-right corner (m).
    pub fn end(&self) -> [f64; 2] {
        [
            self.origin[0] + self.cells[0] as f64 * self.spacing,
            self.origin[1] + self.cells[1] as f64 * self.spacing,
        ]
    }

    fn nodes_per_axis(&self, axis: usize) -> usize {
        self.cells[axis] + 1 + 2 * self.shape.padding()
    }

    /// Nodes, ghosts included.
    pub fn n_nodes(&self) -> usize {
        self.nodes_per_axis(0) * self.nodes_per_axis(1)
    }

    /// Integer coordinates `(i, j)` of node `n`: `i = 0` on the left wall, `i = nx` on the
    /// right one, negative or above `nx` for ghosts.
    pub fn node_coordinates(&self, n: usize) -> [i64; 2] {
        let pad = self.shape.padding() as i64;
        let row = self.nodes_per_axis(0);
        [(n % row) as i64 - pad, (n / row) as i64 - pad]
    }

    pub fn node_position(&self, n: usize) -> [f64; 2] {
        let [i, j] = self.node_coordinates(n);
        [
            self.origin[0] + i as f64 * self.spacing,
            self.origin[1] + j as f64 * self.spacing,
        ]
    }

    /// The stencil of a particle at `x` (m); an error if its support leaves the grid and
    /// its ghost layers (the particle left the domain).
    pub fn stencil(&self, particle: usize, x: [f64; 2]) -> Result<Stencil, MpmError> {
        self.stencil_with_kinks(particle, x, [false; 2])
    }

    /// Linear hats have a kink on each node line: a particle exactly on one takes its
    /// gradient from the cell above it, or with `below[a]` from the cell below along axis
    /// `a`. The weights are the same either way.
    pub(crate) fn stencil_with_kinks(
        &self,
        particle: usize,
        x: [f64; 2],
        below: [bool; 2],
    ) -> Result<Stencil, MpmError> {
        let pad = self.shape.padding() as i64;
        let width = self.shape.width();
        let mut axes = [(0i64, [0.0; 3], [0.0; 3]); 2];
        for a in 0..2 {
            let xi = (x[a] - self.origin[a]) / self.spacing;
            let lo = self.walls[a][0].then_some(0.0);
            let hi = self.walls[a][1].then_some(self.cells[a] as f64);
            let (base, w, dw) =
                if below[a] && xi.fract() == 0.0 && self.shape == ShapeFunction::Linear {
                    (xi as i64 - 1, [0.0, 1.0, 0.0], [-1.0, 1.0, 0.0])
                } else {
                    self.shape.weights_1d_walled(xi, lo, hi)
                };
            let last = base + width as i64 - 1;
            if !xi.is_finite() || base < -pad || last > self.cells[a] as i64 + pad {
                return Err(MpmError::ParticleLeftGrid {
                    particle,
                    position: x,
                });
            }
            axes[a] = (base, w, dw);
        }
        let row = self.nodes_per_axis(0);
        let mut s = Stencil {
            nodes: [0; 9],
            weights: [0.0; 9],
            gradients: [[0.0; 2]; 9],
            len: 0,
        };
        let inv_dx = 1.0 / self.spacing;
        let ((bx, wx, dwx), (by, wy, dwy)) = (axes[0], axes[1]);
        for b in 0..width {
            for a in 0..width {
                let i = (bx + a as i64 + pad) as usize;
                let j = (by + b as i64 + pad) as usize;
                let k = s.len;
                s.nodes[k] = j * row + i;
                s.weights[k] = wx[a] * wy[b];
                s.gradients[k] = [dwx[a] * wy[b] * inv_dx, wx[a] * dwy[b] * inv_dx];
                s.len += 1;
            }
        }
        Ok(s)
    }
}
