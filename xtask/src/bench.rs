//! `cargo xtask bench`: the divan benchmarks and the MPM column benchmark (a harness of its
//! own), then the figures of merit as ratios of medians measured in the same run.
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

pub fn run(root: &Path) -> Result<bool, String> {
    let mut ok = true;
    let mut outputs = Vec::new();
    for (package, bench) in [
        ("talus-cone", "projection"),
        ("talus-ssn", "footing"),
        ("talus", "step"),
        // Minutes: the 100k column takes several per step; TALUS_MPM_BENCH_SIZES=10k
        // skips it.
        ("talus-mpm", "column_step"),
        // The a = 2 column at h = 1/60 s (~2 min): finished, Newton its per step.
        ("talus-mpm", "column_a2_large_step"),
    ] {
        println!("== cargo bench -p {package} --bench {bench}");
        let out = run_checked(
            root,
            "cargo",
            &["bench", "-q", "-p", package, "--bench", bench],
        )?;
        let text = String::from_utf8_lossy(&out.stdout).into_owned();
        print!("{text}");
        if !out.status.success() {
            eprint!("{}", String::from_utf8_lossy(&out.stderr));
            ok = false;
        }
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
    let step = &outputs[2];
    let under = |group: &str, case: &str| {
        step.find(group)
            .and_then(|at| median_seconds(&step[at..], case))
    };
    println!("\nNewton iteration / elastic factorization and solve, same mesh (target <= 1.3)");
    for case in ["lu 32x14", "llt 32x14", "lu 104x48", "llt 104x48"] {
        match (
            under("newton_iteration", case),
            under("elastic_solve", case),
        ) {
            (Some(a), Some(b)) => println!(
                "{case}: {:.3} ({:.2} ms / {:.2} ms)",
                a / b,
                a * 1e3,
                b * 1e3
            ),
            _ => {
                println!("{case}: median not found in the benchmark output");
                ok = false;
            }
        }
    }
    let column = &outputs[3];
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
    match outputs[4]
        .lines()
        .find(|l| l.starts_with("column a2 large step: "))
    {
        Some(line) => println!("{line}"),
        None => {
            println!("column_a2_large_step: summary not found in the benchmark output");
            ok = false;
        }
    }
    Ok(ok)
}
