//! The round-off floor of the stopping test (`docs/solver.md`, "The round-off floor").
//!
//! `F(σ) = σ − P_C(σ − ρ y(Wσ + q))` cannot be evaluated more accurately than the rounding
//! of `z = Wσ + q`, whose error is about `ε (|W| |σ| + |q|)` componentwise (the large
//! quasi-static terms cancel in `z`). Measured with the stopping test's ρ, that is the
//! floor a Newton iteration can reach; below it, steps only move round-off around.
use talus_bipotential::FlowRule;

use crate::operator::{Operator, PointBlocks};

/// The solve ends at the floor only when its residual is within this factor of the
/// estimate: the estimate is a first-order bound without the (problem dependent) number of
/// terms per row, and stagnation far above it is a genuine failure.
pub(crate) const FLOOR_FACTOR: f64 = 1e3;

/// Stagnation: over the last `STAGNATION_WINDOW` iterations the residual has not fallen
/// below `STAGNATION_DECREASE` times its value at the start of that window.
pub(crate) const STAGNATION_WINDOW: usize = 3;
pub(crate) const STAGNATION_DECREASE: f64 = 0.5;

/// `φ = ε · max(‖σ‖∞, max_i ρ_i · max_{k ∈ i} (|W| |σ| + |q|)_k)` with the stopping test's
/// ρ_i: the rounding error of `F` at `sigma`, in the residual's units. For a structured
/// `W = S + h² B M⁻¹ Bᵀ`, `|W|` is taken factor by factor (`|S| + h² |B| M⁻¹ |B|ᵀ`), the
/// bound of the product as it is computed.
pub(crate) fn floor_estimate<const D: usize>(
    operator: &Operator<D>,
    blocks: Option<&PointBlocks<D>>,
    sigma: &[f64],
    q: &[f64],
    residual_rho: &[f64],
    rules: &[FlowRule<D>],
) -> f64 {
    let mut bound: Vec<f64> = q.iter().map(|v| v.abs()).collect();
    match operator {
        Operator::Dense(m) => {
            for (j, s) in sigma.iter().enumerate() {
                for (i, b) in bound.iter_mut().enumerate() {
                    *b += (m[(i, j)] * s).abs();
                }
            }
        }
        Operator::Sparse(m) => {
            let (cp, ri, v) = (m.symbolic().col_ptr(), m.symbolic().row_idx(), m.val());
            for (j, s) in sigma.iter().enumerate() {
                for k in cp[j]..cp[j + 1] {
                    bound[ri[k]] += (v[k] * s).abs();
                }
            }
        }
        Operator::Structured(s) => {
            let blocks = blocks.expect("structured operators carry point blocks");
            let mut u = vec![0.0; s.lumped_mass.len()];
            let n_points = s.compliance.len();
            for i in 0..n_points {
                let (dofs, vals) = blocks.point(i);
                let n_i = dofs.len();
                for (a, &j) in dofs.iter().enumerate() {
                    u[j] += (0..D)
                        .map(|r| (vals[r * n_i + a] * sigma[D * i + r]).abs())
                        .sum::<f64>();
                }
            }
            let h2 = s.h * s.h;
            for (x, m) in u.iter_mut().zip(&s.lumped_mass) {
                *x *= h2 / m;
            }
            for (i, c) in s.compliance.iter().enumerate() {
                let (dofs, vals) = blocks.point(i);
                let n_i = dofs.len();
                for r in 0..D {
                    let su: f64 = (0..D).map(|k| (c[(r, k)] * sigma[D * i + k]).abs()).sum();
                    let bu: f64 = (0..n_i).map(|a| vals[r * n_i + a].abs() * u[dofs[a]]).sum();
                    bound[D * i + r] += su + bu;
                }
            }
        }
    }
    let sigma_inf = sigma.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    // A relaxed rule reads z through `p = σ + N z` as well as `ρ y(z)` (`docs/derivations.md`,
    // 'Duvaut–Lions relaxation'): z's rounding reaches F scaled by ρ + ‖N‖.
    let gain = |i: usize, rho: f64| {
        rho + rules
            .get(i)
            .and_then(|r| r.relaxation())
            .map_or(0.0, |n| n.deviatoric().max(n.volumetric()))
    };
    let worst = bound
        .chunks(D)
        .zip(residual_rho)
        .enumerate()
        .map(|(i, (b, rho))| gain(i, *rho) * b.iter().fold(0.0f64, |m, v| m.max(*v)))
        .fold(sigma_inf, f64::max);
    f64::EPSILON * worst
}

/// True when the residual history (start and after every step) shows no decrease by
/// `STAGNATION_DECREASE` over the last `STAGNATION_WINDOW` steps.
pub(crate) fn stagnated(history: &[f64]) -> bool {
    no_decrease(history, STAGNATION_WINDOW, STAGNATION_DECREASE)
}

/// True when no value of the last `window` entries of `history` (start and after every
/// step) is below `decrease` times the entry `window` steps back.
pub(crate) fn no_decrease(history: &[f64], window: usize, decrease: f64) -> bool {
    if history.len() <= window {
        return false;
    }
    let window = &history[history.len() - 1 - window..];
    let best = window[1..].iter().fold(f64::INFINITY, |m, v| m.min(*v));
    best >= decrease * window[0]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stagnation_needs_a_full_window_without_halving() {
        assert!(!stagnated(&[1.0, 0.9, 0.9]));
        assert!(stagnated(&[1.0, 0.9, 0.8, 0.7]));
        assert!(!stagnated(&[1.0, 0.9, 0.8, 0.4]));
        assert!(stagnated(&[5.0, 1.0, 0.9, 0.8, 0.7]));
    }

    #[test]
    fn stall_window_counts_steps_from_the_value_window_steps_back() {
        // Window 4, decrease 0.5: the best of the four values after 8 must fall below 4.
        assert!(
            !no_decrease(&[8.0, 7.0, 6.0, 5.0], 4, 0.5),
            "window not full"
        );
        assert!(no_decrease(&[8.0, 7.0, 6.0, 5.0, 4.5], 4, 0.5));
        assert!(!no_decrease(&[8.0, 7.0, 6.0, 5.0, 3.9], 4, 0.5));
        assert!(
            !no_decrease(&[8.0, 3.9, 6.0, 5.0, 4.5], 4, 0.5),
            "any value counts"
        );
        assert!(
            no_decrease(&[100.0, 8.0, 7.0, 6.0, 5.0, 4.5], 4, 0.5),
            "only the last window"
        );
    }

    #[test]
    fn dense_floor_is_epsilon_times_scaled_absolute_product() {
        // W = [[1, -1], [-1, 1]], σ = (1e8, 1e8), q = (0, 0): Wσ = 0 exactly, but each row
        // sums |W||σ| = 2e8; ρ = (0.5, 1) → φ = ε · max(1e8, 0.5·2e8, 1·2e8) = 2e8 ε.
        let w = faer::Mat::from_fn(2, 2, |i, j| if i == j { 1.0 } else { -1.0 });
        let phi = floor_estimate::<1>(
            &Operator::Dense(w),
            None,
            &[1e8, 1e8],
            &[0.0, 0.0],
            &[0.5, 1.0],
            &[],
        );
        assert_eq!(phi, 2e8 * f64::EPSILON);
    }
}
