//! The same scene gives the same numbers whatever the thread count: the paper's footing
//! (non-associative, the no-pivot LU; associative, the Cholesky) refined to 64 × 28 P2
//! cells, whose factorization splits its elimination tree into subtrees factorized on
//! different threads (`talus_ssn::factorization`), run by `talus run` on 1 and on 2 threads
//! (`RAYON_NUM_THREADS`). history.csv (its `seconds` columns aside) and the last VTU must
//! agree to the byte.
use crate::common;
use std::path::{Path, PathBuf};

fn run(threads: usize, scene: &Path, out: PathBuf) -> PathBuf {
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_talus"))
        .arg("run")
        .arg(scene)
        .arg("--out")
        .arg(&out)
        .env("TALUS_LOG", "warn")
        .env("RAYON_NUM_THREADS", threads.to_string())
        .status()
        .unwrap();
    assert!(status.success(), "{threads} threads");
    out
}

/// history.csv without the columns whose name says they are wall time.
fn history_without_times(out: &Path) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let keep: Vec<usize> = (0..header.len())
        .filter(|&i| !header[i].contains("seconds"))
        .collect();
    assert!(keep.len() > 5, "{header:?}");
    let mut rows = vec![keep
        .iter()
        .map(|&i| header[i].to_string())
        .collect::<Vec<_>>()];
    for line in lines {
        let cells: Vec<&str> = line.split(',').collect();
        rows.push(keep.iter().map(|&i| cells[i].to_string()).collect());
    }
    rows
}

fn last_vtu(out: &Path) -> Vec<u8> {
    let mut vtus: Vec<PathBuf> = std::fs::read_dir(out.join("vtu"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "vtu"))
        .collect();
    vtus.sort();
    std::fs::read(vtus.last().expect("a VTU")).unwrap()
}

/// The footing at 64 × 28 P2 cells, 4 steps, `dilatancy_angle` replaced by `dilatancy`,
/// run on 1 and on 2 threads: the same bytes.
fn same_bytes_on_one_and_two_threads(name: &str, dilatancy: &str) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let text = std::fs::read_to_string(root.join("footing.toml")).unwrap();
    let text = common::replaced(&text, "cells = [32, 14]", "cells = [64, 28]");
    let text = common::replaced(&text, "steps = 300", "steps = 4");
    let text = common::replaced(
        &text,
        "dilatancy_angle = 14.2906",
        &format!("dilatancy_angle = {dilatancy}"),
    );
    let dir = common::target_tmp_dir("thread_count", name);
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, text).unwrap();
    let one = run(1, &scene, dir.join("one"));
    let two = run(2, &scene, dir.join("two"));
    let (h1, h2) = (history_without_times(&one), history_without_times(&two));
    assert_eq!(h1.len(), 6, "header, step 0 and 4 steps");
    assert_eq!(h1, h2);
    assert_eq!(last_vtu(&one), last_vtu(&two));
}

#[test]
fn the_paper_footing_gives_the_same_bytes_on_one_and_two_threads() {
    same_bytes_on_one_and_two_threads("footing_64x28", "14.2906");
}

/// Associative (ψ = φ): the Newton matrix is symmetric and factorized by the supernodal
/// Cholesky (`SymmetricPatternLlt`), on the same subtree schedule.
#[test]
fn the_associative_footing_gives_the_same_bytes_on_one_and_two_threads() {
    same_bytes_on_one_and_two_threads("footing_64x28_associative", "27.0");
}
