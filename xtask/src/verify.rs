//! `cargo xtask verify`: the Siconos suite, the Clarabel agreement and every case of
//! `talus verify`, as one table, written to `docs/verification.md`. `--quick` skips the slow
//! cases (P1 Prandtl runs, mesh refinement).
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use serde_json::Value;

use crate::{run_checked, run_output};

/// One row of the verification table.
struct Row {
    case: String,
    quantity: String,
    reference: f64,
    computed: f64,
    error: f64,
    tolerance: f64,
    passed: bool,
    seconds: f64,
    source: String,
}

fn siconos_rows(root: &Path, talus: &str) -> Result<Vec<Row>, String> {
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
    println!("Siconos plasticity suite (talus reduced, default settings, tol 1e-12, from σ = 0)");
    println!(
        "{:<42} {:<12} {:>10} {:>11} {:>11} {:>9}",
        "file", "status", "iterations", "‖F‖∞", "relative", "ms"
    );
    let mut rows = Vec::new();
    for file in &files {
        let path = file.to_str().ok_or("non-UTF-8 path")?;
        // Exit 3 or 6 (not converged, round-off floor) is a row's status, read from its
        // JSON: only a failure to start the command stops the suite.
        let out = run_output(root, talus, &["reduced", path, "--json"])?;
        let name = file
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let v: Value = serde_json::from_str(String::from_utf8_lossy(&out.stdout).trim())
            .unwrap_or(Value::Null);
        let status = v["status"].as_str().unwrap_or("error").to_string();
        let relative = v["relative_residual"].as_f64().unwrap_or(f64::NAN);
        let seconds = v["seconds"].as_f64().unwrap_or(f64::NAN);
        println!(
            "{:<42} {:<12} {:>10} {:>11.3e} {:>11.3e} {:>9.2}",
            name,
            status,
            v["iterations"].as_u64().unwrap_or(0),
            v["residual"].as_f64().unwrap_or(f64::NAN),
            relative,
            seconds * 1e3
        );
        rows.push(Row {
            case: format!(
                "siconos_{}",
                name.trim_start_matches("plasticity_2d_")
                    .trim_end_matches(".dat")
            ),
            quantity: format!(
                "‖F‖∞ / max(1, ‖σ‖∞), {} iterations, {status}",
                v["iterations"].as_u64().unwrap_or(0)
            ),
            reference: 0.0,
            computed: relative,
            error: relative,
            tolerance: 1e-12,
            passed: status == "converged" && relative <= 1e-12,
            seconds,
            source: "Siconos plasticity test suite (INRIA)".into(),
        });
    }
    println!();
    Ok(rows)
}

/// talus-ssn's comparison with Clarabel, built and run with the workspace's features: a
/// module of the crates' one test binary each (`tests/suite.rs`), chosen by its path.
const CLARABEL_TEST: &str = "clarabel_agreement::";

fn clarabel_row(root: &Path) -> Result<Row, String> {
    let start = Instant::now();
    // A failing test is this row's FAIL, judged from its output below.
    let out = run_output(
        root,
        "cargo",
        &[
            "test",
            "--release",
            "-q",
            "--workspace",
            "--exclude",
            "talus-mumps",
            "--test",
            "suite",
            CLARABEL_TEST,
            "--",
            "--nocapture",
        ],
    )?;
    let text = String::from_utf8_lossy(&out.stdout);
    let rel = text
        .lines()
        .find(|l| l.contains("‖σ_ssn − σ_clarabel‖∞"))
        .and_then(|l| l.split(": ").nth(1))
        .and_then(|r| r.split_whitespace().next())
        .and_then(|v| v.parse::<f64>().ok())
        .unwrap_or(f64::NAN);
    Ok(Row {
        case: "siconos_footing_100_theta0_vs_clarabel".into(),
        quantity: "‖σ_ssn − σ_Clarabel‖∞ / ‖σ_Clarabel‖∞ (Clarabel at 1e-12 gap and feasibility)"
            .into(),
        reference: 0.0,
        computed: rel,
        error: rel,
        tolerance: 1e-6,
        passed: out.status.success() && rel <= 1e-6,
        seconds: start.elapsed().as_secs_f64(),
        source: "Clarabel 0.11 interior-point solution of the same QP".into(),
    })
}

