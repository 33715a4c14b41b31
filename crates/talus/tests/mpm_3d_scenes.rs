//! 3D MPM scenes through the app (`[analysis] geometry = "3d"` with a `[grid]`,
//! `docs/3d-mpm.md`, issue 25 items 2 and 5):
//!
//! - a plane-strain problem run as 3D gives the 2D run's history: the 2D model is the 3D
//!   one with `ε_zz = ε_yz = ε_xz = 0` (e.g. Zienkiewicz & Taylor, The Finite Element
//!   Method, vol. 1, §6.2), which a 3D grid one cell thick with slip walls on its back and
//!   front faces imposes (`crates/mpm/tests/plane_strain_in_3d.rs` shows it for the
//!   library to 1e-11). The two runs are independent formulations (2D and 3D grids,
//!   stencils, Mandel sizes, friction cones) through the same scene reader, model build,
//!   engine and history writer; forces and energies of the 3D run are the 2D ones (per
//!   metre) times the thickness;
//! - the column of `scenes/column_3d.toml` holds the lattice particles of its quarter
//!   cylinder (counted here from the lattice) with `ρ` times their volume;
//! - an elastic column in an oedometer settles in uniaxial strain,
//!   `σ_yy = −ρ g (H − y)`, `σ_xx = σ_zz = K₀ σ_yy` (Coombs et al. 2020, CMAME 369; the
//!   library's `elastic_column_gravity_3d.rs`), read from the run's last particle VTU;
//! - bad 3D inputs are refused naming the field.
use crate::common;
use std::path::{Path, PathBuf};

use common::{array, history_column, replaced};
use talus::model::mpm::MpmModel;
use talus::run::mpm::{run_mpm_scene, run_mpm_scene_3d};
use talus::run::RunOptions;
use talus::scene::{MpmScene, SceneError, SceneFile};

/// A sand column 0.1 × 0.2 m (5 × 10 cells of dx = 0.02 m, 4 particles each) against a
/// slip wall at x = 0, collapsing on a Coulomb floor μ = 0.5: the library's
/// `plane_strain_in_3d.rs` case, 60 steps of 1 ms.
const COLUMN_2D: &str = r#"
title = "plane-strain sand column"
gravity = [0.0, -9.81]

[grid]
origin = [0.0, 0.0]
spacing = 0.02
cells = [20, 12]

[[body]]
rectangle = [[0.0, 0.0], [0.1, 0.2]]

[material]
young_modulus = 1.0e7
poisson_ratio = 0.3
friction_angle = 30.0
cohesion = 0.0
dilatancy_angle = 0.0
cone_fit = "plane_strain"
density = 1800.0

[[wall]]
side = "left"
condition = "slip"

[[wall]]
name = "floor"
side = "bottom"
condition = "friction"
friction = 0.5

[time]
step = 1.0e-3
steps = 60

[output]
runout = true
vtu_every = 0
"#;

/// [`COLUMN_2D`] one cell thick in z (0.02 m) with slip walls on both z faces, listed
/// before the floor so that its friction acts along x alone on their nodes.
fn column_3d() -> String {
    let text = replaced(
        COLUMN_2D,
        "gravity = [0.0, -9.81]",
        "gravity = [0.0, -9.81, 0.0]",
    );
    let text = replaced(
        &text,
        "origin = [0.0, 0.0]\nspacing = 0.02\ncells = [20, 12]",
        "origin = [0.0, 0.0, 0.0]\nspacing = 0.02\ncells = [20, 12, 1]",
    );
    let text = replaced(
        &text,
        "rectangle = [[0.0, 0.0], [0.1, 0.2]]",
        "box = [[0.0, 0.0, 0.0], [0.1, 0.2, 0.02]]",
    );
    let text = replaced(
        &text,
        "[[wall]]\nside = \"left\"",
        "[[wall]]\nside = \"back\"\ncondition = \"slip\"\n\n[[wall]]\nside = \"front\"\n\
         condition = \"slip\"\n\n[[wall]]\nside = \"left\"",
    );
    replaced(&text, "[grid]", "[analysis]\ngeometry = \"3d\"\n\n[grid]")
}

fn out_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("mpm_3d_scenes")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn scene3(text: &str) -> talus::scene::MpmScene3 {
    match SceneFile::parse(text, None).unwrap_or_else(|e| panic!("{e}")) {
        SceneFile::Mpm3(s) => s,
        _ => panic!("not read as a 3D MPM scene"),
    }
}

