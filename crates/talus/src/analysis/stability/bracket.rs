//! Bracketing, then bisection, of the factor of safety: the largest `F` whose trial is
//! stable and the smallest whose trial fails by the criterion, until
//! `(hi − lo) ≤ tolerance · lo`. A trial whose solve did not converge is no evidence of
//! failure (`criterion`): it only caps the search (the `ceiling`), never ends the bracket.
//! The search stays within `[MIN_FACTOR, MAX_FACTOR]`: a body still at rest
//! at `MAX_FACTOR` has no mechanism ([`Next::NoMechanism`]), one still failing at
//! `MIN_FACTOR` has no stable factor ([`Next::NoStableFactor`]); neither gets a number.
/// The factors the search, a bracket or a first guess may reach: a strength divided or a
/// weight multiplied by more than 100 is no longer a soil near failure (and overflows the
/// scales of `docs/scenes.md`, 'Limits', long before 1e300).
pub const MIN_FACTOR: f64 = 1e-2;
pub const MAX_FACTOR: f64 = 1e2;

/// Beyond the known side, the next trial multiplies (or divides) by this.
pub const EXPANSION: f64 = 2.0;

/// What steers the next trial ([`Bracket::next_guided`]; `continuation::Planner::guide` makes it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Guide {
    /// The collapse factor extrapolated from the stable trials, if any.
    pub estimate: Option<f64>,
    /// Beyond the largest stable factor with nothing failing and no estimate, the next
    /// trial multiplies it by this.
    pub expansion: f64,
}

/// The trials so far: the largest stable `F` and the smallest failing `F`.
#[derive(Debug, Clone, PartialEq)]
pub struct Bracket {
    pub lo: Option<f64>,
    pub hi: Option<f64>,
    /// The smallest factor whose trial did not converge (below `hi`).
    pub ceiling: Option<f64>,
    tolerance: f64,
    /// Factors to try first (a given bracket's ends, or the first guess).
    pending: Vec<f64>,
    /// Trials whose outcome contradicted an earlier one (a stable `F` above a failing one):
    /// the failing one is kept, so the bracket never widens.
    pub contradictions: Vec<f64>,
    /// The width `upper − lo` before the last guided trial inside the bracket
    /// ([`Bracket::next_guided`]): a guess that did not halve it is followed by a bisection.
    last_width: Option<f64>,
}

/// A width within this relative margin of half the last one counts as halved
/// ([`Bracket::next_guided`]'s crawl test): far above the rounding of a bisection (1e-15),
/// far below any guided trial's shrink.
const HALVED_MARGIN: f64 = 1e-9;

/// What to do next.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Next {
    Try(f64),
    /// `hi − lo ≤ tolerance · lo`.
    Done {
        lo: f64,
        hi: f64,
    },
    /// Between the largest stable factor and the smallest unconverged one no trial failed
    /// by the criterion, and they are within the tolerance: no bracket.
    Unbracketed,
    /// The trial at the search's upper end `up_to` came to rest, and no trial failed: no
    /// mechanism up to `up_to` (a confined body), hence no factor of safety.
    NoMechanism {
        up_to: f64,
    },
    /// The trial at the search's lower end `down_to` failed, and no trial came to rest.
    NoStableFactor {
        down_to: f64,
    },
}

/// What a trial tells the bracket.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    Stable,
    Fails,
    /// Not converged: no evidence either way.
    Unknown,
}

impl Bracket {
    /// From a first guess (one trial) or a given bracket (its two ends, each checked).
    /// The search stays within `[MIN_FACTOR, MAX_FACTOR]` (where the settings keep a
    /// given bracket and the first guess).
    pub fn new(tolerance: f64, first_guess: f64, given: Option<[f64; 2]>) -> Self {
        let pending = match given {
            Some([lo, hi]) => vec![hi, lo],
            None => vec![first_guess],
        };
        Self {
            lo: None,
            hi: None,
            ceiling: None,
            tolerance,
            pending,
            contradictions: Vec::new(),
            last_width: None,
        }
    }

    /// Whether `f` is still worth a trial: strictly inside the current bracket.
    fn open(&self, f: f64) -> bool {
        self.lo.is_none_or(|lo| f > lo) && self.upper().is_none_or(|hi| f < hi)
    }

    /// The lowest factor above which the search need not go.
    fn upper(&self) -> Option<f64> {
        match (self.hi, self.ceiling) {
            (Some(h), Some(c)) => Some(h.min(c)),
            (h, c) => h.or(c),
        }
    }

