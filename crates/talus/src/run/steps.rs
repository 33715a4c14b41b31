//! The one run loop of `talus run`, FEM and MPM alike: step to the end with the engine's
//! [`Run`] (the stepper and its collapse watch),
//! one `history.csv` row per step (the common columns, then the method's own), the fields
//! due after each step, and the end-of-run files even when a step fails.
use std::io::Write;
use std::path::{Path, PathBuf};

use talus_engine::{
    CollapseWatch, Discretization, Failed, Run, StepError, StepReport, StepSettings, Stepper,
};

use super::checkpoint::{self, Checkpoint, Plan, SceneRecord};
use super::{folder, io_err, progress_bar, RunError, RunOptions, StepProgress};
use crate::output::{CollapseTime, Results, RunStatus};

/// The columns every `history.csv` starts with (`docs/scenes.md`, 'Outputs'). `residual`
/// is `‖F‖∞` of the step's last solve; `relative_residual` is it over `max(1, ‖σ‖∞)`, the
/// quantity compared with `[solver] tolerance`.
pub const HISTORY_COLUMNS: &str = "step,time,h,substeps,newton_iterations,failed_newton_iterations,max_newton_iterations,backtracks,residual,relative_residual,seconds";

/// What a method adds to the run loop: its columns, its files, its progress message, and
/// the named boundaries and monitors of `summary.json`.
pub trait RunOutputs<D: Discretization<N>, const N: usize = 4> {
    /// `,name,...`: the columns after [`HISTORY_COLUMNS`].
    fn columns(&self) -> String;
    /// `,value,...`: those columns for `state` after `report`'s step (`None`: step 0).
    fn row(
        &mut self,
        step: usize,
        state: &D::State,
        report: Option<&StepReport<D::Stats>>,
    ) -> String;
    /// The fields due after `step` (0: the initial state).
    fn after_step(&mut self, step: usize, state: &D::State) -> Result<(), RunError>;
    /// A short status for the progress bar.
    fn message(&self, report: &StepReport<D::Stats>, state: &D::State) -> String;
    /// The end-of-run files (collections, plots), finished or not, after `step`.
    fn finish(&mut self, state: &D::State, step: usize) -> Result<(), RunError>;
    /// The reactions, monitors and reported curve recorded so far.
    fn results(&self) -> &Results;
    /// What the outputs recorded so far (curves, collection, counters), for a checkpoint.
    fn save(&self) -> serde_json::Value;
    /// Continues from what [`RunOutputs::save`] returned after `step`: also removes the
    /// files of later steps and rewrites the collections as they were then.
    fn restore(&mut self, saved: serde_json::Value, step: usize) -> Result<(), RunError>;
    /// The state the next step starts from, after `step`, when the run does not start at
    /// step 0 (resumed, or a staged run's next stage): e.g. for the increments of the
    /// next step's fields.
    fn begin(&mut self, _step: usize, _state: &D::State) {}
}

/// Where [`run_steps`] starts.
pub enum Begin<S> {
    /// Step 0 from this state: `history.csv` and the step-0 fields written afresh, the
    /// files an earlier run left in the folder (its checkpoint among them) removed first
    /// (`folder::clear_owned`).
    Fresh(S),
    /// After the span's first step from this state, the outputs of the steps before it
    /// kept: the next stage of a staged run (`super::stages`).
    Continue(S),
    /// After a checkpoint's step, the folder's outputs cut back to it (`talus resume`).
    Resumed(Box<Checkpoint<S>>),
}

impl<S> Begin<S> {
    /// How often the run checkpoints: the resumed run's plan, or `options.checkpoint_every`
    /// with the scene at `path` whose text is `source`.
    fn plan(&self, path: Option<&Path>, source: &str, options: &RunOptions) -> Option<Plan> {
        // Under `mpirun` rank 0 alone checkpoints; the others resume from its checkpoint.
        if !crate::ranks::ranks().is_root() {
            return None;
        }
        match self {
            Self::Resumed(c) => Some(Plan {
                every: c.every,
                scene: c.scene.clone(),
            }),
            Self::Fresh(_) | Self::Continue(_) => (options.checkpoint_every > 0).then(|| Plan {
                every: options.checkpoint_every,
                scene: SceneRecord::new(path, source),
            }),
        }
    }
}

/// The steps a call of [`run_steps`] takes: `from + 1 ..= to` of a run of `total` (one
/// stage of a staged run, or the whole run: `from = 0`, `to = total`).
#[derive(Debug, Clone, Copy)]
pub struct Span {
    pub from: usize,
    pub to: usize,
    pub total: usize,
    /// A staged run's stage: reaching `to`, the run loop leaves `summary.json` and
    /// [`RunOutputs::finish`] to its caller, which adds the stage's entry first and ends
    /// the files only at the run's end. A stop before `to` (failure, collapse,
    /// interruption) ends the run here as any other.
    pub stage: bool,
}

