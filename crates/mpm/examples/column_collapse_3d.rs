//! The axisymmetric granular column collapse of Lube, Huppert, Sparks & Hallworth (2004),
//! "Axisymmetric collapses of granular columns", J. Fluid Mech. 508, 175–199, in 3D: a
//! cylinder of radius R₀ and height H₀ = a R₀ on a rough floor spreads to a deposit of
//! radius R∞ with
//!
//!   (R∞ − R₀)/R₀ = 1.24 a        for a < 1.7,
//!   (R∞ − R₀)/R₀ = 1.6 a^(1/2)   above.
//!
//! A quarter of the cylinder (`Particles::fill_quarter_cylinder`) stands for the whole: slip
//! walls on the symmetry planes x = 0 and z = 0, a Coulomb floor μ = 0.6, and the 2D
//! scenes' sand (`scenes/column_a*.toml`: φ = 30°, c = 0, ψ = 0, E = 10 MPa, ν = 0.3,
//! ρ = 1800 kg/m³), dx = R₀/10 by default, 2 × 2 × 2 particles per cell, h = 1 ms, FLIP
//! 0.95. The cone fit is the outer cone (Drucker-Prager through Mohr-Coulomb's compression
//! meridian) by default, or `plane_strain` / `inner`. The front is the largest distance of
//! a particle centre from the axis.
//!
//! `cargo run --release -p talus-mpm --example column_collapse_3d -- A [CELLS_PER_R0] [FIT]`
use std::time::Instant;

use talus_bipotential::{ConeFit, DruckerPrager, DruckerPragerParameters};
use talus_mpm::{
    kinetic_energy, radial_front, Grid, GridBoundary, Mpm, MpmSettings, MpmStepper, Particles,
    ShapeFunction, Side, Wall, WallCondition,
};

const G: f64 = 9.81;
const R0: f64 = 0.1;
const RHO: f64 = 1800.0;

/// Lube et al. (2004)'s runout law.
fn lube(a: f64) -> f64 {
    if a < 1.7 {
        1.24 * a
    } else {
        1.6 * a.sqrt()
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let a: f64 = args.get(1).map_or(Ok(0.5), |s| s.parse())?;
    let per_r0: f64 = args.get(2).map_or(Ok(10.0), |s| s.parse())?;
    let cone_fit = match args.get(3).map(String::as_str) {
        None | Some("outer") => ConeFit::OuterCone,
        Some("inner") => ConeFit::InnerCone,
        Some("plane_strain") => ConeFit::PlaneStrain,
        Some(other) => {
            return Err(format!("cone fit {other:?}: outer, inner or plane_strain").into())
        }
    };
    let start = Instant::now();
    let h0 = a * R0;
    let dx = R0 / per_r0;
    // The grid reaches 1.4 times the law's deposit; it is as high as the column plus 2 dx.
    let reach = 1.4 * R0 * (1.0 + lube(a));
    let n = (reach / dx).ceil() as usize;
    let ny = (1.05 * h0 / dx).ceil() as usize + 2;
    let grid = Grid::try_new_3d([0.0; 3], dx, [n, ny, n], ShapeFunction::QuadraticBSpline)?;
    let wall = |side, condition| Wall { side, condition };
    // The symmetry planes before the floor: on their nodes friction acts on the other
    // tangential component alone.
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
        cone_fit,
    })?;
    let mpm = Mpm::try_new(
        grid,
        boundary,
        &sand,
        [0.0, -G, 0.0],
        MpmSettings::default(),
    )?;
    let mut p = Particles::fill_quarter_cylinder([0.0; 3], R0, h0, dx, 2, RHO)?;
    let mass0: f64 = p.mass.iter().sum();
    let volume0: f64 = p.volume.iter().sum();
    println!(
        "a = {a}: R0 = {R0} m, H0 = {h0} m, dx = {dx} m, grid {n} x {ny} x {n} cells, \
         {} particles, {cone_fit:?}",
        p.len()
    );
    let mut stepper = MpmStepper::new(mpm);
    let step = 1e-3;
    // Lube et al.'s flows stop within ~3 √(H0/g); stop once the kinetic energy is 1e-6 of
    // the column's potential energy after that, or at 4 √(H0/g) + 0.5 s (the 2D scenes').
    let t_flow = (h0 / G).sqrt();
    let t_end = 4.0 * t_flow + 0.5;
    let potential = mass0 * G * 0.5 * h0;
    let steps = (t_end / step).round() as usize;
    let mut free_dofs = 0;
    for k in 1..=steps {
        let report = stepper.advance(&mut p, step)?;
        if let Some(s) = &report.stats {
            free_dofs = free_dofs.max(s.free_dofs);
        }
        let t = k as f64 * step;
        let ke = kinetic_energy(&p);
        if k % 50 == 0 {
            println!(
                "  t = {t:.3} s: front {:.4} m, KE/PE = {:.2e}, {} Newton iterations, {:.0} s",
                radial_front(&p, [0.0, 0.0]),
                ke / potential,
                report.newton_iterations,
                start.elapsed().as_secs_f64()
            );
        }
        if t > 3.0 * t_flow && ke < 1e-6 * potential {
            println!("  at rest at t = {t:.3} s");
            break;
        }
    }
    let front = radial_front(&p, [0.0, 0.0]);
    let runout = (front - R0) / R0;
    let volume: f64 = p.volume.iter().sum();
    let mass: f64 = p.mass.iter().sum();
    println!(
        "a = {a}: (R∞ − R0)/R0 = {runout:.3}, Lube et al. {:.3} (ratio {:.3}); \
         mass {:.3e} → {:.3e} kg, volume change {:+.2} %, {} particles, up to {free_dofs} \
         free velocities, {:.0} s",
        lube(a),
        runout / lube(a),
        mass0,
        mass,
        100.0 * (volume / volume0 - 1.0),
        p.len(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}
