//! The exit codes of the `talus` command, one table for every subcommand (README,
//! 'Exit codes'; `talus --help`).
use std::process::ExitCode;

use talus::run::RunError;

/// Why `talus` stopped. No two causes share a code; 2 is clap's for usage errors and 101
/// Rust's for a panic (a bug).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Exit {
    Success,
    /// A scene, mesh or problem file refused (field, value, line), or too large a model
    /// without `--allow-large`.
    InvalidInput,
    /// A step (or `talus reduced`'s Newton) did not converge, or failed otherwise.
    NotConverged,
    /// The body collapsed (`docs/scenes.md`, 'Collapse').
    Collapsed,
    /// An output could not be written.
    Io,
    /// `talus reduced` stopped at the problem's round-off floor above the tolerance.
    RoundOffFloor,
    /// `talus verify`: a case outside its tolerance.
    VerificationFailed,
    /// SIGINT or SIGTERM: the run wrote what it had and stopped.
    Interrupted,
}

impl Exit {
    pub const fn code(self) -> u8 {
        match self {
            Exit::Success => 0,
            Exit::InvalidInput => 1,
            Exit::NotConverged => 3,
            Exit::Collapsed => 4,
            Exit::Io => 5,
            Exit::RoundOffFloor => 6,
            Exit::VerificationFailed => 7,
            Exit::Interrupted => 130,
        }
    }

    /// The exit of a run that stopped with `e`.
    pub fn of_run_error(e: &RunError) -> Self {
        match e {
            RunError::Scene(_) => Exit::InvalidInput,
            RunError::Io { .. } | RunError::Output(_) => Exit::Io,
            RunError::Step { .. } | RunError::MpmStep { .. } => Exit::NotConverged,
            RunError::Collapsed(_) => Exit::Collapsed,
            RunError::Interrupted { .. } => Exit::Interrupted,
            RunError::Checkpoint(c) if c.is_io() => Exit::Io,
            // Missing, corrupt, another scene's or another run's, outputs that do not reach
            // it, or an output folder another run or resume is using.
            RunError::Checkpoint(_) => Exit::InvalidInput,
        }
    }
}

impl From<Exit> for ExitCode {
    fn from(e: Exit) -> Self {
        ExitCode::from(e.code())
    }
}

/// The table printed by `talus --help`.
pub const TABLE: &str = "\
Exit codes:
  0    success
  1    invalid input (scene, mesh or problem file; a model too large without --allow-large;
       an output folder another run or resume is using; `talus resume`: no checkpoint, a
       corrupt one, another run's, or a scene changed since)
  2    usage (unknown option or subcommand)
  3    a step did not converge (or failed); `talus reduced`: Newton did not converge
  4    collapsed: the body accelerated without bound under its loads
  5    an output file could not be written, or a checkpoint read
  6    `talus reduced`: stopped at the round-off floor above the tolerance
  7    `talus verify`: a case failed
  130  interrupted (SIGINT/SIGTERM); the outputs written so far are complete";
