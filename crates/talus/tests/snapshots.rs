//! Snapshot regression tests (insta, YAML) of small scenes: the history (reaction force,
//! footing displacement, Newton iterations per step) and a few Gauss-point stresses and the
//! largest cumulative plastic strain at the end, all rounded to 6 significant digits, so
//! that an unintended change in the numbers fails. Timings and residuals (round-off below
//! the tolerance) are not snapshotted.
//!
//! Regenerate after an intended change with
//!   INSTA_UPDATE=always cargo test --release -p talus --test suite snapshots::
//! and review the diff of `tests/snapshots/`.
use serde::Serialize;
use talus::model::fem::ReactionForce;
use talus::model::fem::{FromScene, Model};
use talus::run::fem::run_scene;
use talus::run::RunOptions;
use talus::scene::Scene;

use crate::common;
const FOOTING: &str = include_str!("../../../scenes/footing.toml");

/// `text` with each `(from, to)` replaced once; `from` must be present.
fn edited(text: &str, edits: &[(&str, &str)]) -> String {
    let mut text = text.to_string();
    for (from, to) in edits {
        text = common::replaced(&text, from, to);
    }
    text
}

/// `x` rounded to `sig` significant digits (decimal), with −0.0 as 0.
fn round_sig(x: f64, sig: usize) -> f64 {
    assert!(x.is_finite(), "non-finite value {x}");
    assert!(sig >= 1);
    let r: f64 = format!("{:.*e}", sig - 1, x).parse().unwrap();
    if r == 0.0 {
        0.0
    } else {
        r
    }
}

fn r6(x: f64) -> f64 {
    round_sig(x, 6)
}

/// `x` rounded to the decimal place of the `sig`-th significant digit of `scale`, with −0.0
/// as 0: components far below the largest of a tensor (e.g. a shear stress that vanishes by
/// symmetry, up to round-off) snapshot as 0 instead of as round-off digits.
fn round_at_scale(x: f64, scale: f64, sig: usize) -> f64 {
    assert!(
        x.is_finite() && scale.is_finite(),
        "non-finite value {x} / {scale}"
    );
    if scale == 0.0 {
        return round_sig(x, sig);
    }
    let decimals = sig as i32 - 1 - scale.abs().log10().floor() as i32;
    let r = if decimals >= 0 {
        format!("{:.*}", decimals as usize, x).parse().unwrap()
    } else {
        let q = 10f64.powi(-decimals);
        (x / q).round() * q
    };
    if r == 0.0 {
        0.0
    } else {
        r
    }
}

/// Cumulative plastic strains below this are the round-off of an elastic solve (the
/// solver tolerance is 1e-12 relative) and snapshot as 0.
const PLASTIC_STRAIN_FLOOR: f64 = 1e-9;

#[derive(Serialize)]
struct Row {
    step: usize,
    reaction_force: f64,
    footing_displacement: f64,
    newton_iterations: usize,
}

#[derive(Serialize)]
struct PointStress {
    label: &'static str,
    /// Gauss point index.
    point: usize,
    /// Gauss point position (m).
    position: [f64; 2],
    /// Mandel components (σxx, σyy, σzz, √2 σxy), Pa, to 6 significant digits of the
    /// largest.
    sigma: [f64; 4],
}

#[derive(Serialize)]
struct Snapshot {
    gauss_points: usize,
    history: Vec<Row>,
    stresses: Vec<PointStress>,
    max_plastic_strain: f64,
}

