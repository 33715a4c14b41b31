//! `talus`: implicit elasto-plasticity of geomaterials by semi-smooth Newton.
use std::process::ExitCode;

use std::io::IsTerminal;
use std::path::PathBuf;

use clap::{Parser, Subcommand};
use talus::model::fem::ReactionForce;
use talus::model::size::{available_memory, SizeEstimate};
use talus::run::checkpoint::{self, Checkpoint, CheckpointError};
use talus::run::fem::{resume_scene, run_scene};
use talus::run::folder;
use talus::run::mpm::{resume_mpm_scene, run_mpm_scene, run_mpm_scene_3d, MpmRunSummary};
use talus::run::{stop_when, RunError, RunOptions};
use talus::scene::{builtin_footing, MpmScene, Scene, SceneFile};

mod cli;

use cli::exit::{self, Exit};
use cli::ranks::{error, output_folder, reports};
use cli::{interrupt, reduced};

#[derive(Parser)]
#[command(
    name = "talus",
    version = concat!(env!("CARGO_PKG_VERSION"), " (commit ", env!("TALUS_COMMIT"), ")"),
    about = "Implicit elasto-plasticity of geomaterials by semi-smooth Newton",
    after_help = exit::TABLE
)]
struct Cli {
    /// Log every step (and every halving), not one line per tenth of the run.
    #[arg(short, long, global = true)]
    verbose: bool,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene (default: the built-in paper footing, scenes/footing.toml).
    Run {
        /// Scene file (TOML): finite elements with `[mesh]`, material points with `[grid]`.
        /// Without it, the built-in footing of the paper's Fig. 3.
        scene: Option<PathBuf>,
        /// Output folder: history.csv, vtu/, solution.pvd, PNG plots. The files an earlier
        /// run left there are removed first (other files are kept); a folder another run
        /// or resume is using is refused (docs/scenes.md, 'Durable outputs').
        #[arg(long, default_value = "out")]
        out: PathBuf,
        /// Run even when the estimated memory exceeds what is available or the steps ×
        /// stress points exceed 1e11 (docs/scenes.md, 'Size').
        #[arg(long)]
        allow_large: bool,
        /// Write the full state to OUT/checkpoint/ every N steps and when interrupted, for
        /// `talus resume OUT` (docs/scenes.md, 'Checkpoints and resume').
        #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
        checkpoint_every: Option<u64>,
    },
    /// Continue a killed or interrupted run from its last checkpoint: history.csv and the
    /// VTUs are cut back to it, and the run goes on as if never stopped. Refused, the
    /// folder left as it was, when the scene file changed since, the checkpoint is not
    /// the folder's run's, or another run or resume is using the folder.
    Resume {
        /// The output folder of a run started with `--checkpoint-every`.
        out: PathBuf,
    },
    /// Run the verification cases (closed forms, published values, independent solves).
    Verify {
        /// One JSON object per case and line (for `cargo xtask verify`).
        #[arg(long)]
        json: bool,
        /// Skip the slow cases (P1 Prandtl runs, mesh refinement).
        #[arg(long)]
        quick: bool,
        /// Write the cases' PNG figures into this folder.
        #[arg(long)]
        figures: Option<PathBuf>,
    },
    /// Solve one reduced problem `z = Wσ + q` in the Siconos plasticity format.
    Reduced(reduced::Args),
}

