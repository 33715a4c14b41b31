//! The step control: which sub-step size the next solve tries (`docs/solver.md`, 'The step
//! control'). Sizes are `h / 2^level`, so that the sub-steps tile the step exactly. A
//! failed solve halves the size; a size is doubled again after `grow_after` accepted
//! sub-steps whose solves were cheap, at a time the doubled size tiles; a doubling that
//! fails doubles that size's patience, one that holds halves it. The size and the
//! patience carry over from step to step: where the problem was hard, the next steps start
//! small.

/// Patience never exceeds this many sub-steps: a hard stretch that ends is left after at
/// most this many sub-steps at the smaller size.
const MAX_PATIENCE: usize = 64;

/// How the control grows the sub-step back ([`crate::StepSettings::growth`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Growth {
    /// Accepted sub-steps at one size before twice that size is tried (the patience a size
    /// starts with); at least 1.
    pub after: usize,
    /// A sub-step counts toward growth only if its solves took at most this many Newton
    /// iterations in all: an expensive success says the larger size would likely fail.
    pub cheap_iterations: usize,
}

/// What the control remembers between steps (saved in checkpoints through
/// [`crate::StepperMemory`]).
#[derive(Debug, Clone, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct StepControl {
    /// Halvings of the next sub-step: its size is `h / 2^level`.
    pub level: usize,
    /// Cheap accepted sub-steps at this level since it was entered.
    pub streak: usize,
    /// Per level, the cheap accepted sub-steps needed before trying the next larger size
    /// (missing entries: `Growth::after`).
    pub patience: Vec<usize>,
    /// The level the last growth left, while its first sub-step is pending: a failure
    /// there doubles that level's patience.
    pub grown_from: Option<usize>,
}

impl StepControl {
    fn patience(&self, level: usize, growth: &Growth) -> usize {
        self.patience
            .get(level)
            .copied()
            .unwrap_or(growth.after)
            .max(1)
    }

    fn set_patience(&mut self, level: usize, value: usize, growth: &Growth) {
        if self.patience.len() <= level {
            self.patience.resize(level + 1, growth.after.max(1));
        }
        self.patience[level] = value.clamp(1, MAX_PATIENCE);
    }

    /// The sub-step at `position` (in units of `h / 2^max_level`) of a step was accepted
    /// after `iterations` Newton iterations; the next sub-step's level follows.
    pub fn accepted(
        &mut self,
        position: usize,
        iterations: usize,
        max_level: usize,
        growth: &Growth,
    ) {
        if let Some(from) = self.grown_from.take() {
            // The larger size held: trust it sooner next time.
            let p = self.patience(from, growth);
            self.set_patience(from, p / 2, growth);
        }
        if iterations > growth.cheap_iterations {
            self.streak = 0;
            return;
        }
        self.streak += 1;
        let level = self.level;
        // The doubled sub-step must start on its own grid.
        let tiles = level > 0 && position.is_multiple_of(1usize << (max_level - level + 1));
        if tiles && self.streak >= self.patience(level, growth) {
            self.level = level - 1;
            self.streak = 0;
            self.grown_from = Some(level);
        }
    }

    /// A sub-step's solve failed: the next try is half its size. `false` when that would
    /// exceed `max_level` (the step fails).
    pub fn failed(&mut self, max_level: usize, growth: &Growth) -> bool {
        if let Some(from) = self.grown_from.take() {
            // The doubling failed at once: wait longer before the next one.
            let p = self.patience(from, growth);
            self.set_patience(from, 2 * p, growth);
        }
        self.streak = 0;
        if self.level >= max_level {
            return false;
        }
        self.level += 1;
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GROWTH: Growth = Growth {
        after: 2,
        cheap_iterations: 10,
    };

    #[test]
    fn a_failure_halves_and_two_cheap_successes_on_the_grid_double() {
        let mut c = StepControl::default();
        assert!(c.failed(4, &GROWTH));
        assert_eq!(c.level, 1);
        // Position in units of h/16: the first half ends at 8, not on the grid of h.
        c.accepted(8, 5, 4, &GROWTH);
        assert_eq!(c.level, 1);
        c.accepted(16, 5, 4, &GROWTH);
        assert_eq!(c.level, 0, "two cheap sub-steps at h/2, on the grid of h");
    }

    #[test]
    fn expensive_successes_do_not_count() {
        let mut c = StepControl {
            level: 1,
            ..Default::default()
        };
        c.accepted(8, 30, 4, &GROWTH);
        c.accepted(16, 30, 4, &GROWTH);
        assert_eq!(c.level, 1);
        assert_eq!(c.streak, 0);
    }

    #[test]
    fn a_failed_doubling_doubles_the_patience_and_a_held_one_halves_it() {
        let mut c = StepControl {
            level: 1,
            ..Default::default()
        };
        c.accepted(8, 5, 4, &GROWTH);
        c.accepted(16, 5, 4, &GROWTH);
        assert_eq!((c.level, c.grown_from), (0, Some(1)));
        assert!(c.failed(4, &GROWTH));
        assert_eq!(c.patience(1, &GROWTH), 4, "doubled");
        for k in 1..=4 {
            c.accepted(16 + 8 * k, 5, 4, &GROWTH);
        }
        assert_eq!(c.level, 0, "grown again after 4");
        c.accepted(64, 5, 4, &GROWTH);
        assert_eq!(c.patience(1, &GROWTH), 2, "halved when the doubling held");
    }

    #[test]
    fn the_smallest_size_cannot_fail_further() {
        let mut c = StepControl {
            level: 3,
            ..Default::default()
        };
        assert!(!c.failed(3, &GROWTH));
    }
}