impl Span {
    pub fn whole(steps: usize) -> Self {
        Self {
            from: 0,
            to: steps,
            total: steps,
            stage: false,
        }
    }
}

/// What the run loop returns when the run was neither interrupted nor collapsed: every
/// step's report, the last state, and the step that failed (the files written before it
/// are kept).
pub struct Stepped<D: Discretization<N>, const N: usize = 4> {
    pub reports: Vec<StepReport<D::Stats>>,
    pub state: D::State,
    pub failure: Option<(usize, StepError<D::Error>)>,
}

/// Steps from `begin` through `span` by `h`, writing `out/history.csv`, what `outputs`
/// asks, a checkpoint every `options.checkpoint_every` steps (a resumed run: its own
/// plan; and at an interruption) of the scene at `scene_path` with text `scene_source`,
/// and `out/summary.json` at the end, finished or failed (a stage that reaches its end:
/// by its caller, [`Span::stage`]). The observer's `Break` (the
/// binary's SIGINT/SIGTERM among them) stops it after the step in progress:
/// `RunError::Interrupted`; a collapse ends it with `RunError::Collapsed`. The folder is
/// held ([`folder::lock`]) until it returns; a resume it refuses (another run holds the
/// folder, a `history.csv` that does not reach the checkpoint, outputs it cannot restore)
/// is refused before any file is touched.
#[allow(clippy::too_many_arguments)]
pub fn run_steps<D, O, const N: usize>(
    stepper: &mut Stepper<D, N>,
    begin: Begin<D::State>,
    span: Span,
    h: f64,
    outputs: &mut O,
    options: &RunOptions,
    scene_path: Option<&Path>,
    scene_source: &str,
) -> Result<Stepped<D, N>, RunError>
where
    D: Discretization<N>,
    D::State: serde::Serialize,
    O: RunOutputs<D, N>,
{
    let steps = span.total;
    let out: &Path = &options.out_dir;
    // No other run or resume writes here meanwhile (the `talus` binary holds the folder
    // for its whole command: this takes the same lock again). The lock creates the folder,
    // and removes it again if it stays empty.
    let _lock = folder::lock(out)?;
    let summary_path = out.join("summary.json");
    let history_path = out.join("history.csv");
    let mut begin = begin;
    // What can refuse a resume is read before anything is written: the rows it keeps,
    // and the listed files that still exist.
    let resumed = match &mut begin {
        Begin::Resumed(c) => Some(Resuming {
            kept: checkpoint::history_prefix(&history_path, c.step)?,
            // Under `mpirun` the snapshots are in rank 0's folder, whichever rank reads
            // the list (`run/pieces.rs`): every rank keeps the same list.
            files: checkpoint::keep_existing_files(crate::run::pieces::folder(out), &mut c.outputs)
                .into(),
        }),
        Begin::Fresh(_) | Begin::Continue(_) => None,
    };
    check_writable(out)?;
    let plan = begin.plan(scene_path, scene_source, options);
    let plan = plan.as_ref();
    let (mut run, mut state, first) = match begin {
        Begin::Fresh(state) => {
            // Stale files of an earlier run (VTUs of later steps, its checkpoint) would
            // not match the new ones.
            folder::clear_owned(out)?;
            // Under `mpirun` no rank writes its piece of step 0's VTU into rank 0's folder
            // before rank 0 has cleared it, nor into a folder that is not rank 0's.
            super::pieces::check_shared_folder()?;
            let mut history = History::create(history_path, &outputs.columns())?;
            let row = outputs.row(0, &state, None);
            history.row::<D::Stats>(0, stepper.discretization().time(&state), None, &row)?;
            outputs.after_step(0, &state)?;
            (Run::start(stepper, &state), state, 1)
        }
        Begin::Continue(state) => {
            let _ = std::fs::remove_file(&summary_path);
            outputs.begin(span.from, &state);
            (Run::start(stepper, &state), state, span.from + 1)
        }
        Begin::Resumed(c) => {
            let c = *c;
            let Resuming { kept, files } = resumed.unwrap_or_default();
            // Refused, if at all, before it removes or writes a file.
            outputs.restore(c.outputs, c.step)?;
            files.report(out);
            checkpoint::write_history(&history_path, &kept)?;
            let _ = std::fs::remove_file(&summary_path);
            outputs.begin(c.step, &c.state);
            stepper.restore_memory(c.stepper);
            tracing::info!(step = c.step, "resumed from the checkpoint");
            (Run::resume(stepper, c.watch), c.state, c.step + 1)
        }
    };
    let mut history = History::append(out.join("history.csv"))?;
    let bar = progress_bar(steps, options.progress);
    if let Some(bar) = &bar {
        bar.set_position(first as u64 - 1);
    }
    let mut reports = Vec::new();
    let mut failure = None;
    let mut collapse = None;
    let mut last_checkpoint = None;
    let save = |step: usize,
                state: &D::State,
                stepper: &Stepper<D, N>,
                watch: &CollapseWatch,
                outputs: &O|
     -> Result<(), RunError> {
        let Some(plan) = plan else { return Ok(()) };
        let clock = std::time::Instant::now();
        checkpoint::write(
            out,
            &Checkpoint {
                talus: checkpoint::WRITER.to_string(),
                scene: plan.scene.clone(),
                every: plan.every,
                step,
                steps,
                h,
                state,
                stepper: stepper.memory(),
                watch: watch.clone(),
                outputs: outputs.save(),
            },
        )?;
        tracing::info!(
            step,
            seconds = clock.elapsed().as_secs_f64(),
            "checkpoint written"
        );
        Ok(())
    };
    let mut interrupted = None;
    let mut iterations_so_far = 0;
    for step in first..=span.to {
        let (report, collapsed) = match run.step(&mut state, step, h) {
            Ok(r) => r,
            Err(Failed {
                step,
                error,
                collapse: c,
            }) => {
                collapse = c;
                failure = Some((step, error));
                break;
            }
        };
        let row = outputs.row(step, &state, Some(&report));
        let failed = |e| output_failed(&*outputs, &summary_path, steps, step, e);
        history
            .row(step, report.time, Some(&report), &row)
            .map_err(failed)?;
        // A line per step at debug level (`talus run -v`, `TALUS_LOG=debug`); at info, one
        // per tenth of the run, with the cost so far, so that a piped log stays readable.
        tracing::debug!(
            step,
            time = report.time,
            iterations = report.newton_iterations,
            substeps = report.substeps,
            residual = report.relative_residual,
            "step"
        );
        iterations_so_far += report.total_newton_iterations();
        if step == span.to || step % steps.div_ceil(10).max(1) == 0 {
            tracing::info!(
                "step {step}/{steps} ({}%), t = {:.6e} s, {} Newton iterations so far, last \
                 relative residual {:.2e}",
                100 * step / steps.max(1),
                report.time,
                iterations_so_far,
                report.relative_residual
            );
        }
        if let Some(bar) = &bar {
            bar.set_message(outputs.message(&report, &state));
            bar.inc(1);
        }
        outputs
            .after_step(step, &state)
            .map_err(|e| output_failed(&*outputs, &summary_path, steps, step, e))?;
        let stop = options.observer.as_ref().is_some_and(|observe| {
            let progress = StepProgress {
                step,
                steps,
                time: report.time,
                newton_iterations: report.newton_iterations,
                substeps: report.substeps,
                relative_residual: report.relative_residual,
                message: outputs.message(&report, &state),
            };
            observe(&progress).is_break()
        });
        reports.push(report);
        if collapsed.is_some() {
            collapse = collapsed;
            break;
        }
        if plan.is_some_and(|p| step % p.every == 0) {
            save(step, &state, run.stepper, &run.watch, outputs)
                .map_err(|e| output_failed(&*outputs, &summary_path, steps, step, e))?;
            last_checkpoint = Some(step);
        }
        if stop {
            interrupted = Some(step);
            break;
        }
    }
    if let Some(bar) = bar {
        bar.finish();
    }
    // An interrupted run is resumed from where it stopped, not from its last checkpoint.
    if let Some(step) = interrupted.filter(|&s| last_checkpoint != Some(s) && s >= first) {
        save(step, &state, run.stepper, &run.watch, outputs)?;
    }
    if span.stage && failure.is_none() && collapse.is_none() && interrupted.is_none() {
        return Ok(Stepped {
            reports,
            state,
            failure,
        });
    }
    let last_step = match (&failure, interrupted) {
        (_, Some(step)) => step,
        (Some((step, _)), None) => step - 1,
        (None, None) => first - 1 + reports.len(),
    };
    outputs.finish(&state, last_step)?;
    let (status, error) = match (&failure, &collapse) {
        _ if interrupted.is_some() => (RunStatus::Interrupted, None),
        (_, Some(c)) => (RunStatus::Collapsed, Some(c.to_string())),
        (None, None) => (RunStatus::Finished, None),
        (Some((step, e)), None) => match e {
            StepError::NotConverged { residual, .. } => {
                let advice = advice(run.stepper.settings(), h, *residual);
                tracing::warn!("step {step} did not converge; {advice}");
                (
                    RunStatus::NotConverged,
                    Some(format!("step {step}: {e}; {advice}")),
                )
            }
            _ => (RunStatus::Failed, Some(format!("step {step}: {e}"))),
        },
    };
    let mut summary = outputs.results().summary(status, error, steps);
    summary.collapse = collapse.as_ref().map(|c| CollapseTime {
        step: c.step,
        time: c.time,
    });
    summary.write(&summary_path)?;
    tracing::info!("{}", summary.sentence());
    if let Some(step) = interrupted {
        let time = run.stepper.discretization().time(&state);
        return Err(RunError::Interrupted { step, time });
    }
    if let Some(c) = collapse {
        return Err(RunError::Collapsed(c));
    }
    Ok(Stepped {
        reports,
        state,
        failure,
    })
}