#[test]
fn a_plane_strain_column_run_in_3d_gives_the_2d_history() {
    let thickness = 0.02;
    let out2 = out_dir("plane_strain_2d");
    let scene2 = MpmScene::parse(COLUMN_2D, None).unwrap();
    let run2 = run_mpm_scene(&scene2, &RunOptions::new(&out2)).unwrap_or_else(|e| panic!("{e}"));
    let out3 = out_dir("plane_strain_3d");
    let scene3 = scene3(&column_3d());
    let run3 =
        run_mpm_scene_3d(&scene3, &RunOptions::new(&out3), None).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(run2.particles.len() * 2, run3.particles.len());

    // (history.csv column, factor of the 3D value over the 2D one)
    let columns = [
        ("floor_fx", thickness),
        ("floor_fy", thickness),
        ("front", 1.0),
        ("runout_normalized", 1.0),
        ("kinetic_energy", thickness),
        ("contact_passes", 1.0),
    ];
    let mut worst = 0.0f64;
    for (c2, factor) in columns {
        let a = history_column(&out2, c2);
        let b = history_column(&out3, c2);
        assert_eq!(a.len(), 61, "{c2}: rows");
        assert_eq!(a.len(), b.len(), "{c2}: rows");
        let scale = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(scale > 0.0, "{c2} is zero throughout");
        let diff = a
            .iter()
            .zip(&b)
            .map(|(x, y)| (y / factor - x).abs())
            .fold(0.0f64, f64::max);
        println!("{c2}: max |3D/factor − 2D| = {diff:.3e} of max |2D| = {scale:.4e}");
        worst = worst.max(diff / scale);
    }
    // The z reaction of the floor vanishes.
    let fy = history_column(&out2, "floor_fy");
    let fy_scale = fy.iter().fold(0.0f64, |m, v| m.max(v.abs())) * thickness;
    let fz = history_column(&out3, "floor_fz");
    let fz_max = fz.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    // It did flow: the front moved and the sand yielded.
    let front = history_column(&out2, "front");
    let advance = front.last().unwrap() - front[0];
    let yielded = run2
        .particles
        .plastic_strain
        .iter()
        .fold(0.0f64, |m, v| m.max(*v));
    println!(
        "largest relative difference {worst:.3e}; |floor_fz| ≤ {:.2e} of |floor_fy|; front \
         +{advance:.4e} m, plastic strain up to {yielded:.3}",
        fz_max / fy_scale
    );
    assert!(advance > 1e-3 && yielded > 0.01, "the column did not flow");
    assert!(worst <= 1e-9, "3D differs from 2D by {worst:.3e}");
    // Measured 6e-17: round-off of forces that cancel between the particle layers.
    assert!(fz_max <= 1e-12 * fy_scale, "floor_fz {fz_max:.3e} N");
}

/// `scenes/column_3d.toml`: the particles of the quarter cylinder R₀ = 0.1 m, H₀ = 0.05 m
/// on the lattice of `dx / 2` (those whose centre lies within R₀ of the axis), each of
/// mass ρ (dx/2)³; the runout is radial.
#[test]
fn the_3d_column_scene_holds_its_quarter_cylinder() {
    let scene = common::shipped_mpm_scene_3d("column_3d.toml");
    let model = MpmModel::from_scene_3d(&scene).unwrap_or_else(|e| panic!("{e}"));
    let (r0, h0, d, rho) = (0.1, 0.05, 0.01, 1800.0);
    let n = |l: f64| (l / d).round() as usize;
    let mut count = 0;
    for i in 0..n(r0) {
        for k in 0..n(r0) {
            let (x, z) = ((i as f64 + 0.5) * d, (k as f64 + 0.5) * d);
            if x * x + z * z <= r0 * r0 {
                count += n(h0);
            }
        }
    }
    let p = &model.particles;
    assert_eq!(p.len(), count);
    let mass: f64 = p.mass.iter().sum();
    let expected = rho * count as f64 * d * d * d;
    assert!(
        (mass / expected - 1.0).abs() <= 1e-12,
        "mass {mass} kg vs {expected}"
    );
    // Within the lattice's band of the quarter cylinder's volume.
    let volume: f64 = p.volume.iter().sum();
    let cylinder = std::f64::consts::FRAC_PI_4 * r0 * r0 * h0;
    assert!(
        (volume / cylinder - 1.0).abs() <= d / r0,
        "volume {volume} m³ vs {cylinder}"
    );
    println!(
        "{count} particles, mass {mass:.4} kg, volume {volume:.4e} m³ (πR²H/4 = {cylinder:.4e})"
    );
    assert!(matches!(
        model.runout,
        talus::model::mpm::Runout::Radial { axis, radius } if axis == [0.0, 0.0] && radius == r0
    ));
}

