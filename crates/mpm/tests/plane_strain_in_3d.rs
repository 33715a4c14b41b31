//! A plane-strain problem run in 3D reproduces the 2D run (the 2D model is the 3D one with
//! `ε_zz = ε_yz = ε_xz = 0`; e.g. Zienkiewicz & Taylor, The Finite Element Method, vol. 1,
//! §6.2): the 3D grid is one cell thick with slip walls on both z faces, filled with the
//! 2D particles repeated over `per_cell` layers. Every 3D particle then carries its 2D
//! twin's data; the z velocities vanish (the z faces' open knot vectors make
//! `Σ_p ∂N_i/∂z = 0` per node over a layer pair, so `v_z = 0` solves the z equations), and
//! each 3D nodal equation is its 2D one times the nodes' z weight. The two runs differ by
//! the Newton iterations' stopping points and round-off only.
//!
//! Cases: the elastic column of `elastic_column_gravity.rs` (a linear problem), and the
//! small sand column of `sand_column` collapsing on a Coulomb floor (μ = 0.5; plastic flow
//! and the friction active set, whose 3D cone reduces to 2D's stick/slide when the z
//! reaction vanishes). Tolerance 1e-9 (of ρgH on stresses, of dx on positions): ten times
//! the engine's relative residual 1e-10 at which either Newton iteration may stop. Measured
//! (2 × 2 particles per cell in 2D, 2 × 2 × 2 in 3D): ≤ 1e-13 for the column, ≤ 7e-12 on
//! stresses for the collapse (150 steps of 1 ms: plastic strain up to 1.9, front 5 cm on).
use talus_bipotential::{ConeFit, DruckerPrager, DruckerPragerParameters};
use talus_mpm::{
    Grid, GridBoundary, Mpm, MpmSettings, MpmStepper, Particles, ShapeFunction, Side, Wall,
    WallCondition,
};

const G: f64 = 9.81;

fn material(cohesion: f64) -> DruckerPrager {
    DruckerPrager::try_new(DruckerPragerParameters {
        young_modulus: 1e7,
        poisson_ratio: 0.3,
        friction_angle: 30.0,
        cohesion,
        dilatancy_angle: 0.0,
        cone_fit: ConeFit::PlaneStrain,
    })
    .unwrap()
}

struct Case {
    spacing: f64,
    cells: [usize; 2],
    body: [[f64; 2]; 2],
    density: f64,
    walls: Vec<Wall>,
    cohesion: f64,
    h: f64,
    steps: usize,
}