    /// The next trial, blind: doubling (or halving) beyond the known side, then bisection.
    pub fn next_trial(&mut self) -> Next {
        self.next(None)
    }

    /// The next trial steered by `guide` (`continuation`): the same ends as
    /// [`Bracket::next_trial`] (`Done`, `Unbracketed`, `NoMechanism`, `NoStableFactor`),
    /// the same halving while only failing trials are known, but
    /// - beyond the largest stable `lo` with nothing above: just above the estimate
    ///   (`estimate · (1 + 0.45 tolerance)`), at least `lo · (1 + 0.9 tolerance)` (a
    ///   failure there ends the search) and at most `lo · guide.expansion`; `lo ·
    ///   guide.expansion` without an estimate;
    /// - inside `[lo, upper]`: when one trial can end the search (`lo (1 + tol) ≥ upper /
    ///   (1 + tol)`), the point of that interval nearest the estimate; otherwise just
    ///   below or above the estimate (the side away from the nearer end), but no further
    ///   than the point where the expected outcome leaves a bracket one trial can end
    ///   (`lo (1 + tol)²` above, `upper / (1 + tol)²` below) when the estimate is on the
    ///   same side of it, kept a tenth of the width from either end; the middle without an estimate, or when the last
    ///   guided trial did not halve the width (so the search never crawls).
    pub fn next_guided(&mut self, guide: &Guide) -> Next {
        self.next(Some(guide))
    }

    /// [`Bracket::next_trial`] without a guide, [`Bracket::next_guided`] with one: they
    /// differ only in the two `Try`s above the largest stable factor.
    fn next(&mut self, guide: Option<&Guide>) -> Next {
        while let Some(f) = self.pending.pop() {
            if self.open(f) {
                return Next::Try(f);
            }
        }
        let tol = self.tolerance;
        match (self.lo, self.hi, self.upper()) {
            (Some(lo), Some(hi), _) if hi - lo <= tol * lo => Next::Done { lo, hi },
            (Some(lo), _, Some(up)) if up - lo <= tol * lo => Next::Unbracketed,
            (Some(lo), _, Some(up)) => Next::Try(match guide {
                None => 0.5 * (lo + up),
                Some(g) => self.guided_inside(lo, up, g),
            }),
            (Some(lo), _, None) if lo >= MAX_FACTOR => Next::NoMechanism { up_to: lo },
            (Some(lo), _, None) => {
                let f = match guide {
                    None => lo * EXPANSION,
                    Some(g) => {
                        let far = lo * g.expansion.max(1.0 + tol);
                        let estimate = g.estimate.filter(|e| e.is_finite());
                        estimate.map_or(far, |e| {
                            (e * (1.0 + 0.45 * tol)).clamp(lo * (1.0 + 0.9 * tol), far)
                        })
                    }
                };
                Next::Try(f.min(MAX_FACTOR))
            }
            // Failing at the lower end; an unconverged trial there is no evidence.
            (None, Some(hi), _) if hi <= MIN_FACTOR => Next::NoStableFactor { down_to: hi },
            (None, _, Some(up)) if up <= MIN_FACTOR => Next::Unbracketed,
            (None, _, Some(up)) => Next::Try((up / EXPANSION).max(MIN_FACTOR)),
            // Nothing tried yet and nothing pending cannot happen (`new` queues one).
            (None, _, None) => Next::Try(1.0),
        }
    }

    /// The guided trial inside `[lo, up]` ([`Bracket::next_guided`]).
    fn guided_inside(&mut self, lo: f64, up: f64, guide: &Guide) -> f64 {
        let tol = self.tolerance;
        let estimate = guide.estimate.filter(|e| e.is_finite());
        let width = up - lo;
        // A bisection halves the width exactly, but its rounding can leave it an ulp above
        // half: that is not a crawl (the Tresca cut's trial 7 once turned on it).
        let crawled = self
            .last_width
            .is_some_and(|last| width > 0.5 * last * (1.0 + HALVED_MARGIN));
        self.last_width = Some(width);
        let (a, b) = (up / (1.0 + tol), lo * (1.0 + tol));
        match estimate {
            // Either outcome ends the search.
            _ if a <= b => estimate.map_or(0.5 * (a + b), |e| e.clamp(a, b)),
            Some(e) if !crawled && e > lo && e < up => {
                // Where the expected outcome leaves a bracket one trial can end (a failure
                // at or below `lo (1 + tol)²`, a stable trial at or above `up / (1 +
                // tol)²`): the aim moves there when the estimate is still on the same
                // side of it, saving the trial a near miss costs.
                let aim = if e - lo > up - e {
                    let one_left = up / ((1.0 + tol) * (1.0 + tol)) * (1.0 + 1e-12);
                    let aim = e * (1.0 - 0.45 * tol);
                    if one_left < e {
                        aim.max(one_left)
                    } else {
                        aim
                    }
                } else {
                    let one_left = lo * (1.0 + tol) * (1.0 + tol) * (1.0 - 1e-12);
                    let aim = e * (1.0 + 0.45 * tol);
                    if one_left > e {
                        aim.min(one_left)
                    } else {
                        aim
                    }
                };
                aim.clamp(lo + 0.1 * width, up - 0.1 * width)
            }
            _ => 0.5 * (lo + up),
        }
    }