/// The elastic column W × W × H = 0.2 × 0.2 × 1 m (dx = 0.05 m, linear hats, 2560
/// particles) on a fixed floor with slip walls on its four sides, released from rest, 20
/// steps of h = 25 dx / c_p: the library test's column, here through a scene file.
/// Tolerance 2 % of ρgH, as the library test's (it measures 1.4 %).
#[test]
fn an_elastic_column_in_3d_settles_in_uniaxial_strain() {
    let (e, nu, rho, g, width, height, dx): (f64, f64, f64, f64, f64, f64, f64) =
        (1e7, 0.3, 2000.0, 9.81, 0.2, 1.0, 0.05);
    let modulus = e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let h = 25.0 * dx / (modulus / rho).sqrt();
    let steps = 20;
    let text = format!(
        r#"
gravity = [0.0, -{g}, 0.0]

[analysis]
geometry = "3d"

[grid]
origin = [0.0, 0.0, 0.0]
spacing = {dx}
cells = [4, 22, 4]
shape = "linear"

[[body]]
box = [[0.0, 0.0, 0.0], [{width}, {height}, {width}]]

[material]
model = "elastic"
young_modulus = {e}
poisson_ratio = {nu}
density = {rho}

[[wall]]
side = "left"
condition = "slip"

[[wall]]
side = "right"
condition = "slip"

[[wall]]
side = "back"
condition = "slip"

[[wall]]
side = "front"
condition = "slip"

[[wall]]
name = "floor"
side = "bottom"
condition = "fixed"

[time]
step = {h}
steps = {steps}

[output]
vtu_every = 0
plots = false
"#
    );
    let scene = scene3(&text);
    let model = MpmModel::from_scene_3d(&scene).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(model.particles.len(), 2560);
    let y0: Vec<f64> = model.particles.position.iter().map(|x| x[1]).collect();
    let out = out_dir("elastic_column");
    let options = RunOptions {
        write_fields: true,
        ..RunOptions::new(&out)
    };
    run_mpm_scene_3d(&scene, &options, None).unwrap_or_else(|e| panic!("{e}"));
    let xml = std::fs::read_to_string(out.join(format!("vtu/step_{steps:05}.vtu"))).unwrap();
    let stress = array(&xml, "stress");
    let points = array(&xml, "Points");
    assert_eq!(stress.len(), 6 * 2560, "6 stress components a particle");
    assert_eq!(points.len(), 3 * 2560);
    // The particles fill the column in z too.
    let z_max = points.chunks(3).map(|p| p[2]).fold(0.0f64, f64::max);
    assert!(z_max > 0.75 * width, "z up to {z_max}");
    let k0 = nu / (1.0 - nu);
    let scale = rho * g * height;
    let (mut eyy, mut exx, mut ezz, mut shear) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    // VTK order XX, YY, ZZ, XY, YZ, XZ.
    for (s, y) in stress.chunks(6).zip(&y0) {
        let syy = -rho * g * (height - y);
        eyy = eyy.max((s[1] - syy).abs() / scale);
        exx = exx.max((s[0] - k0 * syy).abs() / scale);
        ezz = ezz.max((s[2] - k0 * syy).abs() / scale);
        shear = shear.max(s[3].abs().max(s[4].abs()).max(s[5].abs()) / scale);
    }
    // The floor carries the column's weight ρ g W² H (N).
    let fy = *history_column(&out, "floor_fy").last().unwrap();
    let weight = rho * g * width * width * height;
    println!(
        "max |Δσ_yy|/(ρgH) = {eyy:.4}, |σ_xx − K0 σ_yy| {exx:.4}, |σ_zz − K0 σ_yy| {ezz:.4}, \
         shear {shear:.2e}; floor {fy:.2} N vs ρgW²H = {weight:.2} N (rel. {:.2e})",
        (fy.abs() / weight - 1.0).abs()
    );
    assert!(eyy <= 0.02, "σ_yy error {eyy:.4} of ρgH");
    assert!(exx <= 0.02, "σ_xx error {exx:.4} of ρgH");
    assert!(ezz <= 0.02, "σ_zz error {ezz:.4} of ρgH");
    // No shear in uniaxial strain: measured 2.6e-14 (round-off), not the 2 % of the
    // normal stresses' discretization error.
    assert!(shear <= 1e-10, "shear {shear:.4e} of ρgH");
    // The column has come to rest on the floor: measured 1.1e-7 (history.csv's digits and
    // what motion is left), not the 2 % of the stresses' discretization error.
    assert!((fy.abs() / weight - 1.0).abs() <= 1e-5, "floor {fy} N");
}

