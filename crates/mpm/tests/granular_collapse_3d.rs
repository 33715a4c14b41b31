//! A 3D granular column collapse (the axisymmetric case of Lube, Huppert, Sparks &
//! Hallworth 2004, "Axisymmetric collapses of granular columns", J. Fluid Mech. 508,
//! 175–199; its runout is measured by `examples/column_collapse_3d.rs`, too slow for a
//! test): a quarter cylinder (R₀ = 0.1 m, a = H₀/R₀ = 0.5) on a Coulomb floor (μ = 0.6)
//! between slip walls on its symmetry planes x = 0 and z = 0, coarse (dx = R₀/5), for 0.3 s
//! (four flow times √(H₀/g)), checks what must hold whatever the resolution:
//!
//! - mass: the particles' masses never change, and P2G (eq. 11) puts all of it on the
//!   grid, `Σ m_i = Σ m_p` to round-off, at the start and the end;
//! - the walls: no particle crosses the symmetry planes or the floor;
//! - symmetry: the setup is invariant under the swap x ↔ z, so every particle moves as its
//!   mirror image, to the solver's tolerance (1e-9 dx, as `plane_strain_in_3d.rs`);
//! - it flowed: the front advanced by more than a cell (Lube's deposit reaches 1.62 R₀).
//!
//! The total particle volume is printed, not checked: MPM's `V ← det(I + h ∇v) V` does not
//! conserve it although the sand is non-dilatant (measured: +1.7 % after 0.3 s here).
use std::collections::HashMap;

use talus_bipotential::{ConeFit, DruckerPrager, DruckerPragerParameters};
use talus_mpm::transfer::{particles_to_grid, stencils};
use talus_mpm::{
    radial_front, Grid, GridBoundary, Mpm, MpmSettings, MpmStepper, Particles, ShapeFunction, Side,
    Wall, WallCondition,
};

const G: f64 = 9.81;
const R0: f64 = 0.1;

fn grid_mass(mpm: &Mpm<6>, p: &Particles<6>) -> f64 {
    let s = stencils(mpm.grid(), p).unwrap();
    particles_to_grid(mpm.grid(), p, &s, [0.0, -G, 0.0])
        .mass
        .iter()
        .sum()
}

#[test]
fn quarter_cylinder_collapse_keeps_mass_walls_and_symmetry() {
    let (a, dx) = (0.5, R0 / 5.0);
    let h0 = a * R0;
    let grid =
        Grid::try_new_3d([0.0; 3], dx, [12, 5, 12], ShapeFunction::QuadraticBSpline).unwrap();
    let wall = |side, condition| Wall { side, condition };
    let boundary = GridBoundary {
        walls: vec![
            wall(Side::Left, WallCondition::Slip),
            wall(Side::Back, WallCondition::Slip),
            wall(Side::Bottom, WallCondition::Friction { coefficient: 0.6 }),
        ],
        prescribed: vec![],
    };
    let sand = DruckerPrager::try_new(DruckerPragerParameters {
        young_modulus: 1e7,
        poisson_ratio: 0.3,
        friction_angle: 30.0,
        cohesion: 0.0,
        dilatancy_angle: 0.0,
        cone_fit: ConeFit::OuterCone,
    })
    .unwrap();
    let mpm = Mpm::try_new(
        grid,
        boundary,
        &sand,
        [0.0, -G, 0.0],
        MpmSettings::default(),
    )
    .unwrap();
    let mut p = Particles::fill_quarter_cylinder([0.0; 3], R0, h0, dx, 2, 1800.0).unwrap();
    let n = p.len();
    // The mirror of each particle: the one whose initial (x, z) is its (z, x).
    let key = |x: &[f64; 3]| (x[0].to_bits(), x[1].to_bits(), x[2].to_bits());
    let index: HashMap<_, _> = p
        .position
        .iter()
        .enumerate()
        .map(|(q, x)| (key(x), q))
        .collect();
    let mirror: Vec<usize> = p
        .position
        .iter()
        .map(|x| index[&key(&[x[2], x[1], x[0]])])
        .collect();
    let mass0: f64 = p.mass.iter().sum();
    let volume0: f64 = p.volume.iter().sum();
    let front0 = radial_front(&p, [0.0, 0.0]);
    assert!((grid_mass(&mpm, &p) - mass0).abs() <= 1e-14 * mass0);

    let mut stepper = MpmStepper::new(mpm);
    let (h, steps) = (1e-3, 300);
    let start = std::time::Instant::now();
    for k in 0..steps {
        stepper
            .advance(&mut p, h)
            .unwrap_or_else(|e| panic!("step {k}: {e}"));
    }
    let seconds = start.elapsed().as_secs_f64();

    let mass: f64 = p.mass.iter().sum();
    assert_eq!(mass, mass0);
    let on_grid = grid_mass(stepper.mpm(), &p);
    assert!(
        (on_grid - mass0).abs() <= 1e-14 * mass0,
        "{on_grid} vs {mass0}"
    );
    for (q, x) in p.position.iter().enumerate() {
        assert!(
            x[0] >= 0.0 && x[1] >= 0.0 && x[2] >= 0.0,
            "particle {q} at {x:?}"
        );
    }
    let volume: f64 = p.volume.iter().sum();
    let dv = volume / volume0 - 1.0;
    let mut asymmetry = 0.0f64;
    for (q, &m) in mirror.iter().enumerate() {
        let (x, y) = (p.position[q], p.position[m]);
        for (i, j) in [(0, 2), (1, 1), (2, 0)] {
            asymmetry = asymmetry.max((x[i] - y[j]).abs() / dx);
        }
    }
    let front = radial_front(&p, [0.0, 0.0]);
    println!(
        "{n} particles, {steps} steps in {seconds:.1} s: front {front0:.4} → {front:.4} m, \
         volume change {:+.3} %, max mirror mismatch {asymmetry:.2e} dx",
        100.0 * dv
    );
    assert!(
        asymmetry <= 1e-9,
        "mirror images differ by {asymmetry:.2e} dx"
    );
    assert!(
        front - front0 > dx,
        "the front moved {:.4} m",
        front - front0
    );
}
