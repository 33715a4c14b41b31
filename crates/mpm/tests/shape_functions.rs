//! Reproducing conditions of the MPM basis (Steffen, Kirby & Berzins 2008, "Analysis and
//! reduction of quadrature errors in the material point method"; Sulsky et al. 1994):
//! the tensor-product hats and quadratic B-splines form a partition of unity,
//! `Σ N_i = 1`, `Σ ∇N_i = 0`, reproduce linear fields, `Σ N_i x_i = x_p` and
//! `Σ x_i ⊗ ∇N_i = I`, and `∇N_i` is the derivative of `N_i` (checked by central finite
//! differences, away from the kinks of the linear hat). A particle whose stencil leaves
//! the grid and its ghost layers is reported as `MpmError::ParticleLeftGrid`.
use proptest::prelude::*;
use talus_mpm::transfer::stencils;
use talus_mpm::{Grid, MpmError, Particles, ShapeFunction, Stencil};

const SHAPES: [ShapeFunction; 2] = [ShapeFunction::Linear, ShapeFunction::QuadraticBSpline];

fn grid(shape: ShapeFunction) -> Grid {
    // An origin off zero and a spacing that is not a power of two, so nothing is exact
    // by accident.
    Grid::try_new([-0.31, 0.17], 0.07, [9, 6], shape).unwrap()
}

/// `N_i(x)` for node `i` (0 outside the stencil).
fn weight(grid: &Grid, node: usize, x: [f64; 2]) -> f64 {
    let s = grid.stencil(0, x).unwrap();
    let found = s.iter().find(|(i, _, _)| *i == node);
    found.map_or(0.0, |(_, w, _)| w)
}

/// Distance from `x` to the nearest grid line, in grid units (the kinks of the hats).
fn distance_to_grid_lines(grid: &Grid, x: [f64; 2]) -> f64 {
    (0..2)
        .map(|a| {
            let xi = (x[a] - grid.origin()[a]) / grid.spacing();
            (xi - xi.round()).abs()
        })
        .fold(f64::INFINITY, f64::min)
}

fn check_reproduction(grid: &Grid, s: &Stencil, x: [f64; 2]) {
    let dx = grid.spacing();
    assert_eq!(s.len, grid.shape().width().pow(2));
    let mut sum_w = 0.0;
    let mut sum_grad = [0.0; 2];
    let mut first_moment = [0.0; 2];
    let mut grad_moment = [[0.0; 2]; 2];
    for (i, w, g) in s.iter() {
        assert!(w >= 0.0, "N_{i}({x:?}) = {w} < 0");
        let xi = grid.node_position(i);
        sum_w += w;
        for a in 0..2 {
            sum_grad[a] += g[a];
            first_moment[a] += w * xi[a];
            for b in 0..2 {
                grad_moment[a][b] += xi[a] * g[b];
            }
        }
    }
    assert!((sum_w - 1.0).abs() <= 1e-14, "Σ N_i = {sum_w} at {x:?}");
    // ∇N_i is O(1/dx): compare Σ ∇N_i with 1/dx.
    for a in 0..2 {
        assert!(
            sum_grad[a].abs() * dx <= 1e-14,
            "Σ ∇N_i = {sum_grad:?} at {x:?}"
        );
        assert!(
            (first_moment[a] - x[a]).abs() <= 1e-14 * (1.0 + x[a].abs()),
            "Σ N_i x_i = {first_moment:?} ≠ {x:?}"
        );
        for b in 0..2 {
            let identity = if a == b { 1.0 } else { 0.0 };
            // Terms are |x_i| / dx ≈ 10: round-off of 9 of them is ~1e-14.
            assert!(
                (grad_moment[a][b] - identity).abs() <= 1e-12,
                "Σ x_i ⊗ ∇N_i = {grad_moment:?} ≠ I at {x:?}"
            );
        }
    }
}

