//! Bodies of their own materials: each particle carries a material index into the
//! `Mpm`'s materials (`Mpm::with_materials`), and each sub-step's reduced problem takes
//! the flow rule and `S_p = V_p S₀` of the particle's material.
//!
//! - Two touching bodies of identical parameters, as two materials, step for step the
//!   same bits as one material (the same arithmetic per particle).
//! - An elastic block on a fixed floor under gravity never flows (its plastic strain stays
//!   at round-off, ≤ 1e-9 of the same block's as cohesionless sand, which slumps), while a
//!   sand column beside it flows.
//! - A particle whose index names no material is an error naming the particle and index.
use crate::sand_column;

use sand_column::sand;
use talus_bipotential::{Elastic, Material};
use talus_mpm::{
    Grid, GridBoundary, Mpm, MpmError, MpmSettings, MpmStepReport, MpmStepper, Particles,
    ShapeFunction, Side, Wall, WallCondition,
};

const DX: f64 = 0.05;
const RHO: f64 = 1800.0;

/// A 1.5 m × 0.6 m grid with a floor (`floor`) and a slip left wall.
fn grid_and_walls(floor: WallCondition) -> (Grid, GridBoundary) {
    let grid = Grid::try_new([0.0, 0.0], DX, [30, 12], ShapeFunction::QuadraticBSpline).unwrap();
    let boundary = GridBoundary {
        walls: vec![
            Wall {
                side: Side::Left,
                condition: WallCondition::Slip,
            },
            Wall {
                side: Side::Bottom,
                condition: floor,
            },
        ],
        prescribed: vec![],
    };
    (grid, boundary)
}

fn bits(v: impl IntoIterator<Item = f64>) -> Vec<u64> {
    v.into_iter().map(f64::to_bits).collect()
}

/// Every particle field but the material indices, as bits.
fn particle_bits(p: &Particles) -> Vec<Vec<u64>> {
    vec![
        bits(p.position.iter().flatten().copied()),
        bits(p.velocity.iter().flatten().copied()),
        bits(p.mass.iter().copied()),
        bits(p.volume.iter().copied()),
        bits(p.stress.iter().flatten().copied()),
        bits(p.plastic_strain.iter().copied()),
        bits(p.external_force.iter().flatten().copied()),
    ]
}

fn report_summary(r: &MpmStepReport) -> (usize, usize, u64, Vec<u64>) {
    (
        r.substeps,
        r.total_newton_iterations(),
        r.relative_residual.to_bits(),
        bits(
            r.stats
                .as_ref()
                .map(|s| s.group_forces.iter().flatten().copied().collect::<Vec<_>>())
                .unwrap_or_default(),
        ),
    )
}

