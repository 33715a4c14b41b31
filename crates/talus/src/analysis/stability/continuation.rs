//! Where the next trial goes: the load–displacement curve the stable trials measured,
//! extrapolated to collapse (`docs/stability.md`, 'Search').
//!
//! Each stable trial ends at rest at its factor `F` having moved `D(F)` from the search's
//! equilibrium (the criterion's measure, [`super::Trial::moved`]). Near collapse the
//! curve flattens: its stiffness falls to zero at the collapse factor `F_c` (Bergan et
//! al. 1978's "current stiffness parameter", which tells a limit point in a continuation).
//! The estimate is where the line through the last two secant stiffnesses
//! `k = ΔF/ΔD` between consecutive stable trials, placed at their middles `F̄`, meets
//! `k = 0`. It only steers the search: every bracket end is still a trial judged by the
//! criterion.

use super::bracket::{Guide, EXPANSION};

/// The first step beyond the largest stable factor, a fraction of it (at most
/// `EXPANSION − 1`, the blind search's doubling): after each new largest stable factor,
/// doubled while the secant compliance grew at most 1.25 times over the one before,
/// divided by that growth once it grew 2 times or more ([`Planner::stable`]). A trial far
/// above collapse is the search's most expensive (on the slope, `F = 2` from `F = 1` took
/// 339 Newton iterations, `F = 1.25` 38).
pub const FIRST_STEP: f64 = 0.25;
/// The smallest step beyond the largest stable factor (a fraction of it).
pub const MIN_STEP: f64 = 0.01;

/// The trials' load–displacement curve and the step beyond the largest stable factor.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Planner {
    /// `(F, D)` of the stable trials, sorted by `F`.
    stable: Vec<(f64, f64)>,
    /// `(F, D)` of the failing trials (by the criterion), sorted by `F`.
    failing: Vec<(f64, f64)>,
    /// The loading's displacement per unit factor, `U` (the loading moved the body by `U`
    /// under the weight of `F = 1`): the compliance the first secant's is compared with.
    reference: Option<f64>,
    /// Strength reduction: an elastic body does not move when its strength drops, so the
    /// first motion is a bend (a growth of at least 2) whatever its size.
    first_motion_bends: bool,
    /// The next step beyond the largest stable factor, as a fraction of it.
    step: f64,
}

impl Planner {
    /// `reference`: the loading's displacement per unit factor, if any
    /// ([`Planner::reference`]); `first_motion_bends` for strength reduction
    /// ([`Planner::first_motion_bends`]).
    pub fn new(reference: Option<f64>, first_motion_bends: bool) -> Self {
        Self {
            reference: reference.filter(|r| r.is_finite() && *r > 0.0),
            first_motion_bends,
            step: FIRST_STEP,
            ..Self::default()
        }
    }

    /// A trial at `factor` failed by the criterion having moved `moved` (m).
    pub fn failing(&mut self, factor: f64, moved: f64) {
        if factor.is_finite() && moved.is_finite() {
            let k = self.failing.partition_point(|p| p.0 < factor);
            self.failing.insert(k, (factor, moved));
        }
    }

    /// How much the last secant's compliance `ΔD/ΔF` grew over the one before (over
    /// `reference` for the first secant, infinite without one; at least 2 there when
    /// `first_motion_bends`).
    fn compliance_growth(&self) -> Option<f64> {
        let secants = self.secants();
        let (_, k) = *secants.last()?;
        Some(match secants[..] {
            [.., (_, kp), _] => kp / k,
            _ => {
                let g = self.reference.map_or(f64::INFINITY, |u| (1.0 / k) / u);
                if self.first_motion_bends {
                    g.max(2.0)
                } else {
                    g
                }
            }
        })
    }

    /// A trial at `factor` came to rest having moved `moved` (m) from the equilibrium.
    /// A new largest stable factor sets the step beyond it from the compliance's growth
    /// ([`Planner::compliance_growth`]): doubled (up to `EXPANSION − 1`) while the curve
    /// stays straight (growth `g` at most 1.25), divided by `g` (down to `MIN_STEP`) once
    /// it bends (`g` at least 2), kept between. Dividing by `g` is Bergan et al.'s (1978)
    /// increment proportional to the current stiffness: on a stiffness falling linearly
    /// to zero at `F_c` the step stays the same fraction of the distance left to `F_c`.
    pub fn stable(&mut self, factor: f64, moved: f64) {
        if !(factor.is_finite() && moved.is_finite()) {
            return;
        }
        let largest = self.stable.last().is_none_or(|p| factor > p.0);
        let k = self.stable.partition_point(|p| p.0 < factor);
        if self.stable.get(k).is_some_and(|p| p.0 == factor) {
            self.stable[k].1 = moved;
        } else {
            self.stable.insert(k, (factor, moved));
        }
        match self.compliance_growth() {
            Some(g) if largest && g <= 1.25 => self.step = (2.0 * self.step).min(EXPANSION - 1.0),
            Some(g) if largest && g >= 2.0 => self.step = (self.step / g).max(MIN_STEP),
            _ => {}
        }
    }

    /// The secant stiffnesses `(F̄, ΔF/ΔD)` between consecutive stable trials where the
    /// displacement grew, `F̄` the secant's middle.
    fn secants(&self) -> Vec<(f64, f64)> {
        self.stable
            .windows(2)
            .filter_map(|w| {
                let (df, dd) = (w[1].0 - w[0].0, w[1].1 - w[0].1);
                (df > 0.0 && dd > 0.0).then(|| (0.5 * (w[0].0 + w[1].0), df / dd))
            })
            .collect()
    }