    /// The outcome of the trial at `f`.
    pub fn record(&mut self, f: f64, outcome: Outcome) {
        if outcome == Outcome::Unknown {
            self.ceiling = Some(self.ceiling.map_or(f, |c| c.min(f)));
            return;
        }
        if outcome == Outcome::Fails {
            if self.lo.is_some_and(|lo| f <= lo) {
                // A failure at or below a stable factor: the bracket restarts below it.
                self.contradictions.push(f);
                self.lo = None;
            }
            self.hi = Some(self.hi.map_or(f, |hi| hi.min(f)));
        } else if self.hi.is_some_and(|hi| f >= hi) {
            self.contradictions.push(f);
        } else {
            self.lo = Some(self.lo.map_or(f, |lo| lo.max(f)));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A search against a known threshold, each trial asked of `next`: failing above
    /// it, unconverged above twice it; the bracket it ends with and its trials.
    fn trials(
        threshold: f64,
        mut b: Bracket,
        mut next: impl FnMut(&mut Bracket) -> Next,
    ) -> (f64, f64, usize) {
        for n in 1..200 {
            match next(&mut b) {
                Next::Try(f) if f > 2.0 * threshold => b.record(f, Outcome::Unknown),
                Next::Try(f) => b.record(
                    f,
                    if f > threshold {
                        Outcome::Fails
                    } else {
                        Outcome::Stable
                    },
                ),
                Next::Done { lo, hi } => return (lo, hi, n - 1),
                other => panic!("{other:?}"),
            }
        }
        panic!("no convergence");
    }

    /// Bisection against a known threshold: every bracket holds it and the last one is
    /// within the tolerance.
    fn search(threshold: f64, tol: f64, first: f64, given: Option<[f64; 2]>) -> (f64, f64, usize) {
        trials(
            threshold,
            Bracket::new(tol, first, given),
            Bracket::next_trial,
        )
    }

    #[test]
    fn brackets_and_bisects_to_the_tolerance() {
        for (threshold, first, given) in [
            (1.38, 1.0, None),
            (0.3, 1.0, None),
            (7.7, 1.0, None),
            (1.38, 1.0, Some([1.2, 1.6])),
            (1.38, 1.0, Some([1.5, 1.9])),
            (1.38, 1.0, Some([0.5, 1.3])),
            (0.45, 1.0, None),
            (1.38, 4.0, None),
        ] {
            let (lo, hi, trials) = search(threshold, 0.005, first, given);
            assert!(lo <= threshold && threshold < hi, "{lo} {hi} {threshold}");
            assert!(hi - lo <= 0.005 * lo);
            assert!(trials < 20, "{trials}");
        }
    }

    #[test]
    fn a_contradiction_never_widens_the_bracket() {
        let mut b = Bracket::new(0.01, 1.0, None);
        b.record(1.0, Outcome::Stable);
        b.record(2.0, Outcome::Fails);
        b.record(1.5, Outcome::Fails);
        b.record(1.8, Outcome::Stable); // above a failure: ignored
        assert_eq!((b.lo, b.hi), (Some(1.0), Some(1.5)));
        assert_eq!(b.contradictions, vec![1.8]);
    }

    /// Trials that do not converge never end the bracket.
    #[test]
    fn unconverged_trials_only_cap_the_search() {
        let mut b = Bracket::new(0.01, 1.0, None);
        b.record(1.0, Outcome::Stable);
        assert_eq!(b.next_trial(), Next::Try(2.0));
        b.record(2.0, Outcome::Unknown);
        assert_eq!(b.next_trial(), Next::Try(1.5));
        b.record(1.5, Outcome::Unknown);
        assert_eq!(b.next_trial(), Next::Try(1.25));
        b.record(1.25, Outcome::Fails);
        assert_eq!(b.hi, Some(1.25));
        // Nothing fails by the criterion between 1 and a ceiling within the tolerance.
        let mut b = Bracket::new(0.01, 1.0, None);
        b.record(1.0, Outcome::Stable);
        b.record(1.005, Outcome::Unknown);
        assert_eq!(b.next_trial(), Next::Unbracketed);
    }

    /// A body that never fails (a confined box) is searched up to `MAX_FACTOR` and no
    /// further, and gets no factor; one that always fails, down to `MIN_FACTOR`.
    #[test]
    fn the_search_ends_at_the_range_without_a_factor() {
        let mut b = Bracket::new(0.005, 1.0, None);
        let mut tried = Vec::new();
        let end = loop {
            match b.next_trial() {
                Next::Try(f) => {
                    tried.push(f);
                    b.record(f, Outcome::Stable);
                }
                other => break other,
            }
        };
        assert_eq!(end, Next::NoMechanism { up_to: MAX_FACTOR });
        assert_eq!(tried.last(), Some(&MAX_FACTOR));
        assert_eq!(tried.len(), 8, "{tried:?}"); // 1, 2, ..., 64, 100
        let mut b = Bracket::new(0.005, 1.0, None);
        let end = loop {
            match b.next_trial() {
                Next::Try(f) => b.record(f, Outcome::Fails),
                other => break other,
            }
        };
        assert_eq!(
            end,
            Next::NoStableFactor {
                down_to: MIN_FACTOR
            }
        );
        // Unconverged all the way down: no evidence, no claim.
        let mut b = Bracket::new(0.005, 1.0, None);
        let end = loop {
            match b.next_trial() {
                Next::Try(f) => b.record(f, Outcome::Unknown),
                other => break other,
            }
        };
        assert_eq!(end, Next::Unbracketed);
        // A threshold just below the upper end is still bracketed.
        let (lo, hi, _) = search(99.0, 0.005, 1.0, None);
        assert!(lo <= 99.0 && 99.0 < hi && hi <= MAX_FACTOR, "{lo} {hi}");
    }

    /// The guided search against a known threshold, with an estimate that is exact,
    /// 3% high, 5% low or nonsense: every bracket holds the threshold and ends within the
    /// tolerance, and a good estimate ends it in fewer trials than bisection.
    fn guided(
        threshold: f64,
        tol: f64,
        estimate: impl Fn(f64) -> Option<f64>,
    ) -> (f64, f64, usize) {
        let guide = Guide {
            estimate: estimate(threshold),
            expansion: 2.0,
        };
        trials(threshold, Bracket::new(tol, 1.0, None), |b| {
            b.next_guided(&guide)
        })
    }

    #[test]
    fn guided_search_keeps_the_bracket_and_its_tolerance() {
        for threshold in [0.45, 1.0, 1.38, 6.69, 40.0] {
            let (_, _, blind) = search(threshold, 0.005, 1.0, None);
            let estimates: [(&str, Box<dyn Fn(f64) -> Option<f64>>); 5] = [
                ("exact", Box::new(Some)),
                ("high", Box::new(|t| Some(1.03 * t))),
                ("low", Box::new(|t| Some(0.95 * t))),
                ("none", Box::new(|_| None)),
                ("nonsense", Box::new(|_| Some(77.0))),
            ];
            for (name, e) in estimates {
                let (lo, hi, trials) = guided(threshold, 0.005, e);
                assert!(
                    lo <= threshold && threshold < hi,
                    "{name}: {lo} {hi} {threshold}"
                );
                assert!(hi - lo <= 0.005 * lo, "{name}: {lo} {hi}");
                assert!(trials < 40, "{name}: {trials}");
                if name == "exact" && threshold > 1.0 {
                    assert!(trials < blind, "{name} {threshold}: {trials} vs {blind}");
                }
            }
        }
    }

    /// The 3D slope's search (`docs/stability.md`, 'Cost'): stable 1.25, failing 1.328, an
    /// estimate 1.2611 from above. Just above the estimate is 1.2639, whose failure would
    /// leave [1.25, 1.2639], more than one trial from the end (the 7th trial of the search
    /// before this rule); the aim is `lo (1 + tol)²` instead, whose failure leaves a
    /// bracket one trial ends. An estimate above that point keeps its aim.
    #[test]
    fn a_near_miss_aims_where_one_trial_is_left() {
        let tol = 0.005;
        let bracket = || {
            let mut b = Bracket::new(tol, 1.0, None);
            b.record(1.25, Outcome::Stable);
            b.record(1.328125, Outcome::Fails);
            b
        };
        let guide = |e: f64| Guide {
            estimate: Some(e),
            expansion: 2.0,
        };
        let Next::Try(f) = bracket().next_guided(&guide(1.2611)) else {
            panic!()
        };
        let one_left = 1.25 * (1.0 + tol) * (1.0 + tol);
        assert!(
            f > 1.2611 && f < one_left && f > one_left * (1.0 - 1e-9),
            "{f}"
        );
        let mut b = bracket();
        let _ = b.next_guided(&guide(1.2611));
        b.record(f, Outcome::Fails);
        let Next::Try(last) = b.next_guided(&guide(1.2611)) else {
            panic!()
        };
        b.record(last, Outcome::Fails);
        // The search's own stopping rule ends it: the trial `one_left` promised.
        let done = b.next_guided(&guide(1.2611));
        assert!(matches!(done, Next::Done { .. }), "{done:?} {b:?}");
        // The estimate above `lo (1 + tol)²`: just above it, as before.
        let Next::Try(f) = bracket().next_guided(&guide(1.27)) else {
            panic!()
        };
        assert_eq!(f, 1.27 * (1.0 + 0.45 * tol));
        // From the other side: stable trials, the estimate near `up`.
        let mut b = Bracket::new(tol, 1.0, None);
        b.record(1.2, Outcome::Stable);
        b.record(1.26, Outcome::Fails);
        let up = 1.26;
        let one_left = up / ((1.0 + tol) * (1.0 + tol));
        let Next::Try(f) = b.next_guided(&guide(1.249)) else {
            panic!()
        };
        assert!(
            f < 1.249 && f > one_left && f < one_left * (1.0 + 1e-9),
            "{f}"
        );
        b.record(f, Outcome::Stable);
        let Next::Try(last) = b.next_guided(&guide(1.249)) else {
            panic!()
        };
        b.record(last, Outcome::Stable);
        let done = b.next_guided(&guide(1.249));
        assert!(matches!(done, Next::Done { .. }), "{done:?} {b:?}");
    }

    /// A bisection is not a crawl, even when its rounding leaves the new width an ulp above
    /// half the old one (`[1.25, 1.348425]` bisected and the middle stable: 0.0492125000000001
    /// against 0.04921249999999999), so the next trial follows the estimate; a guided trial
    /// that shrank the width by less than half is a crawl, and a bisection follows it.
    #[test]
    fn a_bisection_is_not_a_crawl_whatever_its_rounding() {
        let tol = 0.005;
        let guide = |estimate: Option<f64>| Guide {
            estimate,
            expansion: 2.0,
        };
        let (lo, up) = (1.25, 1.348425);
        let mut b = Bracket::new(tol, 1.0, None);
        b.record(lo, Outcome::Stable);
        b.record(up, Outcome::Fails);
        let Next::Try(middle) = b.next_guided(&guide(None)) else {
            panic!()
        };
        assert_eq!(middle, 0.5 * (lo + up));
        b.record(middle, Outcome::Stable);
        assert!(
            up - middle > 0.5 * (up - lo),
            "the rounding this test is about"
        );
        let estimate = middle + 0.3 * (up - middle);
        let Next::Try(f) = b.next_guided(&guide(Some(estimate))) else {
            panic!()
        };
        assert!(
            (f / estimate - 1.0).abs() <= tol,
            "{f}: the estimate {estimate}, not the middle {}",
            0.5 * (middle + up)
        );
        // A crawl: a stable trial just above the bracket's lower end.
        let mut b = Bracket::new(tol, 1.0, None);
        b.record(lo, Outcome::Stable);
        b.record(up, Outcome::Fails);
        let _ = b.next_guided(&guide(Some(1.26)));
        b.record(1.26, Outcome::Stable);
        let Next::Try(f) = b.next_guided(&guide(Some(1.27))) else {
            panic!()
        };
        assert_eq!(f, 0.5 * (1.26 + up));
    }

    /// Unconverged trials cap the guided search as they cap the blind one.
    #[test]
    fn guided_search_never_ends_on_an_unconverged_trial() {
        let guide = Guide {
            estimate: Some(1.5),
            expansion: 2.0,
        };
        let mut b = Bracket::new(0.01, 1.0, None);
        assert_eq!(b.next_guided(&guide), Next::Try(1.0));
        b.record(1.0, Outcome::Stable);
        let Next::Try(f) = b.next_guided(&guide) else {
            panic!()
        };
        assert!((f - 1.5 * (1.0 + 0.45 * 0.01)).abs() < 1e-12, "{f}");
        b.record(f, Outcome::Unknown);
        assert_eq!(b.hi, None);
        b.record(1.005, Outcome::Unknown);
        assert_eq!(b.next_guided(&guide), Next::Unbracketed);
    }
}
