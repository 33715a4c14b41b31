//! The PIC/FLIP blend of eq. 13 damps the part of the particle velocities the grid does
//! not carry: with no grid velocity and no grid acceleration, G2P gives `v_p ← α v_p`.
//! With `flip_reference_time = Some(t_ref)` a step `h` uses `α^(h/t_ref)`, so over a time
//! `T` that part decays by `α^(T/t_ref)` whatever the step (docs/mpm.md, "The PIC/FLIP
//! blend is a damping per unit time"); with `None` it decays by `α^(T/h)`.
//!
//! The velocity field invisible to the grid: every particle of a block has a twin at the
//! same place with the opposite velocity, so P2G (eq. 11) gives zero momentum at every
//! node. The twins drift apart by `2 h |v|` per step; with |v| = 1e-6 m/s and dx = 0.1 m
//! the grid sees a relative 1e-7 of the field, far below the 1e-5 tolerance.
use talus_bipotential::{ConeFit, DruckerPrager, DruckerPragerParameters};
use talus_mpm::MpmStepper;
use talus_mpm::{Grid, GridBoundary, Mpm, MpmSettings, Particles, ShapeFunction};

const SPEED: f64 = 1e-6;
const ALPHA: f64 = 0.9;
const T_REF: f64 = 1e-3;
const DURATION: f64 = 1e-2;

fn mpm(reference: Option<f64>) -> Mpm {
    let soil = DruckerPrager::try_new(DruckerPragerParameters {
        young_modulus: 1e7,
        poisson_ratio: 0.3,
        friction_angle: 30.0,
        cohesion: 1e12,
        dilatancy_angle: 0.0,
        cone_fit: ConeFit::PlaneStrain,
    })
    .unwrap();
    let grid = Grid::try_new([0.0, 0.0], 0.1, [20, 16], ShapeFunction::QuadraticBSpline).unwrap();
    let settings = MpmSettings {
        flip_ratio: ALPHA,
        flip_reference_time: reference,
        ..MpmSettings::default()
    };
    Mpm::try_new(grid, GridBoundary::default(), &soil, [0.0, 0.0], settings).unwrap()
}

/// Twins with opposite velocities along (1, 2)/√5.
fn twins() -> Particles {
    let mut p = Particles::fill_rectangle([[0.6, 0.5], [1.4, 1.1]], 0.1, 2, 2000.0).unwrap();
    let dir = [1.0 / 5f64.sqrt(), 2.0 / 5f64.sqrt()];
    for v in p.velocity.iter_mut() {
        *v = [SPEED * dir[0], SPEED * dir[1]];
    }
    let mut twin = p.clone();
    for v in twin.velocity.iter_mut() {
        *v = [-v[0], -v[1]];
    }
    p.extend(&twin);
    p
}

/// Mean particle speed over SPEED after DURATION in steps of `h`.
fn decay(mpm: &Mpm, h: f64) -> f64 {
    let mut p = twins();
    let mut mpm = MpmStepper::new(mpm.clone());
    let steps = (DURATION / h).round() as usize;
    for _ in 0..steps {
        mpm.advance(&mut p, h).unwrap();
    }
    p.velocity.iter().map(|v| v[0].hypot(v[1])).sum::<f64>() / p.len() as f64 / SPEED
}

#[test]
fn time_consistent_blend_gives_the_same_damping_for_any_step() {
    let expected = ALPHA.powf(DURATION / T_REF); // 0.349
    let mpm = mpm(Some(T_REF));
    for h in [1e-3, 2.5e-4, 2e-3] {
        let got = decay(&mpm, h);
        assert!(
            (got / expected - 1.0).abs() < 1e-5,
            "h = {h}: decay {got}, closed form α^(T/t_ref) = {expected}"
        );
    }
}

#[test]
fn per_step_blend_damps_by_alpha_per_step() {
    let mpm = mpm(None);
    for h in [1e-3, 2.5e-4] {
        let expected = ALPHA.powf(DURATION / h); // 0.349, then 0.0148
        let got = decay(&mpm, h);
        assert!(
            (got / expected - 1.0).abs() < 1e-5,
            "h = {h}: decay {got}, closed form α^(T/h) = {expected}"
        );
    }
}

#[test]
fn bad_reference_time_is_named() {
    let soil = DruckerPrager::try_new(DruckerPragerParameters {
        young_modulus: 1e7,
        poisson_ratio: 0.3,
        friction_angle: 30.0,
        cohesion: 0.0,
        dilatancy_angle: 0.0,
        cone_fit: ConeFit::PlaneStrain,
    })
    .unwrap();
    let grid = Grid::try_new([0.0, 0.0], 0.1, [4, 4], ShapeFunction::Linear).unwrap();
    for t in [0.0, -1e-3, f64::NAN] {
        let settings = MpmSettings {
            flip_reference_time: Some(t),
            ..MpmSettings::default()
        };
        let e = Mpm::try_new(
            grid.clone(),
            GridBoundary::default(),
            &soil,
            [0.0; 2],
            settings,
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("flip_reference_time"), "{e}");
    }
}
