use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use nalgebra::SMatrix;
use talus_bipotential::{DruckerPrager, FlowRule};

use crate::boundary::{GridBoundary, NodeCondition, Side};
use crate::error::MpmError;
use crate::grid::Grid;
use crate::particles::Particles;
use crate::settings::MpmSettings;
use crate::step::{StepContext, SubstepError};

/// What one step did (all its sub-steps together).
#[derive(Debug, Clone, PartialEq)]
pub struct StepReport {
    /// The step asked for (s).
    pub h: f64,
    /// Sub-steps taken: 1 unless a failed solve split the step, or the step started at a
    /// remembered sub-step size (`MpmSettings::halving_memory`).
    pub substeps: usize,
    pub smallest_h: f64,
    /// Newton iterations over all sub-steps (failed attempts before a halving included),
    /// and the most in one converged sub-step.
    pub newton_iterations: usize,
    pub max_newton_iterations: usize,
    /// `‖F‖∞ / max(1, ‖σ‖∞)` reached by the last sub-step.
    pub residual: f64,
    /// Grid nodes carrying mass, and free velocity components, in the last sub-step.
    pub active_nodes: usize,
    pub free_dofs: usize,
    /// Force each wall, then each prescribed-velocity box, applies to the material in the
    /// last sub-step (N/m): `M a + Bᵀσ − f` on its nodes, friction included.
    pub group_forces: Vec<[f64; 2]>,
    /// Wall time of the whole step, and of its Newton solves (s).
    pub seconds: f64,
    pub solve_seconds: f64,
    /// Most solves one sub-step took to settle the friction walls' stick/slide states.
    pub contact_passes: usize,
    /// Newton iterations of the converged sub-steps' first friction pass (all of them
    /// without friction walls), and line-search backtracks: of those first passes, and of
    /// all passes.
    pub first_pass_iterations: usize,
    pub first_pass_backtracks: usize,
    pub backtracks: usize,
    /// Friction passes after the first that kept the first pass's Schur analysis (same
    /// pattern): every later pass of every sub-step, unless the pattern changed.
    pub reused_analyses: usize,
}

/// The implicit MPM: a grid with its boundary conditions, one Drucker-Prager material,
/// gravity, and settings. [`Mpm::advance`] moves a [`Particles`] set by one step.
#[derive(Debug, Clone)]
pub struct Mpm {
    grid: Grid,
    boundary: GridBoundary,
    conditions: Vec<NodeCondition>,
    flow_rule: FlowRule<4>,
    compliance: SMatrix<f64, 4, 4>,
    gravity: [f64; 2],
    settings: MpmSettings,
    /// Friction passes after the first keep its Schur analysis (true, the default) or
    /// build a new solver each (to check that both give the same step).
    reuse_analysis: bool,
    memory: HalvingMemory,
}

/// The sub-step level the next step starts at, and the steps taken at it without a
/// halving (`MpmSettings::halving_memory`). Atomics: `advance` takes `&self`.
#[derive(Debug, Default)]
struct HalvingMemory {
    level: AtomicUsize,
    clean_steps: AtomicUsize,
}

impl Clone for HalvingMemory {
    fn clone(&self) -> Self {
        Self {
            level: AtomicUsize::new(self.level.load(Ordering::Relaxed)),
            clean_steps: AtomicUsize::new(self.clean_steps.load(Ordering::Relaxed)),
        }
    }
}

impl Mpm {
    /// `gravity` in m/s².
    pub fn try_new(
        grid: Grid,
        boundary: GridBoundary,
        material: &DruckerPrager,
        gravity: [f64; 2],
        settings: MpmSettings,
    ) -> Result<Self, MpmError> {
        boundary.validate()?;
        if !gravity.iter().all(|g| g.is_finite()) {
            return Err(MpmError::invalid(
                "gravity",
                format!("{gravity:?} must be finite"),
            ));
        }
        let a = settings.flip_ratio;
        if !(0.0..=1.0).contains(&a) {
            return Err(MpmError::invalid(
                "flip_ratio",
                format!("{a} must be in [0, 1] (0 = PIC, 1 = FLIP)"),
            ));
        }
        if let Some(t) = settings.flip_reference_time {
            if !(t.is_finite() && t > 0.0) {
                return Err(MpmError::invalid(
                    "flip_reference_time",
                    format!("{t} s must be finite and > 0"),
                ));
            }
        }
        let sides: Vec<Side> = boundary.walls.iter().map(|w| w.side).collect();
        let grid = grid.with_walls(&sides);
        Ok(Self {
            conditions: boundary.node_conditions(&grid),
            grid,
            boundary,
            flow_rule: material.flow_rule::<4>(),
            compliance: material.compliance::<4>(),
            gravity,
            settings,
            reuse_analysis: true,
            memory: HalvingMemory::default(),
        })
    }

    /// Whether friction passes after the first keep its Schur analysis (default true). The
    /// result is the same bit for bit either way; false rebuilds the solver every pass.
    pub fn set_analysis_reuse(&mut self, reuse: bool) {
        self.reuse_analysis = reuse;
    }

