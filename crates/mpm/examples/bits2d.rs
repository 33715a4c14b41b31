//! A digest (FNV-1a over the bits of positions, velocities, stresses, volumes and plastic
//! strains) of six 2D runs after 40 steps: hats and B-splines; a slip wall and a friction
//! floor, fixed walls and a friction side with PIC, a slip floor with a prescribed box.
//! `docs/3d-mpm.md`: the digests before the code became generic over `D` were
//! 740003638dcc3ec5 c9deca08e25e23f7 c6bfad7597b3419b (Linear, cases 0–2) and
//! f2df17304b24b70e b4578746f7fdf846 98c0ae32ae1d1906 (QuadraticBSpline); they are
//! unchanged after it.
use talus_bipotential::{ConeFit, DruckerPrager, DruckerPragerParameters};
use talus_mpm::{
    Grid, GridBoundary, Mpm, MpmSettings, MpmStepper, Particles, PrescribedVelocity, ShapeFunction,
    Side, Wall, WallCondition,
};

fn digest(p: &Particles) -> u64 {
    let mut h: u64 = 1469598103934665603;
    let mut eat = |x: f64| {
        h ^= x.to_bits();
        h = h.wrapping_mul(1099511628211);
    };
    for i in 0..p.len() {
        p.position[i].iter().for_each(|v| eat(*v));
        p.velocity[i].iter().for_each(|v| eat(*v));
        p.stress[i].iter().for_each(|v| eat(*v));
        eat(p.volume[i]);
        eat(p.plastic_strain[i]);
    }
    h
}

fn main() {
    let sand = DruckerPrager::try_new(DruckerPragerParameters {
        young_modulus: 1e7,
        poisson_ratio: 0.3,
        friction_angle: 30.0,
        cohesion: 0.0,
        dilatancy_angle: 0.0,
        cone_fit: ConeFit::PlaneStrain,
    })
    .unwrap();
    for shape in [ShapeFunction::Linear, ShapeFunction::QuadraticBSpline] {
        for case in 0..3 {
            let grid = Grid::try_new([0.0, 0.0], 0.02, [30, 12], shape).unwrap();
            let walls = match case {
                0 => vec![
                    Wall {
                        side: Side::Left,
                        condition: WallCondition::Slip,
                    },
                    Wall {
                        side: Side::Bottom,
                        condition: WallCondition::Friction { coefficient: 0.4 },
                    },
                ],
                1 => vec![
                    Wall {
                        side: Side::Left,
                        condition: WallCondition::Fixed,
                    },
                    Wall {
                        side: Side::Bottom,
                        condition: WallCondition::Fixed,
                    },
                    Wall {
                        side: Side::Right,
                        condition: WallCondition::Friction { coefficient: 0.3 },
                    },
                ],
                _ => vec![Wall {
                    side: Side::Bottom,
                    condition: WallCondition::Slip,
                }],
            };
            let prescribed = if case == 2 {
                vec![PrescribedVelocity {
                    region: [[0.0, 0.18], [0.06, 0.22]],
                    velocity: [None, Some(-0.05)],
                }]
            } else {
                vec![]
            };
            let settings = MpmSettings {
                flip_ratio: if case == 1 { 0.0 } else { 0.95 },
                ..MpmSettings::default()
            };
            let mpm = Mpm::try_new(
                grid,
                GridBoundary { walls, prescribed },
                &sand,
                [0.0, -9.81],
                settings,
            )
            .unwrap();
            let mut st = MpmStepper::new(mpm);
            let mut p =
                Particles::fill_rectangle([[0.0, 0.0], [0.1, 0.2]], 0.02, 2, 1800.0).unwrap();
            if case == 1 {
                for (i, v) in p.velocity.iter_mut().enumerate() {
                    *v = [0.3 * (i % 3) as f64, 0.1];
                }
            }
            for _ in 0..40 {
                st.advance(&mut p, 2e-3).unwrap();
            }
            println!("{shape:?} case {case}: {:016x}", digest(&p));
        }
    }
}
