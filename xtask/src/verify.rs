//! `cargo xtask verify`: the Siconos suite through the release binary, as one table.
use std::path::Path;

use crate::run_checked;

struct Row {
    file: String,
    status: String,
    iterations: u64,
    residual: f64,
    relative: f64,
    millis: f64,
}

pub fn run(root: &Path) -> Result<bool, String> {
    let build = run_checked(
        root,
        "cargo",
        &["build", "--release", "--quiet", "-p", "talus"],
    )?;
    if !build.status.success() {
        return Err(format!(
            "cargo build failed:\n{}",
            String::from_utf8_lossy(&build.stderr)
        ));
    }
    let talus = root.join("target/release/talus");
    let data = root.join("data/siconos-plasticity");
    let mut files: Vec<_> = std::fs::read_dir(&data)
        .map_err(|e| format!("{}: {e}", data.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "dat"))
        .collect();
    files.sort();
    if files.is_empty() {
        return Err(format!("no .dat files in {}", data.display()));
    }
    let mut rows = Vec::new();
    for file in &files {
        let path = file.to_str().ok_or("non-UTF-8 path")?;
        let out = run_checked(
            root,
            talus.to_str().ok_or("non-UTF-8 path")?,
            &["reduced", path, "--json"],
        )?;
        let text = String::from_utf8_lossy(&out.stdout);
        let name = file
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let row = match serde_json::from_str::<serde_json::Value>(text.trim()) {
            Ok(v) => Row {
                file: name,
                status: v["status"].as_str().unwrap_or("?").to_string(),
                iterations: v["iterations"].as_u64().unwrap_or(0),
                residual: v["residual"].as_f64().unwrap_or(f64::NAN),
                relative: v["relative_residual"].as_f64().unwrap_or(f64::NAN),
                millis: v["seconds"].as_f64().unwrap_or(f64::NAN) * 1e3,
            },
            Err(_) => Row {
                file: name,
                status: format!("error: {}", String::from_utf8_lossy(&out.stderr).trim()),
                iterations: 0,
                residual: f64::NAN,
                relative: f64::NAN,
                millis: f64::NAN,
            },
        };
        rows.push(row);
    }
    println!("Siconos plasticity suite (talus reduced, default settings, tol 1e-12, from σ = 0)");
    println!(
        "{:<42} {:<12} {:>10} {:>11} {:>11} {:>9}",
        "file", "status", "iterations", "‖F‖∞", "relative", "ms"
    );
    for r in &rows {
        println!(
            "{:<42} {:<12} {:>10} {:>11.3e} {:>11.3e} {:>9.2}",
            r.file, r.status, r.iterations, r.residual, r.relative, r.millis
        );
    }
    let failed = rows.iter().filter(|r| r.status != "converged").count();
    println!("verify: {} passed, {} failed", rows.len() - failed, failed);
    Ok(failed == 0)
}
