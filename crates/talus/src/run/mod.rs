//! A scene run to its end, FEM or MPM, with history, ParaView files and PNG plots: one run
//! loop over the engine ([`steps`]), each method's outputs ([`fem`], [`mpm`]), checkpoints
//! and resume ([`checkpoint`]).
pub mod checkpoint;
pub mod fem;
pub mod folder;
pub mod mpm;
mod pieces;
mod steps;

use std::io::IsTerminal;
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};

use talus_engine::{Discretization, StepError, Stepper};

use crate::model::fem::FemStepError;
use crate::output::OutputError;
use crate::scene::SceneError;
use checkpoint::{Checkpoint, CheckpointError};
pub use steps::{Begin, RunOutputs, Span, Stepped, HISTORY_COLUMNS};
pub use talus_engine::Collapsed;

#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error("{0}")]
    Scene(#[from] SceneError),
    #[error("cannot write {path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error(transparent)]
    Output(OutputError),
    /// The run stopped at `step`; what was written before it is kept.
    #[error("step {step}: {source}")]
    Step { step: usize, source: FemStepError },
    /// The body collapsed (`docs/scenes.md`, 'Collapse'); what was written before is kept.
    #[error("{0}")]
    Collapsed(Collapsed),
    /// SIGINT/SIGTERM stopped the run after `step` (at `time`, s); its outputs are written.
    #[error(
        "interrupted after step {step} (t = {time:.6e} s); the outputs written so far are complete"
    )]
    Interrupted { step: usize, time: f64 },
    /// An MPM run stopped at `step`, which started at `time` (s); what was written before
    /// it is kept.
    #[error("step {step} (from t = {time:.6} s): {source}")]
    MpmStep {
        step: usize,
        time: f64,
        source: StepError<talus_mpm::MpmError>,
    },
    /// A checkpoint could not be written, or not resumed.
    #[error(transparent)]
    Checkpoint(CheckpointError),
}

// Output and checkpoint failures are this rank's alone under `mpirun` (rank 0 writes the
// folder): `ranks::local_failure` stops every rank before this one drops its MUMPS
// instance, whose end is collective (docs/distributed.md, 'When a rank fails').
impl From<OutputError> for RunError {
    fn from(e: OutputError) -> Self {
        crate::ranks::local_failure(&e);
        RunError::Output(e)
    }
}

impl From<CheckpointError> for RunError {
    fn from(e: CheckpointError) -> Self {
        crate::ranks::local_failure(&e);
        RunError::Checkpoint(e)
    }
}

/// How a run is carried out. New fields come with defaults: build it with
/// `RunOptions { write_fields: true, ..RunOptions::new(out) }`.
#[derive(Clone)]
pub struct RunOptions {
    pub out_dir: PathBuf,
    /// Draw a progress bar on a terminal (tracing logs otherwise).
    pub progress: bool,
    /// Write VTU files and PNG plots (history.csv is always written).
    pub write_fields: bool,
    /// Told of every step (a factor-of-safety search: every trial); a `Break` stops the run
    /// after it (status `interrupted`). The Python package's progress callback and Ctrl-C,
    /// the `talus` binary's SIGINT/SIGTERM ([`stop_when`]).
    pub observer: Option<Observer>,
    /// Write a checkpoint every this many steps, and at an interruption (0: never);
    /// `talus resume` continues from the last one (`crate::run::checkpoint`).
    pub checkpoint_every: usize,
}

/// See [`RunOptions::observer`].
pub type Observer = std::sync::Arc<dyn Fn(&StepProgress) -> ControlFlow<()> + Send + Sync>;

/// What an [`Observer`] is told after each step.
#[derive(Debug, Clone, PartialEq)]
pub struct StepProgress {
    /// The step just completed (1-based) and the run's number of steps.
    pub step: usize,
    pub steps: usize,
    /// Time at the end of the step (s).
    pub time: f64,
    pub newton_iterations: usize,
    pub substeps: usize,
    /// The last solve's residual over its scale (`history.csv`'s `relative_residual`).
    pub relative_residual: f64,
    /// The method's own short status (the progress bar's message).
    pub message: String,
}

