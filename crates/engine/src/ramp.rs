//! Load programmes: a piecewise-linear multiplier in time, `ramp = [[t0, f0], [t1, f1], ...]`
//! (s, dimensionless), held at `f0` before `t0` and at the last value after the last time.
//! Every load and prescribed velocity of a scene may follow one (`docs/scenes.md`, 'Load
//! programmes').

/// Why a list of `[t, f]` points is not a ramp. The scene names the field around it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RampError {
    #[error("is empty: give at least one point [t, f]")]
    Empty,
    #[error("point {index} = [{t}, {f}] must be finite")]
    NotFinite { index: usize, t: f64, f: f64 },
    #[error("times must increase strictly: point {index} has t = {t} s after t = {previous} s")]
    NotIncreasing { index: usize, previous: f64, t: f64 },
}

/// A validated multiplier `f(t)`: times strictly increasing, every value finite.
#[derive(Debug, Clone, PartialEq)]
pub struct Ramp {
    points: Vec<[f64; 2]>,
}

impl Ramp {
    pub fn try_new(points: &[[f64; 2]]) -> Result<Self, RampError> {
        if points.is_empty() {
            return Err(RampError::Empty);
        }
        for (index, &[t, f]) in points.iter().enumerate() {
            if !(t.is_finite() && f.is_finite()) {
                return Err(RampError::NotFinite { index, t, f });
            }
            if index > 0 && t <= points[index - 1][0] {
                return Err(RampError::NotIncreasing {
                    index,
                    previous: points[index - 1][0],
                    t,
                });
            }
        }
        Ok(Self {
            points: points.to_vec(),
        })
    }

    pub fn points(&self) -> &[[f64; 2]] {
        &self.points
    }

    /// `f(t)`: linear between points, the end values outside; exactly `f_k` at `t_k`.
    pub fn at(&self, t: f64) -> f64 {
        let first = self.points[0];
        let last = self.points[self.points.len() - 1];
        if t <= first[0] {
            return first[1];
        }
        if t >= last[0] {
            return last[1];
        }
        // t0 < t < t_last: the first point at or after t has index k ≥ 1.
        let k = self.points.partition_point(|p| p[0] < t);
        let [t1, f1] = self.points[k];
        if t == t1 {
            return f1;
        }
        let [t0, f0] = self.points[k - 1];
        f0 + (f1 - f0) * (t - t0) / (t1 - t0)
    }

    /// Whether a segment shorter than `t1 − t0` overlaps the step `(t0, t1]`: the
    /// multiplier then changes faster than the step resolves (for a velocity, a jump).
    pub fn changes_within(&self, t0: f64, t1: f64) -> bool {
        let h = t1 - t0;
        self.points
            .windows(2)
            .any(|s| s[1][0] - s[0][0] < h && s[0][0] < t1 && s[1][0] > t0)
    }

    /// Whether the slope changes at the start of the step from `t0` to `t1` or inside it
    /// (a breakpoint in `[t0, t1)`, to `1e-9 h` for the rounding of summed steps): the
    /// rate of this step differs from the last one's.
    pub fn slope_changes_from(&self, t0: f64, t1: f64) -> bool {
        let tol = 1e-9 * (t1 - t0);
        self.kinks().any(|t| t >= t0 - tol && t < t1 - tol)
    }

    /// Whether the slope changes strictly inside the step (a breakpoint in `(t0, t1)`, to
    /// `1e-9 h`): the step's mean rate is then neither side's.
    pub fn slope_changes_inside(&self, t0: f64, t1: f64) -> bool {
        let tol = 1e-9 * (t1 - t0);
        self.kinks().any(|t| t > t0 + tol && t < t1 - tol)
    }

    /// The times where the slope changes (held values outside have slope 0).
    fn kinks(&self) -> impl Iterator<Item = f64> + '_ {
        let p = &self.points;
        let slope = |k: usize| {
            if k == 0 || k == p.len() {
                0.0
            } else {
                (p[k][1] - p[k - 1][1]) / (p[k][0] - p[k - 1][0])
            }
        };
        (0..p.len())
            .filter(move |&k| slope(k) != slope(k + 1))
            .map(move |k| p[k][0])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn piecewise_linear_held_outside() {
        let r = Ramp::try_new(&[[1.0, 0.0], [3.0, 2.0], [4.0, -1.0]]).unwrap();
        for (t, f) in [
            (-5.0, 0.0),
            (1.0, 0.0),
            (2.0, 1.0),
            (2.5, 1.5),
            (3.0, 2.0),
            (3.5, 0.5),
            (4.0, -1.0),
            (9.0, -1.0),
        ] {
            assert_eq!(r.at(t), f, "f({t})");
        }
        let single = Ramp::try_new(&[[0.5, 3.0]]).unwrap();
        assert_eq!((single.at(0.0), single.at(7.0)), (3.0, 3.0));
    }

    #[test]
    fn fast_segments_are_seen_by_the_steps_they_overlap() {
        let r = Ramp::try_new(&[[0.0, 0.0], [1.0, 1.0], [1.001, -1.0]]).unwrap();
        assert!(!r.changes_within(0.5, 0.51));
        assert!(r.changes_within(0.995, 1.005));
        assert!(r.changes_within(1.0, 1.01));
        assert!(!r.changes_within(1.01, 1.02));
        // a segment as long as the step is resolved
        assert!(!r.changes_within(0.0, 1.0));
    }

    #[test]
    fn slope_changes_at_breakpoints_only() {
        // kinks at 0 (0 → 1), 1 (1 → 0); 2 is collinear (0 → 0), 3 (0 → −1), 4 (−1 → 0)
        let r =
            Ramp::try_new(&[[0.0, 0.0], [1.0, 1.0], [2.0, 1.0], [3.0, 1.0], [4.0, 0.0]]).unwrap();
        let kinks: Vec<f64> = r.kinks().collect();
        assert_eq!(kinks, vec![0.0, 1.0, 3.0, 4.0]);
        assert!(r.slope_changes_from(1.0, 1.1) && !r.slope_changes_inside(1.0, 1.1));
        assert!(r.slope_changes_from(1.0 + 1e-15, 1.1));
        assert!(!r.slope_changes_from(0.9, 1.0 - 1e-15));
        assert!(r.slope_changes_inside(0.95, 1.05));
        assert!(!r.slope_changes_from(1.5, 2.5) && !r.slope_changes_inside(1.5, 2.5));
        assert!(Ramp::try_new(&[[2.0, 3.0]])
            .unwrap()
            .kinks()
            .next()
            .is_none());
    }

    #[test]
    fn bad_points_are_refused() {
        assert_eq!(Ramp::try_new(&[]), Err(RampError::Empty));
        assert!(matches!(
            Ramp::try_new(&[[0.0, 1.0], [f64::NAN, 1.0]]),
            Err(RampError::NotFinite { index: 1, .. })
        ));
        assert!(matches!(
            Ramp::try_new(&[[0.0, f64::INFINITY]]),
            Err(RampError::NotFinite { index: 0, .. })
        ));
        assert_eq!(
            Ramp::try_new(&[[0.0, 0.0], [2.0, 1.0], [2.0, 3.0]]),
            Err(RampError::NotIncreasing {
                index: 2,
                previous: 2.0,
                t: 2.0
            })
        );
    }
}
