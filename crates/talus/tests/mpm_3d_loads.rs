//! Surface loads, a uniform initial stress and monitors in 3D MPM scenes
//! (`docs/3d-mpm.md`, 'Scenes'; `docs/scenes.md`, '3D MPM scenes'):
//!
//! - a surface load on an elastic box on a slip floor between slip walls: summing eq. 15
//!   over the grid's nodes, `Σ_i (Bᵀσ)_i = 0` (the shape gradients sum to zero), so the
//!   walls' reactions add up to `−Σ f + Σ m a`: at rest the floor carries the weight plus
//!   the pushed load, `ρ g V + p A`, and the walls of constant z the horizontal traction,
//!   `−t_z A` (`mpm_load_programmes.rs` shows the same in 2D);
//! - a uniform isotropic stress, without gravity, in a box walled on all six faces: in
//!   equilibrium with the walls' normal reactions (`σ·n`), so nothing moves and the stress
//!   stays; the six plain components given land in the Mandel slots
//!   `(xx, yy, zz, √2 yz, √2 xz, √2 xy)` and come back as plain components in the VTU;
//!   the K₀ procedure in 3D, `σ_yy = −ρ g (surface − y)`, `σ_xx = σ_zz = K₀ σ_yy`;
//! - a monitor in a box falling freely under a gravity with three components records the
//!   box's motion, every particle's own: the implicit step `v_{n+1} = v_n + h g`,
//!   `x_{n+1} = x_n + h v_{n+1}` gives `v_n = n h g` and `u_n = n (n + 1) h² g / 2`;
//! - 2D: `traction = [0, −p]` is `pressure = p` to the bit;
//! - bad inputs are refused naming the field, with its line.
use crate::common;
use std::path::{Path, PathBuf};

use common::{array, history_column, history_without_seconds, replaced};
use talus::model::mpm::MpmModel;
use talus::run::mpm::{run_mpm_scene, run_mpm_scene_3d};
use talus::run::RunOptions;
use talus::scene::{MpmScene, MpmScene3, SceneError, SceneFile};

fn out_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("mpm_3d_loads")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn scene3(text: &str) -> MpmScene3 {
    match SceneFile::parse(text, None).unwrap_or_else(|e| panic!("{e}")) {
        SceneFile::Mpm3(s) => s,
        _ => panic!("not read as a 3D MPM scene"),
    }
}

fn run3(text: &str, name: &str, fields: bool) -> PathBuf {
    let out = out_dir(name);
    let options = RunOptions {
        write_fields: fields,
        ..RunOptions::new(&out)
    };
    run_mpm_scene_3d(&scene3(text), &options, None).unwrap_or_else(|e| panic!("{e}"));
    out
}

const RHO: f64 = 1000.0;
const G: f64 = 9.81;
/// The box's side (m): 0.4 × 0.4 × 0.4, dx = 0.1, 2 particles per cell and axis.
const SIDE: f64 = 0.4;

/// An elastic box `[0, 0.4]³` on a slip floor (`floor`) between slip walls on x and on z
/// (`back`, `front`), PIC (`flip_ratio = 0`) and h = 0.1 s, 100 times the elastic wave
/// time across a cell: each implicit step is nearly the static solve. `loads` are added
/// at the end.
fn loaded_box(loads: &str) -> String {
    format!(
        r#"
gravity = [0.0, -{G}, 0.0]

[analysis]
geometry = "3d"

[grid]
origin = [0.0, 0.0, 0.0]
spacing = 0.1
cells = [4, 5, 4]

[[body]]
box = [[0.0, 0.0, 0.0], [{SIDE}, {SIDE}, {SIDE}]]

[material]
model = "elastic"
young_modulus = 1.0e7
poisson_ratio = 0.3
density = {RHO}

[[wall]]
side = "left"
condition = "slip"

[[wall]]
side = "right"
condition = "slip"

[[wall]]
name = "back"
side = "back"
condition = "slip"

[[wall]]
name = "front"
side = "front"
condition = "slip"

[[wall]]
name = "floor"
side = "bottom"
condition = "slip"

[time]
step = 0.1
steps = 8

[mpm]
flip_ratio = 0.0

[output]
vtu_every = 0
plots = false
{loads}"#
    )
}