/// What a resume read before touching the folder: `history.csv` up to the checkpoint's
/// row, and the files of its collection found missing.
#[derive(Default)]
struct Resuming {
    kept: String,
    files: ListedFiles,
}

/// The files the checkpoint's collection listed that are no longer on disk (e.g. `vtu/`
/// removed), and how many are left listed.
#[derive(Default)]
struct ListedFiles {
    missing: Vec<String>,
    left: usize,
}

impl From<(Vec<String>, usize)> for ListedFiles {
    fn from((missing, left): (Vec<String>, usize)) -> Self {
        Self { missing, left }
    }
}

impl ListedFiles {
    /// Warns of the files dropped from `solution.pvd`; with none left, the collection the
    /// restore did not rewrite (it lists only missing files) is removed until the next VTU
    /// writes it.
    fn report(&self, out: &Path) {
        let Some(first) = self.missing.first() else {
            return;
        };
        tracing::warn!(
            "{} file(s) of the checkpoint's solution.pvd are missing from {} ({first}{}): \
             the resumed solution.pvd lists only the files on disk",
            self.missing.len(),
            out.display(),
            if self.missing.len() > 1 { ", ..." } else { "" }
        );
        if self.left == 0 {
            let _ = std::fs::remove_file(out.join("solution.pvd"));
        }
    }
}

