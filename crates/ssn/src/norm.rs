//! `‖v‖∞` with NaN kept: one implementation for the Newton loop and the linear algebra.

/// `‖v‖∞`, NaN if any entry is. Maxima are exact in any order: eight lanes, so that the
/// loop vectorizes.
pub(crate) fn inf_norm(v: &[f64]) -> f64 {
    let mut lanes = [0.0f64; 8];
    let mut nan = false;
    let chunks = v.chunks_exact(8);
    let rest = chunks.remainder();
    for chunk in chunks {
        for (m, x) in lanes.iter_mut().zip(chunk) {
            let a = x.abs();
            *m = if a > *m { a } else { *m };
            nan |= x.is_nan();
        }
    }
    for x in rest {
        lanes[0] = lanes[0].max(x.abs());
        nan |= x.is_nan();
    }
    if nan {
        f64::NAN
    } else {
        lanes.into_iter().fold(0.0, f64::max)
    }
}

#[cfg(test)]
mod tests {
    use super::inf_norm;

    #[test]
    fn inf_norm_is_the_largest_magnitude_and_nan_wherever_a_nan_is() {
        for n in [0, 1, 7, 8, 9, 16, 23] {
            let v: Vec<f64> = (0..n).map(|k| ((k * 37 % 11) as f64 - 5.0) * 1.5).collect();
            let naive = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            assert_eq!(inf_norm(&v), naive, "length {n}");
            for at in 0..n {
                let mut w = v.clone();
                w[at] = f64::NAN;
                assert!(inf_norm(&w).is_nan(), "NaN at {at} of {n}");
            }
        }
    }
}
