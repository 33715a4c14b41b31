//! Load programmes in MPM scenes (`gravity_ramp`, `ramp` on `[[prescribed]]` and
//! `[[surface_load]]`): each sub-step takes the loads and velocities of its end time
//! `tₙ₊₁`, scaled by their ramps there; bad ramps are refused with the field named.
use talus::model::mpm::MpmModel;
use talus::scene::MpmScene;
use talus_engine::Stepper;
use talus_mpm::GroupForces;
use talus_mpm::MpmState;

const MATERIAL: &str = "[material]
young_modulus = 1.0e7
poisson_ratio = 0.3
friction_angle = 30.0
cohesion = 1.0e9
cone_fit = \"plane_strain\"
density = 2.0e3
";

const RAMP: [[f64; 2]; 4] = [[0.0, 0.0], [1.0, 1.0], [1.5, 0.4], [2.0, 0.4]];
const RAMP_TOML: &str = "[[0.0, 0.0], [1.0, 1.0], [1.5, 0.4], [2.0, 0.4]]";

/// The ramp written out independently of `talus::scene::Ramp`.
fn f(t: f64) -> f64 {
    let k = RAMP.partition_point(|p| p[0] < t).clamp(1, RAMP.len() - 1);
    let ([t0, f0], [t1, f1]) = (RAMP[k - 1], RAMP[k]);
    f0 + (f1 - f0) * ((t - t0) / (t1 - t0)).clamp(0.0, 1.0)
}

/// An elastic column `[0, W] × [0, H]` (W = 0.2 m, H = 1 m, dx = 0.05 m, 2 × 2 particles per
/// cell) between slip walls on a fixed floor (listed last: it owns the corner nodes), with
/// `loads` added at the top level and `tables` at the end.
fn column(loads: &str, tables: &str) -> String {
    format!(
        "{loads}
[grid]
origin = [0.0, 0.0]
spacing = 0.05
cells = [4, 24]
[[body]]
rectangle = [[0.0, 0.0], [0.2, 1.0]]
{MATERIAL}
[[wall]]
side = \"left\"
condition = \"slip\"
[[wall]]
side = \"right\"
condition = \"slip\"
[[wall]]
side = \"bottom\"
condition = \"fixed\"
[time]
step = 0.05
steps = 60
{tables}"
    )
}

fn scene(text: &str) -> MpmScene {
    MpmScene::parse(text, None).unwrap_or_else(|e| panic!("{e}"))
}

fn momentum_y(state: &MpmState) -> f64 {
    let p = &state.particles;
    (0..p.len()).map(|k| p.mass[k] * p.velocity[k][1]).sum()
}

/// Steps `text` (the column) and checks the floor's vertical force against `load · f(tₙ₊₁)`
/// (N/m, the total downward load at multiplier 1): exactly once inertia is accounted for,
/// and to 1e-3 of the load away from the ramp's kinks.
///
/// Exact: summing eq. 15 over every active node, `Σ_i (Bᵀσ)_i = 0` (the shape gradients
/// sum to zero: a translation strains nothing), and on the slip walls the vertical
/// components are free (no force), so the floor's force is `Σ f_y(tₙ₊₁) + Σ_i m_i Δv_i/h`.
/// P2G conserves momentum and so does G2P for any FLIP blend (`Σ_p m_p N_i = m_i`), so the
/// grid's momentum change is the particles', `(Pₙ₊₁ − Pₙ)/h`. A load taken at `tₙ` misses
/// by `load · (f(tₙ₊₁) − f(tₙ))`, 5% of it on the rising segment.
///
/// Quasi-static: a linear segment needs no acceleration, so the inertia is the response to
/// the kinks. At a kink the column's mean velocity changes by `ū Δṙ`, with `ū = ρ g H²/(3
/// E_oed)` = 0.49 mm the mass-averaged static settlement (`E_oed = E(1 − ν)/((1 + ν)(1 −
/// 2ν))` = 13.5 MPa) and `Δṙ ≤ 1.2 /s`: an inertia of `ū Δṙ/(g h)` ≈ 1.2e-3 of the weight
/// at most (3.6e-3 of the load for the top load, `ū = p H/E_oed`), which the implicit step
/// damps by `1/√(1 + ω²h²)` ≈ 1/6.6 per step (first mode `ω = π c/(2H)` ≈ 129 rad/s,
/// `c = √(E_oed/ρ)`): two steps after a kink, ~1e-4 at most, against 5e-2 for loads of `tₙ`
/// (measured: 1.0e-4 under gravity, 1.5e-4 under the top load).
fn floor_force_follows_the_ramp(text: &str, load: f64) {
    let scene = scene(text);
    let model = MpmModel::from_scene(&scene).unwrap_or_else(|e| panic!("{e}"));
    let mut stepper = Stepper::new(&model.mpm, model.step_settings);
    let mut state = MpmState {
        time: 0.0,
        particles: model.particles.clone(),
    };
    let h = scene.spec.time.step;
    let floor = 2; // walls in the order of the scene
    let mut worst_exact: f64 = 0.0;
    let mut worst_quasi_static: f64 = 0.0;
    for step in 1..=scene.spec.time.steps {
        let before = momentum_y(&state);
        let report = stepper
            .advance(&mut state, h)
            .unwrap_or_else(|e| panic!("step {step}: {e}"));
        assert_eq!(report.substeps, 1, "step {step} was not halved");
        let t = report.time;
        let force = report.group_forces()[floor][1];
        let inertia = (momentum_y(&state) - before) / h;
        let exact = (force - load * f(t) - inertia).abs() / load;
        assert!(
            exact <= 1e-10,
            "step {step}, t = {t}: floor force {force} vs {} + inertia {inertia} (f = {})",
            load * f(t),
            f(t)
        );
        worst_exact = worst_exact.max(exact);
        let since_kink = RAMP
            .iter()
            .map(|p| t - p[0])
            .filter(|d| *d >= -1e-12)
            .fold(f64::INFINITY, f64::min);
        if since_kink > 2.0 * h - 1e-12 {
            let quasi_static = (force - load * f(t)).abs() / load;
            assert!(
                quasi_static <= 1e-3,
                "step {step}, t = {t}: floor force {force} vs load · f(tₙ₊₁) = {}",
                load * f(t)
            );
            worst_quasi_static = worst_quasi_static.max(quasi_static);
        }
    }
    println!("worst exact {worst_exact:.2e}, worst quasi-static {worst_quasi_static:.2e}");
    // held at the last value
    assert!((state.time - 3.0).abs() < 1e-9);
}

