//! `summary.json` of the paper footing (`scenes/footing.toml`, 300 steps to 3 mm): its
//! limit load is recomputed here from history.csv by an independent implementation of the
//! documented criterion (`docs/scenes.md`, 'summary.json': the longest tail of the
//! force–settlement curve within 1% of the final force, spanning ≥ 20% of the settlement
//! range): same start, same settlement (a settlement of history.csv), same mean force. A
//! run stopped on the elastic branch has no limit; a run whose step fails says so.
use std::path::{Path, PathBuf};

use talus::run::fem::run_scene;
use talus::run::RunOptions;
use talus::scene::Scene;

fn out_dir(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("summary_json")
        .join(name)
}

fn footing_text() -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/footing.toml"))
        .unwrap()
}

fn run(text: &str, name: &str) -> (serde_json::Value, Vec<(f64, f64)>) {
    let scene = Scene::parse(text, None).unwrap();
    let out = out_dir(name);
    let _ = run_scene(&scene, &RunOptions::new(out.clone()));
    let summary =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let history = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let mut lines = history.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let (d, f) = (
        header
            .iter()
            .position(|h| *h == "footing_displacement")
            .unwrap(),
        header.iter().position(|h| *h == "reaction_force").unwrap(),
    );
    let curve = lines
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            (v[d], v[f])
        })
        .collect();
    (summary, curve)
}

/// The criterion, written again: the first index from which every force is within
/// `tolerance` of the last, if that tail spans `span` of the settlement and has
/// `min_points` points.
fn limit_of(curve: &[(f64, f64)], tolerance: f64, span: f64, min_points: usize) -> Option<usize> {
    let n = curve.len();
    let last = curve[n - 1].1;
    let start = (0..n).find(|&s| {
        curve[s..]
            .iter()
            .all(|p| (p.1 - last).abs() <= tolerance * last.abs())
    })?;
    let range = curve[n - 1].0 - curve[0].0;
    (curve[n - 1].0 - curve[start].0 >= span * range && n - start >= min_points).then_some(start)
}

#[test]
fn paper_footing_limit_agrees_with_history() {
    let (s, curve) = run(&footing_text(), "paper_footing");
    assert_eq!(s["status"], "finished");
    assert_eq!(s["steps"], 300);
    assert_eq!(curve.len(), 301, "step 0 and 300 steps");
    let limit = &s["limit"];
    let (tolerance, span, min_points) = (
        limit["tolerance"].as_f64().unwrap(),
        limit["span"].as_f64().unwrap(),
        limit["min_points"].as_u64().unwrap() as usize,
    );
    assert_eq!(
        (tolerance, span, min_points),
        (0.01, 0.2, 3),
        "the documented criterion"
    );
    assert!(limit["criterion"].as_str().unwrap().contains("1%"));

    let start = limit_of(&curve, tolerance, span, min_points).expect("the footing plateaus");
    let force: f64 = curve[start..].iter().map(|p| p.1).sum::<f64>() / (curve.len() - start) as f64;
    let (got_force, got_settlement, got_step) = (
        limit["force"].as_f64().unwrap(),
        limit["settlement"].as_f64().unwrap(),
        limit["step"].as_u64().unwrap() as usize,
    );
    println!(
        "limit {got_force:.6e} N/m from {got_settlement:.4e} m (step {got_step}); recomputed {force:.6e} N/m from step {start}; final {:.6e} N/m",
        curve[300].1
    );
    assert_eq!(got_step, start);
    // history.csv carries 11 significant digits.
    assert!(
        (got_force - force).abs() <= 1e-9 * force,
        "{got_force} vs {force}"
    );
    assert!(
        curve
            .iter()
            .any(|p| (p.0 - got_settlement).abs() <= 1e-12 * got_settlement.max(1e-12)),
        "{got_settlement} is not a settlement of history.csv"
    );
    assert!((curve[start].0 - got_settlement).abs() <= 1e-12);
    // The reaction and the named boundary agree with the last row.
    assert!((s["reaction"]["force"].as_f64().unwrap() - curve[300].1).abs() <= 1e-9 * curve[300].1);
    let fy = s["boundaries"]["footing"]["final"][1].as_f64().unwrap();
    assert!(
        (fy + curve[300].1).abs() <= 1e-9 * curve[300].1,
        "footing_fy = −reaction_force"
    );
    // A limit, not the elastic branch: the plateau starts well after step 0 and the force
    // at its start is within 1% of the end while step 0's is not.
    assert!(start > 10 && (curve[0].1 - curve[300].1).abs() > tolerance * curve[300].1);
}

#[test]
fn a_run_stopped_on_the_rising_branch_has_no_limit() {
    let text = footing_text()
        .replacen("cells = [32, 14]", "cells = [16, 6]", 1)
        .replacen("step = 1.0e-2", "step = 5.0e-2", 1)
        .replacen("steps = 300", "steps = 4", 1);
    let (s, curve) = run(&text, "rising");
    assert_eq!(s["status"], "finished");
    assert!(s["limit"].is_null(), "{}", s["limit"]);
    assert_eq!(limit_of(&curve, 0.01, 0.2, 3), None);
    assert!(s["reaction"]["force"].as_f64().unwrap() > 0.0);
}

#[test]
fn a_failed_run_writes_its_status_and_error() {
    let text = footing_text()
        .replacen("cells = [32, 14]", "cells = [16, 6]", 1)
        .replacen(
            "[output]",
            "[solver]\nmax_iterations = 1\nmax_step_halvings = 0\n\n[output]",
            1,
        );
    let (s, curve) = run(&text, "failed");
    assert_eq!(s["status"], "not_converged");
    assert_eq!(s["steps"], 0);
    assert_eq!(s["steps_requested"], 300);
    assert!(
        s["error"].as_str().unwrap().contains("did not converge"),
        "{}",
        s["error"]
    );
    assert_eq!(curve.len(), 1, "step 0 only");
    assert!(s["limit"].is_null());
}