    /// The collapse factor: from above, where the line through the two smallest failing
    /// trials' `(F, D)` comes down to the largest stable trial's `D` (their motion over
    /// the criterion's steps shrinks as `F` nears `F_c` from above); else from below,
    /// [`Planner::stiffness_zero`]. Only an estimate above the largest stable factor and
    /// below the smallest failing one.
    pub fn estimate(&self) -> Option<f64> {
        let lo = self.stable.last().copied();
        let hi = self.failing.first().map(|p| p.0);
        let inside =
            |e: f64| e.is_finite() && lo.is_none_or(|p| e > p.0) && hi.is_none_or(|h| e < h);
        let above = match (lo, &self.failing[..]) {
            (Some((fl, dl)), &[(fa, da), (fb, db), ..]) if fa > fl && da > dl && db > da => {
                Some(fa - (da - dl) * (fb - fa) / (db - da))
            }
            _ => None,
        };
        above
            .filter(|e| inside(*e))
            .or_else(|| self.stiffness_zero().filter(|e| inside(*e)))
    }

    /// Where the line through the last two secant stiffnesses `(F̄, k)` meets `k = 0`,
    /// when the stiffness fell between them; `None` unless above the largest stable
    /// factor.
    pub fn stiffness_zero(&self) -> Option<f64> {
        let secants = self.secants();
        let [.., (fa, ka), (fb, kb)] = secants[..] else {
            return None;
        };
        // A straight curve up to round-off gives no estimate.
        if !(kb < ka * (1.0 - 1e-12) && fb > fa) {
            return None;
        }
        let estimate = fb + kb * (fb - fa) / (ka - kb);
        let lo = self.stable.last()?.0;
        (estimate.is_finite() && estimate > lo).then_some(estimate)
    }

    pub fn guide(&self) -> Guide {
        Guide {
            estimate: self.estimate(),
            expansion: 1.0 + self.step,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On a curve whose stiffness falls linearly to zero at `F_c`, `dF/dD = α (F_c − F)`
    /// (`D = −ln(F_c − F)/α`), the estimate from three close trials is `F_c` to the
    /// secants' error (0.2% here); the displacement is measured from the first, as the
    /// search measures it from its equilibrium.
    #[test]
    fn a_stiffness_falling_to_zero_is_extrapolated_to_its_zero() {
        for (fc, alpha) in [(6.69, 1e3), (1.39, 50.0), (30.0, 1e4)] {
            let d = |f: f64| -(fc - f).ln() / alpha;
            let mut p = Planner::new(None, false);
            let fs = [0.9 * fc, 0.93 * fc, 0.95 * fc];
            for f in fs {
                p.stable(f, d(f) - d(fs[0]));
            }
            let e = p.estimate().unwrap();
            assert!((e / fc - 1.0).abs() < 2e-3, "{e} {fc}");
            // Far trials (stiffness halved) still land within 10%.
            let mut p = Planner::new(None, false);
            for f in [0.25 * fc, 0.5 * fc, 0.75 * fc] {
                p.stable(f, d(f));
            }
            let e = p.estimate().unwrap();
            assert!((e / fc - 1.0).abs() < 0.1, "{e} {fc}");
        }
    }

    /// The step beyond the largest stable factor: divided by the compliance's growth `g`
    /// once the curve bends (Bergan et al.'s increment proportional to the current
    /// stiffness); for strength reduction the first motion is a bend however small,
    /// measured against the loading's `U` per unit factor.
    #[test]
    fn the_step_shrinks_with_the_stiffness() {
        let expansion = |reference, bends, moved: f64| {
            let mut p = Planner::new(reference, bends);
            p.stable(1.0, 0.0);
            p.stable(1.25, moved);
            p.guide().expansion
        };
        // Moved 4 U per unit factor: g = 4, the step 0.25 / 4.
        assert_eq!(expansion(Some(1.0), true, 1.0), 1.0625);
        assert_eq!(expansion(Some(1.0), false, 1.0), 1.0625);
        // g = 0.4: strength reduction still halves, gravity increase doubles (straight).
        assert_eq!(expansion(Some(1.0), true, 0.1), 1.125);
        assert_eq!(expansion(Some(1.0), false, 0.1), 1.5);
        // g = 1.6: kept by gravity increase.
        assert_eq!(expansion(Some(1.0), false, 0.4), 1.25);
        // g = 2.5: divided by 2.5, more than the halving of the rule before.
        assert_eq!(expansion(Some(1.0), false, 0.625), 1.1);
        // No reference: infinite growth, the smallest step.
        assert_eq!(expansion(None, true, 1.0), 1.0 + MIN_STEP);
        // A second bend divides again, by the ratio of the two secants' compliances.
        let mut p = Planner::new(Some(1.0), true);
        p.stable(1.0, 0.0);
        p.stable(1.25, 1.0); // compliance 4, step 0.0625
        p.stable(1.3, 1.8); // compliance 16: g = 4, step 0.015625
        assert_eq!(p.guide().expansion, 1.015625);
    }

    /// A straight (elastic) curve has no estimate; nor has one point.
    #[test]
    fn no_estimate_without_softening() {
        let mut p = Planner::new(None, false);
        p.stable(1.0, 0.125);
        assert_eq!(p.estimate(), None);
        p.stable(2.0, 0.25);
        p.stable(3.0, 0.375);
        assert_eq!(p.stable, [(1.0, 0.125), (2.0, 0.25), (3.0, 0.375)]);
        assert_eq!(p.secants(), [(1.5, 8.0), (2.5, 8.0)]);
        assert_eq!(p.estimate(), None);
        // A stiffness lower by round-off only (one ulp of D) gives none either.
        p.stable(4.0, 0.5 + f64::EPSILON);
        assert_eq!(p.estimate(), None);
    }
}