fn check_finite_differences(grid: &Grid, s: &Stencil, x: [f64; 2]) {
    let dx = grid.spacing();
    let delta = 1e-6 * dx;
    for (i, _, g) in s.iter() {
        for a in 0..2 {
            let (mut xp, mut xm) = (x, x);
            xp[a] += delta;
            xm[a] -= delta;
            let fd = (weight(grid, i, xp) - weight(grid, i, xm)) / (2.0 * delta);
            // Round-off of the difference is ~1e-16 / 1e-6 = 1e-10 in grid units; the
            // B-spline is C¹ and piecewise quadratic, so crossing one of its knots costs
            // O(delta) = 1e-6 at most.
            assert!(
                (fd - g[a]).abs() * dx <= 1e-5,
                "∂N_{i}/∂x_{a} at {x:?}: analytic {} vs finite differences {fd}",
                g[a]
            );
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn reproduction_and_gradients(u in 0.0..1.0f64, v in 0.0..1.0f64, quadratic: bool) {
        let shape = SHAPES[quadratic as usize];
        let grid = grid(shape);
        let (o, e) = (grid.origin(), grid.end());
        let x = [o[0] + u * (e[0] - o[0]), o[1] + v * (e[1] - o[1])];
        let s = grid.stencil(0, x).unwrap();
        check_reproduction(&grid, &s, x);
        if shape == ShapeFunction::QuadraticBSpline || distance_to_grid_lines(&grid, x) > 1e-4 {
            check_finite_differences(&grid, &s, x);
        }
    }

    /// Inside the ghost band (a particle may go 1 cell past a wall with hats, 1.5 cells
    /// with B-splines; here a quarter to three quarters of that) the stencil is still
    /// whole, so the same identities hold.
    #[test]
    fn reproduction_in_the_ghost_band(t in -0.49..0.49f64, quadratic: bool) {
        let shape = SHAPES[quadratic as usize];
        let grid = grid(shape);
        let reach = if quadratic { 1.5 } else { 1.0 };
        let (o, e) = (grid.origin(), grid.end());
        let dx = grid.spacing();
        for x in [
            [o[0] - reach * dx * (1.0 + t) / 2.0, o[1] + 0.5 * (e[1] - o[1])],
            [e[0] + reach * dx * (1.0 + t) / 2.0, o[1] + 0.5 * (e[1] - o[1])],
            [o[0] + 0.5 * (e[0] - o[0]), o[1] - reach * dx * (1.0 + t) / 2.0],
            [o[0] + 0.5 * (e[0] - o[0]), e[1] + reach * dx * (1.0 + t) / 2.0],
        ] {
            let s = grid.stencil(0, x).unwrap();
            check_reproduction(&grid, &s, x);
        }
    }
}

/// 1D closed forms at a few points (grid units): hat `1 − |ξ|`; quadratic B-spline
/// `3/4 − ξ²` for `|ξ| ≤ 1/2`, `(3/2 − |ξ|)²/2` for `1/2 ≤ |ξ| ≤ 3/2`.
#[test]
fn one_dimensional_closed_forms() {
    fn hat(r: f64) -> f64 {
        (1.0 - r.abs()).max(0.0)
    }
    fn bspline(r: f64) -> f64 {
        let r = r.abs();
        if r <= 0.5 {
            0.75 - r * r
        } else if r <= 1.5 {
            0.5 * (1.5 - r).powi(2)
        } else {
            0.0
        }
    }
    for xi in [-1.3, -0.5, 0.0, 0.2, 0.49, 0.5, 0.51, 1.0, 2.75, 7.999] {
        for (shape, n) in [
            (ShapeFunction::Linear, hat as fn(f64) -> f64),
            (ShapeFunction::QuadraticBSpline, bspline),
        ] {
            let (base, w, _) = shape.weights_1d(xi);
            for (k, wk) in w.iter().enumerate().take(shape.width()) {
                let node = base + k as i64;
                let expected = n(xi - node as f64);
                assert!(
                    (wk - expected).abs() <= 1e-15,
                    "{shape:?} at ξ = {xi}: node {node} weight {wk} vs {expected}"
                );
            }
            // The nodes left out carry no weight.
            for node in [base - 1, base + shape.width() as i64] {
                assert!(
                    n(xi - node as f64) <= 1e-15,
                    "{shape:?} at ξ = {xi}: node {node} left out"
                );
            }
        }
    }
}

#[test]
fn particle_beyond_the_ghost_layers_left_the_grid() {
    for shape in SHAPES {
        let grid = grid(shape);
        let (o, e) = (grid.origin(), grid.end());
        let dx = grid.spacing();
        let mid = [0.5 * (o[0] + e[0]), 0.5 * (o[1] + e[1])];
        // Hats keep 1 ghost layer (a particle may reach 1 cell past a wall), B-splines 2
        // (1.5 cells): 2.5 cells out is beyond both.
        let outside = [
            [o[0] - 2.5 * dx, mid[1]],
            [e[0] + 2.5 * dx, mid[1]],
            [mid[0], o[1] - 2.5 * dx],
            [mid[0], e[1] + 2.5 * dx],
            [f64::NAN, mid[1]],
        ];
        for x in outside {
            let mut particles = Particles::default();
            particles.push(mid, 1.0, 1.0);
            particles.push(x, 1.0, 1.0);
            match stencils(&grid, &particles) {
                Err(MpmError::ParticleLeftGrid { particle, position }) => {
                    assert_eq!(particle, 1, "{shape:?} at {x:?}");
                    assert_eq!(position[1].to_bits(), x[1].to_bits());
                }
                other => panic!("{shape:?}: particle at {x:?} gave {other:?}"),
            }
        }
        // Just inside the last ghost layer the stencil exists.
        let reach = if shape == ShapeFunction::Linear {
            0.99
        } else {
            1.49
        };
        for x in [[o[0] - reach * dx, mid[1]], [e[0] + reach * dx, mid[1]]] {
            assert!(
                grid.stencil(0, x).is_ok(),
                "{shape:?}: {x:?} is inside the ghost band"
            );
        }
    }
}
