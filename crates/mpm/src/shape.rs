//! Shape functions `N_i` of the background grid (Sulsky et al. 1994; Steffen et al. 2008):
//! tensor products of 1D linear hats or quadratic B-splines centred at the nodes. The
//! quadratic B-spline is C¹, so a particle crossing a cell face sees no jump in `∇N_i`
//! (the cell-crossing noise of linear MPM).

/// Which 1D basis the grid uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ShapeFunction {
    /// Hat functions: support 2 cells, 2 nodes per axis (4 per particle).
    Linear,
    /// Quadratic B-splines: support 3 cells, 3 nodes per axis (9 per particle).
    #[default]
    QuadraticBSpline,
}

impl ShapeFunction {
    /// Nodes per axis a particle touches.
    pub fn width(&self) -> usize {
        match self {
            ShapeFunction::Linear => 2,
            ShapeFunction::QuadraticBSpline => 3,
        }
    }

    /// Ghost node layers kept outside the grid on each side, so that a particle slightly
    /// past a wall still has its whole stencil.
    pub(crate) fn padding(&self) -> usize {
        match self {
            ShapeFunction::Linear => 1,
            ShapeFunction::QuadraticBSpline => 2,
        }
    }

    /// For a coordinate `xi` in grid units (node `k` at `xi = k`): the first node of the
    /// stencil, the weights and their derivatives in grid units (divide by `dx`).
    pub fn weights_1d(&self, xi: f64) -> (i64, [f64; 3], [f64; 3]) {
        match self {
            ShapeFunction::Linear => {
                let base = xi.floor();
                let f = xi - base;
                (base as i64, [1.0 - f, f, 0.0], [-1.0, 1.0, 0.0])
            }
            ShapeFunction::QuadraticBSpline => {
                let base = (xi - 0.5).floor();
                let f = xi - base; // in [0.5, 1.5)
                let w = [
                    0.5 * (1.5 - f) * (1.5 - f),
                    0.75 - (f - 1.0) * (f - 1.0),
                    0.5 * (f - 0.5) * (f - 0.5),
                ];
                let dw = [f - 1.5, -2.0 * (f - 1.0), f - 0.5];
                (base as i64, w, dw)
            }
        }
    }
}

/// The quadratic B-spline on knots `t` (non-decreasing, repeats allowed, `0/0 := 0`) and
/// its derivative at `x`, by the Cox–de Boor recursion.
fn quadratic_bspline(t: [f64; 4], x: f64) -> (f64, f64) {
    let step = |a: f64, b: f64| if a <= x && x < b { 1.0 } else { 0.0 };
    let div = |num: f64, den: f64| if den > 0.0 { num / den } else { 0.0 };
    let (b0, b1, b2) = (step(t[0], t[1]), step(t[1], t[2]), step(t[2], t[3]));
    let l0 = div(x - t[0], t[1] - t[0]) * b0 + div(t[2] - x, t[2] - t[1]) * b1;
    let l1 = div(x - t[1], t[2] - t[1]) * b1 + div(t[3] - x, t[3] - t[2]) * b2;
    let value = div(x - t[0], t[2] - t[0]) * l0 + div(t[3] - x, t[3] - t[1]) * l1;
    (value, 2.0 * (div(l0, t[2] - t[0]) - div(l1, t[3] - t[1])))
}

impl ShapeFunction {
    /// As [`ShapeFunction::weights_1d`], on a grid walled at `lo` and/or `hi` (grid units,
    /// node lines). Quadratic B-splines then use the open knot vector at a wall: node `k`
    /// keeps its knots `k − 1.5 … k + 1.5` clamped to `[lo, hi]`, so the basis still sums to
    /// one inside, and at the wall only the first ghost node's function is non-zero (it
    /// carries the wall's velocity exactly). `xi` is clamped into the walled interval.
    pub fn weights_1d_walled(
        &self,
        xi: f64,
        lo: Option<f64>,
        hi: Option<f64>,
    ) -> (i64, [f64; 3], [f64; 3]) {
        let mut x = xi;
        if let Some(lo) = lo {
            x = x.max(lo);
        }
        if let Some(hi) = hi {
            // Half-open knot spans: stay just inside the last one.
            x = x.min(hi - 1e-12 * (1.0 + hi.abs()));
        }
        let near = |w: Option<f64>| w.is_some_and(|w| (x - w).abs() < 1.5);
        if *self == ShapeFunction::Linear || !(near(lo) || near(hi)) {
            return self.weights_1d(x);
        }
        let base = (x - 0.5).floor();
        let clamp = |k: f64| {
            let k = lo.map_or(k, |lo| k.max(lo));
            hi.map_or(k, |hi| k.min(hi))
        };
        let mut w = [0.0; 3];
        let mut dw = [0.0; 3];
        for a in 0..3 {
            let k = base + a as f64;
            let t = [k - 1.5, k - 0.5, k + 0.5, k + 1.5].map(clamp);
            (w[a], dw[a]) = quadratic_bspline(t, x);
        }
        (base as i64, w, dw)
    }
}
