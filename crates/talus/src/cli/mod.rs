//! The `talus` binary's own concerns: its exit codes, its SIGINT/SIGTERM handler (which
//! reaches a run through `RunOptions::observer`, `talus::run::stop_when`), and the
//! `reduced` subcommand, and what a rank of `mpirun -np N talus` does differently.
pub mod exit;
pub mod interrupt;
pub mod ranks;
pub mod reduced;
