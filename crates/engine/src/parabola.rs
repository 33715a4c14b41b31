//! The extrapolated predictor along a parabola (`docs/solver.md`, 'Time stepping'): from
//! the line `σₙ + h σ̇ₙ` to `σₙ + h (2σ̇ₙ − σ̇ₙ₋₁)`, the parabola through the last three
//! stresses, when the last sub-step showed it clearly closer.
//!
//! Both predictions' errors on the sub-step just ended follow from its rates alone:
//! `h ‖σ̇ₙ₊₁ − σ̇ₙ‖` for the line, `h ‖σ̇ₙ₊₁ − 2σ̇ₙ + σ̇ₙ₋₁‖` for the parabola. Under steady
//! flow the parabola's is smaller by a factor h and Newton needs an iteration fewer; where
//! the plastic zone still spreads it is not, and the line is kept.

/// The parabola is taken when on the last sub-step it would have been at least this factor
/// closer than the line (‖·‖∞). Measured on eight scenes (`docs/solver.md`, 'The
/// parabolic predictor'): 1 cost iterations on the 40-step footings, 0.5 to 0.1 gave the
/// same counts.
pub(crate) const PARABOLA_GAIN: f64 = 0.25;

/// What the parabolic predictor needs from the sub-steps before: part of a checkpoint
/// ([`StepperMemory`](crate::StepperMemory)).
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Parabola {
    /// h of the sub-step that measured the stepper's stress rate (0: not known).
    pub rate_h: f64,
    /// The rate before it and the h of its sub-step.
    pub previous: Option<(Vec<f64>, f64)>,
    /// Whether the next sub-step extrapolates along the parabola.
    pub next: bool,
}

impl Parabola {
    /// `sigma += h σ̇ₙ`, or `h (2σ̇ₙ − σ̇ₙ₋₁)` when chosen and both rates were measured
    /// over sub-steps of this `h` (equal spacing). Returns whether it took the parabola.
    pub(crate) fn extrapolate(&self, sigma: &mut [f64], rate: &[f64], h: f64) -> bool {
        match &self.previous {
            Some((before, before_h)) if self.next && self.rate_h == h && *before_h == h => {
                for ((s, r), b) in sigma.iter_mut().zip(rate).zip(before) {
                    *s += h * (2.0 * r - b);
                }
                true
            }
            _ => {
                for (s, r) in sigma.iter_mut().zip(rate) {
                    *s += h * r;
                }
                false
            }
        }
    }

    /// After an accepted sub-step of `h` that extrapolated from `used` (the rate measured
    /// over `self.rate_h`, `None` if it did not extrapolate) and measured `new` (`None`
    /// if its loading was not smooth): chooses the next prediction, then shifts the rates.
    pub(crate) fn record(&mut self, used: Option<Vec<f64>>, new: Option<&[f64]>, h: f64) {
        self.next = match (new, &used, &self.previous) {
            (Some(new), Some(used), Some((before, before_h)))
                if self.rate_h == h && *before_h == h =>
            {
                let (mut line, mut parabola) = (0.0f64, 0.0f64);
                for ((n, u), b) in new.iter().zip(used).zip(before) {
                    line = line.max((n - u).abs());
                    parabola = parabola.max((n - 2.0 * u + b).abs());
                }
                parabola < PARABOLA_GAIN * line
            }
            _ => false,
        };
        self.previous = used.map(|u| (u, self.rate_h));
        self.rate_h = if new.is_some() { h } else { 0.0 };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Stresses on the parabola σ(t) = a + b t + c t², and the rate of step k.
    fn sigma(t: f64) -> Vec<f64> {
        vec![1.0 + 2.0 * t + 3.0 * t * t, -4.0 + 0.5 * t - 7.0 * t * t]
    }
    fn rate(k: usize, h: f64) -> Vec<f64> {
        let (a, b) = (sigma(k as f64 * h), sigma((k - 1) as f64 * h));
        a.iter().zip(&b).map(|(x, y)| (x - y) / h).collect()
    }

    /// Steps k = 1, 2, 3 recorded at h: the memory after step 3.
    fn after_three(h: f64, rates: [Vec<f64>; 3]) -> Parabola {
        let mut m = Parabola::default();
        let [r1, r2, r3] = rates;
        m.record(None, Some(&r1), h);
        m.record(Some(r1), Some(&r2), h);
        m.record(Some(r2), Some(&r3), h);
        m
    }

    #[test]
    fn a_parabola_in_time_is_predicted_exactly_and_the_straight_line_is_not() {
        let h = 0.1;
        let m = after_three(h, [rate(1, h), rate(2, h), rate(3, h)]);
        assert!(
            m.next,
            "on a parabola the line's error is c h², the parabola's 0"
        );
        let exact = sigma(4.0 * h);
        let mut along = sigma(3.0 * h);
        assert!(m.extrapolate(&mut along, &rate(3, h), h));
        for (p, e) in along.iter().zip(&exact) {
            assert!((p - e).abs() < 1e-12, "{p} against {e}");
        }
        // The line from the last rate misses by 2 c h² (c = 3 in the first component).
        let mut line = sigma(3.0 * h);
        assert!(!Parabola::default().extrapolate(&mut line, &rate(3, h), h));
        assert!(((exact[0] - line[0]) - 2.0 * 3.0 * h * h).abs() < 1e-12);
    }

    #[test]
    fn a_kink_in_the_rate_keeps_the_line() {
        let h = 0.1;
        // A constant rate, then a jump: the parabola would have been further off.
        let (a, b) = (vec![1.0, 1.0], vec![5.0, -3.0]);
        let m = after_three(h, [a.clone(), a, b]);
        assert!(!m.next);
    }

    #[test]
    fn a_change_of_sub_step_size_keeps_the_line() {
        let h = 0.1;
        let mut m = after_three(h, [rate(1, h), rate(2, h), rate(3, h)]);
        assert!(m.next);
        let mut s = sigma(3.0 * h);
        // A halved sub-step: the rates were not measured over h / 2.
        assert!(!m.extrapolate(&mut s, &rate(3, h), h / 2.0));
        // A step whose loading was not smooth forgets the rate's spacing.
        m.record(Some(rate(3, h)), None, h);
        assert!(!m.next);
        assert_eq!(m.rate_h, 0.0);
    }
}
