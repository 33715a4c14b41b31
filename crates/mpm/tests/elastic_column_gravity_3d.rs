//! The 3D elastic column under its own weight in an oedometer (the elastic column of the
//! MPM literature, e.g. Coombs et al. 2020, "Ghost stabilisation of the material point
//! method for stable quasi-static and dynamic analysis of large deformation problems",
//! CMAME 369; the 2D case is `elastic_column_gravity.rs`): a square column W × W × H on a
//! fixed floor, slip walls on its four sides (x and z faces of the grid), released from
//! rest under gravity, comes to rest in uniaxial strain with
//!
//!   σ_yy(y) = −ρ g (H − y),   σ_xx = σ_zz = K0 σ_yy,   K0 = ν / (1 − ν),
//!   σ_yz = σ_xz = σ_xy = 0.
//!
//! Same column, grid, step (25 × dx / c_p), stopping rule and tolerances as the 2D test:
//! the slip walls make the 3D problem the same 1D problem, so the same error (2D measures
//! 1.4 % with hats and less with B-splines) must hold; shear stresses must vanish to the
//! same 2 %.
use std::time::Instant;

use talus_bipotential::{ConeFit, DruckerPrager, DruckerPragerParameters};
use talus_mpm::MpmStepper;
use talus_mpm::{
    Grid, GridBoundary, Mpm, MpmSettings, Particles, ShapeFunction, Side, Wall, WallCondition,
};

const E: f64 = 1e7;
const NU: f64 = 0.3;
const RHO: f64 = 2000.0;
const G: f64 = 9.81;
const WIDTH: f64 = 0.2;
const HEIGHT: f64 = 1.0;
const DX: f64 = 0.05;
const STEP_OVER_LIMIT: f64 = 25.0;

fn settle(shape: ShapeFunction) {
    let start = Instant::now();
    let material = DruckerPrager::try_new(DruckerPragerParameters {
        young_modulus: E,
        poisson_ratio: NU,
        friction_angle: 30.0,
        cohesion: 1e12,
        dilatancy_angle: 0.0,
        cone_fit: ConeFit::OuterCone,
    })
    .unwrap();
    let n = (WIDTH / DX).round() as usize;
    let cells = [n, (HEIGHT / DX).round() as usize + 4, n];
    let grid = Grid::try_new_3d([0.0; 3], DX, cells, shape).unwrap();
    assert_eq!(grid.end()[0], WIDTH, "the column's sides lie on the walls");
    assert_eq!(grid.end()[2], WIDTH, "the column's sides lie on the walls");
    let wall = |side, condition| Wall { side, condition };
    let boundary = GridBoundary {
        walls: vec![
            wall(Side::Left, WallCondition::Slip),
            wall(Side::Right, WallCondition::Slip),
            wall(Side::Back, WallCondition::Slip),
            wall(Side::Front, WallCondition::Slip),
            wall(Side::Bottom, WallCondition::Fixed),
        ],
        prescribed: vec![],
    };
    let gravity = [0.0, -G, 0.0];
    let mpm = Mpm::try_new(grid, boundary, &material, gravity, MpmSettings::default()).unwrap();
    let mut mpm = MpmStepper::new(mpm);
    let cuboid = [[0.0, 0.0, 0.0], [WIDTH, HEIGHT, WIDTH]];
    let mut p = Particles::fill_box(cuboid, DX, 2, RHO).unwrap();
    let y0: Vec<f64> = p.position.iter().map(|x| x[1]).collect();

    let modulus = E * (1.0 - NU) / ((1.0 + NU) * (1.0 - 2.0 * NU));
    let c_p = (modulus / RHO).sqrt();
    let h = STEP_OVER_LIMIT * DX / c_p;
    // Elastic energy of the settled column, (ρg)² W² H³ / (6M).
    let elastic = (RHO * G).powi(2) * WIDTH * WIDTH * HEIGHT.powi(3) / (6.0 * modulus);
    let mut steps = 0;
    let min_steps = (5.0 * 4.0 * HEIGHT / c_p / h).ceil() as usize;
    while steps < min_steps || talus_mpm::kinetic_energy(&p) > 1e-12 * elastic {
        let r = mpm.advance(&mut p, h).unwrap();
        assert_eq!(r.substeps, 1, "a step was halved");
        steps += 1;
        assert!(
            steps <= 500,
            "{shape:?}: kinetic energy {:.3e} J after {steps} steps",
            talus_mpm::kinetic_energy(&p)
        );
    }

    let k0 = NU / (1.0 - NU);
    let scale = RHO * G * HEIGHT;
    let (mut eyy, mut exx, mut ezz, mut shear) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (s, y) in p.stress.iter().zip(&y0) {
        let syy = -RHO * G * (HEIGHT - y);
        eyy = eyy.max((s[1] - syy).abs() / scale);
        exx = exx.max((s[0] - k0 * syy).abs() / scale);
        ezz = ezz.max((s[2] - k0 * syy).abs() / scale);
        shear = shear.max(s[3].abs().max(s[4].abs()).max(s[5].abs()) / scale);
    }
    let top = p.position.iter().map(|x| x[1]).fold(f64::MIN, f64::max);
    let top0 = y0.iter().copied().fold(f64::MIN, f64::max);
    let settlement = top0 - top;
    let expected = RHO * G * (HEIGHT * HEIGHT - (0.25 * DX).powi(2)) / (2.0 * modulus);
    println!(
        "3D {shape:?}: {} particles, h = {h:.3e} s, {steps} steps, settlement {settlement:.4e} m \
         (1D elastic {expected:.4e} m), max |Δσ_yy|/(ρgH) = {eyy:.4}, \
         max |σ_xx − K0 σ_yy|/(ρgH) = {exx:.4}, max |σ_zz − K0 σ_yy|/(ρgH) = {ezz:.4}, \
         max |shear|/(ρgH) = {shear:.2e}, {:.1} s",
        p.len(),
        start.elapsed().as_secs_f64()
    );
    assert!(eyy <= 0.02, "σ_yy error {eyy:.4} of ρgH");
    assert!(exx <= 0.02, "σ_xx error {exx:.4} of ρgH");
    assert!(ezz <= 0.02, "σ_zz error {ezz:.4} of ρgH");
    assert!(shear <= 0.02, "shear stress {shear:.4} of ρgH");
    assert!(
        (settlement / expected - 1.0).abs() <= 0.02,
        "settlement {settlement:.4e} m vs {expected:.4e} m"
    );
}

#[test]
fn quadratic_bspline_column_3d_matches_the_oedometric_solution() {
    settle(ShapeFunction::QuadraticBSpline);
}

#[test]
fn linear_column_3d_matches_the_oedometric_solution() {
    settle(ShapeFunction::Linear);
}