fn main() -> ExitCode {
    // On a terminal a progress bar reports the run; elsewhere (CI, files) a line per tenth
    // of the run does, without colour codes; `-v`: a line per step.
    let cli = Cli::parse();
    #[cfg(feature = "mpi")]
    let mpi = match talus::ranks::init() {
        Ok(mpi) => mpi,
        Err(e) => {
            eprintln!("error: {e}");
            return Exit::InvalidInput.into();
        }
    };
    let terminal = std::io::stderr().is_terminal();
    let default_filter = match (cli.verbose, terminal) {
        // The other ranks of `mpirun` repeat rank 0's log.
        _ if !reports() => "error",
        (true, _) => "info,talus=debug,talus_engine=debug",
        (false, true) => "warn",
        (false, false) => "info",
    };
    let (filter, bad_filter) = log_filter(default_filter);
    tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_ansi(terminal)
        .with_writer(std::io::stderr)
        .init();
    if let Some(why) = bad_filter {
        tracing::warn!("{why}");
    }
    if let Err(e) = interrupt::install() {
        tracing::warn!("no SIGINT/SIGTERM handler ({e}): an interrupted run leaves no summary");
    }
    // On a worker of rayon's pool (docs/performance.md); errors as text, since a boxed
    // error need not be Send.
    let result = talus_ssn::on_pool(|| {
        let r: Result<ExitCode, Box<dyn std::error::Error>> = match cli.command {
            // One process' tool: under `mpirun`, rank 0 alone solves and prints.
            Command::Reduced(_) if !reports() => Ok(ExitCode::SUCCESS),
            Command::Reduced(args) => reduced::run(&args).or_else(|e| {
                error(&e);
                Ok(e.exit().into())
            }),
            Command::Run {
                scene,
                out,
                allow_large,
                checkpoint_every,
            } => run(
                scene,
                out,
                allow_large,
                checkpoint_every.unwrap_or(0) as usize,
            ),
            Command::Resume { out } => resume(out),
            Command::Verify {
                json,
                quick,
                figures,
            } => verify(json, quick, figures),
        };
        r.map_err(|e| e.to_string())
    });
    let code = match result {
        Ok(code) => code,
        Err(e) => {
            error(e);
            Exit::InvalidInput.into()
        }
    };
    #[cfg(feature = "mpi")]
    let code = cli::ranks::finish(&mpi, code);
    code
}

fn run(
    scene: Option<PathBuf>,
    out: PathBuf,
    allow_large: bool,
    checkpoint_every: usize,
) -> Result<ExitCode, Box<dyn std::error::Error>> {
    let scene = match scene {
        Some(path) => SceneFile::from_path(&path)?,
        None => SceneFile::Fem(builtin_footing()),
    };
    talus::ranks::set_root_folder(out.clone());
    let out = output_folder(out);
    // Before anything is allocated: the estimated memory and work (docs/scenes.md, 'Size').
    let estimate = match &scene {
        SceneFile::Fem(s) => Some(SizeEstimate::of_fem(s)?),
        SceneFile::Mpm(s) => Some(SizeEstimate::of_mpm(s)),
        SceneFile::Mpm3(s) => Some(SizeEstimate::of_mpm(s)),
        // The size estimate counts triangles' points: a 3D FEM scene has none yet.
        SceneFile::Fem3(_) => None,
    };
    let available = available_memory();
    if let Some(estimate) = estimate {
        tracing::info!(
            points = estimate.points,
            bytes = estimate.bytes,
            available,
            "size estimate"
        );
        if let Err(e) = estimate.check(available) {
            if !allow_large {
                error(e);
                return Ok(Exit::InvalidInput.into());
            }
            tracing::warn!("{e} (--allow-large: running anyway)");
        }
    }
    // The folder is this run's until it ends (docs/scenes.md, 'Durable outputs').
    let _lock = match folder::lock(&out) {
        Ok(lock) => lock,
        Err(e) => return Ok(refused(e)),
    };
    // Rank 0 alone writes checkpoints (another rank resumes from rank 0's) and pictures;
    // every rank its piece of the VTUs (`run/pieces.rs`).
    let options = interruptible(RunOptions {
        progress: reports(),
        write_fields: true,
        checkpoint_every: if reports() { checkpoint_every } else { 0 },
        ..RunOptions::new(out.clone())
    });
    match scene {
        SceneFile::Fem(scene) => run_fem(&scene, &options, None),
        SceneFile::Fem3(scene) => run_fem3(&scene, &options, None),
        SceneFile::Mpm(scene) => run_mpm(&scene, &options, None),
        SceneFile::Mpm3(scene) => run_mpm3(&scene, &options, None),
    }
}

/// The error, and the exit code, of a resume refused or a folder in use.
fn refused(e: CheckpointError) -> ExitCode {
    error(&e);
    Exit::of_run_error(&RunError::Checkpoint(e)).into()
}