/// Both runs, then the largest stress and position differences between each 3D particle
/// and its 2D twin, the largest |v_z| and |σ_yz|, |σ_xz|, and the 2D run's largest plastic
/// strain and front advance (m), to show the case did flow.
fn compare(case: &Case, shape: ShapeFunction) -> ([f64; 4], f64, f64) {
    let per_cell = 2;
    let dx = case.spacing;
    let wall = |side, condition| Wall { side, condition };
    let grid2 = Grid::try_new([0.0; 2], dx, case.cells, shape).unwrap();
    let boundary2 = GridBoundary {
        walls: case.walls.clone(),
        prescribed: vec![],
    };
    let material = material(case.cohesion);
    let settings = MpmSettings::default();
    let mpm2 = Mpm::try_new(grid2, boundary2, &material, [0.0, -G], settings).unwrap();
    let [nx, ny] = case.cells;
    let grid3 = Grid::try_new_3d([0.0; 3], dx, [nx, ny, 1], shape).unwrap();
    // The z walls first: the friction floor then acts on x alone on their nodes.
    let mut walls3 = vec![
        wall(Side::Back, WallCondition::Slip),
        wall(Side::Front, WallCondition::Slip),
    ];
    walls3.extend(case.walls.iter().copied());
    let boundary3 = GridBoundary {
        walls: walls3,
        prescribed: vec![],
    };
    let mpm3 = Mpm::try_new(grid3, boundary3, &material, [0.0, -G, 0.0], settings).unwrap();
    let mut p2 = Particles::fill_rectangle(case.body, dx, per_cell, case.density).unwrap();
    let [[x0, y0], [x1, y1]] = case.body;
    let mut p3 =
        Particles::fill_box([[x0, y0, 0.0], [x1, y1, dx]], dx, per_cell, case.density).unwrap();
    // The lattices: 2D j-then-i, 3D k-then-j-then-i, so twin of 3D particle q is q mod n.
    let n = p2.len();
    assert_eq!(p3.len(), per_cell * n);
    for q in 0..p3.len() {
        let (a, b) = (p3.position[q], p2.position[q % n]);
        assert!(a[0] == b[0] && a[1] == b[1]);
    }
    let front0 = talus_mpm::front(&p2);
    let (mut s2, mut s3) = (MpmStepper::new(mpm2), MpmStepper::new(mpm3));
    for step in 0..case.steps {
        s2.advance(&mut p2, case.h)
            .unwrap_or_else(|e| panic!("2D step {step}: {e}"));
        s3.advance(&mut p3, case.h)
            .unwrap_or_else(|e| panic!("3D step {step}: {e}"));
    }
    let height = y1 - y0;
    let scale = case.density * G * height;
    let (mut ds, mut dpos, mut vz, mut shear_z) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for q in 0..p3.len() {
        let (a, b) = (&p3.stress[q], &p2.stress[q % n]);
        // Mandel: 2D (xx, yy, zz, √2 xy), 3D (xx, yy, zz, √2 yz, √2 xz, √2 xy).
        for (i, j) in [(0, 0), (1, 1), (2, 2), (5, 3)] {
            ds = ds.max((a[i] - b[j]).abs() / scale);
        }
        shear_z = shear_z.max(a[3].abs().max(a[4].abs()) / scale);
        for c in 0..2 {
            dpos = dpos.max((p3.position[q][c] - p2.position[q % n][c]).abs() / dx);
        }
        vz = vz.max(p3.velocity[q][2].abs());
    }
    let plastic = p2.plastic_strain.iter().copied().fold(0.0, f64::max);
    let advance = talus_mpm::front(&p2) - front0;
    println!(
        "{shape:?}: {} 2D / {} 3D particles, {} steps: max |Δσ|/(ρgH) = {ds:.2e}, \
         max |Δx|/dx = {dpos:.2e}, max |v_z| = {vz:.2e} m/s, max |σ_yz|, |σ_xz| = {shear_z:.2e} ρgH; \
         2D: max plastic strain {plastic:.3}, front advanced {advance:.4} m",
        n,
        p3.len(),
        case.steps
    );
    ([ds, dpos, vz, shear_z], plastic, advance)
}

/// Every difference within `tolerance` (`vz` in m/s against `tolerance` m/s: the
/// velocities here are below 1 m/s).
fn check(shape: ShapeFunction, d: [f64; 4], tolerance: f64) {
    let [ds, dpos, vz, shear] = d;
    assert!(
        ds <= tolerance,
        "{shape:?}: stresses differ by {ds:.2e} ρgH"
    );
    assert!(
        dpos <= tolerance,
        "{shape:?}: positions differ by {dpos:.2e} dx"
    );
    assert!(vz <= tolerance, "{shape:?}: v_z = {vz:.2e} m/s");
    assert!(
        shear <= tolerance,
        "{shape:?}: out-of-plane shear {shear:.2e} ρgH"
    );
}

#[test]
fn elastic_column_in_3d_reproduces_plane_strain() {
    let wall = |side, condition| Wall { side, condition };
    let case = Case {
        spacing: 0.05,
        cells: [4, 24],
        body: [[0.0, 0.0], [0.2, 1.0]],
        density: 2000.0,
        walls: vec![
            wall(Side::Left, WallCondition::Slip),
            wall(Side::Right, WallCondition::Slip),
            wall(Side::Bottom, WallCondition::Fixed),
        ],
        cohesion: 1e12,
        h: 1.5e-2,
        steps: 17,
    };
    for shape in [ShapeFunction::Linear, ShapeFunction::QuadraticBSpline] {
        let (d, _, _) = compare(&case, shape);
        check(shape, d, 1e-9);
    }
}

#[test]
fn frictional_collapse_in_3d_reproduces_plane_strain() {
    let wall = |side, condition| Wall { side, condition };
    let case = Case {
        spacing: 0.02,
        cells: [20, 12],
        body: [[0.0, 0.0], [0.1, 0.2]],
        density: 1800.0,
        walls: vec![
            wall(Side::Left, WallCondition::Slip),
            wall(Side::Bottom, WallCondition::Friction { coefficient: 0.5 }),
        ],
        cohesion: 0.0,
        h: 1e-3,
        steps: 150,
    };
    for shape in [ShapeFunction::Linear, ShapeFunction::QuadraticBSpline] {
        let (d, plastic, advance) = compare(&case, shape);
        check(shape, d, 1e-9);
        // The comparison means something only if the column flowed and slid.
        assert!(plastic > 0.05, "{shape:?}: plastic strain {plastic}");
        assert!(advance > 0.02, "{shape:?}: the front advanced {advance} m");
    }
}