#[test]
fn gravity_ramp_floor_force_follows_the_ramp() {
    let (rho, g, w, hgt) = (2.0e3, 9.81, 0.2, 1.0);
    let text = column(
        &format!("gravity = [0.0, -9.81]\ngravity_ramp = {RAMP_TOML}"),
        "",
    );
    floor_force_follows_the_ramp(&text, rho * g * w * hgt);
}

/// The same identity for a surface load `p` on the top row: `p · W` (N/m) in total.
/// The base force at multiplier 1 is kept apart from the particles' constant force, so each
/// sub-step's force is `f(tₙ₊₁) · p √V_p`, not a product of earlier scalings.
#[test]
fn ramped_surface_load_floor_force_follows_the_ramp() {
    let p = 2.0e4;
    let text = column(
        "",
        &format!(
            "[[surface_load]]\nregion = [[0.0, 0.98], [0.2, 1.0]]\npressure = {p}\nramp = {RAMP_TOML}\n"
        ),
    );
    let model = MpmModel::from_scene(&scene(&text)).unwrap();
    assert!(
        model
            .particles
            .external_force
            .iter()
            .all(|f| *f == [0.0; 2]),
        "the ramped load is not a constant particle force"
    );
    assert_eq!(model.mpm.programme().surface_loads.len(), 1);
    floor_force_follows_the_ramp(&text, p * 0.2);
}

/// A box prescribing `v` with a ramp, inside a weightless elastic block, stepped by PIC
/// (`flip_ratio = 0`): a particle whose quadratic B-spline stencil (±1.5 dx) stays inside
/// the box takes `Σ_i N_i v f(tₙ₊₁) = v f(tₙ₊₁)` (partition of unity) and moves by
/// `h v f(tₙ₊₁)` per step. Ignoring the ramp moves it by `h v` per step; taking `f(tₙ)`
/// leaves it `h v` behind (1e-3 m) once the ramp has risen.
#[test]
fn ramped_prescribed_box_moves_its_particles_with_the_ramp() {
    let (v, h) = ([0.02, -0.01], 0.05);
    let ramp = [[0.0, 0.0], [0.4, 1.0], [0.8, 0.25]];
    let text = format!(
        "[grid]
origin = [0.0, 0.0]
spacing = 0.1
cells = [20, 12]
[[body]]
rectangle = [[0.3, 0.2], [1.7, 1.0]]
{MATERIAL}
[[prescribed]]
name = \"plate\"
region = [[0.6, 0.4], [1.4, 0.8]]
velocity = [{}, {}]
ramp = [[0.0, 0.0], [0.4, 1.0], [0.8, 0.25]]
[time]
step = {h}
steps = 20
[mpm]
flip_ratio = 0.0
",
        v[0], v[1]
    );
    let f = |t: f64| {
        let k = ramp.partition_point(|p| p[0] < t).clamp(1, ramp.len() - 1);
        let ([t0, f0], [t1, f1]) = (ramp[k - 1], ramp[k]);
        f0 + (f1 - f0) * ((t - t0) / (t1 - t0)).clamp(0.0, 1.0)
    };
    let scene = scene(&text);
    let model = MpmModel::from_scene(&scene).unwrap_or_else(|e| panic!("{e}"));
    let mut stepper = Stepper::new(&model.mpm, model.step_settings);
    let mut state = MpmState {
        time: 0.0,
        particles: model.particles.clone(),
    };
    let x0 = model.particles.position.clone();
    // Stencils inside the box with room for the largest displacement (≤ 0.02 · 0.6 m).
    let margin = 1.5 * 0.1 + 0.02;
    let inner: Vec<usize> = (0..x0.len())
        .filter(|&p| {
            let [x, y] = x0[p];
            x >= 0.6 + margin && x <= 1.4 - margin && y >= 0.4 + margin && y <= 0.8 - margin
        })
        .collect();
    assert!(inner.len() >= 20, "{} particles inside", inner.len());
    let mut moved = 0.0;
    for step in 1..=scene.spec.time.steps {
        let report = stepper
            .advance(&mut state, h)
            .unwrap_or_else(|e| panic!("step {step}: {e}"));
        assert_eq!(report.substeps, 1);
        moved += h * f(report.time);
        for &p in &inner {
            for a in 0..2 {
                let u = state.particles.position[p][a] - x0[p][a];
                assert!(
                    (u - v[a] * moved).abs() <= 1e-13,
                    "step {step}, particle {p}: u_{a} = {u} vs v f summed = {}",
                    v[a] * moved
                );
                assert!(
                    (state.particles.velocity[p][a] - v[a] * f(report.time)).abs() <= 1e-14,
                    "step {step}, particle {p}: v_{a}"
                );
            }
        }
    }
    // 0.05 · (0.125 + … ) summed: the ramp's integral on the steps' end times.
    assert!(moved > 0.4 && moved < 0.6, "{moved}");
}

