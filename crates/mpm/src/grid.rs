//! The background grid: cubic cells of side `dx` over `[x0, x0 + nx dx] × [y0, y0 + ny dx]`
//! (× `[z0, z0 + nz dx]` in 3D), plus ghost node layers outside it (see [`ShapeFunction`]).
use crate::dimension::{Dimension, Mandel, Vector};
use crate::error::MpmError;
use crate::shape::ShapeFunction;
use crate::side::Side;

type Array<const D: usize, T> = <Mandel<D> as Dimension>::StencilArray<T>;

/// Up to 9 nodes (2D) or 27 (3D) a particle touches, with `N_i(x_p)` and `∇N_i(x_p)` (1/m).
#[derive(Debug, Clone, Copy)]
pub struct Stencil<const D: usize = 4>
where
    Mandel<D>: Dimension,
{
    pub nodes: Array<D, usize>,
    pub weights: Array<D, f64>,
    pub gradients: Array<D, Vector<D>>,
    pub len: usize,
}

impl<const D: usize> Stencil<D>
where
    Mandel<D>: Dimension,
{
    pub fn iter(&self) -> impl Iterator<Item = (usize, f64, Vector<D>)> + '_ {
        let (n, w, g) = (
            self.nodes.as_ref(),
            self.weights.as_ref(),
            self.gradients.as_ref(),
        );
        (0..self.len).map(move |k| (n[k], w[k], g[k]))
    }
}

/// A uniform background grid. Nodes are numbered x fastest, then y, then z, ghosts
/// included.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid<const D: usize = 4>
where
    Mandel<D>: Dimension,
{
    origin: Vector<D>,
    spacing: f64,
    cells: <Mandel<D> as Dimension>::Cells,
    shape: ShapeFunction,
    /// Walled sides, `[axis][low, high]`: shape functions conform to them and particles
    /// cannot cross them.
    walls: [[bool; 2]; 3],
}

impl Grid<4> {
    /// A 2D grid: `origin` (m) is the lower-left corner, `spacing` the cell side `dx` (m),
    /// `cells` the number of cells per axis.
    pub fn try_new(
        origin: [f64; 2],
        spacing: f64,
        cells: [usize; 2],
        shape: ShapeFunction,
    ) -> Result<Self, MpmError> {
        Self::build(origin, spacing, cells, shape)
    }
}

impl Grid<6> {
    /// A 3D grid of `cells = [nx, ny, nz]` cubes of side `spacing` (m) from the corner
    /// `origin` (m) of smallest coordinates; y is vertical.
    pub fn try_new_3d(
        origin: [f64; 3],
        spacing: f64,
        cells: [usize; 3],
        shape: ShapeFunction,
    ) -> Result<Self, MpmError> {
        Self::build(origin, spacing, cells, shape)
    }
}

