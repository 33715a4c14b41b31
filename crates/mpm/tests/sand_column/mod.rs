//! The small cohesionless sand column of the engine's halving tests: 0.1 m × 0.2 m on a
//! fixed floor with a slip left wall, 4 particles per cell, at rest and stress free (its
//! first step starts at the cone's apex).
#![allow(dead_code)] // each test binary uses part of it
use talus_bipotential::{ConeFit, DruckerPrager, DruckerPragerParameters};
use talus_mpm::{
    Grid, GridBoundary, Mpm, MpmSettings, Particles, ShapeFunction, Side, Wall, WallCondition,
};

/// φ = 30°, c = 0, ψ = 0, E = 10 MPa, ν = 0.3.
pub fn sand() -> DruckerPrager {
    DruckerPrager::try_new(DruckerPragerParameters {
        young_modulus: 1e7,
        poisson_ratio: 0.3,
        friction_angle: 30.0,
        cohesion: 0.0,
        dilatancy_angle: 0.0,
        cone_fit: ConeFit::PlaneStrain,
    })
    .unwrap()
}

pub fn small_column() -> (Mpm, Particles) {
    let grid = Grid::try_new([0.0, 0.0], 0.02, [20, 12], ShapeFunction::QuadraticBSpline).unwrap();
    let boundary = GridBoundary {
        walls: vec![
            Wall {
                side: Side::Left,
                condition: WallCondition::Slip,
            },
            Wall {
                side: Side::Bottom,
                condition: WallCondition::Fixed,
            },
        ],
        prescribed: vec![],
    };
    let mpm = Mpm::try_new(
        grid,
        boundary,
        &sand(),
        [0.0, -9.81],
        MpmSettings::default(),
    )
    .unwrap();
    let particles = Particles::fill_rectangle([[0.0, 0.0], [0.1, 0.2]], 0.02, 2, 1800.0).unwrap();
    (mpm, particles)
}
