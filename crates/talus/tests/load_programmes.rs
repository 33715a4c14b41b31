//! Load programmes (`ramp = [[t, f], ...]`) and normal pressure in FEM scenes: loads and
//! prescribed velocities are those of the end of each step, scaled by their ramp; the
//! reaction of a column under ramped gravity follows the ramp exactly once inertia is
//! accounted for; bad ramps are refused with the field named.
use talus::model::fem::ReactionForce;
use talus::model::fem::{FromScene, Model, State};
use talus::run::fem::solver_settings;
use talus::scene::Scene;
use talus_engine::{Predictor, StepSettings, Stepper};
use talus_fem::assembly::add_mul;

const MATERIAL: &str = "[material]
young_modulus = 1.0e7
poisson_ratio = 0.3
friction_angle = 30.0
cohesion = 1.0e9
cone_fit = \"plane_strain\"
density = 2.0e3
";

/// An elastic column `[0, W] × [−H, 0]`, P2, fixed base named `base`, rollers on both
/// sides, weight ramped by `gravity_ramp`.
fn column(w: f64, h: f64, ramp: &str, step: f64, steps: usize) -> String {
    format!(
        "gravity = [0.0, -9.81]
gravity_ramp = {ramp}
[mesh.rectangle]
x = [0.0, {w}]
y = [-{h}, 0.0]
cells = [2, 8]
order = \"P2\"
{MATERIAL}
[[boundary]]
name = \"base\"
nodes = \"bottom\"
fix = \"xy\"
[[boundary]]
nodes = \"left\"
fix = \"x\"
[[boundary]]
nodes = \"right\"
fix = \"x\"
[time]
step = {step}
steps = {steps}
[output]
reaction = \"base\"
"
    )
}

fn scene(text: &str) -> Scene {
    Scene::parse(text, None).expect("scene parses")
}

/// The reaction the stepper reports on the base is `Σ f_y(tₙ₊₁) − Σ M (vₙ₊₁ − vₙ)_y / h`:
/// summing eq. 15's free rows `M a + Bᵀσ = f` with the base rows, `Σ_all (Bᵀσ)_y = 0`
/// (a rigid translation has no strain), so the support carries the whole weight at the end
/// of the step less the inertia of the free nodes (the base does not move). With
/// `Σ f_y = −ρ g W H f(tₙ₊₁)` this holds to rounding at every step, whatever the ramp; a
/// force taken at `tₙ` in one place and at `tₙ₊₁` in another, or a base share of the
/// weight left out of the ramp, breaks it at the first step where the ramp moves.
#[test]
fn gravity_ramp_base_reaction_follows_the_ramp() {
    let (w, hgt, rho, g) = (0.2, 1.0, 2.0e3, 9.81);
    let weight = rho * g * w * hgt;
    let ramp = [[0.0, 0.0], [1.0, 1.0], [1.5, 0.4], [2.0, 0.4]];
    let text = column(
        w,
        hgt,
        "[[0.0, 0.0], [1.0, 1.0], [1.5, 0.4], [2.0, 0.4]]",
        0.05,
        60,
    );
    let scene = scene(&text);
    let model = Model::from_scene(&scene).unwrap();
    assert_eq!(model.ramped_forces.len(), 1, "gravity is the ramped load");
    let mut state = model.initial_state(&scene).unwrap();
    let mut stepper = Stepper::new(
        &model,
        StepSettings::with_solver(solver_settings(&scene), 0),
    );
    let dofs = model.assembly.dofs();
    let vertical: Vec<usize> = (0..dofs.n_nodes())
        .filter_map(|n| dofs.free(n, 1))
        .collect();
    let f = |t: f64| {
        let k = ramp.partition_point(|p| p[0] < t).clamp(1, ramp.len() - 1);
        let ([t0, f0], [t1, f1]) = (ramp[k - 1], ramp[k]);
        f0 + (f1 - f0) * ((t - t0) / (t1 - t0)).clamp(0.0, 1.0)
    };
    let h = scene.spec.time.step;
    let mut elastic_starts = Vec::new();
    for step in 1..=scene.spec.time.steps {
        let before = state.velocity_free.clone();
        let record = stepper.advance(&mut state, h).unwrap();
        if record.predictors[0] == Predictor::Elastic {
            elastic_starts.push(step);
        }
        let t = record.time;
        let inertia: f64 = vertical
            .iter()
            .map(|&i| model.assembly.lumped_mass_free[i] * (state.velocity_free[i] - before[i]) / h)
            .sum();
        let want = -weight * f(t) - inertia;
        assert!(
            (record.reaction_force() - want).abs() <= 1e-10 * weight,
            "step {step}, t = {t}: reaction {} vs {want} (f = {})",
            record.reaction_force(),
            f(t)
        );
        // The implicit step damps the column's first mode (ω ≈ 129 rad/s, ω h ≈ 6.5) by
        // 1/(1 + ω²h²) ≈ 1/43 per step, and a piecewise-linear ramp needs no acceleration
        // between its kinks: two steps after a kink the reaction is quasi-static.
        let since_kink = ramp
            .iter()
            .map(|p| t - p[0])
            .filter(|d| *d >= -1e-12)
            .fold(f64::INFINITY, f64::min);
        if since_kink > 2.0 * h - 1e-12 {
            assert!(
                (record.reaction_force() + weight * f(t)).abs() <= 1e-3 * weight,
                "step {step}, t = {t}: reaction {} vs −ρgWH f = {}",
                record.reaction_force(),
                -weight * f(t)
            );
        }
    }
    // The force rate changes at t = 0, 1 and 1.5 (not at 2: 0.4 is held on both sides):
    // the steps starting there cannot extrapolate the last rate; all others do.
    assert_eq!(elastic_starts, vec![1, 21, 31]);
    // held at the last value
    assert!((state.time - 3.0).abs() < 1e-9);
    assert!((model.reaction(&state) + 0.4 * weight).abs() <= 1e-6 * weight);
}