/// `talus resume OUT`: the folder held, the checkpoint read, its scene checked and parsed,
/// the run continued. Every refusal leaves the folder as it was.
fn resume(out: PathBuf) -> Result<ExitCode, Box<dyn std::error::Error>> {
    talus::ranks::set_root_folder(out.clone());
    // Another rank of `mpirun` resumes from copies in its scratch folder.
    let out = match cli::ranks::resume_folder(out) {
        Ok(out) => out,
        Err(e) => {
            error(format!(
                "the checkpoint of rank 0's folder cannot be read: {e}"
            ));
            return Ok(Exit::InvalidInput.into());
        }
    };
    // Held before the checkpoint is read: a second resume of the folder stops here. A
    // folder that does not exist is not created (no checkpoint in it, below).
    let _lock = if out.is_dir() {
        match folder::lock(&out) {
            Ok(lock) => Some(lock),
            Err(e) => return Ok(refused(e)),
        }
    } else {
        None
    };
    let checkpoint = match checkpoint::read(&out) {
        Ok(c) => c,
        Err(e) => return Ok(refused(e)),
    };
    let source = match checkpoint.current_scene() {
        Ok(s) => s,
        Err(e) => return Ok(refused(e)),
    };
    let scene = SceneFile::parse(&source, checkpoint.scene.path.clone())?;
    let scene_name = match &checkpoint.scene.path {
        Some(p) if checkpoint.scene.held => format!("{} (as the checkpoint holds it)", p.display()),
        Some(p) => p.display().to_string(),
        None if checkpoint.scene.held => "the scene the checkpoint holds".to_string(),
        None => "the built-in footing".to_string(),
    };
    if reports() {
        eprintln!(
            "resuming {scene_name} from its checkpoint of step {} of {}",
            checkpoint.step, checkpoint.steps
        );
    }
    let options = interruptible(RunOptions {
        progress: reports(),
        write_fields: true,
        ..RunOptions::new(out.clone())
    });
    match scene {
        SceneFile::Fem(scene) => run_fem(&scene, &options, Some(checkpoint)),
        SceneFile::Fem3(scene) => run_fem3(&scene, &options, Some(checkpoint)),
        SceneFile::Mpm(scene) => run_mpm(&scene, &options, Some(checkpoint)),
        SceneFile::Mpm3(scene) => run_mpm3(&scene, &options, Some(checkpoint)),
    }
}

fn run_fem(
    scene: &Scene,
    options: &RunOptions,
    resumed: Option<Checkpoint<serde_json::Value>>,
) -> Result<ExitCode, Box<dyn std::error::Error>> {
    let out = options.out_dir.clone();
    if scene.spec.stability.is_some() && scene.spec.stage.is_empty() {
        if options.checkpoint_every > 0 || resumed.is_some() {
            error(
                "a [stability] scene's trials are not checkpointed: run it without \
                 --checkpoint-every",
            );
            return Ok(Exit::InvalidInput.into());
        }
        return run_stability(scene, out);
    }
    let summary = match resumed {
        Some(c) => resume_scene(scene, c, options),
        None => run_scene(scene, options),
    };
    let summary = match ended(summary, &out) {
        Ok(summary) => summary,
        Err(code) => return Ok(code.into()),
    };
    report_fem_run(&summary, scene.spec.analysis.geometry.force_unit(), &out);
    Ok(ExitCode::SUCCESS)
}

/// `talus run` of a 3D scene (`docs/3d.md`): a factor-of-safety search, or the run loop;
/// no stages there.
fn run_fem3(
    scene: &talus::scene::Scene3,
    options: &RunOptions,
    resumed: Option<Checkpoint<serde_json::Value>>,
) -> Result<ExitCode, Box<dyn std::error::Error>> {
    let out = options.out_dir.clone();
    if scene.spec.stability.is_some() {
        if options.checkpoint_every > 0 || resumed.is_some() {
            error(
                "a [stability] scene's trials are not checkpointed: run it without \
                 --checkpoint-every",
            );
            return Ok(Exit::InvalidInput.into());
        }
        return run_stability(scene, out);
    }
    let summary = talus::run::fem::run_scene_3d(scene, options, resumed);
    let summary = match ended(summary, &out) {
        Ok(summary) => summary,
        Err(code) => return Ok(code.into()),
    };
    report_fem_run(&summary, scene.spec.analysis.geometry.force_unit(), &out);
    Ok(ExitCode::SUCCESS)
}

