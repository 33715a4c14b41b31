//! The cylindrical cavity expanded by displacement (`scenes/cavity_expansion.toml`,
//! `docs/axisymmetry.md`, 'Cavity expansion'): its collapse pressure against the
//! Mohr-Coulomb thick cylinder's and, for φ = 0, Hill's Tresca cylinder; the reaction of a
//! boundary driven along x is reported along its motion.
use crate::common;
use talus::analysis::verification::{
    cavity_expansion_case, cavity_pressure, CAVITY, CAVITY_EXPANSION,
};
use talus::scene::Scene;

use common::{history_column, replaced, talus_run};

/// The shipped scene's pressure at u(a) = 24 mm within 1e-5 of the collapse pressure
/// (measured 1.1e-6).
#[test]
fn cavity_pressure_reaches_the_mohr_coulomb_thick_cylinder_collapse() {
    for c in cavity_expansion_case() {
        println!(
            "{}: reference {:.6e}, computed {:.6e}, error {:.2e}",
            c.quantity,
            c.reference,
            c.computed,
            c.error()
        );
        assert!(c.passed(), "{}: error {:.3e}", c.quantity, c.error());
    }
}

/// The closed form's Tresca limit: as φ → 0, `p_a = p0 + 2c ln(b/a)` (Hill 1950, The
/// Mathematical Theory of Plasticity, ch. V), and the scene made von Mises (φ = 0,
/// `k_d = √2`, Tresca in plane strain) collapses there too.
#[test]
fn a_frictionless_cavity_collapses_at_hills_pressure() {
    let hill = CAVITY.p0 + 2.0 * CAVITY.cohesion * (CAVITY.b / CAVITY.a).ln();
    // O(φ): 1.8e-7 at φ = 1e-5° (smaller φ meets c cot φ's rounding).
    let limit = CAVITY.collapse_pressure(1e-5);
    assert!((limit / hill - 1.0).abs() < 1e-6, "{limit} against {hill}");
    let text = replaced(
        CAVITY_EXPANSION,
        "friction_angle = 30.0",
        "friction_angle = 0.0",
    );
    let text = replaced(&text, "k_d = 1.224744871391589", "k_d = 1.4142135623730951");
    let scene = Scene::parse(&text, None).unwrap();
    let p = cavity_pressure(&scene).expect("the run finishes");
    println!(
        "Tresca cavity: {p:.6e} Pa against Hill's {hill:.6e}: {:.2e}",
        p / hill - 1.0
    );
    // Measured 8.6e-9.
    assert!((p / hill - 1.0).abs() < 1e-6, "{p} against {hill}");
    // The frictional collapse is another pressure: the check tells them apart.
    let frictional = CAVITY.collapse_pressure(30.0);
    assert!((frictional / hill - 1.0).abs() > 0.1);
}

/// A reported boundary driven along +x is reported along its motion: `reaction_force` is
/// its push along +x (the `cavity_fx` column) and `footing_displacement` the wall's
/// outward displacement, 0.2 mm a step; the plateau is found and summarised.
#[test]
fn a_boundary_driven_along_x_reports_its_reaction_along_its_motion() {
    let text = replaced(CAVITY_EXPANSION, "steps = 120", "steps = 20");
    let text = replaced(&text, "plots = true", "plots = false");
    let (out, stdout, _) = talus_run("cavity_expansion", "direction", &text);
    let reaction = history_column(&out, "reaction_force");
    let fx = history_column(&out, "cavity_fx");
    assert_eq!(reaction, fx);
    // Step 0: p0 on the wall, 2π a H p0.
    let at_rest = CAVITY.wall_push(CAVITY.p0);
    assert!(
        (reaction[0] / at_rest - 1.0).abs() < 1e-9,
        "{}",
        reaction[0]
    );
    let u = history_column(&out, "footing_displacement");
    for (k, u) in u.iter().enumerate() {
        assert!((u - 2e-4 * k as f64).abs() < 1e-15, "step {k}: {u}");
    }
    // The plateau (from the wall's yield, 2.2 mm) is read as the limit load: within 1% of
    // the collapse push 2π a H p_a (56.26 kN) over these 4 mm.
    let limit: f64 = stdout
        .split("limit load ")
        .nth(1)
        .and_then(|t| t.split(' ').next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no limit load in: {stdout}"));
    let collapse = CAVITY.wall_push(CAVITY.collapse_pressure(CAVITY.phi));
    assert!(
        (limit / collapse - 1.0).abs() < 0.01,
        "{limit} against {collapse}"
    );
}
