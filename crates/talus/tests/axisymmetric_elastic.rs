//! Elastic axisymmetric checks (`docs/axisymmetry.md`, 'Verification'): Lamé's thick
//! cylinder and Sneddon's rigid circular punch.
use talus::analysis::verification::{
    circular_punch, lame_axisymmetric, lame_errors, punch_stiffness, sneddon_stiffness,
};

fn report(cases: &[talus::analysis::verification::CaseResult]) {
    for c in cases {
        println!(
            "{} {}: reference {:.6e}, computed {:.6e}, error {:.2e} (tol {:.1e})",
            c.case,
            c.quantity,
            c.reference,
            c.computed,
            c.error(),
            c.tolerance
        );
    }
    for c in cases {
        assert!(
            c.passed(),
            "{} {}: error {:.3e}",
            c.case,
            c.quantity,
            c.error()
        );
    }
}

#[test]
fn lame_cylinder_axisymmetric_matches_the_closed_form() {
    report(&lame_axisymmetric());
}

#[test]
fn circular_punch_matches_sneddon() {
    report(&circular_punch());
}

/// The check discriminates: on 2 × 1 cells the displacement error is above the 8 × 4
/// tolerance.
#[test]
fn coarse_lame_misses_the_tolerance() {
    let (du, ds, _) = lame_errors(2, "axisymmetric").expect("coarse run");
    println!("2 × 1 cells: u error {du:.3e}, σ error {ds:.3e}");
    assert!(du > 1.5e-4 && ds > 3e-3);
}

#[test]
fn punch_stiffness_by_domain_size() {
    for (size, cells) in [(10.0, 20), (20.0, 24), (40.0, 28)] {
        let k = punch_stiffness(size, cells).unwrap();
        println!(
            "L = {size} a, {cells} cells: K/K_Sneddon = {:.5}",
            k / sneddon_stiffness(1.0)
        );
    }
}