/// The run's cost in one line, and the summary, of a FEM run in 2D or 3D.
fn report_fem_run<const D: usize>(
    summary: &talus::run::fem::RunSummary<D>,
    force_unit: &str,
    out: &std::path::Path,
) where
    talus_fem::Mandel<D>: talus_fem::Dimension,
{
    // The run's cost in one line (issue 24): accepted and failed Newton iterations, the
    // sub-steps the halvings added and the smallest sub-step.
    let records = &summary.records;
    let accepted: usize = records.iter().map(|r| r.newton_iterations).sum();
    let failed: usize = records.iter().map(|r| r.failed_newton_iterations).sum();
    let substeps: usize = records.iter().map(|r| r.substeps).sum();
    let worst = records
        .iter()
        .map(|r| r.max_newton_iterations)
        .max()
        .unwrap_or(0);
    let smallest_h = records
        .iter()
        .map(|r| r.smallest_h)
        .fold(f64::INFINITY, f64::min);
    let at_floor: usize = records
        .iter()
        .flat_map(|r| &r.statuses)
        .filter(|s| **s == talus_ssn::Status::RoundOffFloor)
        .count();
    let floor = if at_floor > 0 {
        format!(" ({at_floor} accepted at the round-off floor)")
    } else {
        String::new()
    };
    let last = records.last();
    if !reports() {
        return;
    }
    println!(
        "{} steps in {:.2} s; Newton iterations {accepted} accepted + {failed} failed ({:.1} \
         per step, at most {worst} in a solve); {substeps} sub-steps{floor}, smallest h \
         {:.3e} s; final reaction {:.4e} {} at {:.4e} m; outputs in {}",
        records.len(),
        summary.seconds,
        (accepted + failed) as f64 / records.len().max(1) as f64,
        if smallest_h.is_finite() {
            smallest_h
        } else {
            0.0
        },
        last.map(|r| r.reaction_force()).unwrap_or(0.0),
        force_unit,
        summary.displacements.last().copied().unwrap_or(0.0),
        out.display()
    );
    print_summary(out);
}

/// A `[stability]` scene: the factor of safety (`docs/stability.md`).
fn run_stability<const D: usize, const N: usize>(
    scene: &impl talus::analysis::stability::StabilityScene<D>,
    out: PathBuf,
) -> Result<ExitCode, Box<dyn std::error::Error>>
where
    talus_fem::Mandel<D>: talus_fem::Dimension<Point = [f64; N]>,
{
    // Not by the run loop, which clears them for the other scenes: the files an earlier
    // run left (its VTUs, its checkpoint) would be mixed with the trials'.
    if let Err(e) = folder::clear_owned(&out) {
        return Ok(refused(e));
    }
    let options = interruptible(RunOptions {
        progress: reports(),
        write_fields: reports(),
        ..RunOptions::new(out.clone())
    });
    let run = match ended(talus::analysis::stability::run(scene, &options), &out) {
        Ok(run) => run,
        Err(code) => return Ok(code.into()),
    };
    if !reports() {
        return Ok(ExitCode::SUCCESS);
    }
    println!(
        "loading in {} steps, then {} trials in {:.2} s; outputs in {}",
        run.equilibrium.steps,
        run.trials.len(),
        run.seconds,
        out.display()
    );
    print_summary(&out);
    Ok(ExitCode::SUCCESS)
}

fn run_mpm(
    scene: &MpmScene,
    options: &RunOptions,
    resumed: Option<Checkpoint<serde_json::Value>>,
) -> Result<ExitCode, Box<dyn std::error::Error>> {
    let out = options.out_dir.clone();
    let summary = match resumed {
        Some(c) => resume_mpm_scene(scene, c, options),
        None => run_mpm_scene(scene, options),
    };
    report_mpm_run(summary, &out)
}

/// `talus run` of a 3D MPM scene (`docs/3d-mpm.md`).
fn run_mpm3(
    scene: &talus::scene::MpmScene3,
    options: &RunOptions,
    resumed: Option<Checkpoint<serde_json::Value>>,
) -> Result<ExitCode, Box<dyn std::error::Error>> {
    let out = options.out_dir.clone();
    report_mpm_run(run_mpm_scene_3d(scene, options, resumed), &out)
}

