//! An unsymmetric 5-point operator on an `m × m` grid (`n = m²` unknowns), each row given
//! by one rank (rows `k` with `k mod size = rank`), so that no entry is summed between
//! ranks: shared by `tests/distributed_solve.rs` and `examples/solve_twice.rs`.

/// This rank's entries `(rows, cols, values)`.
pub fn five_point_entries(
    m: usize,
    rank: usize,
    size: usize,
) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
    let (mut rows, mut cols, mut values) = (Vec::new(), Vec::new(), Vec::new());
    for k in (rank..m * m).step_by(size) {
        let (i, j) = (k / m, k % m);
        let mut push = |c: usize, v: f64| {
            rows.push(k);
            cols.push(c);
            values.push(v);
        };
        push(k, 4.3 + (k % 7) as f64 * 0.01);
        if i > 0 {
            push(k - m, -1.1);
        }
        if i + 1 < m {
            push(k + m, -0.9);
        }
        if j > 0 {
            push(k - 1, -1.05);
        }
        if j + 1 < m {
            push(k + 1, -0.95);
        }
    }
    (rows, cols, values)
}

/// The right-hand side both programs solve for.
pub fn five_point_rhs(n: usize) -> Vec<f64> {
    (0..n).map(|k| 1.0 + (k % 13) as f64).collect()
}

/// A hash of the bits of `x`.
pub fn bits_hash(x: &[f64]) -> u64 {
    x.iter().fold(0u64, |h, y| h.rotate_left(5) ^ y.to_bits())
}
