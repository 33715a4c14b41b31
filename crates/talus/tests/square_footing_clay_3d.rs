//! A rigid rough square footing on undrained clay (φ = 0) in 3D
//! (`scenes/square_footing_clay_3d.toml`), bracketing Tresca's bearing capacity factor.
//!
//! Tresca's `N_c` for a rough square footing is 5.78 (Salgado, Lyamin, Sloan & Yu 2004,
//! Géotechnique 54(5), their bounds' mean) to 5.90 (Gourvenec, Randolph & Kingsnorth
//! 2006). Drucker-Prager at φ = 0 is a von Mises cylinder `‖dev σ‖ ≤ k_d c`: with
//! `k_d = √2` (`cone_fit = "plane_strain"`) it is inscribed in Tresca's hexagon, with
//! `k_d = 2√6/3` (`"outer_cone"`) circumscribed about it, so by the limit theorems their
//! limit loads bound Tresca's from below and above. Displacement elements overestimate
//! a limit load, by the mesh's error: the test runs two meshes, extrapolates
//! `N(h) = N₀ + C h^p` to h → 0 with p = 1 and with the p = 1.14 of a three-mesh fit
//! (6×5×6, 9×7×9, 12×10×12 cells: 6.721, 6.224, 5.987; `docs/3d.md`), and requires
//! the inscribed `N₀ ≤ 5.78`, the circumscribed `N₀ ≥ 5.90`. A weightless φ = 0 body's
//! limit load is proportional to the cylinder's radius, so the circumscribed load is the
//! inscribed one times `(2√6/3)/√2 = 2/√3`, which the coarse mesh checks to 1e-3 (the
//! elastic part does not scale; the plateau does).
use talus::analysis::verification::{extrapolated, square_footing_nc, TRESCA_SQUARE_NC};

/// `N_c` and the last step's rise of the quarter footing on `cells` with `fit`.
fn bearing_factor(cells: [usize; 3], fit: &str) -> (f64, f64) {
    square_footing_nc(cells, fit).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn von_mises_cylinders_inscribed_and_circumscribed_bracket_tresca_n_c() {
    let (coarse, rise_c) = bearing_factor([6, 5, 6], "plane_strain");
    let (fine, rise_f) = bearing_factor([9, 7, 9], "plane_strain");
    let (outer, _) = bearing_factor([6, 5, 6], "outer_cone");
    println!("N_c inscribed: 6x5x6 {coarse:.4}, 9x7x9 {fine:.4}; circumscribed 6x5x6 {outer:.4}");
    // On the plateau: the last step adds less than 0.1 %.
    assert!(
        rise_c.abs() < 1e-3 && rise_f.abs() < 1e-3,
        "{rise_c} {rise_f}"
    );
    // The circumscribed cylinder's load is the inscribed one's times 2/√3.
    let ratio = outer / coarse;
    assert!((ratio / (2.0 / 3f64.sqrt()) - 1.0).abs() < 1e-3, "{ratio}");
    // Displacement elements converge from above.
    assert!(fine < coarse, "{fine} !< {coarse}");
    let (h_c, h_f): (f64, f64) = (1.0 / 6.0, 1.0 / 9.0);
    let [lower, upper] = TRESCA_SQUARE_NC;
    for p in [1.0f64, 1.14] {
        let inscribed = extrapolated(p, (h_c, coarse), (h_f, fine));
        let circumscribed = inscribed * 2.0 / 3f64.sqrt();
        println!("p = {p}: N0 inscribed {inscribed:.3}, circumscribed {circumscribed:.3}");
        assert!(
            inscribed <= lower,
            "p = {p}: inscribed {inscribed} > {lower}"
        );
        assert!(
            circumscribed >= upper,
            "p = {p}: circumscribed {circumscribed} < {upper}"
        );
        // And the bracket is not vacuous: within 15 % of the range it brackets.
        assert!(inscribed > lower / 1.15 && circumscribed < upper * 1.15);
    }
}