impl RunOptions {
    /// Files under `out_dir`, no progress bar, no VTU or plots, no observer.
    pub fn new(out_dir: impl Into<PathBuf>) -> Self {
        Self {
            out_dir: out_dir.into(),
            progress: false,
            write_fields: false,
            observer: None,
            checkpoint_every: 0,
        }
    }
}

pub(crate) fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> RunError + '_ {
    move |source| {
        let e = RunError::Io {
            path: path.to_path_buf(),
            source,
        };
        crate::ranks::local_failure(&e);
        e
    }
}

/// A progress bar over `steps` when `progress` is asked for and stderr is a terminal.
pub(crate) fn progress_bar(steps: usize, progress: bool) -> Option<indicatif::ProgressBar> {
    (progress && std::io::stderr().is_terminal()).then(|| {
        let bar = indicatif::ProgressBar::new(steps as u64);
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{bar:40} {pos}/{len} steps, {elapsed} elapsed, eta {eta} {msg}",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        bar
    })
}

/// A method's state as a checkpoint holds it: its array sizes, so that a checkpoint of
/// another model is refused before any step indexes out of bounds.
pub trait Shape {
    /// What the sizes are, in words.
    const SIZES: &'static str;
    fn sizes(&self) -> Vec<usize>;
}

/// The one path of a run, fresh or resumed, FEM or MPM: the checkpoint's state checked
/// against `state`'s shape, then the steps of `span` by `h` with the run loop (from
/// `state` after `span.from` when that is not 0: a staged run's next stage). A failed
/// step comes back in [`Stepped::failure`].
pub(crate) fn execute<D, O, const N: usize>(
    stepper: &mut Stepper<D, N>,
    state: D::State,
    resumed: Option<Checkpoint<serde_json::Value>>,
    outputs: &mut O,
    span: Span,
    h: f64,
    options: &RunOptions,
    scene: (Option<&Path>, &str),
) -> Result<Stepped<D, N>, RunError>
where
    D: Discretization<N>,
    D::State: Shape + serde::Serialize + serde::de::DeserializeOwned,
    O: RunOutputs<D, N>,
{
    let resumed = match resumed {
        Some(c) => Some(c.with_state::<D::State>(&options.out_dir)?),
        None => None,
    };
    if let Some(c) = &resumed {
        let n_stress = stepper.discretization().stress(&state).len();
        let rate = c.stepper.stress_rate.as_ref().map_or(n_stress, Vec::len);
        let (saved, wanted) = (c.state.sizes(), state.sizes());
        if saved != wanted || rate != n_stress {
            return Err(CheckpointError::Corrupt {
                path: checkpoint::path(&options.out_dir),
                why: format!(
                    "its state has sizes {saved:?} ({}) and a stress rate of {rate}, the \
                     scene's model {wanted:?}",
                    <D::State as Shape>::SIZES
                ),
            }
            .into());
        }
    }
    let begin = match resumed {
        Some(c) => Begin::Resumed(Box::new(c)),
        None if span.from > 0 => Begin::Continue(state),
        None => Begin::Fresh(state),
    };
    steps::run_steps(stepper, begin, span, h, outputs, options, scene.0, scene.1)
}

/// `options` with an observer that also stops the run once `requested` says so (the
/// `talus` binary's SIGINT/SIGTERM flag): the library reads no global of its own.
pub fn stop_when(
    options: RunOptions,
    requested: impl Fn() -> bool + Send + Sync + 'static,
) -> RunOptions {
    let inner = options.observer.clone();
    RunOptions {
        observer: Some(std::sync::Arc::new(move |p: &StepProgress| {
            let own = inner.as_ref().map_or(ControlFlow::Continue(()), |o| o(p));
            if requested() {
                ControlFlow::Break(())
            } else {
                own
            }
        })),
        ..options
    }
}
