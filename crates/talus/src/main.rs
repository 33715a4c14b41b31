//! `talus`: implicit elasto-plasticity of geomaterials by semi-smooth Newton.
use std::process::ExitCode;

use clap::{Parser, Subcommand};

mod reduced;

#[derive(Parser)]
#[command(
    name = "talus",
    version,
    about = "Implicit elasto-plasticity of geomaterials by semi-smooth Newton"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Solve one reduced problem `z = Wσ + q` in the Siconos plasticity format.
    Reduced(reduced::Args),
}

fn main() -> ExitCode {
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_env("TALUS_LOG")
                .unwrap_or_else(|_| "warn".into()),
        )
        .with_writer(std::io::stderr)
        .init();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Reduced(args) => reduced::run(&args),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(1)
        }
    }
}