/// Two touching sand bodies (a 0.4 m × 0.3 m block, split at x = 0.35 m) slumping on a
/// rough floor: as one material, or as two materials of identical parameters.
#[test]
fn two_materials_of_identical_parameters_step_as_one_bit_for_bit() {
    let floor = WallCondition::Friction { coefficient: 0.5 };
    // Every floor node stuck at a sub-step's start, so that steps take second friction
    // passes (with the contact predictor this block settles in one).
    let all_stuck = MpmSettings {
        contact_predictor: false,
        ..MpmSettings::default()
    };
    let left = Particles::fill_rectangle([[0.15, 0.0], [0.35, 0.3]], DX, 2, RHO).unwrap();
    let right = Particles::fill_rectangle([[0.35, 0.0], [0.55, 0.3]], DX, 2, RHO).unwrap();

    let (grid, boundary) = grid_and_walls(floor);
    let one = Mpm::try_new(grid, boundary, &sand(), [0.0, -9.81], all_stuck).unwrap();
    let mut one_particles = left.clone();
    one_particles.extend(&right);
    assert!(one_particles.material.is_empty(), "all of material 0");

    let (grid, boundary) = grid_and_walls(floor);
    let materials = [
        Material::DruckerPrager(sand()),
        Material::DruckerPrager(sand()),
    ];
    let two = Mpm::with_materials(grid, boundary, &materials, [0.0, -9.81], all_stuck).unwrap();
    assert_eq!(two.materials().len(), 2);
    let mut two_particles = left.with_material(0);
    two_particles.extend(&right.with_material(1));
    let n_left = two_particles.material.iter().filter(|m| **m == 0).count();
    assert_eq!(two_particles.material.len(), two_particles.len());
    assert!(n_left > 0 && n_left < two_particles.len());

    let (mut one, mut two) = (MpmStepper::new(one), MpmStepper::new(two));
    let h = 4e-3;
    let mut friction_passes = 0;
    let mut flowed = 0.0f64;
    for step in 1..=25 {
        let a = one.advance(&mut one_particles, h).unwrap();
        let b = two.advance(&mut two_particles, h).unwrap();
        assert_eq!(
            report_summary(&a),
            report_summary(&b),
            "step {step}: reports"
        );
        assert!(
            particle_bits(&one_particles) == particle_bits(&two_particles),
            "step {step}: the particles differ in some bit"
        );
        friction_passes = friction_passes.max(a.stats.as_ref().map_or(0, |s| s.contact_passes));
        flowed = one_particles
            .plastic_strain
            .iter()
            .copied()
            .fold(flowed, f64::max);
    }
    // The comparison covers plastic flow and the friction passes (`after_solve`'s
    // problems), not only elastic steps.
    println!("max plastic strain {flowed:.3e}, up to {friction_passes} friction passes");
    assert!(flowed > 1e-3, "the block did not flow: {flowed:.3e}");
    assert!(friction_passes > 1, "no step took a second friction pass");
    assert_eq!(two_particles.material.len(), two_particles.len());
}

/// The plastic strain of `block`'s particles and of `column`'s after 0.1 s on a fixed
/// floor: a 0.2 m × 0.2 m block at x ∈ [0.1, 0.3] m of `block` and a 0.15 m × 0.3 m column
/// at x ∈ [0.7, 0.85] m of `column` (indices into `materials`).
fn block_and_column(materials: &[Material], block: usize, column: usize) -> (Vec<f64>, Vec<f64>) {
    let (grid, boundary) = grid_and_walls(WallCondition::Fixed);
    let mpm = Mpm::with_materials(
        grid,
        boundary,
        materials,
        [0.0, -9.81],
        MpmSettings::default(),
    )
    .unwrap();
    let mut particles = Particles::fill_rectangle([[0.1, 0.0], [0.3, 0.2]], DX, 2, RHO)
        .unwrap()
        .with_material(block);
    let n_block = particles.len();
    particles.extend(
        &Particles::fill_rectangle([[0.7, 0.0], [0.85, 0.3]], DX, 2, RHO)
            .unwrap()
            .with_material(column),
    );
    let mut stepper = MpmStepper::new(mpm);
    for _ in 0..25 {
        stepper.advance(&mut particles, 4e-3).unwrap();
    }
    let (b, c) = particles.plastic_strain.split_at(n_block);
    (b.to_vec(), c.to_vec())
}

#[test]
fn an_elastic_block_never_flows_beside_a_sand_column_that_does() {
    let elastic = Material::Elastic(Elastic::try_new(1e8, 0.25).unwrap());
    let sand = Material::DruckerPrager(sand());
    let (block, column) = block_and_column(&[elastic, sand], 0, 1);
    // The witness: the same block as cohesionless sand slumps.
    let (sand_block, _) = block_and_column(&[sand], 0, 0);
    let max = |v: &[f64]| v.iter().copied().fold(0.0f64, f64::max);
    let (elastic_max, witness_max, column_max) = (max(&block), max(&sand_block), max(&column));
    println!(
        "max plastic strain: elastic block {elastic_max:.3e}, the same block of sand \
         {witness_max:.3e}, the sand column {column_max:.3e}"
    );
    assert!(
        witness_max > 1e-3,
        "the sand block did not flow: {witness_max:.3e}"
    );
    assert!(
        column_max > 1e-3,
        "the sand column did not flow: {column_max:.3e}"
    );
    assert!(
        elastic_max <= 1e-9 * witness_max,
        "the elastic block flowed: {elastic_max:.3e} (sand: {witness_max:.3e})"
    );
}

