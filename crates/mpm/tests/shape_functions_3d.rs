//! Reproducing conditions of the 3D MPM basis, the tensor product of the 1D hats or
//! quadratic B-splines along x, y and z (Steffen, Kirby & Berzins 2008, "Analysis and
//! reduction of quadrature errors in the material point method", §2; Sulsky et al. 1994):
//! a partition of unity, `Σ N_i = 1` and `Σ ∇N_i = 0`, linear completeness,
//! `Σ N_i x_i = x_p` and `Σ x_i ⊗ ∇N_i = I`, and `∇N_i` the derivative of `N_i` (central
//! finite differences, away from the linear hats' kinks), on an open grid; on a grid
//! walled on all six faces (the open knot vector of `ShapeFunction::weights_1d_walled`)
//! the partition of unity and the derivatives (an open-knot basis reproduces `x` with
//! its Greville abscissae as coefficients, not with the node positions, so the moments
//! are not checked there). Bad input is refused naming the field and the value.
use proptest::prelude::*;
use talus_bipotential::{ConeFit, DruckerPrager, DruckerPragerParameters};
use talus_mpm::transfer::stencils;
use talus_mpm::{
    Grid, GridBoundary, Mpm, MpmError, MpmSettings, Particles, ShapeFunction, Side, Stencil, Wall,
    WallCondition,
};

const SHAPES: [ShapeFunction; 2] = [ShapeFunction::Linear, ShapeFunction::QuadraticBSpline];
const ALL_SIDES: [Side; 6] = [
    Side::Left,
    Side::Right,
    Side::Bottom,
    Side::Top,
    Side::Back,
    Side::Front,
];

fn grid(shape: ShapeFunction, walled: bool) -> Grid<6> {
    // An origin off zero and a spacing that is not a power of two, so nothing is exact by
    // accident; unequal cell counts, so that an axis mix-up shows.
    let g = Grid::try_new_3d([-0.31, 0.17, 0.05], 0.07, [5, 4, 6], shape).unwrap();
    if walled {
        g.with_walls(&ALL_SIDES)
    } else {
        g
    }
}

fn weight(grid: &Grid<6>, node: usize, x: [f64; 3]) -> f64 {
    let s = grid.stencil(0, x).unwrap();
    let found = s.iter().find(|(i, _, _)| *i == node);
    found.map_or(0.0, |(_, w, _)| w)
}

fn distance_to_grid_lines(grid: &Grid<6>, x: [f64; 3]) -> f64 {
    (0..3)
        .map(|a| {
            let xi = (x[a] - grid.origin()[a]) / grid.spacing();
            (xi - xi.round()).abs()
        })
        .fold(f64::INFINITY, f64::min)
}

fn check_reproduction(grid: &Grid<6>, s: &Stencil<6>, x: [f64; 3], moments: bool) {
    let dx = grid.spacing();
    assert_eq!(s.len, grid.shape().width().pow(3));
    let mut sum_w = 0.0;
    let mut sum_grad = [0.0; 3];
    let mut first_moment = [0.0; 3];
    let mut grad_moment = [[0.0; 3]; 3];
    for (i, w, g) in s.iter() {
        assert!(w >= 0.0, "N_{i}({x:?}) = {w} < 0");
        let xi = grid.node_position(i);
        sum_w += w;
        for a in 0..3 {
            sum_grad[a] += g[a];
            first_moment[a] += w * xi[a];
            for b in 0..3 {
                grad_moment[a][b] += xi[a] * g[b];
            }
        }
    }
    assert!((sum_w - 1.0).abs() <= 1e-14, "Σ N_i = {sum_w} at {x:?}");
    for a in 0..3 {
        // ∇N_i is O(1/dx); 27 terms of round-off.
        assert!(
            sum_grad[a].abs() * dx <= 1e-13,
            "Σ ∇N_i = {sum_grad:?} at {x:?}"
        );
        if !moments {
            continue;
        }
        assert!(
            (first_moment[a] - x[a]).abs() <= 1e-14 * (1.0 + x[a].abs()),
            "Σ N_i x_i = {first_moment:?} ≠ {x:?}"
        );
        for b in 0..3 {
            let identity = if a == b { 1.0 } else { 0.0 };
            // Terms are |x_i| / dx ≈ 10: round-off of 27 of them is a few 1e-14.
            assert!(
                (grad_moment[a][b] - identity).abs() <= 1e-12,
                "Σ x_i ⊗ ∇N_i = {grad_moment:?} ≠ I at {x:?}"
            );
        }
    }
}