/// Runs `text` and collects the snapshot; `probe` is a position whose nearest Gauss point
/// is reported besides the first and last.
fn run_case(name: &str, text: &str, probe: (&'static str, [f64; 2])) -> Snapshot {
    let scene = Scene::parse(text, None).expect("scene parses");
    let model = Model::from_scene(&scene).expect("model builds");
    let positions = &model.assembly.gauss_points;
    let n = positions.len();
    let dist = |p: &[f64; 2]| (p[0] - probe.1[0]).hypot(p[1] - probe.1[1]);
    let near = (0..n)
        .min_by(|&a, &b| dist(&positions[a]).total_cmp(&dist(&positions[b])))
        .unwrap();
    let out = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("snapshots")
        .join(name);
    let summary = run_scene(&scene, &RunOptions::new(out)).expect("every step converges");
    assert_eq!(summary.records.len(), scene.spec.time.steps);
    let history = summary
        .records
        .iter()
        .zip(&summary.displacements)
        .enumerate()
        .map(|(i, (r, d))| Row {
            step: i + 1,
            reaction_force: r6(r.reaction_force()),
            footing_displacement: r6(*d),
            newton_iterations: r.newton_iterations,
        })
        .collect();
    let state = &summary.final_state;
    let stresses = [("first", 0), (probe.0, near), ("last", n - 1)]
        .into_iter()
        .map(|(label, p)| PointStress {
            label,
            point: p,
            position: positions[p].map(r6),
            sigma: {
                let s = &state.sigma[4 * p..4 * p + 4];
                let scale = s.iter().fold(0.0, |m: f64, x| m.max(x.abs()));
                std::array::from_fn(|k| round_at_scale(s[k], scale, 6))
            },
        })
        .collect();
    let max_plastic_strain = state.plastic_strain.iter().copied().fold(0.0, f64::max);
    let max_plastic_strain = if max_plastic_strain < PLASTIC_STRAIN_FLOOR {
        0.0
    } else {
        r6(max_plastic_strain)
    };
    Snapshot {
        gauss_points: n,
        history,
        stresses,
        max_plastic_strain,
    }
}

/// The paper footing (non-associative, gravity, surcharge, K0 initial stress) on a coarse
/// 16×6 P2 mesh, 20 steps of 5e-2 s (1 mm of settlement).
#[test]
fn footing_coarse_p2() {
    let text = edited(
        FOOTING,
        &[
            ("cells = [32, 14]", "cells = [16, 6]"),
            ("step = 1.0e-2", "step = 5.0e-2"),
            ("steps = 300", "steps = 20"),
        ],
    );
    let snap = run_case("footing_coarse_p2", &text, ("under_footing", [0.0, -0.1]));
    insta::assert_yaml_snapshot!("footing_coarse_p2_history", snap);
}

/// Associative (θ = φ) weightless footing, P1, no surcharge and no initial stress.
#[test]
fn footing_associative_weightless_p1() {
    let text = edited(
        FOOTING,
        &[
            ("gravity = [0.0, -9.81]\n", ""),
            ("cells = [32, 14]", "cells = [16, 8]"),
            ("order = \"P2\"", "order = \"P1\""),
            ("dilatancy_angle = 14.2906  # atan(tan 27° / 2)\n", ""),
            ("value = [0.0, -20.0e3]   # Pa", "value = [0.0, 0.0]"),
            ("value = [0.0, -20.0e3]", "value = [0.0, 0.0]"),
            ("[initial_stress]", "[removed_initial_stress]"),
            ("step = 1.0e-2", "step = 5.0e-2"),
            ("steps = 300", "steps = 20"),
        ],
    );
    // Drop the initial stress section (up to the blank line before [time]).
    let start = text.find("[removed_initial_stress]").unwrap();
    let end = text.find("[time]").unwrap();
    let text = format!("{}{}", &text[..start], &text[end..]);
    let snap = run_case(
        "footing_associative_weightless_p1",
        &text,
        ("under_footing", [0.0, -0.1]),
    );
    insta::assert_yaml_snapshot!("footing_associative_weightless_p1_history", snap);
}

/// Von Mises (φ = 0, c = 10 kPa) weightless footing, P2: the Prandtl limit is (2 + π) c b.
#[test]
fn footing_von_mises_p2() {
    let text = r#"title = "von Mises footing"
[mesh.rectangle]
x = [-1.0, 1.0]
y = [-1.0, 0.0]
cells = [16, 8]
order = "P2"

[material]
young_modulus = 1.0e7
poisson_ratio = 0.3
friction_angle = 0.0
cohesion = 1.0e4
cone_fit = "plane_strain"
density = 100.0

[[boundary]]
nodes = "bottom"
fix = "xy"

[[boundary]]
nodes = "left"
fix = "x"

[[boundary]]
nodes = "right"
fix = "x"

[[boundary]]
name = "footing"
nodes = { box = [[-0.25, -1e-9], [0.25, 1e-9]] }
fix = "xy"
velocity = [0.0, -5.0e-3]

[time]
step = 0.1
steps = 20

[output]
reaction = "footing"
"#;
    let snap = run_case("footing_von_mises_p2", text, ("under_footing", [0.0, -0.1]));
    insta::assert_yaml_snapshot!("footing_von_mises_p2_history", snap);
}

/// An elastic soil column (0.2 m × 1 m, P2) under its own weight: the reaction on the
/// fixed base is the weight ρ g V = 3924 N/m once the column has settled.
#[test]
fn gravity_column_elastic() {
    let text = r#"title = "elastic column under gravity"
gravity = [0.0, -9.81]
[mesh.rectangle]
x = [0.0, 0.2]
y = [-1.0, 0.0]
cells = [2, 10]
order = "P2"

[material]
young_modulus = 1.0e7
poisson_ratio = 0.3
friction_angle = 30.0
cohesion = 1.0e6
cone_fit = "plane_strain"
density = 2.0e3

[[boundary]]
name = "base"
nodes = "bottom"
fix = "xy"

[[boundary]]
nodes = "left"
fix = "x"

[[boundary]]
nodes = "right"
fix = "x"

[time]
step = 0.1
steps = 5

[output]
reaction = "base"
"#;
    let snap = run_case("gravity_column_elastic", text, ("mid_depth", [0.1, -0.5]));
    insta::assert_yaml_snapshot!("gravity_column_elastic_history", snap);
}

#[test]
fn round_sig_rounds_and_has_no_negative_zero() {
    assert_eq!(round_sig(123.456789, 6), 123.457);
    assert_eq!(round_sig(-0.000123456789, 6), -0.000123457);
    assert_eq!(round_sig(9.999999e5, 6), 1.0e6);
    assert_eq!(round_sig(-0.0, 6).to_bits(), 0.0f64.to_bits());
    assert_eq!(format!("{}", round_sig(-0.0, 6)), "0");
    assert_eq!(round_at_scale(1.33917e-4, 9155.99, 6), 0.0);
    assert_eq!(
        round_at_scale(-1.3e-4, 9155.99, 6).to_bits(),
        0.0f64.to_bits()
    );
    assert_eq!(round_at_scale(-3924.00049, 9155.99, 6), -3924.0);
    assert_eq!(round_at_scale(-60.18874, 20020.6, 6), -60.2);
    assert_eq!(round_at_scale(-408306.4, 408306.4, 6), -408306.0);
    assert_eq!(round_at_scale(1234567.0, 1234567.0, 6), 1234570.0);
}