fn line_of(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.contains(needle))
        .expect("needle in text")
        + 1
}

/// Bad ramps are refused with the field, its line and the offending point, by the same
/// check as FEM scenes.
#[test]
fn bad_mpm_ramps_name_the_field_and_line() {
    let tables = "[[prescribed]]
region = [[0.0, 0.9], [0.2, 1.2]]
velocity_y = -0.01
ramp = PRESCRIBED
[[surface_load]]
region = [[0.0, 0.98], [0.2, 1.0]]
pressure = 1.0e3
ramp = SURFACE
";
    let good = "[[0.0, 0.0], [1.0, 1.0]]";
    let text = |gravity: &str, prescribed: &str, surface: &str| {
        column(
            &format!("gravity = [0.0, -9.81]\ngravity_ramp = {gravity}"),
            &tables
                .replace("PRESCRIBED", prescribed)
                .replace("SURFACE", surface),
        )
    };
    MpmModel::from_scene(&scene(&text(good, good, good)))
        .unwrap_or_else(|e| panic!("good ramps accepted: {e}"));
    for (bad, message) in [
        ("[]", "is empty"),
        (
            "[[0.0, 0.0], [1.0, nan]]",
            "point 1 = [1, NaN] must be finite",
        ),
        (
            "[[0.0, 0.0], [2.0, 1.0], [1.5, 1.0]]",
            "point 2 has t = 1.5 s after t = 2 s",
        ),
    ] {
        for (field, text, needle) in [
            ("gravity_ramp", text(bad, good, good), "gravity_ramp"),
            (
                "prescribed[0].ramp",
                text(good, bad, good),
                &format!("ramp = {bad}"),
            ),
            (
                "surface_load[0].ramp",
                text(good, good, bad),
                &format!("ramp = {bad}"),
            ),
        ] {
            let err = MpmModel::from_scene(&scene(&text))
                .err()
                .unwrap_or_else(|| panic!("{field} = {bad} accepted"));
            assert_eq!(err.field, field, "{err}");
            assert_eq!(err.line, Some(line_of(&text, needle)), "{err}");
            assert!(err.to_string().contains(message), "{err}");
        }
    }
    // gravity_ramp without gravity
    let text = column(&format!("gravity_ramp = {good}"), "");
    let err = MpmModel::from_scene(&scene(&text)).err().unwrap();
    assert_eq!(err.field, "gravity_ramp", "{err}");
    assert!(err.to_string().contains("not given"), "{err}");
}

/// The K₀ initial stress balances the gravity of `t = 0`, `f(0) g`: a ramp starting at 1/2
/// halves it (exactly: a power of two), as in FEM scenes.
#[test]
fn k0_stress_balances_the_gravity_of_the_start() {
    let k0 = "[initial_stress]\nk0 = 0.5\nsurface = 1.0\n";
    let stress = |ramp: &str| {
        let text = column(&format!("gravity = [0.0, -9.81]\n{ramp}"), k0);
        MpmModel::from_scene(&scene(&text))
            .unwrap_or_else(|e| panic!("{e}"))
            .particles
            .stress
    };
    let full = stress("");
    let half = stress("gravity_ramp = [[0.0, 0.5], [1.0, 1.0]]");
    assert!(full.iter().all(|s| s[1] < 0.0));
    for (a, b) in full.iter().zip(&half) {
        assert_eq!(a.map(|v| 0.5 * v), *b);
    }
}
