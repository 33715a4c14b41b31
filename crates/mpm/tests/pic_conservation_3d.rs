//! The 3D transfers conserve what PIC conserves (Jiang, Schroeder, Selle, Teran &
//! Stomakhin 2015, "The affine particle-in-cell method", §3; Sulsky et al. 1994): with the
//! FLIP weight α = 0 (`flip_ratio = 0`), P2G (eq. 11) keeps mass, linear momentum and —
//! because the basis is linearly complete, `Σ_i N_i x_i = x_p` — angular momentum,
//! `Σ_i x_i × (mv)_i = Σ_p x_p × m_p v_p`; a sub-step keeps mass and linear momentum
//! (`Σ_i ∇N_i = 0`: the internal forces sum to zero); G2P dissipates angular momentum, so a
//! rigid rotation's `|L|` may only decrease. A uniform translation is exact: no strain, no
//! stress, volumes unchanged. As `pic_conservation.rs` in 2D, with a rotation about an
//! oblique axis.
use talus_bipotential::{ConeFit, DruckerPrager, DruckerPragerParameters};
use talus_mpm::transfer::{particles_to_grid, stencils};
use talus_mpm::MpmStepper;
use talus_mpm::{Grid, GridBoundary, Mpm, MpmSettings, Particles, ShapeFunction};

const SHAPES: [ShapeFunction; 2] = [ShapeFunction::Linear, ShapeFunction::QuadraticBSpline];
const DX: f64 = 0.1;
const H: f64 = 0.01;
const STEPS: usize = 10;

fn pic(shape: ShapeFunction) -> Mpm<6> {
    let material = DruckerPrager::try_new(DruckerPragerParameters {
        young_modulus: 1e7,
        poisson_ratio: 0.3,
        friction_angle: 30.0,
        cohesion: 1e12, // never yields
        dilatancy_angle: 0.0,
        cone_fit: ConeFit::OuterCone,
    })
    .unwrap();
    let grid = Grid::try_new_3d([0.0; 3], DX, [20, 16, 18], shape).unwrap();
    let settings = MpmSettings {
        flip_ratio: 0.0,
        ..MpmSettings::default()
    };
    Mpm::try_new(grid, GridBoundary::default(), &material, [0.0; 3], settings).unwrap()
}

/// A 0.8 × 0.6 × 0.5 m block, 8 particles per cell, 5 cells from every face of the grid.
fn block() -> Particles<6> {
    Particles::fill_box([[0.6, 0.5, 0.7], [1.4, 1.1, 1.2]], DX, 2, 2000.0).unwrap()
}

