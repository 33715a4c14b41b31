//! The geotechnical post-processing fields of the VTUs (`docs/scenes.md`, 'Outputs';
//! `docs/mpm.md`, 'Outputs'), read back from the ASCII files:
//! - `principal_stress` of a known tensor (FEM cell and MPM particle VTUs);
//! - FEM `strain` of a homogeneous block under uniaxial strain, simple shear (tensor
//!   shear component, not the engineering one) and axisymmetric radial expansion (hoop
//!   strain `u_r / r`), against the closed forms;
//! - FEM `strain` equal to the constant-strain triangle's `sym ∇u` of the written nodal
//!   displacement, and `plastic_strain_increment` equal to `Δε − S Δσ` recomputed from the
//!   written strains and stresses, equal in norm to the increment of the solver's
//!   cumulative `plastic_strain`, and zero in an elastic step;
//! - MPM `displacement` equal to the particles' position change, and their `material`.
use crate::common;
use std::f64::consts::SQRT_2;
use std::path::{Path, PathBuf};

use common::{array, replaced, target_tmp_dir};
use std::ops::ControlFlow;
use std::sync::Arc;
use talus::output::{
    write_particle_vtu, write_vtu, FieldSnapshot, MeshView, OutputError, ParticleSnapshot,
};

use talus::run::fem::{resume_scene, run_scene};
use talus::run::mpm::run_mpm_scene;
use talus::run::{checkpoint, RunError, RunOptions, StepProgress};
use talus::scene::{Scene, SceneFile};

const FOOTING: &str = include_str!("../../../scenes/footing.toml");