    /// Halvings the next step starts with (`MpmSettings::halving_memory`): 0 = full h.
    pub fn remembered_halvings(&self) -> usize {
        self.memory.level.load(Ordering::Relaxed)
    }

    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    pub fn boundary(&self) -> &GridBoundary {
        &self.boundary
    }

    pub fn settings(&self) -> &MpmSettings {
        &self.settings
    }

    /// One step of `h` (s). A sub-step whose Newton solve fails is redone as two halves,
    /// down to `h / 2^max_step_halvings`; past that the step fails with
    /// [`MpmError::NotConverged`] and `particles` is left as before the step. With
    /// `halving_memory > 0` the step starts at the sub-step size the last halved step
    /// converged with (see [`MpmSettings::halving_memory`]).
    pub fn advance(&self, particles: &mut Particles, h: f64) -> Result<StepReport, MpmError> {
        if !(h.is_finite() && h > 0.0) {
            return Err(MpmError::invalid(
                "h",
                format!("{h} s must be finite and > 0"),
            ));
        }
        particles.validate()?;
        let start = Instant::now();
        let mut report = StepReport {
            h,
            substeps: 0,
            smallest_h: h,
            newton_iterations: 0,
            max_newton_iterations: 0,
            residual: 0.0,
            active_nodes: 0,
            free_dofs: 0,
            group_forces: Vec::new(),
            seconds: 0.0,
            solve_seconds: 0.0,
            contact_passes: 0,
            first_pass_iterations: 0,
            first_pass_backtracks: 0,
            backtracks: 0,
            reused_analyses: 0,
        };
        // Start at the sub-step the last halved step converged with (its failed attempts
        // at larger sizes would most likely fail again), still within max_step_halvings.
        let remember = self.settings.halving_memory > 0;
        let level = if remember {
            self.remembered_halvings()
                .min(self.settings.max_step_halvings)
        } else {
            0
        };
        let mut trial = particles.clone();
        let parts = 1usize << level;
        for _ in 0..parts {
            self.advance_level(&mut trial, h / parts as f64, level, &mut report)?;
        }
        *particles = trial;
        if remember {
            let deepest = (h / report.smallest_h).log2().round() as usize;
            let m = &self.memory;
            if deepest > level {
                m.level.store(deepest, Ordering::Relaxed);
                m.clean_steps.store(0, Ordering::Relaxed);
            } else if m.clean_steps.fetch_add(1, Ordering::Relaxed) + 1
                >= self.settings.halving_memory
            {
                m.level.store(level.saturating_sub(1), Ordering::Relaxed);
                m.clean_steps.store(0, Ordering::Relaxed);
            }
        }
        report.seconds = start.elapsed().as_secs_f64();
        Ok(report)
    }

    fn advance_level(
        &self,
        particles: &mut Particles,
        h: f64,
        level: usize,
        report: &mut StepReport,
    ) -> Result<(), MpmError> {
        let context = StepContext {
            grid: &self.grid,
            conditions: &self.conditions,
            n_groups: self.boundary.n_groups(),
            flow_rule: &self.flow_rule,
            compliance: &self.compliance,
            gravity: self.gravity,
            settings: &self.settings,
            reuse_analysis: self.reuse_analysis,
        };
        let mut trial = particles.clone();
        match context.substep(&mut trial, h) {
            Ok(outcome) => {
                *particles = trial;
                let r = &outcome.report;
                if let Some(floor) = r.round_off_floor {
                    tracing::warn!(
                        h,
                        residual = floor.reached / r.scale,
                        floor_estimate = floor.estimate / r.scale,
                        "MPM step accepted at the round-off floor, above the tolerance"
                    );
                }
                report.substeps += 1;
                report.smallest_h = report.smallest_h.min(h);
                report.newton_iterations += r.iterations;
                report.max_newton_iterations = report.max_newton_iterations.max(r.iterations);
                report.residual = r.residual / r.scale;
                report.active_nodes = outcome.active_nodes;
                report.free_dofs = outcome.free_dofs;
                report.group_forces = outcome.group_forces;
                report.solve_seconds += outcome.solve_seconds;
                report.contact_passes = report.contact_passes.max(outcome.contact_passes);
                report.first_pass_iterations += outcome.first_pass_iterations;
                report.first_pass_backtracks += outcome.first_pass_backtracks;
                report.backtracks += outcome.backtracks;
                report.reused_analyses += outcome.reused_analyses;
                Ok(())
            }
            Err(SubstepError::NotConverged(r)) => {
                // The failed attempt's work counts too.
                report.newton_iterations += r.iterations;
                report.backtracks += r.backtracks;
                report.solve_seconds += r.seconds;
                if level >= self.settings.max_step_halvings {
                    return Err(MpmError::NotConverged {
                        h,
                        halvings: level,
                        status: r.status,
                        iterations: r.iterations,
                        residual: r.residual / r.scale,
                    });
                }
                tracing::warn!(h, status = %r.status, "MPM step did not converge: halving h");
                self.advance_level(particles, 0.5 * h, level + 1, report)?;
                self.advance_level(particles, 0.5 * h, level + 1, report)
            }
            Err(SubstepError::Fatal(e)) => Err(e),
        }
    }
}
