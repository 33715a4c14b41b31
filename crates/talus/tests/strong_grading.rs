//! A `[mesh.rectangle]` whose cells span more than 1e3 in size along an axis draws a
//! warning naming the key, the span and a ratio that would make it 100
//! (`docs/performance.md`, 'Grading kept while refining'); the shipped footing does not.
use crate::common;
use common::{replaced, talus_run, FOOTING};

/// `talus run`'s stderr at `warn` for the footing with `cells` and one step.
fn warnings(name: &str, cells: &str) -> String {
    let text = replaced(FOOTING, "cells = [32, 14]", &format!("cells = {cells}"));
    let text = replaced(&text, "steps = 300", "steps = 1");
    let text = replaced(&text, "plots = true", "plots = false");
    talus_run("strong_grading", name, &text).2
}

#[test]
fn a_grading_kept_over_many_cells_is_warned_with_a_milder_ratio() {
    // ratio 1.1 from the surface over 100 cells: 1.1^99 = 1.25e4.
    let stderr = warnings("steep", "[8, 100]");
    let line = stderr
        .lines()
        .find(|l| l.contains("mesh.rectangle.ratio"))
        .unwrap_or_else(|| panic!("no warning: {stderr}"));
    assert!(line.contains("along y") && line.contains("1.3e4"), "{line}");
    // The ratio offered makes the span 100: 100^(1/99) = 1.0476.
    assert!(line.contains("ratio = 1.0476"), "{line}");
    assert!(!stderr.contains("along x"), "x is uniform: {stderr}");
}

#[test]
fn the_shipped_footing_draws_no_grading_warning() {
    let stderr = warnings("shipped", "[32, 14]");
    assert!(!stderr.contains("mesh.rectangle.ratio"), "{stderr}");
}