fn out_dir(name: &str) -> PathBuf {
    let dir = target_tmp_dir("vtu_fields", name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn vtu(out: &Path, step: usize) -> String {
    std::fs::read_to_string(out.join(format!("vtu/step_{step:05}.vtu"))).unwrap()
}

/// Mandel `(xx, yy, zz, √2 xy)` from plain components ordered `[xx, yy, xy, zz]`.
fn mandel([xx, yy, xy, zz]: [f64; 4]) -> [f64; 4] {
    [xx, yy, zz, SQRT_2 * xy]
}

/// Runs the FEM scene `text` writing its fields to `out`.
fn run_fem(text: &str, out: &Path) {
    let scene = Scene::parse(text, None).unwrap();
    let options = RunOptions {
        write_fields: true,
        ..RunOptions::new(out)
    };
    run_scene(&scene, &options).unwrap();
}

/// The 6 VTK components `XX, YY, ZZ, XY, YZ, XZ` of element `e` of a tensor array.
fn tensor_of(a: &[f64], e: usize) -> [f64; 6] {
    a[6 * e..6 * e + 6].try_into().unwrap()
}

fn assert_close(what: &str, got: f64, want: f64, tol: f64) {
    assert!(
        (got - want).abs() <= tol,
        "{what}: {got:e}, expected {want:e} (tolerance {tol:e})"
    );
}

// ------------------------------------------------------------------ principal stresses

/// `[σxx, σyy, σxy, σzz] = [−3, −1, √3, −2]` kPa: the in-plane eigenvalues are
/// `(σxx + σyy)/2 ± √(((σxx − σyy)/2)² + σxy²) = −2 ± √(1 + 3) = −2 ± 2` kPa and σzz = −2,
/// so `(σ1, σ2, σ3) = (0, −2, −4)` kPa. `[1, −1, 0, 5]` kPa: σzz is the largest,
/// `(5, 1, −1)`. Pure shear τ: `(τ, 0, −τ)`.
#[test]
fn principal_stresses_of_known_tensors() {
    let k = 1e3;
    let plain = [
        [-3.0 * k, -k, 3f64.sqrt() * k, -2.0 * k],
        [k, -k, 0.0, 5.0 * k],
        [0.0, 0.0, 25.0 * k, 0.0],
    ];
    let expected = [
        [0.0, -2.0 * k, -4.0 * k],
        [5.0 * k, k, -k],
        [25.0 * k, 0.0, -25.0 * k],
    ];
    let stress = plain.map(mandel);
    let out = out_dir("principal");

    // Three P1 triangles (any mesh: the field is per cell).
    let nodes = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [2.0, 0.0]];
    let triangles = vec![vec![0, 1, 2], vec![0, 2, 3], vec![1, 4, 2]];
    let zero = [[0.0; 2]; 5];
    let fem = out.join("cells.vtu");
    write_vtu(
        &fem,
        &FieldSnapshot {
            mesh: MeshView {
                nodes: &nodes,
                elements: &triangles,
            },
            time: 0.0,
            displacement: &zero,
            velocity: &zero,
            stress: &stress,
            plastic_strain: &[0.0; 3],
            material: None,
            pore_pressure: None,
        },
    )
    .unwrap();
    let position = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]];
    let particles = out.join("particles.vtu");
    write_particle_vtu(
        &particles,
        &ParticleSnapshot {
            time: 0.0,
            position: &position,
            velocity: &[[0.0; 2]; 3],
            volume: &[1.0; 3],
            mass: &[1.0; 3],
            stress: &stress,
            plastic_strain: &[0.0; 3],
        },
    )
    .unwrap();
    for path in [fem, particles] {
        let xml = std::fs::read_to_string(&path).unwrap();
        assert!(xml.contains(r#"Name="principal_stress" NumberOfComponents="3""#));
        let p = array(&xml, "principal_stress");
        assert_eq!(p.len(), 9);
        for (i, want) in expected.iter().enumerate() {
            for c in 0..3 {
                assert_close(
                    &format!("{}: tensor {i}, σ{}", path.display(), c + 1),
                    p[3 * i + c],
                    want[c],
                    1e-12 * 25.0 * k,
                );
            }
        }
    }
}

/// A stress whose principal stresses overflow is refused, naming `stress`; nothing is
/// written.
#[test]
fn overflowing_principal_stresses_are_refused() {
    let big = f64::MAX / 2.0;
    let stress = [mandel([big, -big, big, 0.0])];
    let path = out_dir("overflow").join("p.vtu");
    let err = write_particle_vtu(
        &path,
        &ParticleSnapshot {
            time: 0.0,
            position: &[[0.0, 0.0]],
            velocity: &[[0.0; 2]],
            volume: &[1.0],
            mass: &[1.0],
            stress: &stress,
            plastic_strain: &[0.0],
        },
    )
    .unwrap_err();
    assert!(
        matches!(
            err,
            OutputError::Invalid {
                field: "stress",
                ..
            }
        ),
        "{err}"
    );
    assert!(!path.exists());
}

// ------------------------------------------------------------------ FEM strain, homogeneous

/// A P1 block `[0, 1] × [0, 2]` of 2 × 2 cells (8 triangles), elastic (E = 1e7 Pa,
/// ν = 0.3), one step of h = 0.01 s under `boundaries`. A scene needs a free dof, so the
/// motions below are set about the block's centre: there the exact homogeneous field is at
/// rest, the free dofs (the centre node, and the mid-side nodes along a roller) need no
/// force and no acceleration, and one dynamic step gives the affine field exactly.
fn block(boundaries: &str) -> String {
    format!(
        r#"title = "homogeneous block"

[mesh.rectangle]
x = [0.0, 1.0]
y = [0.0, 2.0]
cells = [2, 2]
order = "P1"

[material]
{ELASTIC}
density = 2000.0

{boundaries}

[time]
step = 0.01
steps = 1

[output]
vtu_every = 1
plots = false
"#
    )
}

const ELASTIC: &str = "model = \"elastic\"\nyoung_modulus = 1.0e7\npoisson_ratio = 0.3";
const E: f64 = 1.0e7;
const NU: f64 = 0.3;
const H: f64 = 2.0;
const STEP: f64 = 0.01;
const N_BLOCK_CELLS: usize = 8;

/// Uniaxial strain: smooth sides (x fixed), the bottom pushed up and the top down at
/// v/2 = 0.5 mm/s each, so `u_y = −v h (y − H/2) / H`: `εyy = −v h / H = −5e-6`,
/// `εxx = εzz = εxy = 0` (plane strain). Elastic: `σyy = (λ + 2μ) εyy`,
/// `σxx = σzz = λ εyy`, principal `(λ εyy, λ εyy, (λ + 2μ) εyy)`, and no plastic strain
/// increment: `Δεᵖ = Δε − S Δσ = 0` (step 1; step 0 has no step: 0).
#[test]
fn uniaxial_strain_in_a_block() {
    let v = 1.0e-3;
    let out = out_dir("uniaxial");
    run_fem(
        &block(&format!(
            "[[boundary]]\nnodes = \"left\"\nfix = \"x\"\n\n\
             [[boundary]]\nnodes = \"right\"\nfix = \"x\"\n\n\
             [[boundary]]\nnodes = \"bottom\"\nfix = \"xy\"\nvelocity = [0.0, {:e}]\n\n\
             [[boundary]]\nnodes = \"top\"\nfix = \"xy\"\nvelocity = [0.0, {:e}]\n",
            v / 2.0,
            -v / 2.0
        )),
        &out,
    );
    let eyy = -v * STEP / H;
    let lambda = E * NU / ((1.0 + NU) * (1.0 - 2.0 * NU));
    let mu = E / (2.0 * (1.0 + NU));

    let step0 = vtu(&out, 0);
    assert_eq!(array(&step0, "strain"), [0.0; 6 * N_BLOCK_CELLS]);
    assert_eq!(
        array(&step0, "plastic_strain_increment"),
        [0.0; 6 * N_BLOCK_CELLS]
    );

    let xml = vtu(&out, 1);
    let strain = array(&xml, "strain");
    let stress = array(&xml, "stress");
    let increment = array(&xml, "plastic_strain_increment");
    let principal = array(&xml, "principal_stress");
    assert_eq!(strain.len(), 6 * N_BLOCK_CELLS, "6 components per cell");
    for e in 0..N_BLOCK_CELLS {
        let want = [0.0, eyy, 0.0, 0.0, 0.0, 0.0];
        for (c, (g, w)) in tensor_of(&strain, e).iter().zip(want).enumerate() {
            assert_close(
                &format!("ε of cell {e}, component {c}"),
                *g,
                w,
                1e-9 * eyy.abs(),
            );
        }
        let s = tensor_of(&stress, e);
        let scale = (lambda + 2.0 * mu) * eyy.abs();
        assert_close("σxx", s[0], lambda * eyy, 1e-9 * scale);
        assert_close("σyy", s[1], (lambda + 2.0 * mu) * eyy, 1e-9 * scale);
        assert_close("σzz", s[2], lambda * eyy, 1e-9 * scale);
        let want = [lambda * eyy, lambda * eyy, (lambda + 2.0 * mu) * eyy];
        for c in 0..3 {
            assert_close("principal", principal[3 * e + c], want[c], 1e-9 * scale);
        }
        for (c, d) in tensor_of(&increment, e).iter().enumerate() {
            assert_close(
                &format!("Δεᵖ of cell {e}, component {c} (elastic)"),
                *d,
                0.0,
                1e-9 * eyy.abs(),
            );
        }
    }
}

/// Simple shear: the sides' mid nodes held, the top slid at +v/2 and the bottom at −v/2,
/// so `u_x = v h (y − H/2) / H`: the tensor shear strain is `εxy = v h / (2H) = 2.5e-6`
/// (the engineering `γxy = 2 εxy` is not what is written), the others 0; elastic
/// `σxy = 2μ εxy`.
#[test]
fn simple_shear_strain_is_the_tensor_component() {
    let v = 1.0e-3;
    let out = out_dir("shear");
    run_fem(
        &block(&format!(
            "[[boundary]]\nnodes = \"left\"\nfix = \"xy\"\n\n\
             [[boundary]]\nnodes = \"right\"\nfix = \"xy\"\n\n\
             [[boundary]]\nnodes = \"bottom\"\nfix = \"xy\"\nvelocity = [{:e}, 0.0]\n\n\
             [[boundary]]\nnodes = \"top\"\nfix = \"xy\"\nvelocity = [{:e}, 0.0]\n",
            -v / 2.0,
            v / 2.0
        )),
        &out,
    );
    let exy = v * STEP / (2.0 * H);
    let mu = E / (2.0 * (1.0 + NU));
    let xml = vtu(&out, 1);
    let strain = array(&xml, "strain");
    let stress = array(&xml, "stress");
    for e in 0..N_BLOCK_CELLS {
        let want = [0.0, 0.0, 0.0, exy, 0.0, 0.0];
        for (c, (g, w)) in tensor_of(&strain, e).iter().zip(want).enumerate() {
            assert_close(&format!("ε of cell {e}, component {c}"), *g, w, 1e-9 * exy);
        }
        assert_close(
            "σxy",
            tensor_of(&stress, e)[3],
            2.0 * mu * exy,
            1e-9 * mu * exy,
        );
    }
}

/// Axisymmetric radial expansion of a P1 column `r ∈ [1, 2]`, `y ∈ [0, 1]`, 1 × 2 cells:
/// the inner side moves out at `α r = α`, the outer at `2α`, top and bottom smooth
/// (y fixed), so `u_r = α h r` exactly (the free dofs, the sides' mid nodes' y, need no
/// force: `∫ ∂N/∂y σyy r dA` vanishes off the top and bottom) and
/// `ε = (εrr, εyy, εθθ, εry) = (α h, 0, α h, 0)`: the hoop strain `u_r / r` at each Gauss
/// point (plane strain would write εzz = 0).
#[test]
fn axisymmetric_hoop_strain_is_u_r_over_r() {
    let alpha = 1.0e-3;
    let text = format!(
        r#"title = "radial expansion"

[mesh.rectangle]
x = [1.0, 2.0]
y = [0.0, 1.0]
cells = [1, 2]
order = "P1"

[analysis]
geometry = "axisymmetric"

[material]
{ELASTIC}
density = 2000.0

[[boundary]]
nodes = "bottom"
fix = "y"

[[boundary]]
nodes = "top"
fix = "y"

[[boundary]]
nodes = "left"
fix = "x"
velocity = [{inner:e}, 0.0]

[[boundary]]
nodes = "right"
fix = "x"
velocity = [{outer:e}, 0.0]

[time]
step = {STEP:e}
steps = 1

[output]
vtu_every = 1
plots = false
"#,
        inner = alpha,
        outer = 2.0 * alpha
    );
    let out = out_dir("hoop");
    run_fem(&text, &out);
    let e = alpha * STEP;
    let strain = array(&vtu(&out, 1), "strain");
    assert_eq!(strain.len(), 6 * 4);
    for cell in 0..4 {
        let want = [e, 0.0, e, 0.0, 0.0, 0.0];
        for (c, (g, w)) in tensor_of(&strain, cell).iter().zip(want).enumerate() {
            assert_close(&format!("ε of cell {cell}, component {c}"), *g, w, 1e-9 * e);
        }
    }
}

// ------------------------------------------------------------------ FEM plastic increment

/// The paper footing (`scenes/footing.toml`) on a coarse P1 mesh, `steps` steps.
fn coarse_footing(steps: usize, vtu_every: usize) -> String {
    let mut text = FOOTING.to_string();
    for (from, to) in [
        ("cells = [32, 14]", "cells = [8, 4]"),
        ("order = \"P2\"", "order = \"P1\""),
        ("steps = 300", &format!("steps = {steps}")),
        ("vtu_every = 30", &format!("vtu_every = {vtu_every}")),
        ("plots = true", "plots = false"),
    ] {
        text = replaced(&text, from, to);
    }
    text
}

/// `sym ∇u` of a P1 triangle (constant-strain triangle) from its corner coordinates and
/// displacements, as VTK components `XX, YY, ZZ, XY, YZ, XZ` (plane strain: ZZ = 0).
fn cst_strain(x: [[f64; 2]; 3], u: [[f64; 2]; 3]) -> [f64; 6] {
    // ∂N_a/∂x = (y_b − y_c) / 2A, ∂N_a/∂y = (x_c − x_b) / 2A, (a, b, c) cyclic.
    let two_a =
        (x[1][0] - x[0][0]) * (x[2][1] - x[0][1]) - (x[2][0] - x[0][0]) * (x[1][1] - x[0][1]);
    let mut g = [[0.0; 2]; 2]; // g[i][j] = ∂u_i/∂x_j
    for (a, ua) in u.iter().enumerate() {
        let (b, c) = ((a + 1) % 3, (a + 2) % 3);
        let dn = [(x[b][1] - x[c][1]) / two_a, (x[c][0] - x[b][0]) / two_a];
        for (gi, ui) in g.iter_mut().zip(ua) {
            for (gij, dnj) in gi.iter_mut().zip(dn) {
                *gij += ui * dnj;
            }
        }
    }
    [g[0][0], g[1][1], 0.0, 0.5 * (g[0][1] + g[1][0]), 0.0, 0.0]
}

/// Isotropic elastic compliance on plain components `XX, YY, ZZ, XY`:
/// `ε_ij = ((1 + ν) σ_ij − ν tr σ δ_ij) / E` (tensor shear: `εxy = (1 + ν) σxy / E`).
fn compliance(e: f64, nu: f64, s: &[f64; 6]) -> [f64; 6] {
    let tr = s[0] + s[1] + s[2];
    [
        ((1.0 + nu) * s[0] - nu * tr) / e,
        ((1.0 + nu) * s[1] - nu * tr) / e,
        ((1.0 + nu) * s[2] - nu * tr) / e,
        (1.0 + nu) * s[3] / e,
        0.0,
        0.0,
    ]
}

/// `sqrt(xx² + yy² + zz² + 2 xy²)`: the Mandel (Frobenius) norm of plain components.
fn norm(t: &[f64; 6]) -> f64 {
    (t[0] * t[0] + t[1] * t[1] + t[2] * t[2] + 2.0 * t[3] * t[3]).sqrt()
}

/// The footing flows plastically from its first steps. At each written step k ≥ 1, per
/// element (P1: one Gauss point, so the cell value is the point's):
/// - `strain` is the constant-strain triangle's `sym ∇u` of the written nodal
///   displacement (free and prescribed nodes alike);
/// - `plastic_strain_increment` is `Δε − S Δσ`, recomputed from the written `strain` and
///   `stress` of steps k − 1 and k with the closed-form isotropic compliance of
///   E = 1e9 Pa, ν = 0.3;
/// - its norm is the step's increment of the solver's cumulative `plastic_strain`
///   (`Σ ‖z_p‖ / V_p`, from the solve itself) when the step took one sub-step;
/// - with `vtu_every = 3` the step-3 VTU holds the increment of step 3 alone, not of the
///   three steps since the last VTU.
#[test]
fn plastic_strain_increment_is_the_step_strain_minus_its_elastic_part() {
    let (e_young, nu) = (1.0e9, 0.3);
    let steps = 4;
    let out = out_dir("footing_every_step");
    run_fem(&coarse_footing(steps, 1), &out);
    let history = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let substeps: Vec<usize> = history
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(3).unwrap().parse().unwrap())
        .collect();
    assert_eq!(substeps.len(), steps + 1);

    let first = vtu(&out, 0);
    let connectivity = array(&first, "connectivity");
    let n_cells = connectivity.len() / 3;
    assert_eq!(n_cells, 64);
    let points = array(&first, "Points");
    let corners = |e: usize| -> [usize; 3] { [0, 1, 2].map(|k| connectivity[3 * e + k] as usize) };
    let mut max_increment: f64 = 0.0;
    let mut max_strain_step: f64 = 0.0;
    let mut previous = first;
    for (k, &n_substeps) in substeps.iter().enumerate().skip(1) {
        let xml = vtu(&out, k);
        let (strain, strain0) = (array(&xml, "strain"), array(&previous, "strain"));
        let (stress, stress0) = (array(&xml, "stress"), array(&previous, "stress"));
        let increment = array(&xml, "plastic_strain_increment");
        let (plastic, plastic0) = (
            array(&xml, "plastic_strain"),
            array(&previous, "plastic_strain"),
        );
        let u = array(&xml, "displacement");
        for e in 0..n_cells {
            let c = corners(e);
            let x = c.map(|n| [points[3 * n], points[3 * n + 1]]);
            let un = c.map(|n| [u[3 * n], u[3 * n + 1]]);
            let eps = tensor_of(&strain, e);
            let cst = cst_strain(x, un);
            let scale = norm(&cst).max(1e-30);
            for comp in 0..6 {
                assert_close(
                    &format!("step {k}, cell {e}: strain component {comp} vs sym ∇u"),
                    eps[comp],
                    cst[comp],
                    1e-9 * scale,
                );
            }
            let (s, s0, e0) = (
                tensor_of(&stress, e),
                tensor_of(&stress0, e),
                tensor_of(&strain0, e),
            );
            let ds: [f64; 6] = std::array::from_fn(|i| s[i] - s0[i]);
            let de: [f64; 6] = std::array::from_fn(|i| eps[i] - e0[i]);
            let elastic = compliance(e_young, nu, &ds);
            let want: [f64; 6] = std::array::from_fn(|i| de[i] - elastic[i]);
            let got = tensor_of(&increment, e);
            let tol = 1e-9 * norm(&de).max(norm(&elastic)).max(1e-30);
            for comp in 0..6 {
                assert_close(
                    &format!("step {k}, cell {e}: Δεᵖ component {comp}"),
                    got[comp],
                    want[comp],
                    tol,
                );
            }
            if n_substeps == 1 {
                let dp = plastic[e] - plastic0[e];
                assert_close(
                    &format!("step {k}, cell {e}: ‖Δεᵖ‖ vs Δ plastic_strain"),
                    norm(&got),
                    dp,
                    1e-9 * norm(&de).max(dp).max(1e-30),
                );
            }
            max_increment = max_increment.max(norm(&got));
            max_strain_step = max_strain_step.max(norm(&de));
        }
        previous = xml;
    }
    assert!(
        substeps[1..].contains(&1),
        "no step of one sub-step: {substeps:?}"
    );
    assert!(
        max_increment > 0.1 * max_strain_step,
        "the footing must flow: max ‖Δεᵖ‖ {max_increment:e}, max ‖Δε‖ {max_strain_step:e}"
    );

    // Every third step: the step-3 VTU holds the increment of step 3 only.
    let sparse = out_dir("footing_every_third_step");
    run_fem(&coarse_footing(3, 3), &sparse);
    assert!(!sparse.join("vtu/step_00002.vtu").exists());
    let got = array(&vtu(&sparse, 3), "plastic_strain_increment");
    let want = array(&vtu(&out, 3), "plastic_strain_increment");
    assert_eq!(got.len(), want.len());
    for (i, (g, w)) in got.iter().zip(&want).enumerate() {
        assert_close(&format!("entry {i}"), *g, *w, 1e-12 * max_increment);
    }
}

