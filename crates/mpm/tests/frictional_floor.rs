//! Coulomb friction on the floor: a rigid-ish block launched along a frictional floor
//! decelerates at `μ g` until it stops (a closed form of any dynamics textbook, e.g.
//! Meriam & Kraige, Dynamics, §3/4), and a block resting on the floor is not dragged by a
//! horizontal push below `μ m g` (the stick side of the active set).
use talus_bipotential::{ConeFit, DruckerPrager, DruckerPragerParameters};
use talus_mpm::MpmStepper;
use talus_mpm::{
    Grid, GridBoundary, Mpm, MpmSettings, Particles, ShapeFunction, Side, Wall, WallCondition,
};

const G: f64 = 9.81;

fn stiff_block() -> DruckerPrager {
    DruckerPrager::try_new(DruckerPragerParameters {
        young_modulus: 1e8,
        poisson_ratio: 0.3,
        friction_angle: 30.0,
        cohesion: 1e9, // never yields: the block stays elastic
        dilatancy_angle: 30.0,
        cone_fit: ConeFit::PlaneStrain,
    })
    .unwrap()
}

fn floor(mu: f64, shape: ShapeFunction) -> Mpm {
    let grid = Grid::try_new([0.0, 0.0], 0.05, [60, 8], shape).unwrap();
    let boundary = GridBoundary {
        walls: vec![Wall {
            side: Side::Bottom,
            condition: WallCondition::Friction { coefficient: mu },
        }],
        prescribed: vec![],
    };
    let settings = MpmSettings {
        flip_ratio: 0.0,
        ..MpmSettings::default()
    };
    Mpm::try_new(grid, boundary, &stiff_block(), [0.0, -G], settings).unwrap()
}

fn mean_velocity(p: &Particles) -> [f64; 2] {
    let (m, q) = p.mass_and_momentum();
    [q[0] / m, q[1] / m]
}

#[test]
fn sliding_block_decelerates_at_mu_g() {
    let mu = 0.3;
    let (v0, h) = (1.0, 5e-3);
    for shape in [ShapeFunction::Linear, ShapeFunction::QuadraticBSpline] {
        let mpm = floor(mu, shape);
        let mut mpm = MpmStepper::new(mpm);
        let mut block =
            Particles::fill_rectangle([[0.2, 0.0], [0.6, 0.2]], 0.05, 2, 2000.0).unwrap();
        // Settle on the floor first (no friction work while at rest), then launch.
        for _ in 0..10 {
            mpm.advance(&mut block, h).unwrap();
        }
        for v in block.velocity.iter_mut() {
            *v = [v0, 0.0];
        }
        let stop = v0 / (mu * G);
        let steps = (0.6 * stop / h).round() as usize;
        for _ in 0..steps {
            mpm.advance(&mut block, h).unwrap();
        }
        let t = steps as f64 * h;
        let expected = v0 - mu * G * t;
        let v = mean_velocity(&block);
        assert!(
            (v[0] - expected).abs() <= 0.03 * v0,
            "{shape:?}: mean velocity {:.4} m/s after {t:.3} s, Coulomb gives {expected:.4}",
            v[0]
        );
        // And it comes to rest, not backwards.
        for _ in 0..(0.6 * stop / h).round() as usize {
            mpm.advance(&mut block, h).unwrap();
        }
        let v = mean_velocity(&block);
        assert!(
            v[0].abs() <= 0.01 * v0,
            "{shape:?}: still moving at {:.4} m/s",
            v[0]
        );
    }
}

#[test]
fn push_below_the_friction_limit_does_not_slide() {
    let mu = 0.5;
    let h = 5e-3;
    let mpm = floor(mu, ShapeFunction::QuadraticBSpline);
    let mut mpm = MpmStepper::new(mpm);
    let mut block = Particles::fill_rectangle([[0.2, 0.0], [0.6, 0.2]], 0.05, 2, 2000.0).unwrap();
    let weight: f64 = block.mass.iter().sum::<f64>() * G;
    // Push every particle sideways with 60% of what friction can hold, in total.
    let n = block.len() as f64;
    for f in block.external_force.iter_mut() {
        *f = [0.6 * mu * weight / n, 0.0];
    }
    for _ in 0..40 {
        mpm.advance(&mut block, h).unwrap();
    }
    let v = mean_velocity(&block);
    assert!(v[0].abs() < 1e-3, "pushed block slides at {:.3e} m/s", v[0]);
    // Past the limit it accelerates at (F − μ m g)/m.
    for f in block.external_force.iter_mut() {
        *f = [1.5 * mu * weight / n, 0.0];
    }
    let steps = 40;
    for _ in 0..steps {
        mpm.advance(&mut block, h).unwrap();
    }
    let expected = 0.5 * mu * G * steps as f64 * h;
    let v = mean_velocity(&block);
    assert!(
        (v[0] - expected).abs() <= 0.05 * expected,
        "past the limit: {:.4} m/s, expected {expected:.4}",
        v[0]
    );
}
