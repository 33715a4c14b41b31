//! Elastic checks of the time stepper, run through the same code as `talus verify`:
//! - one implicit elastic step equals the direct solve `(M + h² K) v = M vₙ + h (f − Bᵀσₙ)
//!   − h² K_fD v_D` with `K = Bᵀ S⁻¹ B` assembled densely (`docs/derivations.md`, 'The
//!   reduced system');
//! - the patch test: an affine velocity field is kept exactly and every Gauss point sees the
//!   uniform strain rate, for P1 and P2 on a graded (irregular) mesh.
use talus::analysis::verification::{elastic_patch_test, elastic_step_identity, CaseResult};

fn assert_passes(results: Vec<CaseResult>) {
    assert!(!results.is_empty());
    for r in results {
        assert!(r.computed.is_finite(), "{}: no result", r.case);
        assert!(
            r.passed(),
            "{}: {} = {:e} > {:e}",
            r.case,
            r.quantity,
            r.error(),
            r.tolerance
        );
    }
}

#[test]
fn elastic_step_equals_direct_velocity_solve() {
    assert_passes(elastic_step_identity());
}

#[test]
fn patch_test_uniform_strain_rate_p1_and_p2() {
    assert_passes(elastic_patch_test());
}