fn check_finite_differences(grid: &Grid<6>, s: &Stencil<6>, x: [f64; 3]) {
    let dx = grid.spacing();
    let delta = 1e-6 * dx;
    for (i, _, g) in s.iter() {
        for a in 0..3 {
            let (mut xp, mut xm) = (x, x);
            xp[a] += delta;
            xm[a] -= delta;
            let fd = (weight(grid, i, xp) - weight(grid, i, xm)) / (2.0 * delta);
            // As in 2D (shape_functions.rs): round-off 1e-10, a knot crossed O(1e-6).
            assert!(
                (fd - g[a]).abs() * dx <= 1e-5,
                "∂N_{i}/∂x_{a} at {x:?}: analytic {} vs finite differences {fd}",
                g[a]
            );
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1500))]

    #[test]
    fn reproduction_and_gradients_3d(
        u in 0.0..1.0f64, v in 0.0..1.0f64, w in 0.0..1.0f64, quadratic: bool, walled: bool
    ) {
        let shape = SHAPES[quadratic as usize];
        let grid = grid(shape, walled);
        let (o, e) = (grid.origin(), grid.end());
        // Keep the finite-difference points inside a walled grid (it clamps outside).
        let m = if walled { 1e-4 } else { 0.0 };
        let t = |s: f64| m + (1.0 - 2.0 * m) * s;
        let x = [
            o[0] + t(u) * (e[0] - o[0]),
            o[1] + t(v) * (e[1] - o[1]),
            o[2] + t(w) * (e[2] - o[2]),
        ];
        let s = grid.stencil(0, x).unwrap();
        check_reproduction(&grid, &s, x, !walled);
        if shape == ShapeFunction::QuadraticBSpline || distance_to_grid_lines(&grid, x) > 1e-4 {
            check_finite_differences(&grid, &s, x);
        }
    }
}

/// The 3D weights are the products of the 1D ones (the same 1D basis the 2D grid uses).
#[test]
fn weights_are_tensor_products_of_the_1d_basis() {
    for shape in SHAPES {
        let grid = grid(shape, false);
        let x = [-0.1234, 0.2901, 0.2222];
        let s = grid.stencil(0, x).unwrap();
        let xi = (0..3).map(|a| (x[a] - grid.origin()[a]) / grid.spacing());
        let axes: Vec<_> = xi.map(|xi| shape.weights_1d(xi)).collect();
        let width = shape.width();
        for (k, (node, w, _)) in s.iter().enumerate() {
            let local = [k % width, (k / width) % width, k / (width * width)];
            let expected = axes[0].1[local[0]] * axes[1].1[local[1]] * axes[2].1[local[2]];
            assert!((w - expected).abs() <= 1e-16, "{shape:?} node {node}");
            let c = grid.node_coordinates(node);
            for a in 0..3 {
                assert_eq!(c[a], axes[a].0 + local[a] as i64, "{shape:?} axis {a}");
            }
        }
    }
}

/// At a walled face only the first ghost layer's functions are non-zero (open knots), so
/// a wall's velocity holds exactly on the face.
#[test]
fn on_a_walled_face_only_the_wall_nodes_carry_weight() {
    let grid = grid(ShapeFunction::QuadraticBSpline, true);
    let (o, e) = (grid.origin(), grid.end());
    let x = [o[0], 0.5 * (o[1] + e[1]), e[2]];
    let s = grid.stencil(0, x).unwrap();
    for (i, w, _) in s.iter() {
        let c = grid.node_coordinates(i);
        // The high face is sampled 1e-12 dx inside (half-open knot spans).
        if w > 1e-9 {
            assert_eq!(c[0], grid.wall_node(Side::Left), "node {c:?}: N = {w}");
            assert_eq!(c[2], grid.wall_node(Side::Front), "node {c:?}: N = {w}");
        }
    }
}

