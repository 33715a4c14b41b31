//! Drained triaxial compression (`scenes/triaxial.toml`, axisymmetric): the peak deviator
//! and the dilatancy ratio match the Drucker-Prager closed forms to 1e-6
//! (`docs/axisymmetry.md`, 'Triaxial compression'), for two cone fits and θ = 0, θ = φ.
use talus::analysis::verification::{
    run_triaxial, triaxial_compression, triaxial_peak_deviator, triaxial_scene,
};

#[test]
fn triaxial_compression_matches_the_closed_forms() {
    let cases = triaxial_compression();
    assert_eq!(cases.len(), 8);
    for c in &cases {
        println!(
            "{} {}: reference {:.10e}, computed {:.10e}, error {:.2e}",
            c.case,
            c.quantity,
            c.reference,
            c.computed,
            c.error()
        );
    }
    for c in &cases {
        assert!(
            c.passed(),
            "{} {}: error {:.3e}",
            c.case,
            c.quantity,
            c.error()
        );
    }
}

/// The check can fail: the same sample in plane strain (no hoop strain, the out-of-plane
/// stress free to differ from the cell pressure) misses the axisymmetric peak.
#[test]
fn plane_strain_misses_the_triaxial_peak() {
    let scene = triaxial_scene("outer_cone", 30.0, 30.0, "plane_strain");
    let run = run_triaxial(&scene).expect("plane-strain run");
    // Per metre of thickness: the platen's force over its width R, not π R².
    let q = run.q * std::f64::consts::PI * 0.025;
    let reference = triaxial_peak_deviator(run.k_d, 30.0, 5.0e3, 1.0e5);
    println!("plane strain q = {q:.6e}, triaxial closed form {reference:.6e}");
    assert!((q - reference).abs() > 1e-2 * reference);
}