fn refused(text: &str) -> SceneError {
    match SceneFile::parse(text, None) {
        Err(e) => e,
        Ok(SceneFile::Mpm3(s)) => MpmModel::from_scene_3d(&s).err().expect("refused"),
        Ok(SceneFile::Mpm(s)) => MpmModel::from_scene(&s).err().expect("refused"),
        Ok(_) => panic!("not an MPM scene"),
    }
}

#[test]
fn bad_3d_mpm_inputs_are_named() {
    let good = column_3d();
    let cases: Vec<(String, &str, &str)> = vec![
        // 2-component vectors in a 3D scene
        (
            replaced(
                &good,
                "gravity = [0.0, -9.81, 0.0]",
                "gravity = [0.0, -9.81]",
            ),
            "gravity",
            "2 components",
        ),
        (
            replaced(&good, "cells = [20, 12, 1]", "cells = [20, 12]"),
            "grid.cells",
            "2 components",
        ),
        (
            replaced(
                &good,
                "box = [[0.0, 0.0, 0.0], [0.1, 0.2, 0.02]]",
                "box = [[0.0, 0.0], [0.1, 0.2]]",
            ),
            "body[0].box",
            "2 components",
        ),
        // a 2D body in a 3D scene
        (
            replaced(
                &good,
                "box = [[0.0, 0.0, 0.0], [0.1, 0.2, 0.02]]",
                "rectangle = [[0.0, 0.0, 0.0], [0.1, 0.2, 0.02]]",
            ),
            "body[0].rectangle",
            "box",
        ),
        // zero extents
        (
            replaced(
                &good,
                "box = [[0.0, 0.0, 0.0], [0.1, 0.2, 0.02]]",
                "box = [[0.0, 0.0, 0.0], [0.1, 0.2, 0.0]]",
            ),
            "body[0].box",
            "max > min",
        ),
        (
            replaced(&good, "cells = [20, 12, 1]", "cells = [20, 12, 0]"),
            "grid.cells",
            "between 1",
        ),
        (
            replaced(
                &good,
                "box = [[0.0, 0.0, 0.0], [0.1, 0.2, 0.02]]",
                "cylinder = { centre = [0.0, 0.0], base = 0.0, radius = 0.0, height = 0.1 }",
            ),
            "body[0].cylinder.radius",
            "> 0",
        ),
        // a cylinder leaving the grid (a whole one around x = 0, z = 0)
        (
            replaced(
                &good,
                "box = [[0.0, 0.0, 0.0], [0.1, 0.2, 0.02]]",
                "cylinder = { centre = [0.0, 0.0], base = 0.0, radius = 0.005, height = 0.1 }",
            ),
            "body[0].cylinder",
            "outside the grid",
        ),
        // two shapes
        (
            replaced(
                &good,
                "box = [[0.0, 0.0, 0.0], [0.1, 0.2, 0.02]]",
                "box = [[0.0, 0.0, 0.0], [0.1, 0.2, 0.02]]\ncylinder = { centre = [0.0, 0.0], \
                 base = 0.0, radius = 0.005, height = 0.1, quarter = true }",
            ),
            "body[0].cylinder",
            "one shape",
        ),
        (
            replaced(&good, "geometry = \"3d\"", "geometry = \"axisymmetric\""),
            "gravity",
            "3 components",
        ),
    ];
    for (text, field, words) in cases {
        let err = refused(&text);
        assert_eq!(err.field, field, "{err}");
        assert!(err.message.contains(words), "{field}: {err}");
        assert!(err.line.is_some(), "{field}: no line: {err}");
    }
}

#[test]
fn a_2d_mpm_scene_refuses_3d_keys_and_vectors_by_name() {
    let cases: Vec<(String, &str)> = vec![
        (
            replaced(
                COLUMN_2D,
                "gravity = [0.0, -9.81]",
                "gravity = [0.0, -9.81, 0.0]",
            ),
            "gravity",
        ),
        (
            replaced(COLUMN_2D, "side = \"left\"", "side = \"back\""),
            "wall[0].side",
        ),
        (
            replaced(
                COLUMN_2D,
                "rectangle = [[0.0, 0.0], [0.1, 0.2]]",
                "cylinder = { centre = [0.0, 0.0], base = 0.0, radius = 0.1, height = 0.1 }",
            ),
            "body[0].cylinder",
        ),
        (
            replaced(
                COLUMN_2D,
                "rectangle = [[0.0, 0.0], [0.1, 0.2]]",
                "box = [[0.0, 0.0], [0.1, 0.2]]",
            ),
            "body[0].box",
        ),
    ];
    for (text, field) in cases {
        let err = refused(&text);
        assert_eq!(err.field, field, "{err}");
        assert!(err.line.is_some(), "{field}: no line: {err}");
        assert!(err.message.contains("geometry = \"3d\""), "{field}: {err}");
    }
}
