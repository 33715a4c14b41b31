//! The failure criterion of a trial (`docs/stability.md`, 'Failure criterion'): the growth
//! of the displacement increment, at the monitored node or over the body (the largest nodal
//! increment). After the strength drop (or the extra weight) a stable body moves once and
//! comes to rest: its step increments fall by orders of magnitude within a few steps. A
//! failing one has no equilibrium: only the (quasi-static, tiny) inertia resists, so it
//! accelerates and its increments grow step after step.
//!
//! - **stable** as soon as a step's increment is at most `REST · U`, `U` the largest nodal
//!   displacement the loading produced (the body is at rest: round-off moves it by
//!   ~1e-12 to 1e-9 m on the slope, `REST · U` is ~1e-5 m);
//! - **fails** as soon as the increment has not decreased over `GROWTH_STEPS` consecutive
//!   steps while above `REST · U` (accelerating motion, a mechanism);
//! - **not at rest** when neither happened within the trial's steps: counted as failing
//!   (conservative: the factor is bracketed from below by bodies that came to rest);
//! - **not converged** when a step's Newton solve fails even after its halvings: no
//!   evidence either way (a numerical failure is not a mechanism); the bracket only stops
//!   searching above it (`bracket::Outcome::Unknown`) and never ends on it.
//!
//! Each outcome is in `history.csv`.

/// A step moving by at most this fraction of the loading's displacement is at rest.
pub const REST: f64 = 1e-3;
/// Consecutive steps without a decrease that make a mechanism.
pub const GROWTH_STEPS: usize = 2;
/// A trial needs at least this many steps to show growth.
pub const MIN_STEPS: usize = GROWTH_STEPS + 1;

/// How a trial ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// Came to rest.
    Stable,
    /// The increment grew over `GROWTH_STEPS` steps.
    Fails,
    /// Still moving, without sustained growth, after the trial's steps.
    NotAtRest,
    /// A step's solve failed after its halvings.
    NotConverged,
}

impl Verdict {
    /// What the bracket learns from the trial.
    pub fn outcome(&self) -> super::bracket::Outcome {
        use super::bracket::Outcome;
        match self {
            Verdict::Stable => Outcome::Stable,
            Verdict::Fails | Verdict::NotAtRest => Outcome::Fails,
            Verdict::NotConverged => Outcome::Unknown,
        }
    }

    /// Failing by the criterion (not converged is not failing).
    pub fn fails(&self) -> bool {
        matches!(self, Verdict::Fails | Verdict::NotAtRest)
    }

    pub fn name(&self) -> &'static str {
        match self {
            Verdict::Stable => "stable",
            Verdict::Fails => "fails",
            Verdict::NotAtRest => "not_at_rest",
            Verdict::NotConverged => "not_converged",
        }
    }
}

/// The criterion of a scene: where it measures, the scale `U`, and the trial's steps.
#[derive(Debug, Clone, PartialEq)]
pub struct Criterion {
    /// The monitored node; `None`: the largest increment over the body.
    pub node: Option<usize>,
    pub max_steps: usize,
    /// `U` (m), set from the equilibrium state by [`Criterion::set_scale`].
    pub scale: f64,
}

impl Criterion {
    pub fn new(node: Option<usize>, max_steps: usize) -> Self {
        Self {
            node,
            max_steps,
            scale: 0.0,
        }
    }

    /// `U`: the largest nodal displacement of the equilibrium state (m).
    pub fn set_scale<P: AsRef<[f64]>>(&mut self, displacement: &[P]) {
        self.scale = largest(displacement);
    }

    /// The measure of one step's displacement increment (m), nodes of 2 or 3 components.
    pub fn measure<P: AsRef<[f64]>>(&self, increment: &[P]) -> f64 {
        match self.node {
            Some(n) => length(&increment[n]),
            None => largest(increment),
        }
    }

    /// The verdict after the increments so far, if one is due.
    pub fn judge(&self, increments: &[f64]) -> Option<Verdict> {
        let n = increments.len();
        let last = *increments.last()?;
        if last <= REST * self.scale {
            return Some(Verdict::Stable);
        }
        if self.growing(increments) {
            return Some(Verdict::Fails);
        }
        (n >= self.max_steps).then_some(Verdict::NotAtRest)
    }

    /// `GROWTH_STEPS` consecutive steps without a decrease.
    fn growing(&self, increments: &[f64]) -> bool {
        let n = increments.len();
        n > GROWTH_STEPS
            && increments[n - 1 - GROWTH_STEPS..]
                .windows(2)
                .all(|w| w[1] >= w[0])
    }

    /// The verdict when the step after `increments` did not converge.
    pub fn after_failed_step(&self, _increments: &[f64]) -> Verdict {
        Verdict::NotConverged
    }

    /// The criterion in words, for `summary.json`.
    pub fn describe(&self) -> String {
        let at = match self.node {
            Some(n) => format!("at node {n}"),
            None => "largest over the body".into(),
        };
        format!(
            "displacement increment per step ({at}): stable once a step moves by at most \
             {REST:e} of the loading's largest displacement ({:.3e} m), failing once it has \
             not decreased over {GROWTH_STEPS} consecutive steps, or still moving after {} \
             steps; a step not converged after its halvings is no evidence",
            self.scale, self.max_steps
        )
    }
}

/// A nodal vector's length by `hypot`, component after component: a 2D node's is
/// `x.hypot(y)` to the bit (`0.hypot(x) = |x|`), as before 3D.
fn length<P: AsRef<[f64]>>(p: &P) -> f64 {
    p.as_ref().iter().fold(0.0f64, |l, c| l.hypot(*c))
}

fn largest<P: AsRef<[f64]>>(u: &[P]) -> f64 {
    u.iter().fold(0.0f64, |m, d| m.max(length(d)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn criterion() -> Criterion {
        Criterion {
            node: None,
            max_steps: 12,
            scale: 1e-2,
        }
    }

    /// Increments measured on `scenes/slope.toml` (docs/stability.md; F = 1.39 at
    /// `inertia_ratio = 1e-7`, the others at 1e-6).
    #[test]
    fn measured_sequences() {
        let c = criterion();
        let verdict = |seq: &[f64]| {
            (1..=seq.len())
                .find_map(|n| c.judge(&seq[..n]).map(|v| (v, n)))
                .unwrap_or((Verdict::NotAtRest, seq.len()))
        };
        // F = 1.36: at rest at step 3.
        assert_eq!(
            verdict(&[1.31e-2, 7.60e-5, 1.18e-6, 5e-10]),
            (Verdict::Stable, 3)
        );
        // F = 1.39: moves 0.4 m, then stops at step 7.
        let f139 = [
            1.09e-1, 1.04e-1, 8.96e-2, 5.56e-2, 2.60e-2, 5.51e-3, 1.95e-6,
        ];
        assert_eq!(verdict(&f139), (Verdict::Stable, 7));
        // F = 1.40: accelerates.
        assert_eq!(
            verdict(&[2.82e-1, 4.56e-1, 6.69e-1, 9.75e-1]),
            (Verdict::Fails, 3)
        );
        // Round-off growth below the rest level is rest, not failure.
        assert_eq!(verdict(&[1.6e-12, 8.7e-11, 2.5e-10]), (Verdict::Stable, 1));
        // Slow decay that never reaches rest.
        let slow: Vec<f64> = (0..12).map(|k| 0.1 * 0.9f64.powi(k)).collect();
        assert_eq!(verdict(&slow), (Verdict::NotAtRest, 12));
    }
}