/// The box's top layer of particles (centres at y = 0.375 m).
const TOP: &str = "region = [[0.0, 0.35, 0.0], [0.4, 0.4, 0.4]]";

#[test]
fn a_surface_load_on_a_box_is_carried_by_the_floor_and_the_z_walls() {
    let (p, tz) = (1.0e4, 2.0e3);
    let loads = format!(
        "\n[[surface_load]]\n{TOP}\npressure = {p:e}\n\n\
         [[surface_load]]\n{TOP}\ntraction = [0.0, 0.0, {tz:e}]\n"
    );
    let text = loaded_box(&loads);
    // The loads on the particles: the 64 of the top layer, each of face (dx/2)².
    let model = MpmModel::from_scene_3d(&scene3(&text)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(model.particles.len(), 512);
    let area = SIDE * SIDE;
    let loaded = model
        .particles
        .external_force
        .iter()
        .filter(|f| f.iter().any(|c| *c != 0.0))
        .count();
    assert_eq!(loaded, 64, "the top layer");
    let total: [f64; 3] =
        std::array::from_fn(|a| model.particles.external_force.iter().map(|f| f[a]).sum());
    let want = [0.0, -p * area, tz * area];
    for a in 0..3 {
        assert!(
            (total[a] - want[a]).abs() <= 1e-12 * p * area,
            "Σ f = {total:?} N, want {want:?}"
        );
    }

    let out = run3(&text, "surface_load", false);
    let weight = RHO * G * SIDE.powi(3);
    let fy = *history_column(&out, "floor_fy").last().unwrap();
    let fz: f64 = ["back_fz", "front_fz"]
        .map(|c| *history_column(&out, c).last().unwrap())
        .iter()
        .sum();
    let floor_fz = *history_column(&out, "floor_fz").last().unwrap();
    let (dy, dz) = (fy - (weight + p * area), fz + tz * area);
    println!(
        "floor_fy = {fy:.10e} N vs ρgV + pA = {:.10e} N (rel. {:.2e}); back_fz + front_fz = \
         {fz:.10e} N vs −t_z A = {:.4e} N (rel. {:.2e}); floor_fz = {floor_fz:.2e} N",
        weight + p * area,
        dy.abs() / (weight + p * area),
        -tz * area,
        dz.abs() / (tz * area)
    );
    // At rest after 8 steps of 100 wave times: the inertia left, Σ m Δv / h, is below
    // history.csv's 11 digits (5e-11 relative; measured 0 and 1.8e-16).
    assert!(dy.abs() <= 1e-10 * (weight + p * area), "floor_fy {fy} N");
    assert!(dz.abs() <= 1e-10 * tz * area, "z walls {fz} N");
    // A slip floor carries no z force.
    assert!(floor_fz.abs() <= 1e-12 * weight, "floor_fz {floor_fz} N");
}

/// 2D: a `traction = [0, −p]` is the `pressure = p` it writes out, to the bit, ramped
/// (the programme's forces) or not (the particles' own), and so is its history.
#[test]
fn a_2d_traction_is_the_pressure_it_writes_out() {
    let column = |load: &str| {
        format!(
            r#"
gravity = [0.0, -9.81]

[grid]
origin = [0.0, 0.0]
spacing = 0.05
cells = [4, 24]

[[body]]
rectangle = [[0.0, 0.0], [0.2, 1.0]]

[material]
young_modulus = 1.0e7
poisson_ratio = 0.3
friction_angle = 30.0
cohesion = 1.0e6
cone_fit = "plane_strain"
density = 2.0e3

[[wall]]
side = "left"
condition = "slip"

[[wall]]
side = "right"
condition = "slip"

[[wall]]
name = "floor"
side = "bottom"
condition = "fixed"

[[surface_load]]
region = [[0.0, 0.98], [0.2, 1.0]]
{load}
ramp = [[0.0, 0.0], [0.1, 1.0]]

[[surface_load]]
region = [[0.0, 0.98], [0.2, 1.0]]
{load}

[time]
step = 0.01
steps = 20

[output]
vtu_every = 0
plots = false
"#
        )
    };
    let runs: Vec<(PathBuf, Vec<[f64; 2]>)> = [
        ("pressure", "pressure = 2.0e4"),
        ("traction", "traction = [0.0, -2.0e4]"),
    ]
    .iter()
    .map(|(name, load)| {
        let scene = MpmScene::parse(&column(load), None).unwrap_or_else(|e| panic!("{e}"));
        let out = out_dir(&format!("2d_{name}"));
        let run = run_mpm_scene(&scene, &RunOptions::new(&out)).unwrap_or_else(|e| panic!("{e}"));
        (out, run.particles.position)
    })
    .collect();
    assert_eq!(runs[0].1, runs[1].1, "particle positions");
    assert_eq!(
        history_without_seconds(&runs[0].0),
        history_without_seconds(&runs[1].0),
        "history.csv but `seconds`"
    );
    let fy = history_column(&runs[0].0, "floor_fy");
    println!("floor_fy at the end {:.6e} N/m", fy.last().unwrap());
    assert!(
        fy.last().unwrap() > &(2.0 * 2.0e4 * 0.2),
        "the loads reached the floor"
    );
}

/// A box filling a 4 × 4 × 4 grid, walled on all six faces.
fn walled_box(stress: &str, model: &str) -> String {
    format!(
        r#"
[analysis]
geometry = "3d"

[grid]
origin = [0.0, 0.0, 0.0]
spacing = 0.1
cells = [4, 4, 4]

[[body]]
box = [[0.0, 0.0, 0.0], [0.4, 0.4, 0.4]]

[material]
{model}
density = 2000.0

[[wall]]
name = "left"
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
condition = "slip"

[[wall]]
side = "top"
condition = "slip"

[initial_stress]
stress = {stress}

[time]
step = 1.0e-3
steps = 10

[output]
vtu_every = 10
plots = false
"#
    )
}

const SAND: &str = "young_modulus = 1.0e7\npoisson_ratio = 0.3\nfriction_angle = 30.0\n\
                    cohesion = 0.0\ncone_fit = \"plane_strain\"";

#[test]
fn a_uniform_isotropic_stress_in_a_walled_box_stays_in_equilibrium() {
    let s0 = -5.0e4;
    let text = walled_box(&format!("[{s0:e}, {s0:e}, {s0:e}, 0.0, 0.0, 0.0]"), SAND);
    let model = MpmModel::from_scene_3d(&scene3(&text)).unwrap_or_else(|e| panic!("{e}"));
    let n = model.particles.len();
    assert_eq!(n, 512);
    assert!(model
        .particles
        .stress
        .iter()
        .all(|s| *s == [s0, s0, s0, 0.0, 0.0, 0.0]));
    let out = out_dir("isotropic");
    let options = RunOptions {
        write_fields: true,
        ..RunOptions::new(&out)
    };
    let run = run_mpm_scene_3d(&scene3(&text), &options, None).unwrap_or_else(|e| panic!("{e}"));
    let p = &run.particles;
    let moved = (0..n)
        .map(|k| {
            (0..3)
                .map(|a| (p.position[k][a] - model.particles.position[k][a]).abs())
                .fold(0.0f64, f64::max)
        })
        .fold(0.0f64, f64::max);
    let speed = p
        .velocity
        .iter()
        .flatten()
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let changed = (p.stress.iter())
        .map(|s| {
            let want = [s0, s0, s0, 0.0, 0.0, 0.0];
            (0..6)
                .map(|c| (s[c] - want[c]).abs())
                .fold(0.0f64, f64::max)
        })
        .fold(0.0f64, f64::max);
    // The walls carry σ·n: |σ| A on each face.
    let fy = *history_column(&out, "floor_fy").last().unwrap();
    let fx = *history_column(&out, "left_fx").last().unwrap();
    let load = -s0 * 0.4 * 0.4;
    println!(
        "after 10 steps: max |Δx| = {moved:.2e} m, max |v| = {speed:.2e} m/s, max |Δσ| = \
         {changed:.2e} Pa of {:.1e}; floor_fy = {fy:.10e} N, left_fx = {fx:.10e} N vs |σ| A = \
         {load:.10e} N (rel. {:.2e}, {:.2e})",
        -s0,
        (fy / load - 1.0).abs(),
        (fx / load - 1.0).abs()
    );
    // Measured: no motion at all (0 m; velocities 6e-16 m/s), stresses to 4e-31 Pa.
    assert!(moved <= 1e-12, "particles moved {moved:.3e} m");
    assert!(changed <= 1e-12 * -s0, "stress changed by {changed:.3e} Pa");
    // history.csv's 11 digits.
    assert!((fy / load - 1.0).abs() <= 1e-10, "floor_fy {fy} N");
    assert!((fx / load - 1.0).abs() <= 1e-10, "left_fx {fx} N");
    // The last VTU holds the stress as given, in plain components.
    let xml = std::fs::read_to_string(out.join("vtu/step_00010.vtu")).unwrap();
    let vtu = array(&xml, "stress");
    assert_eq!(vtu.len(), 6 * n);
    assert!(vtu
        .chunks(6)
        .all(|s| (0..6).all(|c| (s[c] - [s0, s0, s0, 0.0, 0.0, 0.0][c]).abs() <= 1e-12 * -s0)));
}

/// `stress = [sxx, syy, szz, syz, sxz, sxy]` (distinct values, an elastic box: no cone) is
/// the Mandel vector `(sxx, syy, szz, √2 syz, √2 sxz, √2 sxy)` at every particle, and the
/// step-0 VTU writes it back in VTK's order `XX, YY, ZZ, XY, YZ, XZ`.
#[test]
fn the_six_components_land_in_their_mandel_slots() {
    let plain = [-1.0e3, -2.0e3, -3.0e3, 40.0, 50.0, 60.0];
    let elastic = "model = \"elastic\"\nyoung_modulus = 1.0e7\npoisson_ratio = 0.3";
    let stress = format!("{:?}", plain);
    let text = walled_box(&stress, elastic);
    let model = MpmModel::from_scene_3d(&scene3(&text)).unwrap_or_else(|e| panic!("{e}"));
    let r2 = std::f64::consts::SQRT_2;
    let mandel = [
        plain[0],
        plain[1],
        plain[2],
        r2 * plain[3],
        r2 * plain[4],
        r2 * plain[5],
    ];
    assert!(model.particles.stress.iter().all(|s| *s == mandel));
    assert_eq!(
        talus::model::mandel_from_components(plain),
        mandel,
        "one conversion"
    );
    // 2D: `[sxx, syy, sxy, szz]`, xy before zz, into `(xx, yy, zz, √2 xy)`.
    assert_eq!(
        talus::model::mandel_from_components([1.0, 2.0, 3.0, 4.0]),
        [1.0, 2.0, 4.0, r2 * 3.0]
    );
    let out = out_dir("six_components");
    let options = RunOptions {
        write_fields: true,
        ..RunOptions::new(&out)
    };
    let text = replaced(&text, "steps = 10", "steps = 1");
    run_mpm_scene_3d(&scene3(&text), &options, None).unwrap_or_else(|e| panic!("{e}"));
    let xml = std::fs::read_to_string(out.join("vtu/step_00000.vtu")).unwrap();
    let vtu = array(&xml, "stress");
    let [xx, yy, zz, yz, xz, xy] = plain;
    let want = [xx, yy, zz, xy, yz, xz];
    let worst = (vtu.chunks(6))
        .map(|s| {
            (0..6)
                .map(|c| (s[c] - want[c]).abs())
                .fold(0.0f64, f64::max)
        })
        .fold(0.0f64, f64::max);
    println!("step-0 VTU against the plain components: {worst:.2e} Pa");
    assert_eq!(vtu.len(), 6 * 512);
    // √2 · (x / √2) rounds to within an ulp of x.
    assert!(worst <= 1e-12 * 3.0e3, "VTU stress {:?}", &vtu[..6]);
}

/// The K₀ procedure in 3D, y vertical: `σ_yy = −(q + ρ g (surface − y))`,
/// `σ_xx = σ_zz = K₀ σ_yy`, no shear, at every particle.
#[test]
fn the_k0_procedure_runs_in_3d() {
    let (k0, surface, q) = (0.6, 0.4, 1.0e3);
    let text = replaced(
        &walled_box("[0.0]", SAND),
        "stress = [0.0]",
        &format!("k0 = {k0}\nsurface = {surface}\nsurcharge = {q:e}"),
    );
    let text = format!("gravity = [0.0, -{G}, 0.0]\n{text}");
    let model = MpmModel::from_scene_3d(&scene3(&text)).unwrap_or_else(|e| panic!("{e}"));
    let mut worst = 0.0f64;
    for (s, x) in model.particles.stress.iter().zip(&model.particles.position) {
        let syy = -(q + 2000.0 * G * (surface - x[1]));
        let want = [k0 * syy, syy, k0 * syy, 0.0, 0.0, 0.0];
        worst = (0..6).fold(worst, |m, c| m.max((s[c] - want[c]).abs()));
    }
    println!("K₀ stresses against the closed form: {worst:.2e} Pa");
    assert!(worst <= 1e-9, "{worst} Pa");
}

/// A box without walls falling freely under `g = (1, −9.81, 2)` m/s², h = 1 ms, 20 steps,
/// a monitor at a particle's centre: the monitor, the particle's VTU values and the closed
/// form agree.
#[test]
fn a_3d_monitor_follows_a_falling_box() {
    let g = [1.0, -9.81, 2.0];
    let (h, steps) = (1.0e-3, 20);
    let text = format!(
        r#"
gravity = [{:?}, {:?}, {:?}]

[analysis]
geometry = "3d"

[grid]
origin = [0.0, 0.0, 0.0]
spacing = 0.1
cells = [6, 6, 6]

[[body]]
box = [[0.2, 0.2, 0.2], [0.4, 0.4, 0.4]]

[material]
model = "elastic"
young_modulus = 1.0e7
poisson_ratio = 0.3
density = 2000.0

[time]
step = {h:e}
steps = {steps}

[output]
vtu_every = 10
plots = false

[[monitor]]
name = "corner"
point = [0.225, 0.375, 0.325]
"#,
        g[0], g[1], g[2]
    );
    let out = run3(&text, "monitor", true);
    let header = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let header = header.lines().next().unwrap().to_string();
    assert!(
        header.ends_with(",corner_ux,corner_uy,corner_uz,corner_vx,corner_vy,corner_vz"),
        "{header}"
    );
    let model = MpmModel::from_scene_3d(&scene3(&text)).unwrap();
    let at = [0.225, 0.375, 0.325];
    let k = (model.particles.position.iter())
        .position(|x| (0..3).all(|a| (x[a] - at[a]).abs() <= 1e-12))
        .expect("a particle at the monitor");
    let xml = std::fs::read_to_string(out.join(format!("vtu/step_{steps:05}.vtu"))).unwrap();
    let (u, v) = (array(&xml, "displacement"), array(&xml, "velocity"));
    let n = steps as f64;
    let mut worst = [0.0f64; 3];
    for (a, c) in ["x", "y", "z"].iter().enumerate() {
        let mu = *history_column(&out, &format!("corner_u{c}"))
            .last()
            .unwrap();
        let mv = *history_column(&out, &format!("corner_v{c}"))
            .last()
            .unwrap();
        let (pu, pv) = (u[3 * k + a], v[3 * k + a]);
        let (cu, cv) = (n * (n + 1.0) / 2.0 * h * h * g[a], n * h * g[a]);
        println!(
            "{c}: monitor u {mu:.10e} v {mv:.10e}; particle u {pu:.10e} v {pv:.10e}; \
             closed form u {cu:.10e} v {cv:.10e}"
        );
        // history.csv's 11 digits; the particle's and the closed form's to round-off.
        worst[0] = worst[0]
            .max((mu - pu).abs() / cu.abs())
            .max((mv - pv).abs() / cv.abs());
        worst[1] = worst[1]
            .max((pu - cu).abs() / cu.abs())
            .max((pv - cv).abs() / cv.abs());
        worst[2] = worst[2].max((mu - cu).abs() / cu.abs());
    }
    println!(
        "relative: monitor vs particle {:.2e}, particle vs closed form {:.2e}, monitor vs \
         closed form {:.2e}",
        worst[0], worst[1], worst[2]
    );
    // The monitor is read from history.csv's 11 digits (5e-11 relative); the particle's
    // VTU values are the closed form's to round-off (measured 1.0e-13 of each).
    assert!(worst[0] <= 1e-10, "monitor vs particle {:.3e}", worst[0]);
    assert!(
        worst[1] <= 1e-12,
        "particle vs closed form {:.3e}",
        worst[1]
    );
    // Every row: the monitor's uy and vy follow the closed form from step 0.
    let (uy, vy) = (
        history_column(&out, "corner_uy"),
        history_column(&out, "corner_vy"),
    );
    assert_eq!(uy.len(), steps + 1);
    for (s, (u, v)) in uy.iter().zip(&vy).enumerate() {
        let s = s as f64;
        let (cu, cv) = (s * (s + 1.0) / 2.0 * h * h * g[1], s * h * g[1]);
        assert!((u - cu).abs() <= 1e-10 * cu.abs(), "step {s}: uy {u}");
        assert!((v - cv).abs() <= 1e-10 * cv.abs(), "step {s}: vy {v}");
    }
    // summary.json: the monitor with its three components of each.
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let m = &summary["monitors"]["corner"];
    for key in ["ux", "uy", "uz", "vx", "vy", "vz"] {
        assert!(m[key].is_f64(), "summary.json monitors.corner.{key}: {m}");
    }
    let uz = m["uz"].as_f64().unwrap();
    assert!(
        (uz / (n * (n + 1.0) / 2.0 * h * h * g[2]) - 1.0).abs() <= 1e-12,
        "uz {uz}"
    );
}

fn refused(text: &str) -> SceneError {
    match SceneFile::parse(text, None) {
        Err(e) => e,
        Ok(SceneFile::Mpm3(s)) => {
            let model = MpmModel::from_scene_3d(&s).err();
            // A monitor is checked when the run sets up its outputs.
            model.unwrap_or_else(|| {
                let out = out_dir("refused");
                run_mpm_scene_3d(&s, &RunOptions::new(&out), None)
                    .err()
                    .and_then(|e| match e {
                        talus::run::RunError::Scene(e) => Some(e),
                        _ => None,
                    })
                    .expect("refused")
            })
        }
        Ok(SceneFile::Mpm(s)) => MpmModel::from_scene(&s).err().expect("refused"),
        Ok(_) => panic!("not an MPM scene"),
    }
}

#[test]
fn bad_3d_loads_stresses_and_monitors_are_named() {
    let good = loaded_box(&format!("\n[[surface_load]]\n{TOP}\npressure = 1.0e3\n"));
    let cases: Vec<(String, &str, &str)> = vec![
        (
            replaced(&good, "pressure = 1.0e3", "traction = [0.0, -1.0e3]"),
            "surface_load[0].traction",
            "2 components",
        ),
        (
            replaced(&good, TOP, "region = [[0.0, 0.35], [0.4, 0.4]]"),
            "surface_load[0].region",
            "2 components",
        ),
        // a box with zero or negative extent
        (
            replaced(&good, TOP, "region = [[0.0, 0.35, 0.4], [0.4, 0.4, 0.0]]"),
            "surface_load[0].region",
            "max ≥ min",
        ),
        (
            replaced(&good, TOP, "region = [[0.0, 0.3, 0.0], [0.4, 0.3, 0.4]]"),
            "surface_load[0].region",
            "holds no particle centre",
        ),
        // two layers: the load would count twice
        (
            replaced(&good, TOP, "region = [[0.0, 0.3, 0.0], [0.4, 0.4, 0.4]]"),
            "surface_load[0].region",
            "more than one particle at (x, z)",
        ),
        (
            replaced(
                &good,
                "pressure = 1.0e3",
                "pressure = 1.0e3\ntraction = [0.0, -1.0e3, 0.0]",
            ),
            "surface_load[0].traction",
            "not both",
        ),
        (
            replaced(&good, "pressure = 1.0e3", ""),
            "surface_load[0]",
            "traction = [tx, ty, tz]",
        ),
        (
            replaced(&good, "pressure = 1.0e3", "pressure = -1.0e3"),
            "surface_load[0].pressure",
            "≥ 0",
        ),
        (
            replaced(&good, "pressure = 1.0e3", "traction = [0.0, nan, 0.0]"),
            "surface_load[0].traction",
            "finite",
        ),
        // a 2D stress in 3D
        (
            format!("{good}\n[initial_stress]\nstress = [-1.0, -1.0, 0.0, -1.0]\n"),
            "initial_stress.stress",
            "4 components",
        ),
        (
            format!("{good}\n[initial_stress]\nk0 = 0.5\nsurface = 0.2\n"),
            "initial_stress.surface",
            "above the surface",
        ),
        (
            format!("{good}\n[initial_stress]\n"),
            "initial_stress",
            "[sxx, syy, szz, syz, sxz, sxy]",
        ),
        // monitors
        (
            format!("{good}\n[[monitor]]\nname = \"top\"\npoint = [0.2, 0.3]\n"),
            "monitor[0].point",
            "2 components",
        ),
        (
            format!("{good}\n[[monitor]]\nname = \"top\"\npoint = [0.2, 0.3, 0.6]\n"),
            "monitor[0].point",
            "outside the grid",
        ),
        (
            format!(
                "{}\n[[monitor]]\nname = \"top\"\npoint = [0.2, 0.75, 0.2]\n",
                replaced(&good, "cells = [4, 5, 4]", "cells = [4, 8, 4]")
            ),
            "monitor[0].point",
            "no material",
        ),
        (
            format!(
                "{good}\n[[monitor]]\nname = \"top\"\npoint = [0.2, 0.3, 0.2]\n\n\
                 [[monitor]]\nname = \"top\"\npoint = [0.1, 0.3, 0.2]\n"
            ),
            "monitor[1].name",
            "top",
        ),
    ];
    for (text, field, words) in cases {
        let err = refused(&text);
        println!("{err}");
        assert_eq!(err.field, field, "{err}");
        assert!(err.message.contains(words), "{field}: {err}");
        assert!(err.line.is_some(), "{field}: no line: {err}");
    }
}

/// A 2D scene refuses the 3D forms: a traction, a region or a monitor point of three
/// components, a stress of six.
#[test]
fn a_2d_scene_refuses_3d_loads_stresses_and_monitors() {
    let good = "gravity = [0.0, -9.81]
[grid]
origin = [0.0, 0.0]
spacing = 0.1
cells = [4, 5]
[[body]]
rectangle = [[0.0, 0.0], [0.4, 0.4]]
[material]
model = \"elastic\"
young_modulus = 1.0e7
poisson_ratio = 0.3
density = 1000.0
[[wall]]
side = \"bottom\"
condition = \"slip\"
[[surface_load]]
region = [[0.0, 0.35], [0.4, 0.4]]
traction = [0.0, -1.0e3]
[time]
step = 0.1
steps = 1
";
    // The good scene builds.
    MpmModel::from_scene(&MpmScene::parse(good, None).unwrap()).unwrap();
    let cases: Vec<(String, &str, &str)> = vec![
        (
            replaced(
                good,
                "traction = [0.0, -1.0e3]",
                "traction = [0.0, -1.0e3, 0.0]",
            ),
            "surface_load[0].traction",
            "3 components",
        ),
        (
            replaced(
                good,
                "region = [[0.0, 0.35], [0.4, 0.4]]",
                "region = [[0.0, 0.35, 0.0], [0.4, 0.4, 0.4]]",
            ),
            "surface_load[0].region",
            "3 components",
        ),
        (
            format!("{good}[[monitor]]\nname = \"top\"\npoint = [0.2, 0.3, 0.1]\n"),
            "monitor[0].point",
            "3 components",
        ),
        (
            format!("{good}[initial_stress]\nstress = [-1.0, -1.0, -1.0, 0.0, 0.0, 0.0]\n"),
            "initial_stress.stress",
            "6 components",
        ),
    ];
    for (text, field, words) in cases {
        let err = refused(&text);
        println!("{err}");
        assert_eq!(err.field, field, "{err}");
        assert!(err.message.contains(words), "{field}: {err}");
        assert!(err.message.contains("geometry = \"3d\""), "{field}: {err}");
        assert!(err.line.is_some(), "{field}: no line: {err}");
    }
}