/// The cost of an MPM run in one line, its runout, and the summary.
fn report_mpm_run<const D: usize>(
    summary: Result<MpmRunSummary<D>, RunError>,
    out: &std::path::Path,
) -> Result<ExitCode, Box<dyn std::error::Error>>
where
    talus_mpm::Mandel<D>: talus_mpm::Dimension,
{
    let summary = match ended(summary, out) {
        Ok(summary) => summary,
        Err(code) => return Ok(code.into()),
    };
    let runout = if summary.runout_reported {
        format!(
            "; final runout {} = {:.4}",
            summary.runout.measure(),
            summary.runout_normalized
        )
    } else {
        String::new()
    };
    if !reports() {
        return Ok(ExitCode::SUCCESS);
    }
    println!(
        "{} steps in {:.2} s; {} Newton iterations, at most {} per step; largest residual {:.3e}{runout}; outputs in {}",
        summary.reports.len(),
        summary.seconds,
        summary.total_newton_iterations(),
        summary.max_newton_iterations(),
        summary.max_residual(),
        out.display()
    );
    print_summary(out);
    Ok(ExitCode::SUCCESS)
}

/// `options` stopped after the step in progress by SIGINT/SIGTERM (`cli::interrupt`); under
/// `mpirun` after the step in progress on every rank, once any rank has the signal (the
/// ranks agree after each step: they reach the signal at different times).
fn interruptible(options: RunOptions) -> RunOptions {
    stop_when(options, || talus::ranks::any(interrupt::requested()))
}

/// The run's result; a failed run prints its error, then `summary.json` in words as its
/// last line, and gives its exit code.
fn ended<T>(result: Result<T, RunError>, out: &std::path::Path) -> Result<T, Exit> {
    result.map_err(|e| {
        error(&e);
        // A scene error stops the run before it starts: no summary of it.
        if !matches!(e, RunError::Scene(_)) {
            print_summary(out);
        }
        Exit::of_run_error(&e)
    })
}

/// The log filter of `TALUS_LOG`, or `default` with the reason when it is set but not a
/// filter (`tracing_subscriber::EnvFilter` syntax: `warn`, `talus=debug`, ...).
fn log_filter(default: &str) -> (tracing_subscriber::EnvFilter, Option<String>) {
    use tracing_subscriber::EnvFilter;
    const LEVELS: [&str; 6] = ["trace", "debug", "info", "warn", "error", "off"];
    let Ok(value) = std::env::var("TALUS_LOG") else {
        return (EnvFilter::new(default), None);
    };
    let bare_word = !value.contains(['=', ',', '[']) && !value.trim().is_empty();
    let parsed = EnvFilter::try_new(&value);
    match parsed {
        Ok(_) if bare_word && !LEVELS.contains(&value.trim().to_lowercase().as_str()) => (
            EnvFilter::new(default),
            Some(format!(
                "TALUS_LOG={value:?} is not a level ({}) nor `target=level`: using {default:?}",
                LEVELS.join(", ")
            )),
        ),
        Ok(filter) => (filter, None),
        Err(e) => (
            EnvFilter::new(default),
            Some(format!(
                "TALUS_LOG={value:?} is not a valid filter ({e}): using {default:?}"
            )),
        ),
    }
}

/// `summary.json` in words (nothing when the run stopped before writing it).
fn print_summary(out: &std::path::Path) {
    if !reports() {
        return;
    }
    if let Ok(summary) = talus::output::Summary::read(&out.join("summary.json")) {
        println!("{}", summary.sentence());
    }
}

fn verify(
    json: bool,
    quick: bool,
    figures: Option<PathBuf>,
) -> Result<ExitCode, Box<dyn std::error::Error>> {
    // Under `mpirun` every rank runs the cases (their solves are MUMPS' collectives, the
    // distributed solver verified); rank 0 alone draws and prints.
    let figures = figures.filter(|_| reports());
    if let Some(dir) = &figures {
        std::fs::create_dir_all(dir)?;
    }
    let results = talus::analysis::verification::all_cases(quick, figures.as_deref());
    let failed = results.iter().filter(|r| !r.passed()).count();
    for r in results.iter().filter(|_| reports()) {
        if json {
            let mut v = serde_json::to_value(r)?;
            v["error"] = serde_json::json!(r.error());
            v["passed"] = serde_json::json!(r.passed());
            println!("{v}");
        } else {
            println!(
                "{:<44} {:>12.6e} {:>12.6e} {:>9.2e} {:>8.1e} {:<5} {:>7.2}",
                r.case,
                r.reference,
                r.computed,
                r.error(),
                r.tolerance,
                if r.passed() { "pass" } else { "FAIL" },
                r.seconds
            );
        }
    }
    Ok(if failed == 0 {
        ExitCode::SUCCESS
    } else {
        Exit::VerificationFailed.into()
    })
}
