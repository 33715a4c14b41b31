//! The material-point cases of `talus verify`, solved by `talus-ssn` on a one-point system
//! (`W = S`, `q = −S σ_trial`): dilatancy ratio `k_d tan θ`, return to the apex
//! `p = c / tan φ`, associative normality.
use talus::analysis::verification::{apex_return, associative_normality, dilatancy_ratio};

#[test]
fn material_point_cases_reproduce_their_closed_forms() {
    let results: Vec<_> = [dilatancy_ratio(), apex_return(), associative_normality()].concat();
    assert_eq!(results.len(), 6);
    for r in results {
        assert!(r.computed.is_finite(), "{}: no result", r.case);
        assert!(
            r.passed(),
            "{}: error {:e} > {:e}",
            r.case,
            r.error(),
            r.tolerance
        );
    }
}