fn centroid(p: &Particles<6>) -> [f64; 3] {
    let m: f64 = p.mass.iter().sum();
    let mut c = [0.0; 3];
    for (x, mp) in p.position.iter().zip(&p.mass) {
        for a in 0..3 {
            c[a] += mp * x[a] / m;
        }
    }
    c
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn norm(a: [f64; 3]) -> f64 {
    a.iter().map(|v| v * v).sum::<f64>().sqrt()
}

/// `Σ m_p |v_p|` and `Σ m_p |x_p − c| |v_p|`: the scales of the round-off.
fn scales(p: &Particles<6>, c: [f64; 3]) -> (f64, f64) {
    let mut s = (0.0, 0.0);
    for ((x, v), m) in p.position.iter().zip(&p.velocity).zip(&p.mass) {
        let r = [x[0] - c[0], x[1] - c[1], x[2] - c[2]];
        s.0 += m * norm(*v);
        s.1 += m * norm(r) * norm(*v);
    }
    s
}

/// P2G keeps mass, momentum, weight and angular momentum about `c` to round-off.
fn check_grid_totals(mpm: &Mpm<6>, p: &Particles<6>) {
    let grid = mpm.grid();
    let s = stencils(grid, p).unwrap();
    let g = particles_to_grid(grid, p, &s, [0.0, -9.81, 0.0]);
    let (m, mv) = p.mass_and_momentum();
    let c = centroid(p);
    let (scale, angular_scale) = scales(p, c);
    let grid_mass: f64 = g.mass.iter().sum();
    assert!(
        (grid_mass - m).abs() <= 1e-14 * m,
        "Σ m_i = {grid_mass}, Σ m_p = {m}"
    );
    let weight: f64 = g.force.iter().map(|f| f[1]).sum();
    assert!((weight + 9.81 * m).abs() <= 1e-13 * 9.81 * m);
    let mut grid_l = [0.0; 3];
    for (i, q) in g.momentum.iter().enumerate() {
        let x = grid.node_position(i);
        let l = cross([x[0] - c[0], x[1] - c[1], x[2] - c[2]], *q);
        for a in 0..3 {
            grid_l[a] += l[a];
        }
    }
    let particle_l = p.angular_momentum(c);
    for a in 0..3 {
        let grid_mv: f64 = g.momentum.iter().map(|q| q[a]).sum();
        assert!(
            (grid_mv - mv[a]).abs() <= 1e-13 * scale,
            "Σ (mv)_i = {grid_mv}, Σ m_p v_p = {}",
            mv[a]
        );
        assert!(
            (grid_l[a] - particle_l[a]).abs() <= 1e-13 * angular_scale,
            "grid L = {grid_l:?}, particles' L = {particle_l:?}"
        );
    }
}

#[test]
fn uniform_translation_is_exact_3d() {
    let v = [0.37, -0.21, 0.13];
    for shape in SHAPES {
        let mut mpm = MpmStepper::new(pic(shape));
        let mut p = block();
        for u in &mut p.velocity {
            *u = v;
        }
        let start = p.clone();
        let (m0, mv0) = p.mass_and_momentum();
        check_grid_totals(mpm.mpm(), &p);
        for step in 1..=STEPS {
            mpm.advance(&mut p, H).unwrap();
            let (m, mv) = p.mass_and_momentum();
            assert_eq!(m, m0);
            for a in 0..3 {
                assert!(
                    (mv[a] - mv0[a]).abs() <= 1e-13 * mv0[a].abs(),
                    "{mv:?} vs {mv0:?}"
                );
            }
            let t = step as f64 * H;
            for k in 0..p.len() {
                for (a, va) in v.iter().enumerate() {
                    assert!(
                        (p.velocity[k][a] - va).abs() <= 1e-13 * va.abs(),
                        "{shape:?}: v_{k} = {:?}",
                        p.velocity[k]
                    );
                    let expected = start.position[k][a] + t * va;
                    assert!(
                        (p.position[k][a] - expected).abs() <= 1e-14 * step as f64,
                        "{shape:?} step {step}: x_{k} = {:?}",
                        p.position[k]
                    );
                }
                assert!((p.volume[k] / start.volume[k] - 1.0).abs() <= 1e-13);
                assert!(
                    p.stress[k].iter().all(|s| s.abs() <= 1e-6),
                    "{shape:?}: σ_{k} = {:?}",
                    p.stress[k]
                );
            }
        }
        check_grid_totals(mpm.mpm(), &p);
    }
}

/// `v = V + ω × (x − c)` about the centroid, ω oblique (|ω| = 0.707 rad/s: h|ω| = 7e-3).
fn rigid_rotation(shape: ShapeFunction, translation: [f64; 3]) {
    let omega = [0.3, -0.5, 0.4];
    let mut mpm = MpmStepper::new(pic(shape));
    let mut p = block();
    let c = centroid(&p);
    for (x, v) in p.position.iter().zip(p.velocity.iter_mut()) {
        let w = cross(omega, [x[0] - c[0], x[1] - c[1], x[2] - c[2]]);
        *v = [0, 1, 2].map(|a| translation[a] + w[a]);
    }
    let (m0, mv0) = p.mass_and_momentum();
    let (scale, _) = scales(&p, c);
    check_grid_totals(mpm.mpm(), &p);
    let l0 = p.angular_momentum(c);
    let mut angular = norm(l0);
    println!("{shape:?}, V = {translation:?}: L0 = {l0:?} kg m²/s");
    for step in 1..=STEPS {
        mpm.advance(&mut p, H).unwrap();
        let (m, mv) = p.mass_and_momentum();
        assert_eq!(m, m0);
        for a in 0..3 {
            assert!(
                (mv[a] - mv0[a]).abs() <= 1e-13 * scale,
                "{shape:?} step {step}: momentum {mv:?} vs {mv0:?} (scale {scale:.3e})"
            );
        }
        check_grid_totals(mpm.mpm(), &p);
        let next = norm(p.angular_momentum(centroid(&p)));
        println!(
            "  step {step}: |L|/|L0| = {:.9}, loss this step {:.3e}",
            next / norm(l0),
            (angular - next) / angular
        );
        assert!(
            next > 0.0 && next <= angular * (1.0 + 1e-12),
            "{shape:?} step {step}: |L| rose from {angular} to {next}"
        );
        angular = next;
    }
}

#[test]
fn rigid_rotation_about_an_oblique_axis_3d() {
    for shape in SHAPES {
        rigid_rotation(shape, [0.0; 3]);
        rigid_rotation(shape, [0.37, -0.21, 0.13]);
    }
}