/// `q` of eq. 16 depends on a ramped traction through `−h² B M⁻¹ f(tₙ₊₁)` only: between two
/// times, for the same state, it changes by `−h² B M⁻¹ f₁ (r(t_b) − r(t_a))` with `f₁` the
/// traction's nodal forces at multiplier 1 (assembled here straight from `talus-fem`).
#[test]
fn ramped_traction_changes_q_by_the_ramp_increment() {
    let text = format!(
        "[mesh.rectangle]
x = [0.0, 2.0]
y = [0.0, 1.0]
cells = [4, 2]
order = \"P2\"
{MATERIAL}
[[boundary]]
nodes = \"bottom\"
fix = \"xy\"
[[traction]]
edges = \"top\"
value = [3.0e3, -2.0e4]
ramp = [[0.0, 0.0], [1.0, 2.0], [3.0, -1.0]]
[time]
step = 0.1
steps = 1
"
    );
    let scene = scene(&text);
    let model = Model::from_scene(&scene).unwrap();
    let asm = &model.assembly;
    assert!(model.force_free.iter().all(|f| *f == 0.0));
    let (unit, _) = asm
        .traction(&model.mesh, &model.mesh.edge_sets["top"], [3.0e3, -2.0e4])
        .unwrap();
    let mut state = State::at_rest(
        asm.n_points(),
        asm.dofs().n_free(),
        asm.dofs().n_prescribed(),
        model.mesh.nodes.len(),
    );
    for (k, s) in state.sigma.iter_mut().enumerate() {
        *s = -1.0e3 * (1 + k % 5) as f64;
    }
    for (k, v) in state.velocity_free.iter_mut().enumerate() {
        *v = 1.0e-4 * ((k % 3) as f64 - 1.0);
    }
    let h = 0.1;
    // (t_a, t_b) = end-of-step times, the ramp there, in the first and second segment
    for (ta, tb, ra, rb) in [
        (0.25, 0.75, 0.5, 1.5),
        (0.5, 2.0, 1.0, 0.5),
        (3.0, 5.0, -1.0, -1.0),
    ] {
        state.time = ta - h;
        let qa = model.reduced_rhs(&state, h);
        state.time = tb - h;
        let qb = model.reduced_rhs(&state, h);
        let drive: Vec<f64> = unit
            .iter()
            .zip(&asm.lumped_mass_free)
            .map(|(f, m)| -h * h * f * (rb - ra) / m)
            .collect();
        let mut want = vec![0.0; qa.len()];
        add_mul(&asm.b_free, &drive, &mut want);
        let scale = qa.iter().fold(0.0f64, |m, q| m.max(q.abs()));
        for (k, w) in want.iter().enumerate() {
            assert!(
                (qb[k] - qa[k] - w).abs() <= 1e-12 * scale,
                "t = {ta} → {tb}: q[{k}] changed by {}, want {w}",
                qb[k] - qa[k]
            );
        }
    }
}

