//! Graded 1D coordinate lists for structured meshes (fine under a footing, coarse far
//! away).
use crate::error::MeshError;

/// `n` cells on `[a, b]` (metres) whose sizes grow geometrically by `ratio` per cell away
/// from `focus ∈ [a, b]` (`ratio < 1` makes them shrink). Returns `n + 1` strictly
/// increasing coordinates with `a` and `b` exact.
///
/// - `ratio == 1`: uniform cells; `focus` is then irrelevant.
/// - `focus` strictly inside and `n ≥ 2`: `focus` is a node; the cells are split between
///   both sides so that the two cells touching `focus` are as close in size as integer
///   counts allow, and within each side neighbours differ by exactly `ratio`.
/// - `focus` at an end: one geometric progression from that end.
///
/// Errors: `n = 0`, `a ≥ b`, non-finite input, `ratio ≤ 0`, `focus` outside `[a, b]`, or
/// a grading so strong that cells vanish in floating point.
pub fn graded_coordinates(
    a: f64,
    b: f64,
    n: usize,
    focus: f64,
    ratio: f64,
) -> Result<Vec<f64>, MeshError> {
    if !(a.is_finite() && b.is_finite() && a < b) {
        return Err(MeshError::invalid(
            "interval",
            format!("[{a}, {b}] must be finite with a < b"),
        ));
    }
    if n == 0 {
        return Err(MeshError::invalid("n", "the number of cells must be ≥ 1"));
    }
    if !(ratio.is_finite() && ratio > 0.0) {
        return Err(MeshError::invalid(
            "ratio",
            format!("{ratio} must be finite and > 0"),
        ));
    }
    if !(focus >= a && focus <= b) {
        return Err(MeshError::invalid(
            "focus",
            format!("{focus} lies outside [{a}, {b}]"),
        ));
    }
    let xs = if ratio == 1.0 || n == 1 {
        (0..=n)
            .map(|i| a + (b - a) * (i as f64) / (n as f64))
            .collect()
    } else if focus == a {
        progression(a, b, n, ratio)
    } else if focus == b {
        let mut x: Vec<f64> = progression(a, b, n, ratio)
            .iter()
            .map(|x| a + b - x)
            .collect();
        x.reverse();
        x[0] = a;
        x[n] = b;
        x
    } else {
        // Pick the split whose two first cells h₀ = L / Σ rᵏ match best.
        let (left, right) = (focus - a, b - focus);
        let first = |len: f64, m: usize| len / geometric_sum(ratio, m);
        let n_left = (1..n)
            .min_by(|&p, &q| {
                let mismatch = |k: usize| (first(left, k) / first(right, n - k)).ln().abs();
                mismatch(p).total_cmp(&mismatch(q))
            })
            .unwrap_or(1);
        let mut x: Vec<f64> = progression(a, focus, n_left, ratio)
            .iter()
            .map(|x| a + focus - x)
            .rev()
            .collect();
        x[0] = a;
        x[n_left] = focus;
        x.extend_from_slice(&progression(focus, b, n - n_left, ratio)[1..]);
        x
    };
    if let Some(i) = (1..xs.len()).find(|&i| xs[i] <= xs[i - 1]) {
        return Err(MeshError::invalid(
            "ratio",
            format!(
                "grading {ratio} over {n} cells makes cell {} vanish in floating point",
                i - 1
            ),
        ));
    }
    Ok(xs)
}

/// `1 + r + … + r^(m−1)`.
fn geometric_sum(r: f64, m: usize) -> f64 {
    (0..m).map(|k| r.powi(k as i32)).sum()
}

/// `m` cells on `[a, b]` growing by `r` from `a`; ends exact.
fn progression(a: f64, b: f64, m: usize, r: f64) -> Vec<f64> {
    let h0 = (b - a) / geometric_sum(r, m);
    let mut x = Vec::with_capacity(m + 1);
    let mut pos = 0.0;
    x.push(a);
    for k in 0..m {
        pos += h0 * r.powi(k as i32);
        x.push(a + pos);
    }
    x[m] = b;
    x
}
