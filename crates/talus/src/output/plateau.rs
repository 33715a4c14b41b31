//! The limit load of a displacement-driven run: where the force–settlement curve of the
//! reported boundary has levelled off. Criterion (`docs/scenes.md`, 'summary.json'): the
//! plateau is the longest tail of the curve whose forces all lie within `tolerance` (relative)
//! of the final force; it is a plateau when that tail spans at least `span` of the whole
//! settlement range and holds at least `min_points` points. Its force is the mean over the
//! tail, and it starts at the settlement of the tail's first point.

/// The thresholds of the criterion.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct PlateauCriterion {
    /// Largest `|F − F_final| / |F_final|` on the plateau.
    pub tolerance: f64,
    /// Smallest share of the settlement range (first to last point) the plateau covers.
    pub span: f64,
    pub min_points: usize,
}

impl Default for PlateauCriterion {
    /// 1% over the last 20% of the settlement: the paper footing's force varies by less
    /// than 1% over the second half of its run (`tests/paper_footing.rs`), while an elastic
    /// or hardening branch changes by more than 1% over a fifth of the range.
    fn default() -> Self {
        Self {
            tolerance: 0.01,
            span: 0.2,
            min_points: 3,
        }
    }
}

impl PlateauCriterion {
    /// The criterion in words, for summary.json and the last line of a run.
    pub fn describe(&self) -> String {
        format!(
            "every force from the plateau's start to the end is within {}% of the final force, over at least {}% of the settlement range and {} points",
            100.0 * self.tolerance,
            100.0 * self.span,
            self.min_points
        )
    }
}

/// A plateau found on a curve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plateau {
    /// Mean force over the plateau.
    pub force: f64,
    /// Settlement of its first point.
    pub settlement: f64,
    /// Index of its first point in the curve.
    pub start: usize,
}

/// The plateau of `curve` (`(settlement, force)` points in order of increasing
/// settlement), if the criterion holds; `None` for a curve without a positive settlement
/// range, a zero or non-finite final force, or a tail too short.
pub fn plateau(curve: &[(f64, f64)], criterion: &PlateauCriterion) -> Option<Plateau> {
    let n = curve.len();
    if n < criterion.min_points.max(2)
        || curve.iter().any(|(d, f)| !(d.is_finite() && f.is_finite()))
    {
        return None;
    }
    let (d_first, (d_last, f_last)) = (curve[0].0, curve[n - 1]);
    let range = d_last - d_first;
    if !(range > 0.0 && f_last != 0.0) {
        return None;
    }
    let band = criterion.tolerance * f_last.abs();
    let mut start = n - 1;
    while start > 0 && (curve[start - 1].1 - f_last).abs() <= band {
        start -= 1;
    }
    let tail = &curve[start..];
    let long_enough = d_last - curve[start].0 >= criterion.span * range;
    (long_enough && tail.len() >= criterion.min_points).then(|| Plateau {
        force: tail.iter().map(|p| p.1).sum::<f64>() / tail.len() as f64,
        settlement: curve[start].0,
        start,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curve(f: impl Fn(f64) -> f64) -> Vec<(f64, f64)> {
        (0..=100)
            .map(|i| 1e-5 * i as f64)
            .map(|d| (d, f(d)))
            .collect()
    }

    #[test]
    fn a_rising_curve_is_not_a_plateau() {
        let c = PlateauCriterion::default();
        // Linear: the last 20% change the force by 20%.
        assert_eq!(plateau(&curve(|d| 1e8 * d), &c), None);
        // Hardening that slows down but still gains 15% over the last fifth.
        assert_eq!(plateau(&curve(|d| 1e5 * (1.0 + 1e3 * d).ln()), &c), None);
    }

    #[test]
    fn an_elastic_rise_then_a_flat_limit_is_found_where_it_starts() {
        // Elastic up to d = 3e-4, then perfectly flat at 1.5e5.
        let c = PlateauCriterion::default();
        let p = plateau(&curve(|d| (5e8 * d).min(1.5e5)), &c).expect("plateau");
        assert_eq!(p.start, 30);
        assert!((p.settlement - 3e-4).abs() < 1e-15);
        assert!((p.force - 1.5e5).abs() < 1e-9);
        // Still rising (1% over the last 38%): the plateau starts at the first point
        // within 1% of the final force, 4e6 (1e-3 − d) ≤ 0.01 (1.5e5 + 4e3): d = 6.2e-4.
        let rising = curve(|d| (5e8 * d).min(1.5e5) + 4e6 * d);
        let p = plateau(&rising, &c).expect("plateau");
        assert_eq!(p.start, 62, "{p:?}");
        let last = rising[100].1;
        assert!(rising[62..]
            .iter()
            .all(|(_, f)| (f - last).abs() <= 0.01 * last));
        assert!((rising[61].1 - last).abs() > 0.01 * last);
    }

    #[test]
    fn noise_below_the_tolerance_keeps_the_plateau_and_above_it_does_not() {
        let c = PlateauCriterion::default();
        // ±0.4% alternating noise on the flat part: twice it stays within 1% of the last.
        let noisy = |amp: f64| {
            curve(move |d| {
                let i = (d / 1e-5).round() as i64;
                (5e8 * d).min(1.5e5) * (1.0 + amp * if i % 2 == 0 { 1.0 } else { -1.0 })
            })
        };
        let p = plateau(&noisy(0.004), &c).expect("plateau under 0.4% noise");
        assert!(p.start <= 31, "{p:?}");
        assert!((p.force - 1.5e5).abs() < 0.004 * 1.5e5);
        // ±0.6%: consecutive points differ by 1.2% of the force, more than the band.
        assert_eq!(plateau(&noisy(0.006), &c), None);
    }

    #[test]
    fn softening_to_a_residual_level_reports_the_residual_plateau() {
        let c = PlateauCriterion::default();
        let peak_then_residual = curve(|d| {
            if d < 3e-4 {
                5e8 * d
            } else {
                (1.5e5 - 2e8 * (d - 3e-4)).max(1.2e5)
            }
        });
        let p = plateau(&peak_then_residual, &c).expect("residual plateau");
        assert!((p.force - 1.2e5).abs() < 1e-9 && p.start == 45, "{p:?}");
    }

    #[test]
    fn degenerate_curves_have_no_plateau() {
        let c = PlateauCriterion::default();
        assert_eq!(plateau(&[], &c), None);
        assert_eq!(
            plateau(&[(0.0, 1.0), (1.0, 1.0)], &c),
            None,
            "too few points"
        );
        assert_eq!(plateau(&[(0.0, 1.0); 10], &c), None, "no settlement");
        assert_eq!(plateau(&curve(|_| 0.0), &c), None, "no force");
        assert_eq!(plateau(&curve(|_| f64::NAN), &c), None);
    }
}