/// `[[pressure]]` on straight edges is the traction `−p n`: on the top of a block, the same
/// nodal forces as `[[traction]] value = [0, −p]` (two assemblies, one through the normal
/// of each edge's triangle, one through a fixed vector).
#[test]
fn pressure_on_a_straight_top_equals_the_downward_traction() {
    let block = |load: &str| {
        format!(
            "[mesh.rectangle]
x = [0.0, 2.0]
y = [0.0, 1.0]
cells = [3, 2]
order = \"P2\"
ratio = [1.3, 1.0]
{MATERIAL}
[[boundary]]
nodes = \"bottom\"
fix = \"xy\"
{load}
[time]
step = 0.1
steps = 1
"
        )
    };
    let p = 5.0e4;
    let by_pressure = Model::from_scene(&scene(&block(&format!(
        "[[pressure]]\nedges = {{ box = [[0.0, 1.0], [2.0, 1.0]] }}\nvalue = {p}"
    ))))
    .unwrap();
    let by_traction = Model::from_scene(&scene(&block(&format!(
        "[[traction]]\nedges = \"top\"\nvalue = [0.0, {}]",
        -p
    ))))
    .unwrap();
    let total: f64 = by_pressure.force_free.iter().map(|f| f.abs()).sum();
    assert!(total > p, "the pressure loads the block");
    for (a, b) in by_pressure.force_free.iter().zip(&by_traction.force_free) {
        assert!((a - b).abs() <= 1e-12 * p, "{a} vs {b}");
    }
}

/// A ramped prescribed velocity moves its nodes by `Σ h v f(tₖ)` (the velocity of the end
/// of each step); following a ramp is smooth loading (the stress rate is extrapolated,
/// across the kink at t = 0.1 too), but a segment shorter than the step is a jump (elastic
/// predictor).
#[test]
fn ramped_velocity_is_taken_at_the_end_of_each_step() {
    let v = -1.0e-3;
    let text = format!(
        "[mesh.rectangle]
x = [0.0, 1.0]
y = [0.0, 0.5]
cells = [4, 2]
order = \"P1\"
{MATERIAL}
[[boundary]]
nodes = \"bottom\"
fix = \"xy\"
[[boundary]]
name = \"plate\"
nodes = \"top\"
fix = \"y\"
velocity = [0.0, {v}]
ramp = [[0.0, 0.0], [0.1, 1.0], [0.21, 1.0], [0.2101, -1.0]]
[time]
step = 0.02
steps = 16
"
    );
    let scene = scene(&text);
    let model = Model::from_scene(&scene).unwrap();
    let mut state = model.initial_state(&scene).unwrap();
    let mut stepper = Stepper::new(
        &model,
        StepSettings::with_solver(solver_settings(&scene), 0),
    );
    let top = model.mesh.node_sets["top"][1];
    let f = |t: f64| {
        if t <= 0.1 {
            t / 0.1
        } else if t <= 0.21 {
            1.0
        } else if t < 0.2101 {
            1.0 - 2.0 * (t - 0.21) / 1e-4
        } else {
            -1.0
        }
    };
    let mut moved = 0.0;
    let mut predictors = Vec::new();
    for step in 1..=16 {
        let record = stepper.advance(&mut state, 0.02).unwrap();
        moved += 0.02 * v * f(record.time);
        let u = state.displacement[top][1];
        assert!(
            (u - moved).abs() <= 1e-12 * v.abs(),
            "step {step}: u = {u}, want {moved}"
        );
        predictors.push(record.predictors[0]);
    }
    use Predictor::{Elastic, Extrapolated};
    // step 1 from rest; 11 holds the fast reversal (0.2, 0.22]; 12 has no rate after it
    let want: Vec<Predictor> = (1..=16)
        .map(|s| {
            if [1, 11, 12].contains(&s) {
                Elastic
            } else {
                Extrapolated
            }
        })
        .collect();
    assert_eq!(predictors, want);
}

/// A scene without ramps keeps its loads in the constant vectors (the path of every scene
/// before load programmes), and `loads_at` returns them unchanged at any time.
#[test]
fn scenes_without_ramps_have_constant_loads() {
    let scene = talus::scene::builtin_footing();
    let model = Model::from_scene(&scene).unwrap();
    assert!(model.ramped_forces.is_empty() && model.velocity_ramps.is_empty());
    for t in [0.0, 0.37, 1.0e3] {
        let loads = model.loads_at(t);
        assert_eq!(loads.force_free, model.force_free);
        assert_eq!(loads.force_prescribed, model.force_prescribed);
        assert_eq!(loads.prescribed_velocity, model.prescribed_velocity);
    }
}

fn line_of(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.contains(needle))
        .expect("needle in text")
        + 1
}

