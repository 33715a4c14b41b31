//! `graded_coordinates`: exact ends, monotone, constant ratio between neighbours on each
//! side of the focus, and clear errors.
use talus_fem::{graded_coordinates, MeshError};

fn sizes(x: &[f64]) -> Vec<f64> {
    x.windows(2).map(|w| w[1] - w[0]).collect()
}

#[test]
fn graded_coordinates_keep_ends_and_ratio() {
    for &(a, b, n, focus, ratio) in &[
        (0.0, 10.0, 12, 0.0, 1.2),
        (-3.0, 7.0, 9, 7.0, 1.3),
        (0.0, 20.0, 15, 5.0, 1.25),
        (0.0, 1.0, 5, 0.5, 0.8),
    ] {
        let x = graded_coordinates(a, b, n, focus, ratio).unwrap();
        assert_eq!(x.len(), n + 1);
        assert_eq!((x[0], x[n]), (a, b));
        assert!(x.windows(2).all(|w| w[1] > w[0]));
        let h = sizes(&x);
        // index of the smallest |x − focus| node: the sides' boundary
        let k = x
            .iter()
            .enumerate()
            .min_by(|p, q| (p.1 - focus).abs().total_cmp(&(q.1 - focus).abs()))
            .unwrap()
            .0;
        assert_eq!(x[k], focus, "the focus is a node");
        for i in k..n - 1 {
            assert!(
                (h[i + 1] / h[i] - ratio).abs() < 1e-9,
                "right side, cell {i}"
            );
        }
        for i in 1..k {
            assert!(
                (h[i - 1] / h[i] - ratio).abs() < 1e-9,
                "left side, cell {i}"
            );
        }
    }
}

/// With an interior focus, the two cells touching it nearly match: moving one cell across
/// the focus changes their size ratio by about `ratio²`, so the best split is within that.
#[test]
fn graded_coordinates_balance_both_sides() {
    let x = graded_coordinates(0.0, 20.0, 15, 5.0, 1.25).unwrap();
    let k = x.iter().position(|&v| v == 5.0).unwrap();
    let h = sizes(&x);
    let r = h[k] / h[k - 1];
    assert!((1.0 / 1.5625..=1.5625).contains(&r), "{r}");
}

#[test]
fn graded_coordinates_ratio_one_is_uniform() {
    let x = graded_coordinates(1.0, 3.0, 4, 2.7, 1.0).unwrap();
    assert_eq!(x, vec![1.0, 1.5, 2.0, 2.5, 3.0]);
}

#[test]
fn graded_coordinates_reject_bad_arguments() {
    let field = |r: Result<Vec<f64>, MeshError>| match r {
        Err(MeshError::InvalidInput { field, .. }) => field,
        other => panic!("expected an error, got {other:?}"),
    };
    assert_eq!(field(graded_coordinates(0.0, 1.0, 0, 0.0, 1.1)), "n");
    assert_eq!(field(graded_coordinates(0.0, 1.0, 4, 0.0, 0.0)), "ratio");
    assert_eq!(field(graded_coordinates(0.0, 1.0, 4, 0.0, -2.0)), "ratio");
    assert_eq!(
        field(graded_coordinates(0.0, 1.0, 4, 0.0, f64::NAN)),
        "ratio"
    );
    assert_eq!(field(graded_coordinates(0.0, 1.0, 4, 1.5, 1.1)), "focus");
    assert_eq!(
        field(graded_coordinates(0.0, 1.0, 4, f64::NAN, 1.1)),
        "focus"
    );
    assert_eq!(field(graded_coordinates(1.0, 1.0, 4, 1.0, 1.1)), "interval");
    assert_eq!(
        field(graded_coordinates(0.0, f64::INFINITY, 4, 0.0, 1.1)),
        "interval"
    );
    // so strong a grading that the first cells underflow
    assert_eq!(field(graded_coordinates(0.0, 1.0, 200, 0.0, 1e3)), "ratio");
}