impl<const D: usize> Grid<D>
where
    Mandel<D>: Dimension,
{
    fn build(
        origin: Vector<D>,
        spacing: f64,
        cells: <Mandel<D> as Dimension>::Cells,
        shape: ShapeFunction,
    ) -> Result<Self, MpmError> {
        if !origin.as_ref().iter().all(|v| v.is_finite()) {
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
        if cells.as_ref().contains(&0) || cells.as_ref().iter().any(|&c| c > 1 << 20) {
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
            walls: [[false; 2]; 3],
        })
    }

    /// Space dimensions: 2 or 3.
    pub fn axes(&self) -> usize {
        Mandel::<D>::AXES
    }

    /// The same grid with walls on `sides`: quadratic B-splines take the open knot vector
    /// there ([`ShapeFunction::weights_1d_walled`]) and particles are kept inside. A z side
    /// of a 2D grid is ignored (`Mpm` refuses it).
    pub fn with_walls(mut self, sides: &[Side]) -> Self {
        for side in sides {
            let (axis, end) = side.axis_and_end();
            if axis < Mandel::<D>::AXES {
                self.walls[axis][end] = true;
            }
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
            self.cells.as_ref().get(axis).copied().unwrap_or(0) as i64 + offset
        }
    }

    /// `x` moved back inside the walled sides (m).
    pub fn keep_inside(&self, mut x: Vector<D>) -> Vector<D> {
        let end = self.end();
        for a in 0..Mandel::<D>::AXES {
            if self.walls[a][0] {
                x[a] = x[a].max(self.origin[a]);
            }
            if self.walls[a][1] {
                x[a] = x[a].min(end[a]);
            }
        }
        x
    }

    pub fn origin(&self) -> Vector<D> {
        self.origin
    }

    pub fn spacing(&self) -> f64 {
        self.spacing
    }

    pub fn cells(&self) -> <Mandel<D> as Dimension>::Cells {
        self.cells
    }

    pub fn shape(&self) -> ShapeFunction {
        self.shape
    }

    /// The corner of largest coordinates (m).
    pub fn end(&self) -> Vector<D> {
        let mut e = self.origin;
        for a in 0..Mandel::<D>::AXES {
            e[a] = self.origin[a] + self.cells[a] as f64 * self.spacing;
        }
        e
    }

    fn nodes_per_axis(&self, axis: usize) -> usize {
        self.cells[axis] + 1 + 2 * self.shape.padding()
    }

    /// Nodes, ghosts included.
    pub fn n_nodes(&self) -> usize {
        (0..Mandel::<D>::AXES)
            .map(|a| self.nodes_per_axis(a))
            .product()
    }

    /// Integer coordinates `(i, j[, k])` of node `n`: `i = 0` on the left wall, `i = nx` on
    /// the right one, negative or above `nx` for ghosts.
    pub fn node_coordinates(&self, n: usize) -> <Mandel<D> as Dimension>::NodeCoordinates {
        let pad = self.shape.padding() as i64;
        let mut c = <Mandel<D> as Dimension>::NodeCoordinates::default();
        let mut rest = n;
        for a in 0..Mandel::<D>::AXES {
            let row = self.nodes_per_axis(a);
            c[a] = (rest % row) as i64 - pad;
            rest /= row;
        }
        c
    }

    pub fn node_position(&self, n: usize) -> Vector<D> {
        let c = self.node_coordinates(n);
        let mut x = self.origin;
        for a in 0..Mandel::<D>::AXES {
            x[a] = self.origin[a] + c[a] as f64 * self.spacing;
        }
        x
    }

    /// The stencil of a particle at `x` (m); an error if its support leaves the grid and
    /// its ghost layers (the particle left the domain).
    pub fn stencil(&self, particle: usize, x: Vector<D>) -> Result<Stencil<D>, MpmError> {
        self.stencil_with_kinks(particle, x, [false; 3])
    }

    /// Linear hats have a kink on each node line: a particle exactly on one takes its
    /// gradient from the cell above it, or with `below[a]` from the cell below along axis
    /// `a`. The weights are the same either way.
    pub(crate) fn stencil_with_kinks(
        &self,
        particle: usize,
        x: Vector<D>,
        below: [bool; 3],
    ) -> Result<Stencil<D>, MpmError> {
        let n_axes = Mandel::<D>::AXES;
        let pad = self.shape.padding() as i64;
        let width = self.shape.width();
        let mut axes = [(0i64, [0.0; 3], [0.0; 3]); 3];
        for a in 0..n_axes {
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
                    position: x.as_ref().to_vec(),
                });
            }
            axes[a] = (base, w, dw);
        }
        let mut s = Stencil::<D> {
            nodes: Default::default(),
            weights: Default::default(),
            gradients: Default::default(),
            len: 0,
        };
        let inv_dx = 1.0 / self.spacing;
        // Tensor products, x fastest; each product is formed axis by axis from 1.0, so a
        // 2D weight is `wx · wy` to the last bit.
        for k in 0..width.pow(n_axes as u32) {
            let mut node = 0;
            let mut local = [0; 3];
            let mut rest = k;
            for l in local.iter_mut().take(n_axes) {
                *l = rest % width;
                rest /= width;
            }
            for a in (0..n_axes).rev() {
                node = node * self.nodes_per_axis(a) + (axes[a].0 + local[a] as i64 + pad) as usize;
            }
            let mut w = 1.0;
            for a in 0..n_axes {
                w *= axes[a].1[local[a]];
            }
            let mut g = Vector::<D>::default();
            for c in 0..n_axes {
                let mut v = 1.0;
                for a in 0..n_axes {
                    v *= if a == c {
                        axes[a].2[local[a]]
                    } else {
                        axes[a].1[local[a]]
                    };
                }
                g[c] = v * inv_dx;
            }
            s.nodes.as_mut()[k] = node;
            s.weights.as_mut()[k] = w;
            s.gradients.as_mut()[k] = g;
            s.len += 1;
        }
        Ok(s)
    }
}