/// Bad ramps are refused, naming the field, the line and the offending value.
#[test]
fn bad_ramps_name_the_field() {
    let good = column(0.2, 1.0, "[[0.0, 0.0], [1.0, 1.0]]", 0.1, 1);
    for (ramp, message) in [
        ("[]", "is empty"),
        (
            "[[0.0, 0.0], [1.0, nan]]",
            "point 1 = [1, NaN] must be finite",
        ),
        ("[[0.0, 0.0], [inf, 1.0]]", "must be finite"),
        (
            "[[0.0, 0.0], [2.0, 1.0], [1.5, 1.0]]",
            "point 2 has t = 1.5 s after t = 2 s",
        ),
        (
            "[[0.0, 0.0], [1.0, 1.0], [1.0, 2.0]]",
            "t = 1 s after t = 1 s",
        ),
    ] {
        let text = good.replace(
            "gravity_ramp = [[0.0, 0.0], [1.0, 1.0]]",
            &format!("gravity_ramp = {ramp}"),
        );
        let err = Model::from_scene(&scene(&text)).err().expect("refused");
        assert_eq!(err.field, "gravity_ramp", "{err}");
        assert_eq!(err.line, Some(line_of(&text, "gravity_ramp")), "{err}");
        assert!(err.to_string().contains(message), "{err}");
    }
    // on a boundary, a traction and a pressure
    let with_base_ramp = good.replace(
        "fix = \"xy\"",
        "fix = \"xy\"\nvelocity = [0.0, 1.0]\nramp = [[1.0, 0.0], [0.5, 1.0]]",
    );
    let err = Model::from_scene(&scene(&with_base_ramp)).err().unwrap();
    assert_eq!(err.field, "boundary[0].ramp", "{err}");
    assert!(err.to_string().contains("t = 0.5 s after t = 1 s"), "{err}");
    for (table, value) in [("traction", "[0.0, -1.0]"), ("pressure", "1.0")] {
        let text = format!(
            "{good}[[{table}]]\nedges = \"top\"\nvalue = {value}\n[[{table}]]\nedges = \"top\"\nvalue = {value}\nramp = []\n"
        );
        let err = Model::from_scene(&scene(&text)).err().unwrap();
        assert_eq!(err.field, format!("{table}[1].ramp"), "{err}");
    }
    // gravity_ramp without gravity
    let text = good.replace("gravity = [0.0, -9.81]\n", "");
    let err = Model::from_scene(&scene(&text)).err().unwrap();
    assert_eq!(err.field, "gravity_ramp", "{err}");
    assert!(err.to_string().contains("not given"), "{err}");
    // a pressure that is not a number
    let text = format!("{good}[[pressure]]\nedges = \"top\"\nvalue = nan\n");
    let err = Model::from_scene(&scene(&text)).err().unwrap();
    assert_eq!(err.field, "pressure[0].value", "{err}");
}

/// The shipped cavity (`scenes/cavity_pressure.toml`, Gmsh P2, one `[[pressure]]` table on
/// the curved wall): at multiplier 1 the pressure pushes the quarter wall of radius a = 1 m
/// out with `p a` in x and in y, and the rising pressure runs to the end (the step where
/// it stops rising starts from the elastic predictor).
#[test]
fn shipped_cavity_scene_loads_its_wall_and_runs() {
    use talus::run::fem::run_scene;
    use talus::run::RunOptions;
    use talus_fem::Dof;
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cavity_pressure.toml");
    let scene = Scene::from_path(&path).unwrap_or_else(|e| panic!("{e}"));
    let model = Model::from_scene(&scene).unwrap_or_else(|e| panic!("{e}"));
    assert!(model.force_free.iter().all(|f| *f == 0.0));
    let [pressure] = &model.ramped_forces[..] else {
        panic!("one ramped load, the pressure");
    };
    let dofs = model.assembly.dofs();
    let mut resultant = [0.0; 2];
    for n in 0..dofs.n_nodes() {
        for (c, r) in resultant.iter_mut().enumerate() {
            *r += match dofs.dof(n, c).unwrap() {
                Dof::Free(i) => pressure.free[i],
                Dof::Prescribed(j) => pressure.prescribed[j],
            };
        }
    }
    let (p, a) = (1.0e5, 1.0);
    for r in resultant {
        assert!((r - p * a).abs() <= 1e-12 * p * a, "{resultant:?}");
    }
    let out = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("cavity_pressure");
    let summary = run_scene(&scene, &RunOptions::new(out)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(summary.records.len(), scene.spec.time.steps);
    // step 26 is the first after t = 1 s, where the pressure is held
    assert_eq!(summary.records[25].predictors[0], Predictor::Elastic);
    assert!(summary.final_state.plastic_strain.iter().any(|e| *e > 0.0));
}