#[test]
fn a_material_index_out_of_range_is_an_error_naming_the_particle_and_the_index() {
    let (grid, boundary) = grid_and_walls(WallCondition::Fixed);
    let materials = [
        Material::DruckerPrager(sand()),
        Material::DruckerPrager(sand()),
    ];
    let mpm = Mpm::with_materials(
        grid,
        boundary,
        &materials,
        [0.0, -9.81],
        MpmSettings::default(),
    )
    .unwrap();
    let mut particles = Particles::fill_rectangle([[0.1, 0.0], [0.3, 0.2]], DX, 2, RHO)
        .unwrap()
        .with_material(1);
    particles.material[5] = 2;
    let Err(e) = mpm.begin_substep(&particles, 1e-3) else {
        panic!("a particle of material 2 with two materials was accepted");
    };
    println!("{e}");
    match &e {
        MpmError::Invalid { field, reason } => {
            assert_eq!(field, "particles.material[5]");
            assert!(
                reason.contains("particle 5") && reason.contains("material 2"),
                "{e}"
            );
            assert!(reason.contains("2 materials"), "{e}");
        }
        other => panic!("not an Invalid: {other:?}"),
    }
    // Through the engine, the same error, the particles untouched.
    let before = particles.clone();
    let mut stepper = MpmStepper::new(mpm.clone());
    let err = stepper.advance(&mut particles, 1e-3).unwrap_err();
    assert!(err.to_string().contains("particles.material[5]"), "{err}");
    assert_eq!(particles, before);

    // A list that is neither empty nor one per particle.
    particles.material.pop();
    let Err(e) = mpm.begin_substep(&particles, 1e-3) else {
        panic!("a short material list was accepted");
    };
    assert!(
        matches!(&e, MpmError::Invalid { field, .. } if field == "particles.material"),
        "{e:?}"
    );
    // No material at all.
    let (grid, boundary) = grid_and_walls(WallCondition::Fixed);
    let e =
        Mpm::with_materials(grid, boundary, &[], [0.0, -9.81], MpmSettings::default()).unwrap_err();
    assert!(
        matches!(&e, MpmError::Invalid { field, .. } if field == "materials"),
        "{e:?}"
    );
}

/// Particle sets built without materials, old checkpoints included, are all of material 0;
/// `extend` and `push` keep the indices of mixed sets.
#[test]
fn material_indices_default_to_zero_and_follow_extend_and_push() {
    let a = Particles::fill_rectangle([[0.0, 0.0], [0.1, 0.1]], DX, 1, RHO).unwrap();
    assert!(a.material.is_empty());
    assert_eq!(a.material_of(0), 0);
    // Written without the field: its JSON has no `material` key, and such a checkpoint
    // (one from before the indices) reads back as all of material 0.
    let json = serde_json::to_value(&a).unwrap();
    assert!(json.get("material").is_none(), "{json}");
    let back: Particles = serde_json::from_value(json).unwrap();
    assert_eq!(back, a);

    let mut mixed = a.clone();
    mixed.extend(&a.clone().with_material(3));
    assert_eq!(mixed.material, vec![0, 0, 0, 0, 3, 3, 3, 3]);
    mixed.push([0.5, 0.5], 1.0, 1.0);
    assert_eq!(mixed.material_of(8), 0);
    assert_eq!(mixed.material.len(), mixed.len());
    mixed.validate().unwrap();
    let json = serde_json::to_value(&mixed).unwrap();
    let back: Particles = serde_json::from_value(json).unwrap();
    assert_eq!(back.material, mixed.material);

    let mut plain = a.clone();
    plain.extend(&a);
    assert!(
        plain.material.is_empty(),
        "two sets without indices keep none"
    );
}
