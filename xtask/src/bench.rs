//! `cargo xtask bench`: the divan benchmarks and the MPM column benchmark (a harness of its
//! own), then the figures of merit as ratios of medians measured in the same run, then the
//! distributed benchmark when MUMPS and `mpirun` are installed.
use std::path::Path;

use crate::run_checked;

/// Median of the divan row whose label contains `label`, in seconds.
fn median_seconds(output: &str, label: &str) -> Option<f64> {
    let line = output.lines().find(|l| l.contains(label))?;
    // Columns: name+fastest │ slowest │ median │ mean │ samples │ iters; nested rows start
    // with a `│` of their own, so count from the end.
    let median = line.split('│').rev().nth(3)?.trim();
    let (value, unit) = median.split_once(' ')?;
    let scale = match unit.trim() {
        "ns" => 1e-9,
        "µs" | "us" => 1e-6,
        "ms" => 1e-3,
        "s" => 1.0,
        _ => return None,
    };
    value.parse::<f64>().ok().map(|v| v * scale)
}

/// `Err` naming the command and its exit status as soon as a benchmark fails (the figures
/// of merit need every one); `Ok(false)` when a figure is missing from an output.
pub fn run(root: &Path) -> Result<bool, String> {
    let mut ok = true;
    let mut outputs = Vec::new();
    for (package, bench) in [
        ("talus-cone", "projection"),
        ("talus-ssn", "footing"),
        // Each ~10 minutes with the 100k mesh: TALUS_STEP_BENCH_SIZES and
        // TALUS_FOOTING_BENCH_SIZES choose the meshes.
        ("talus", "step"),
        ("talus", "footing_steps"),
        // Minutes: the 100k column takes several per step; TALUS_MPM_BENCH_SIZES=10k
        // skips it.
        ("talus", "mpm_column_step"),
        // The a = 2 column at h = 1/60 s (~2 min): finished, Newton its per step.
        ("talus", "mpm_column_a2_large_step"),
        // 3D P2 tetrahedra (~30 s at the default 12k dofs; TALUS_3D_BENCH_SIZES=12x14x12
        // for 50k, 20x21x20 for 205k: docs/3d.md).
        ("talus-fem", "newton_3d"),
    ] {
        println!("== cargo bench -p {package} --bench {bench}");
        let out = run_checked(
            root,
            "cargo",
            &["bench", "-q", "-p", package, "--bench", bench],
        )?;
        let text = String::from_utf8_lossy(&out.stdout).into_owned();
        print!("{text}");
        outputs.push(text);
    }
    let ssn = &outputs[1];
    println!("\nFigures of merit (ratios of medians, same run)");
    let theta0 = median_seconds(ssn, "plasticity_2d_footing_100_theta0.dat");
    for (label, name) in [
        ("clarabel_theta0_tol_1e12", "Clarabel at 1e-12"),
        ("clarabel_theta0_tol_1e8", "Clarabel at 1e-8"),
    ] {
        match (theta0, median_seconds(ssn, label)) {
            (Some(a), Some(b)) => println!(
                "ssn (1e-12) / {name} on footing_100_theta0: {:.3} ({:.2} ms / {:.2} ms)",
                a / b,
                a * 1e3,
                b * 1e3
            ),
            _ => {
                println!("ssn / {name}: median not found in the benchmark output");
                ok = false;
            }
        }
    }
    println!(
        "\nNewton iteration / elastic Cholesky factorization and solve, same mesh (target <= 2.0)"
    );
    ok &= print_ratios(&outputs[2], "step");
    println!("\nFooting: seconds per step, accepted and failed Newton iterations, peak memory");
    let rows: Vec<&str> = outputs[3].lines().filter(|l| l.starts_with('|')).collect();
    if rows.len() < 3 {
        println!("footing_steps: table not found in the benchmark output");
        ok = false;
    }
    for line in rows {
        println!("{line}");
    }
    for line in outputs[3]
        .lines()
        .filter(|l| l.contains("wall non-associative / associative"))
    {
        println!("{line}");
    }
    let column = &outputs[4];
    println!("\nMPM column collapse: plastic step / elastic step, same particles");
    let ratios: Vec<&str> = column
        .lines()
        .filter_map(|l| l.strip_prefix("plastic step / elastic step, "))
        .collect();
    if ratios.is_empty() {
        println!("column_step: ratio not found in the benchmark output");
        ok = false;
    }
    for line in ratios {
        println!("{line}");
    }
    match outputs[5]
        .lines()
        .find(|l| l.starts_with("column a2 large step: "))
    {
        Some(line) => println!("{line}"),
        None => {
            println!("column_a2_large_step: summary not found in the benchmark output");
            ok = false;
        }
    }
    println!("\n3D: Newton iteration / elastic Cholesky factorization and solve (target <= 2.5)");
    ok &= print_ratios(&outputs[6], "newton_3d");
    // MUMPS over MPI ranks against the scenes' own solver (docs/distributed.md), where
    // MUMPS and mpirun are installed (about 4 minutes; TALUS_DISTRIBUTED_BENCH_CASES adds
    // footing_320x156, whose first step alone takes more than 10 minutes on one rank).
    match crate::mpi::missing() {
        Some(missing) => println!("\nDistributed benchmark skipped ({missing})"),
        None => {
            println!("\n== cargo bench -p talus --features mpi --bench distributed");
            let out = run_checked(
                root,
                "cargo",
                &[
                    "bench",
                    "-q",
                    "-p",
                    "talus",
                    "--features",
                    "mpi",
                    "--bench",
                    "distributed",
                ],
            )?;
            print!("{}", String::from_utf8_lossy(&out.stdout));
        }
    }
    Ok(ok)
}

/// Prints the `ratio …` lines of a benchmark's output; `false` when it has none.
fn print_ratios(output: &str, bench: &str) -> bool {
    let ratios: Vec<&str> = output
        .lines()
        .filter_map(|l| l.strip_prefix("ratio "))
        .collect();
    if ratios.is_empty() {
        println!("{bench}: ratios not found in the benchmark output");
    }
    for line in &ratios {
        println!("{line}");
    }
    !ratios.is_empty()
}