#[test]
fn bad_input_is_refused_naming_the_field() {
    let q = ShapeFunction::QuadraticBSpline;
    let field = |e: MpmError| match e {
        MpmError::Invalid { field, .. } => field,
        other => panic!("{other:?}"),
    };
    let e = Grid::try_new_3d([0.0; 3], 0.1, [4, 0, 4], q).unwrap_err();
    assert_eq!(field(e.clone()), "grid.cells");
    assert!(e.to_string().contains("[4, 0, 4]"), "{e}");
    let e = Grid::try_new_3d([0.0; 3], 0.0, [4, 4, 4], q).unwrap_err();
    assert_eq!(field(e), "grid.spacing");
    let e = Grid::try_new_3d([0.0, f64::NAN, 0.0], 0.1, [4, 4, 4], q).unwrap_err();
    assert_eq!(field(e), "grid.origin");
    let e = Particles::fill_box([[0.0, 0.0, 0.0], [0.1, 0.1, 0.0]], 0.1, 2, 1.0).unwrap_err();
    assert_eq!(field(e), "box");
    let e = Particles::fill_cylinder([0.0; 3], 0.0, 0.1, 0.1, 2, 1.0).unwrap_err();
    assert_eq!(field(e), "cylinder.radius");
    let e = Particles::fill_quarter_cylinder([0.0; 3], 0.1, -1.0, 0.1, 2, 1.0).unwrap_err();
    assert_eq!(field(e), "cylinder.height");
    let e = Particles::fill_box([[0.0; 3], [0.1; 3]], 0.1, 0, 1.0).unwrap_err();
    assert_eq!(field(e), "particles_per_cell");

    // A z wall on a 2D grid.
    let material = DruckerPrager::try_new(DruckerPragerParameters {
        young_modulus: 1e7,
        poisson_ratio: 0.3,
        friction_angle: 30.0,
        cohesion: 0.0,
        dilatancy_angle: 0.0,
        cone_fit: ConeFit::PlaneStrain,
    })
    .unwrap();
    let boundary = GridBoundary {
        walls: vec![Wall {
            side: Side::Front,
            condition: WallCondition::Slip,
        }],
        prescribed: vec![],
    };
    let grid2 = Grid::try_new([0.0; 2], 0.1, [4, 4], q).unwrap();
    let e = Mpm::try_new(
        grid2,
        boundary,
        &material,
        [0.0, -9.81],
        MpmSettings::default(),
    )
    .unwrap_err();
    assert_eq!(field(e), "walls[0].side");

    // A particle outside the grid and its ghost layers, named with its three coordinates.
    let grid = grid(q, false);
    let mut p = Particles::fill_box([[0.0, 0.2, 0.1], [0.07, 0.27, 0.17]], 0.07, 1, 1.0).unwrap();
    p.push([0.0, 0.2, 1.0], 1.0, 1.0);
    match stencils(&grid, &p) {
        Err(e @ MpmError::ParticleLeftGrid { .. }) => {
            let MpmError::ParticleLeftGrid { particle, position } = &e else {
                unreachable!()
            };
            assert_eq!((*particle, position.as_slice()), (1, &[0.0, 0.2, 1.0][..]));
            assert!(
                e.to_string().contains("(0.000000, 0.200000, 1.000000)"),
                "{e}"
            );
        }
        other => panic!("{other:?}"),
    }
}

/// The fills: a box's particles tile it; a cylinder's and a quarter's volume is that of
/// the lattice cells whose centre lies inside, within one layer of cells of `π R² H`.
#[test]
fn fills_cover_their_solids() {
    let b = Particles::fill_box([[0.0, 0.0, 0.0], [0.2, 0.1, 0.3]], 0.05, 2, 1000.0).unwrap();
    assert_eq!(b.len(), 8 * 4 * 2 * 6);
    let v: f64 = b.volume.iter().sum();
    assert!((v - 0.2 * 0.1 * 0.3).abs() < 1e-15, "{v}");
    let (r, h, dx) = (0.1, 0.05, 0.01);
    let full = Particles::fill_cylinder([0.5, 0.0, 0.5], r, h, dx, 2, 1800.0).unwrap();
    let quarter = Particles::fill_quarter_cylinder([0.0, 0.0, 0.0], r, h, dx, 2, 1800.0).unwrap();
    let exact = std::f64::consts::PI * r * r * h;
    let vf: f64 = full.volume.iter().sum();
    let vq: f64 = quarter.volume.iter().sum();
    // The rim is a band of cells of width d = dx/2: |ΔV| ≤ 2π R d H.
    let band = 2.0 * std::f64::consts::PI * r * (0.5 * dx) * h;
    assert!((vf - exact).abs() < band, "{vf} vs {exact}");
    assert!((4.0 * vq - exact).abs() < band, "{} vs {exact}", 4.0 * vq);
    assert!(quarter.position.iter().all(|x| x[0] > 0.0 && x[2] > 0.0));
    assert!(full
        .position
        .iter()
        .all(|x| (x[0] - 0.5).hypot(x[2] - 0.5) <= r && x[1] > 0.0 && x[1] < h));
    assert!((full.mass.iter().sum::<f64>() - 1800.0 * vf).abs() < 1e-12);
}