/// What to try after a step that did not converge even halved: the knobs of the scene and
/// their values (`docs/solver.md` says what each costs).
fn advice(settings: &StepSettings, h: f64, residual: f64) -> String {
    format!(
        "what to try: a smaller [time] step (now {h:e} s), more [solver] max_step_halvings \
         (now {}), more [solver] max_iterations (now {}), or a looser [solver] tolerance \
         (now {:e}; the last attempt reached {residual:.2e})",
        settings.max_halvings, settings.solver.max_iterations, settings.solver.tolerance
    )
}

/// A file of step `step` could not be written (a full disk, a removed folder): the run
/// stops, but `summary.json` still says why if it fits (it is small; the failed file's
/// temporary copy was removed), so that the folder tells the same story as the exit code.
fn output_failed<D: Discretization<N>, O: RunOutputs<D, N>, const N: usize>(
    outputs: &O,
    summary_path: &Path,
    steps: usize,
    step: usize,
    e: RunError,
) -> RunError {
    let why = Some(format!("step {step}: {e}"));
    let summary = outputs.results().summary(RunStatus::Failed, why, steps);
    if let Err(w) = summary.write(summary_path) {
        tracing::warn!(error = %w, "summary.json not written either");
    }
    e
}

/// `history.csv`, flushed after every row so that an interrupted run keeps its rows.
struct History {
    path: PathBuf,
    writer: std::io::BufWriter<std::fs::File>,
}

impl History {
    fn create(path: PathBuf, columns: &str) -> Result<Self, RunError> {
        let file = std::fs::File::create(&path).map_err(io_err(&path))?;
        let mut history = Self {
            writer: std::io::BufWriter::new(file),
            path,
        };
        history.line(format!("{HISTORY_COLUMNS}{columns}"))?;
        Ok(history)
    }

    /// The rows of later steps go after the existing ones.
    fn append(path: PathBuf) -> Result<Self, RunError> {
        let file = std::fs::OpenOptions::new()
            .append(true)
            .open(&path)
            .map_err(io_err(&path))?;
        Ok(Self {
            writer: std::io::BufWriter::new(file),
            path,
        })
    }

    fn row<S>(
        &mut self,
        step: usize,
        time: f64,
        report: Option<&StepReport<S>>,
        rest: &str,
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
        line.push_str(rest);
        self.line(line)
    }

    fn line(&mut self, line: String) -> Result<(), RunError> {
        writeln!(self.writer, "{line}")
            .and_then(|_| self.writer.flush())
            .map_err(io_err(&self.path))
    }
}

/// The output folder takes a file: checked before the first step, not found out after it.
fn check_writable(out: &Path) -> Result<(), RunError> {
    let probe = out.join(".talus_write_test");
    std::fs::write(&probe, b"").map_err(io_err(out))?;
    std::fs::remove_file(&probe).map_err(io_err(out))
}
