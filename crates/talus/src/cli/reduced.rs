//! `talus reduced FILE`: one Siconos plasticity problem, solved and reported.
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use super::exit::Exit;
use talus_ssn::siconos::SiconosProblem;
use talus_ssn::{reduced_system_from_siconos, Report, Rho, Settings, SolveError, Solver, Status};

#[derive(clap::Args)]
pub struct Args {
    /// The problem file (Siconos plasticity text format).
    file: PathBuf,
    /// Stop when ‖F‖∞ ≤ tol · max(1, ‖σ‖∞).
    #[arg(long, default_value_t = Settings::reduced().tolerance)]
    tol: f64,
    /// Print the report as one JSON object.
    #[arg(long)]
    json: bool,
    /// Write the solution σ, one number per line, in the file's ordering.
    #[arg(long)]
    solution: Option<PathBuf>,
    /// ρ = factor / max diag W (per point unless --global-rho).
    #[arg(long, default_value_t = Settings::reduced().rho.factor())]
    rho_factor: f64,
    /// One ρ for all points, scaled by the largest diagonal entry of W.
    #[arg(long)]
    global_rho: bool,
    /// Newton iterations before giving up.
    #[arg(long, default_value_t = Settings::reduced().max_iterations)]
    max_iterations: usize,
}

#[derive(Debug, thiserror::Error)]
pub enum ReducedError {
    /// The file could not be read; the error names it.
    #[error(transparent)]
    Read(#[from] talus_ssn::siconos::SiconosError),
    /// The problem read from `path` cannot be solved (e.g. `d` is not 3).
    #[error("{}: {error}", path.display())]
    Solve { path: PathBuf, error: SolveError },
    #[error("cannot write {path}: {source}")]
    Write {
        path: PathBuf,
        source: std::io::Error,
    },
}

impl ReducedError {
    /// Bad input, or an output that could not be written.
    pub fn exit(&self) -> Exit {
        match self {
            ReducedError::Write { .. } => Exit::Io,
            _ => Exit::InvalidInput,
        }
    }
}

pub fn run(args: &Args) -> Result<ExitCode, ReducedError> {
    let problem = SiconosProblem::from_path(&args.file)?;
    let in_file = |error| ReducedError::Solve {
        path: args.file.clone(),
        error,
    };
    let system = reduced_system_from_siconos::<3>(&problem).map_err(in_file)?;
    let rho = if args.global_rho {
        Rho::GlobalDiagonal {
            factor: args.rho_factor,
        }
    } else {
        Rho::PerPointDiagonal {
            factor: args.rho_factor,
        }
    };
    let settings = Settings {
        tolerance: args.tol,
        rho,
        max_iterations: args.max_iterations,
        ..Settings::reduced()
    };
    let mut solver = Solver::new(system, settings).map_err(in_file)?;
    let mut sigma = vec![0.0; problem.n()];
    let report = match solver.solve(&mut sigma) {
        Ok(r) => r,
        Err(SolveError::NotConverged(r)) => *r,
        Err(e) => return Err(in_file(e)),
    };
    let sigma_inf = sigma.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    print_report(args, &report, sigma_inf);
    if let Some(path) = &args.solution {
        write_solution(path, &sigma).map_err(|source| ReducedError::Write {
            path: path.clone(),
            source,
        })?;
    }
    Ok(exit_code(report.status))
}

/// The exit table of `talus::exit`: 0 converged, 3 not converged, 6 stopped at the
/// round-off floor above the tolerance (σ is the best attainable, the tolerance is not
/// met); 1 is bad input (in `main`).
pub fn exit_code(status: Status) -> ExitCode {
    match status {
        Status::Converged => Exit::Success,
        Status::RoundOffFloor => Exit::RoundOffFloor,
        _ => Exit::NotConverged,
    }
    .into()
}

fn print_report(args: &Args, report: &Report, sigma_inf: f64) {
    if args.json {
        let json = serde_json::json!({
            "file": args.file.display().to_string(),
            "status": report.status.as_str(),
            "iterations": report.iterations,
            "residual": report.residual,
            "seconds": report.seconds,
            "relative_residual": report.residual / sigma_inf.max(1.0),
            "sigma_inf": sigma_inf,
            "residual_history": report.residual_history,
            "backtracks": report.backtracks,
            "rho_min": report.rho_range.0,
            "rho_max": report.rho_range.1,
            "round_off_floor": report.round_off_floor.map(|f| serde_json::json!({
                "reached": f.reached,
                "estimate": f.estimate,
            })),
        });
        println!("{json}");
    } else {
        println!("status: {}", report.status);
        println!("iterations: {}", report.iterations);
        println!(
            "residual: {:.3e} (relative to max(1, ‖σ‖∞ = {sigma_inf:.3e}): {:.3e})",
            report.residual,
            report.residual / sigma_inf.max(1.0)
        );
        if let Some(f) = report.round_off_floor {
            println!(
                "round-off floor: reached {:.3e}, estimated {:.3e}",
                f.reached, f.estimate
            );
        }
        println!("seconds: {:.6}", report.seconds);
    }
}

fn write_solution(path: &PathBuf, sigma: &[f64]) -> std::io::Result<()> {
    let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
    for v in sigma {
        writeln!(out, "{v:.17e}")?;
    }
    out.flush()
}