/// A run interrupted after step 2 (its checkpoint) and resumed writes the VTUs of steps 3
/// and 4 byte for byte as the uninterrupted run does: the state before step 3, which the
/// outputs did not keep across the resume, is read back from the checkpoint.
#[test]
fn a_resumed_run_writes_the_same_plastic_strain_increment() {
    let scene = Scene::parse(&coarse_footing(4, 1), None).unwrap();
    let reference = out_dir("footing_reference");
    run_fem(&coarse_footing(4, 1), &reference);
    let out = out_dir("footing_resumed");
    let options = RunOptions {
        write_fields: true,
        checkpoint_every: 2,
        observer: Some(Arc::new(|p: &StepProgress| {
            if p.step == 2 {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        })),
        ..RunOptions::new(&out)
    };
    match run_scene(&scene, &options) {
        Err(RunError::Interrupted { step: 2, .. }) => {}
        Err(e) => panic!("{e}"),
        Ok(_) => panic!("the run was not interrupted"),
    }
    assert!(!out.join("vtu/step_00003.vtu").exists());
    let saved = checkpoint::read(&out).unwrap();
    let options = RunOptions {
        write_fields: true,
        ..RunOptions::new(&out)
    };
    resume_scene(&scene, saved, &options).unwrap();
    for step in [3, 4] {
        let (a, b) = (vtu(&reference, step), vtu(&out, step));
        assert!(a.contains(r#"Name="plastic_strain_increment""#));
        assert!(a == b, "vtu/step_{step:05}.vtu differs after the resume");
    }
}

// ------------------------------------------------------------------ MPM displacement

/// The block and column of `tests/mpm_materials.rs` (`common::BLOCK_AND_COLUMN`): 256
/// block particles (material 0), 72 sand (material 1); 3 steps, a VTU each.
fn block_and_column() -> String {
    let text = replaced(common::BLOCK_AND_COLUMN, "steps = 20", "steps = 3");
    replaced(&text, "vtu_every = 0", "vtu_every = 1\nplots = false")
}

/// A particle's `displacement` is its position minus its position at t = 0: 0 at step 0,
/// and over each step its change equals the change of the written position. The
/// `material` index is the body's material (block 0, sand 1). Particles carry no strain,
/// so there is no `strain` (`docs/mpm.md`).
#[test]
fn mpm_displacement_is_the_position_change() {
    let scene = match SceneFile::parse(&block_and_column(), None) {
        Ok(SceneFile::Mpm(scene)) => scene,
        Ok(_) => panic!("parsed as a FEM scene"),
        Err(e) => panic!("{e}"),
    };
    let out = out_dir("mpm");
    let options = RunOptions {
        write_fields: true,
        ..RunOptions::new(&out)
    };
    let run = run_mpm_scene(&scene, &options).unwrap();

    let first = vtu(&out, 0);
    let x0 = array(&first, "Points");
    let n = x0.len() / 3;
    assert_eq!(n, 256 + 72);
    assert_eq!(array(&first, "displacement"), vec![0.0; 3 * n]);
    let material = array(&first, "material");
    let expected: Vec<f64> = (0..n).map(|p| if p < 256 { 0.0 } else { 1.0 }).collect();
    assert_eq!(material, expected);
    assert!(!first.contains(r#"Name="strain""#));

    let (mut x_prev, mut u_prev) = (x0.clone(), vec![0.0; 3 * n]);
    let mut largest: f64 = 0.0;
    for k in 1..=3 {
        let xml = vtu(&out, k);
        let (x, u) = (array(&xml, "Points"), array(&xml, "displacement"));
        assert_eq!(u.len(), 3 * n);
        for i in 0..3 * n {
            // u_k − u_{k−1} = x_k − x_{k−1} (and u_k = x_k − x_0 exactly).
            assert_close(
                &format!("step {k}, entry {i}"),
                u[i] - u_prev[i],
                x[i] - x_prev[i],
                1e-14,
            );
            assert_eq!(u[i], x[i] - x0[i], "step {k}, entry {i}");
            largest = largest.max((x[i] - x_prev[i]).abs());
        }
        (x_prev, u_prev) = (x, u);
    }
    assert!(largest > 1e-6, "the particles must move: {largest:e} m");
    // The last VTU is the run's final state.
    for (p, x) in run.particles.position.iter().enumerate() {
        assert_eq!([x_prev[3 * p], x_prev[3 * p + 1]], *x, "particle {p}");
    }
}