fn talus_rows(root: &Path, talus: &str, quick: bool) -> Result<Vec<Row>, String> {
    let figures = root.join("docs/img");
    let figures = figures.to_str().ok_or("non-UTF-8 path")?.to_string();
    let mut args = vec!["verify", "--json", "--figures", figures.as_str()];
    if quick {
        args.push("--quick");
    }
    // Exit 7 (a case failed) still prints every case: the table shows which.
    let out = run_output(root, talus, &args)?;
    let mut rows = Vec::new();
    for line in String::from_utf8_lossy(&out.stdout).lines() {
        let v: Value = serde_json::from_str(line)
            .map_err(|e| format!("talus verify printed `{line}`: {e}"))?;
        let num = |k: &str| v[k].as_f64().unwrap_or(f64::NAN);
        rows.push(Row {
            case: v["case"].as_str().unwrap_or("?").into(),
            quantity: v["quantity"].as_str().unwrap_or("").into(),
            reference: num("reference"),
            computed: num("computed"),
            error: num("error"),
            tolerance: num("tolerance"),
            passed: v["passed"].as_bool().unwrap_or(false),
            seconds: num("seconds"),
            source: v["source"].as_str().unwrap_or("").into(),
        });
    }
    if rows.is_empty() {
        return Err(format!(
            "talus verify printed nothing: {}",
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    Ok(rows)
}

fn markdown(rows: &[Row], quick: bool, seconds: f64) -> String {
    let mut md = String::new();
    let _ = writeln!(md, "# Verification\n");
    let _ = writeln!(
        md,
        "Written by `cargo xtask verify{}` ({:.0} s on a 2-core machine, release build). Each case \
         reproduces a closed form, a published value or an independent computation; the source \
         column says which. Errors are relative to the reference unless the reference is 0; \
         one-sided checks (observed order ≥ 1.8, refinement must not increase the error) show 0 \
         error on the good side.\n",
        if quick { " --quick" } else { "" },
        seconds
    );
    let _ = writeln!(
        md,
        "| case | quantity | reference | computed | error | tolerance | | s | source |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|");
    for r in rows {
        let _ = writeln!(
            md,
            "| `{}` | {} | {:.6e} | {:.6e} | {:.2e} | {:.1e} | {} | {:.2} | {} |",
            r.case,
            r.quantity,
            r.reference,
            r.computed,
            r.error,
            r.tolerance,
            if r.passed { "pass" } else { "**FAIL**" },
            r.seconds,
            r.source
        );
    }
    let _ = writeln!(
        md,
        "\nNotes: P1 triangles lock under plastic flow and overestimate Prandtl's load (tolerance \
         10% instead of 5%, to show it, not to hide it). The footing edge makes the limit-load \
         problem singular, so its mesh convergence is slow. The Newton order is measured on the \
         iteration's own merit `‖F_ρ‖₂` (the map Newton linearizes), on steps with at least four \
         iterates above round-off. Figures of the paper footing: [footing.md](footing.md). \
         Factors of safety (slope by strength reduction, vertical cut by gravity increase, the \
         criterion and its measurements): [stability.md](stability.md).\n\n\
         ![Prandtl φ = 30°, P2](img/verification_prandtl_phi30_p2.png)\n\
         ![Newton residuals, paper footing, 60 steps](img/verification_newton_residuals.png)"
    );
    md
}

pub fn run(root: &Path, quick: bool) -> Result<bool, String> {
    let start = Instant::now();
    // The workspace's features with its dev-dependencies' (Clarabel's test target asks for
    // them), as `cargo xtask test` builds them: after its crates stage nothing is rebuilt.
    let build = run_checked(
        root,
        "cargo",
        &[
            "build",
            "--release",
            "--quiet",
            "--workspace",
            "--exclude",
            "talus-mumps",
            "--bin",
            "talus",
            "--test",
            "suite",
        ],
    )?;
    if !build.status.success() {
        return Err(format!(
            "cargo build failed:\n{}",
            String::from_utf8_lossy(&build.stderr)
        ));
    }
    let talus = crate::release_talus(root);
    let talus = talus.to_str().ok_or("non-UTF-8 path")?;
    let mut rows = siconos_rows(root, talus)?;
    rows.push(clarabel_row(root)?);
    rows.extend(talus_rows(root, talus, quick)?);

    println!(
        "{:<46} {:<44} {:>13} {:>13} {:>9} {:>8} {:<5} {:>7}",
        "case", "quantity", "reference", "computed", "error", "tol", "", "s"
    );
    for r in &rows {
        let quantity: String = r.quantity.chars().take(44).collect();
        println!(
            "{:<46} {:<44} {:>13.6e} {:>13.6e} {:>9.2e} {:>8.1e} {:<5} {:>7.2}",
            r.case,
            quantity,
            r.reference,
            r.computed,
            r.error,
            r.tolerance,
            if r.passed { "pass" } else { "FAIL" },
            r.seconds
        );
    }
    let failed = rows.iter().filter(|r| !r.passed).count();
    let doc = root.join("docs/verification.md");
    std::fs::write(&doc, markdown(&rows, quick, start.elapsed().as_secs_f64()))
        .map_err(|e| format!("{}: {e}", doc.display()))?;
    println!(
        "verify: {} passed, {} failed (table written to docs/verification.md)",
        rows.len() - failed,
        failed
    );
    Ok(failed == 0)
}
