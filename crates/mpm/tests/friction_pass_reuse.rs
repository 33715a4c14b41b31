//! The friction passes of a step share one dof numbering and one Schur analysis (a stuck
//! tangential velocity is a zeroed column of `B`): the steps are the same, bit for bit, as
//! with a new solver built for every pass, and a stuck node does not move.
use crate::sand_column;

use talus_engine::StepSettings;
use talus_mpm::GroupForces;
use talus_mpm::{
    Grid, GridBoundary, Mpm, MpmSettings, Particles, ShapeFunction, Side, Wall, WallCondition,
};
use talus_mpm::{MpmStepReport, MpmStepper};

/// A small sand column collapsing on a rough floor (μ = 0.4): the floor nodes switch
/// between stick and slide, so steps take several friction passes.
fn column(reuse: bool) -> (MpmStepper, Particles) {
    let grid = Grid::try_new([0.0, 0.0], 0.02, [20, 8], ShapeFunction::QuadraticBSpline).unwrap();
    let boundary = GridBoundary {
        walls: vec![
            Wall {
                side: Side::Left,
                condition: WallCondition::Slip,
            },
            Wall {
                side: Side::Bottom,
                condition: WallCondition::Friction { coefficient: 0.4 },
            },
        ],
        prescribed: vec![],
    };
    let mpm = Mpm::try_new(
        grid,
        boundary,
        &sand_column::sand(),
        [0.0, -9.81],
        // Every floor node stuck at the start of a sub-step, so that the steps take several
        // passes (with the contact predictor this column settles in about one).
        MpmSettings {
            contact_predictor: false,
            ..MpmSettings::default()
        },
    )
    .unwrap();
    let settings = StepSettings {
        reuse_analysis: reuse,
        ..StepSettings::mpm()
    };
    let mpm = MpmStepper::with_settings(mpm, settings);
    let particles = Particles::fill_rectangle([[0.0, 0.0], [0.06, 0.12]], 0.02, 2, 1800.0).unwrap();
    (mpm, particles)
}

fn run(reuse: bool) -> (Particles, Vec<MpmStepReport>) {
    let (mut mpm, mut particles) = column(reuse);
    let reports = (0..25)
        .map(|_| mpm.advance(&mut particles, 4e-3).unwrap())
        .collect();
    (particles, reports)
}

fn bits(v: impl IntoIterator<Item = f64>) -> Vec<u64> {
    v.into_iter().map(f64::to_bits).collect()
}

#[test]
fn shared_analysis_equals_a_new_solver_per_pass_bit_for_bit() {
    let (shared, shared_reports) = run(true);
    let (fresh, fresh_reports) = run(false);
    let passes: usize = shared_reports.iter().map(|r| r.solves_per_substep).sum();
    let reused: usize = shared_reports.iter().map(|r| r.reused_analyses).sum();
    assert!(
        passes > shared_reports.len() + 5,
        "the test needs steps with several friction passes ({passes} passes in {} steps)",
        shared_reports.len()
    );
    assert!(
        reused > 5,
        "later passes must reuse the analysis ({reused})"
    );
    assert_eq!(
        fresh_reports
            .iter()
            .map(|r| r.reused_analyses)
            .sum::<usize>(),
        0
    );
    for (a, b) in shared_reports.iter().zip(&fresh_reports) {
        assert_eq!(
            (a.newton_iterations, a.solves_per_substep, a.substeps),
            (b.newton_iterations, b.solves_per_substep, b.substeps)
        );
        assert_eq!(
            bits(a.group_forces().iter().flatten().copied()),
            bits(b.group_forces().iter().flatten().copied())
        );
    }
    assert_eq!(
        bits(shared.stress.iter().flatten().copied()),
        bits(fresh.stress.iter().flatten().copied())
    );
    assert_eq!(
        bits(shared.position.iter().flatten().copied()),
        bits(fresh.position.iter().flatten().copied())
    );
    assert_eq!(
        bits(shared.velocity.iter().flatten().copied()),
        bits(fresh.velocity.iter().flatten().copied())
    );
}

/// A floor that holds every node in stick (μ = 100) is a fixed floor: the stuck tangential
/// velocities, kept in the numbering with zeroed columns of `B`, must give the steps of a
/// `Fixed` wall, whose velocities are removed from the numbering (an independent
/// formulation), to round-off.
#[test]
fn stuck_floor_equals_a_fixed_floor() {
    let run = |condition: WallCondition| {
        let grid =
            Grid::try_new([0.0, 0.0], 0.02, [20, 8], ShapeFunction::QuadraticBSpline).unwrap();
        let boundary = GridBoundary {
            walls: vec![Wall {
                side: Side::Bottom,
                condition,
            }],
            prescribed: vec![],
        };
        let mpm = Mpm::try_new(
            grid,
            boundary,
            &sand_column::sand(),
            [0.0, -9.81],
            MpmSettings::default(),
        )
        .unwrap();
        let mut mpm = MpmStepper::new(mpm);
        let mut p = Particles::fill_rectangle([[0.1, 0.0], [0.2, 0.1]], 0.02, 2, 1800.0).unwrap();
        let mut passes = 0;
        for _ in 0..10 {
            passes = passes.max(mpm.advance(&mut p, 4e-3).unwrap().solves_per_substep);
        }
        (p, passes)
    };
    let (stuck, passes) = run(WallCondition::Friction { coefficient: 100.0 });
    assert_eq!(passes, 1, "μ = 100 must keep every floor node in stick");
    let (fixed, _) = run(WallCondition::Fixed);
    let scale = fixed
        .stress
        .iter()
        .flatten()
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let stress = stuck
        .stress
        .iter()
        .flatten()
        .zip(fixed.stress.iter().flatten())
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    let position = stuck
        .position
        .iter()
        .flatten()
        .zip(fixed.position.iter().flatten())
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    // The sand spreads: the front moves by millimetres.
    let initial = Particles::fill_rectangle([[0.1, 0.0], [0.2, 0.1]], 0.02, 2, 1800.0).unwrap();
    let moved = stuck
        .position
        .iter()
        .zip(&initial.position)
        .map(|(a, b)| (a[0] - b[0]).abs())
        .fold(0.0f64, f64::max);
    assert!(
        moved > 1e-3,
        "the test needs a flowing column ({moved:e} m)"
    );
    assert!(
        stress <= 1e-9 * scale && position <= 1e-12,
        "stuck vs fixed floor: stress differs by {stress:e} (scale {scale:e}), position by {position:e} m"
    );
}
