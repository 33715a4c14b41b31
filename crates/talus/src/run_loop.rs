//! The one run loop of `talus run`, FEM and MPM alike: step to the end with the engine,
//! one `history.csv` row per step (the common columns, then the method's own), the fields
//! due after each step, and the end-of-run files even when a step fails.
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::run::{io_err, progress_bar, RunError};
use crate::simulation::engine::{Discretization, StepError, StepReport, Stepper};

/// The columns every `history.csv` starts with (`docs/scenes.md`, 'Outputs'). `residual`
/// is `‖F‖∞` of the step's last solve; `relative_residual` is it over `max(1, ‖σ‖∞)`, the
/// quantity compared with `[solver] tolerance`.
pub const HISTORY_COLUMNS: &str = "step,time,h,substeps,newton_iterations,failed_newton_iterations,max_newton_iterations,backtracks,residual,relative_residual,seconds";

/// What a method adds to the run loop: its columns, its files, its progress message.
pub trait RunOutputs<D: Discretization> {
    /// Column names after [`HISTORY_COLUMNS`].
    fn columns(&self) -> Vec<String>;
    /// The values of those columns for `state` (after `report`'s step; `None` at step 0).
    fn values(&mut self, state: &D::State, report: Option<&StepReport<D::Stats>>) -> Vec<f64>;
    /// The fields due after `step` (0: the initial state).
    fn after_step(&mut self, step: usize, state: &D::State) -> Result<(), RunError>;
    /// A short status for the progress bar.
    fn message(&self, report: &StepReport<D::Stats>, values: &[f64]) -> String;
    /// The end-of-run files (collections, plots), finished or not.
    fn finish(
        &mut self,
        state: &D::State,
        reports: &[StepReport<D::Stats>],
    ) -> Result<(), RunError>;
}

/// What the run loop returns: every step's report, the last state, and the step that
/// failed (the files written before it are kept).
pub struct Stepped<D: Discretization> {
    pub reports: Vec<StepReport<D::Stats>>,
    pub state: D::State,
    pub failure: Option<(usize, StepError<D::Error>)>,
}

/// Steps `state` `steps` times by `h`, writing `out/history.csv` and what `outputs` asks.
pub fn run_steps<D: Discretization, O: RunOutputs<D>>(
    stepper: &mut Stepper<D>,
    mut state: D::State,
    steps: usize,
    h: f64,
    out: &Path,
    outputs: &mut O,
    progress: bool,
) -> Result<Stepped<D>, RunError> {
    std::fs::create_dir_all(out).map_err(io_err(out))?;
    let mut history = History::create(out.join("history.csv"), &outputs.columns())?;
    let values = outputs.values(&state, None);
    history.row::<D::Stats>(0, stepper.discretization().time(&state), None, &values)?;
    outputs.after_step(0, &state)?;
    let bar = progress_bar(steps, progress);
    let mut reports = Vec::new();
    let mut failure = None;
    for step in 1..=steps {
        let report = match stepper.advance(&mut state, h) {
            Ok(r) => r,
            Err(e) => {
                failure = Some((step, e));
                break;
            }
        };
        let values = outputs.values(&state, Some(&report));
        history.row(step, report.time, Some(&report), &values)?;
        tracing::info!(
            step,
            time = report.time,
            iterations = report.newton_iterations,
            substeps = report.substeps,
            residual = report.relative_residual,
            "step"
        );
        if let Some(bar) = &bar {
            bar.set_message(outputs.message(&report, &values));
            bar.inc(1);
        }
        outputs.after_step(step, &state)?;
        reports.push(report);
    }
    if let Some(bar) = bar {
        bar.finish();
    }
    outputs.finish(&state, &reports)?;
    Ok(Stepped {
        reports,
        state,
        failure,
    })
}

/// `history.csv`, flushed after every row so that an interrupted run keeps its rows.
struct History {
    path: PathBuf,
    writer: std::io::BufWriter<std::fs::File>,
}

impl History {
    fn create(path: PathBuf, columns: &[String]) -> Result<Self, RunError> {
        let file = std::fs::File::create(&path).map_err(io_err(&path))?;
        let mut history = Self {
            writer: std::io::BufWriter::new(file),
            path,
        };
        let mut header = HISTORY_COLUMNS.to_string();
        for c in columns {
            header.push(',');
            header.push_str(c);
        }
        history.line(header)?;
        Ok(history)
    }

    fn row<S>(
        &mut self,
        step: usize,
        time: f64,
        report: Option<&StepReport<S>>,
        values: &[f64],
    ) -> Result<(), RunError> {
        let mut line = match report {
            Some(r) => format!(
                "{step},{time:.10e},{:.10e},{},{},{},{},{},{:.6e},{:.6e},{:.6e}",
                r.h,
                r.substeps,
                r.newton_iterations,
                r.failed_newton_iterations,
                r.max_newton_iterations,
                r.backtracks,
                r.residual,
                r.relative_residual,
                r.seconds
            ),
            None => format!("{step},{time:.10e},0,0,0,0,0,0,0,0,0"),
        };
        for v in values {
            line.push_str(&format!(",{v:.10e}"));
        }
        self.line(line)
    }

    fn line(&mut self, line: String) -> Result<(), RunError> {
        writeln!(self.writer, "{line}")
            .and_then(|_| self.writer.flush())
            .map_err(io_err(&self.path))
    }
}
