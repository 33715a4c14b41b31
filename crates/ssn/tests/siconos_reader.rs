//! Tests of the Siconos plasticity `.dat` reader against the shipped files and
//! small hand-written inputs (both header variants, dense and sparse storage).

use std::path::PathBuf;

use talus_ssn::siconos::{SiconosError, SiconosMatrix, SiconosModel, SiconosProblem};

const DATA: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../data/siconos-plasticity/"
);

fn path(name: &str) -> PathBuf {
    PathBuf::from(DATA).join(name)
}

fn load(name: &str) -> SiconosProblem {
    SiconosProblem::from_path(&path(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn text(name: &str) -> String {
    std::fs::read_to_string(path(name)).unwrap()
}

fn num(s: &str) -> f64 {
    s.parse().unwrap()
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    Dense,
    Sparse,
}

fn kind(p: &SiconosProblem) -> Kind {
    match p.matrix {
        SiconosMatrix::Dense { .. } => Kind::Dense,
        SiconosMatrix::Sparse { .. } => Kind::Sparse,
    }
}

// ---------------------------------------------------------------- shipped files

/// (file, d, n_c, storage, Some((eta, theta)) for Drucker-Prager / None for
/// von Mises with sigma_y = 0.5)
/// (eta, theta) of a Drucker-Prager file.
type Dp = Option<(f64, f64)>;

const FILES: [(&str, usize, usize, Kind, Dp); 9] = [
    (
        "plasticity_2d_example1.dat",
        3,
        3,
        Kind::Sparse,
        Some((0.1, 0.1)),
    ),
    (
        "plasticity_2d_example1_theta0.dat",
        3,
        3,
        Kind::Sparse,
        Some((0.1, 0.0)),
    ),
    (
        "plasticity_2d_vonmises_example1.dat",
        3,
        3,
        Kind::Sparse,
        None,
    ),
    (
        "plasticity_2d_footing_1.dat",
        3,
        1,
        Kind::Dense,
        Some((0.1, 0.1)),
    ),
    (
        "plasticity_2d_footing_10.dat",
        3,
        10,
        Kind::Dense,
        Some((0.1, 0.1)),
    ),
    (
        "plasticity_2d_footing_100.dat",
        3,
        100,
        Kind::Dense,
        Some((0.1, 0.1)),
    ),
    (
        "plasticity_2d_footing_100_theta0.05.dat",
        3,
        100,
        Kind::Dense,
        Some((0.1, 0.05)),
    ),
    (
        "plasticity_2d_footing_100_theta0.dat",
        3,
        100,
        Kind::Dense,
        Some((0.1, 0.0)),
    ),
    (
        "plasticity_2d_vonmises_footing_100.dat",
        3,
        100,
        Kind::Dense,
        None,
    ),
];

#[test]
fn every_file_parses_with_expected_shape_and_model() {
    for (name, d, nc, storage, dp) in FILES {
        let p = load(name);
        assert_eq!(p.cone_dimension, d, "{name}");
        assert_eq!(p.n_cones, nc, "{name}");
        assert_eq!(p.n(), d * nc, "{name}");
        assert_eq!(kind(&p), storage, "{name}");
        assert_eq!(p.q.len(), d * nc, "{name}");
        match (&p.matrix, storage) {
            (SiconosMatrix::Dense { n, values }, Kind::Dense) => {
                assert_eq!(*n, d * nc, "{name}");
                assert_eq!(values.len(), n * n, "{name}");
            }
            (SiconosMatrix::Sparse { n, triplets }, Kind::Sparse) => {
                assert_eq!(*n, d * nc, "{name}");
                assert_eq!(triplets.len(), 9, "{name}");
            }
            _ => unreachable!(),
        }
        match (&p.model, dp) {
            (SiconosModel::DruckerPrager { eta, theta }, Some((e, t))) => {
                assert_eq!(eta.len(), nc, "{name}");
                assert_eq!(theta.len(), nc, "{name}");
                assert!(eta.iter().all(|&x| x == e), "{name}: eta {eta:?}");
                assert!(theta.iter().all(|&x| x == t), "{name}: theta {theta:?}");
            }
            (SiconosModel::VonMises { sigma_y }, None) => {
                assert_eq!(sigma_y.len(), nc, "{name}");
                assert!(sigma_y.iter().all(|&x| x == 0.5), "{name}: {sigma_y:?}");
            }
            (m, _) => panic!("{name}: wrong model {m:?}"),
        }
    }
}

#[test]
fn footing_1_values_match_file_text() {
    let p = load("plasticity_2d_footing_1.dat");
    // File lines 8-10 are the columns of the matrix (column-major).
    let m00 = num("1.254679952246591348902520e-06");
    let m10 = num("-2.243337116093276687432429e-07"); // line 8, 2nd value
    let m01 = num("-2.243337116093276952130225e-07"); // line 9, 1st value
    let m21 = num("5.202175058553852059870675e-07"); // line 9, 3rd value
    let m22 = num("7.422624463912060936463346e-07");
    assert_ne!(m10, m01, "the file is non-symmetric in the last bits");
    assert_eq!(p.matrix_entry(0, 0), m00);
    assert_eq!(p.matrix_entry(1, 0), m10);
    assert_eq!(p.matrix_entry(0, 1), m01);
    assert_eq!(p.matrix_entry(2, 1), m21);
    assert_eq!(p.matrix_entry(2, 2), m22);
    assert_eq!(p.matrix_entry(0, 2), num("2.243337116093276952130225e-07"));
    assert_eq!(
        p.q,
        vec![
            num("-8.921148789319381259893191e-06"),
            num("-3.476292585612003673376832e-19"),
            num("-3.053892918902899463688000e-19"),
        ]
    );
    let SiconosMatrix::Dense { values, .. } = &p.matrix else {
        panic!("footing_1 is dense")
    };
    // Row-major: values[1] is entry (0, 1).
    assert_eq!(values[1], m01);
    assert_eq!(values[3], m10);
}

/// Checks every dense entry against an independent, naive reading of the
/// file: text line `first + j` holds column j.
fn check_dense_against_text(name: &str, first_value_line: usize) {
    let p = load(name);
    let n = p.n();
    let t = text(name);
    let lines: Vec<&str> = t.lines().collect();
    for j in 0..n {
        let col: Vec<f64> = lines[first_value_line - 1 + j]
            .split_whitespace()
            .map(num)
            .collect();
        assert_eq!(col.len(), n, "{name}: column {j}");
        for (i, &v) in col.iter().enumerate() {
            assert_eq!(p.matrix_entry(i, j), v, "{name}: entry ({i}, {j})");
        }
    }
    let q: Vec<f64> = lines[first_value_line - 1 + n]
        .split_whitespace()
        .map(num)
        .collect();
    assert_eq!(p.q, q, "{name}: q");
}

#[test]
fn dense_files_match_naive_column_reading() {
    check_dense_against_text("plasticity_2d_footing_1.dat", 8);
    check_dense_against_text("plasticity_2d_footing_10.dat", 7); // old header
    check_dense_against_text("plasticity_2d_footing_100.dat", 8);
    check_dense_against_text("plasticity_2d_vonmises_footing_100.dat", 8);
}

#[test]
fn footing_100_spot_values() {
    let p = load("plasticity_2d_footing_100_theta0.05.dat");
    assert_eq!(p.q[0], num("-8.921148789319381259893191e-06"));
    assert_eq!(p.q[299], num("-5.128173486502632209826924e-03"));
    // Line 8, value 4 = entry (3, 0).
    assert_eq!(p.matrix_entry(3, 0), num("6.421504471496749534068752e-07"));
    let SiconosModel::DruckerPrager { theta, .. } = &p.model else {
        panic!("Drucker-Prager expected")
    };
    assert_eq!(theta[99], num("5.000000000000000277555756e-02"));
}

#[test]
fn sparse_example1_is_identity() {
    for name in [
        "plasticity_2d_example1.dat",
        "plasticity_2d_example1_theta0.dat",
        "plasticity_2d_vonmises_example1.dat",
    ] {
        let p = load(name);
        for i in 0..9 {
            for j in 0..9 {
                let want = if i == j { 1.0 } else { 0.0 };
                assert_eq!(p.matrix_entry(i, j), want, "{name}: ({i}, {j})");
            }
        }
        assert_eq!(p.q, [-1.0, 1.0, 3.0].repeat(3), "{name}");
    }
}

#[test]
fn old_header_file_is_drucker_prager() {
    let p = load("plasticity_2d_footing_10.dat");
    assert_eq!((p.cone_dimension, p.n_cones, p.n()), (3, 10, 30));
    assert!(matches!(p.model, SiconosModel::DruckerPrager { .. }));
    // footing_10 is the leading 30x30 block of footing_100 (same mesh).
    let big = load("plasticity_2d_footing_100.dat");
    for i in 0..30 {
        for j in 0..30 {
            assert_eq!(p.matrix_entry(i, j), big.matrix_entry(i, j), "({i}, {j})");
        }
    }
}

// ---------------------------------------------------------------- inline examples

/// Non-symmetric 3x3, column-major in the file: columns (1 2 3), (4 5 6), (7 8 9).
const DENSE_NEW: &str = "3\n1\n1\n0\n3\n3\n3\t3\n1 2 3\n4 5 6\n7 8 9\n10 20 30\n0.5\n0.25\n";
const DENSE_OLD: &str = "3\n1\n0\n3\n3\n3\t3\n1 2 3\n4 5 6\n7 8 9\n10 20 30\n0.5\n0.25\n";

fn check_dense_1_to_9(p: &SiconosProblem) {
    assert_eq!(p.n(), 3);
    assert_eq!(p.matrix_entry(0, 0), 1.0);
    assert_eq!(p.matrix_entry(1, 0), 2.0);
    assert_eq!(p.matrix_entry(2, 0), 3.0);
    assert_eq!(p.matrix_entry(0, 1), 4.0);
    assert_eq!(p.matrix_entry(0, 2), 7.0);
    assert_eq!(p.matrix_entry(2, 1), 6.0);
    assert_eq!(p.matrix_entry(1, 2), 8.0);
    assert_eq!(p.matrix_entry(2, 2), 9.0);
    let SiconosMatrix::Dense { n, values } = &p.matrix else {
        panic!("dense expected")
    };
    assert_eq!(*n, 3);
    assert_eq!(values, &[1.0, 4.0, 7.0, 2.0, 5.0, 8.0, 3.0, 6.0, 9.0]);
    assert_eq!(p.q, vec![10.0, 20.0, 30.0]);
    assert_eq!(
        p.model,
        SiconosModel::DruckerPrager {
            eta: vec![0.5],
            theta: vec![0.25]
        }
    );
}

#[test]
fn inline_dense_new_header_is_column_major() {
    check_dense_1_to_9(&SiconosProblem::parse(DENSE_NEW).unwrap());
}

#[test]
fn inline_dense_old_header_is_column_major() {
    check_dense_1_to_9(&SiconosProblem::parse(DENSE_OLD).unwrap());
}

#[test]
fn inline_dense_von_mises() {
    let t = "3\n1\n2\n0\n3\n3\n3\t3\n1 2 3\n4 5 6\n7 8 9\n10 20 30\n1.5\n";
    let p = SiconosProblem::parse(t).unwrap();
    assert_eq!(p.matrix_entry(1, 0), 2.0);
    assert_eq!(p.model, SiconosModel::VonMises { sigma_y: vec![1.5] });
}

const BANNER: &str =
    "CSparse Version 4.4.1, June 20, 2024.  Copyright (c) Timothy A. Davis, 2006-2024";

fn sparse_text(header: &str, body: &str, tail: &str) -> String {
    format!("{header}1\n{BANNER}\n{body}{tail}")
}

/// 3x3 non-symmetric with a duplicate at (0, 2): 1.5 + 0.5.
const TRIPLETS: &str = "triplet: 3-by-3, nzmax: 8 nnz: 5\n    0 0 : 1\n    0 2 : 1.5\n    \
                        2 1 : -4\n    1 1 : 2\n    0 2 : 0.5\n";

fn check_sparse(p: &SiconosProblem) {
    assert_eq!(p.n(), 3);
    assert_eq!(p.matrix_entry(0, 0), 1.0);
    assert_eq!(p.matrix_entry(0, 2), 2.0);
    assert_eq!(p.matrix_entry(2, 0), 0.0);
    assert_eq!(p.matrix_entry(2, 1), -4.0);
    assert_eq!(p.matrix_entry(1, 2), 0.0);
    assert_eq!(p.matrix_entry(1, 1), 2.0);
    let SiconosMatrix::Sparse { n, triplets } = &p.matrix else {
        panic!("sparse expected")
    };
    assert_eq!(*n, 3);
    assert_eq!(triplets.len(), 5);
    assert_eq!(triplets[2], (2, 1, -4.0));
    assert_eq!(p.q, vec![-1.0, 1.0, 3.0]);
}

#[test]
fn inline_sparse_new_header() {
    let t = sparse_text("3\n1\n1\n2\n3\n3\n", TRIPLETS, "-1 1 3\n0.3\n0\n");
    let p = SiconosProblem::parse(&t).unwrap();
    check_sparse(&p);
    assert_eq!(
        p.model,
        SiconosModel::DruckerPrager {
            eta: vec![0.3],
            theta: vec![0.0]
        }
    );
}

#[test]
fn inline_sparse_old_header() {
    let t = sparse_text("3\n1\n2\n3\n3\n", TRIPLETS, "-1 1 3\n0.3\n0.1\n");
    let p = SiconosProblem::parse(&t).unwrap();
    check_sparse(&p);
    assert_eq!(
        p.model,
        SiconosModel::DruckerPrager {
            eta: vec![0.3],
            theta: vec![0.1]
        }
    );
}

#[test]
fn inline_sparse_csc_origin() {
    // Columns: 0 -> rows 0, 2; 1 -> empty; 2 -> row 1.
    let t = "3\n1\n2\n2\n3\n3\n2\n".to_string()
        + BANNER
        + "\n3-by-3, nzmax: 3 nnz: 3, 1-norm: 9\n    col 0 : locations 0 to 1\n      0 : 4\n      \
           2 : -5\n    col 1 : locations 2 to 1\n    col 2 : locations 2 to 2\n      1 : 7\n\
           0 0 0\n2\n";
    let p = SiconosProblem::parse(&t).unwrap();
    assert_eq!(p.matrix_entry(0, 0), 4.0);
    assert_eq!(p.matrix_entry(2, 0), -5.0);
    assert_eq!(p.matrix_entry(0, 2), 0.0);
    assert_eq!(p.matrix_entry(1, 2), 7.0);
    assert_eq!(p.matrix_entry(2, 1), 0.0);
    assert_eq!(p.model, SiconosModel::VonMises { sigma_y: vec![2.0] });
}

/// n = d * n_c = 2 is the one size where the new header's `storage n n`
/// looks like the old header's `n n`; the token after must settle it.
#[test]
fn header_ambiguity_at_n_equal_2() {
    let body = "triplet: 2-by-2, nzmax: 2 nnz: 2\n    0 1 : 3\n    1 0 : 4\n";
    // New header: d=2, n_c=1, model 2 (von Mises), storage 2, 2 x 2.
    let new = sparse_text("2\n1\n2\n2\n2\n2\n", body, "5 6\n0.5\n");
    let p = SiconosProblem::parse(&new).unwrap();
    assert_eq!(p.model, SiconosModel::VonMises { sigma_y: vec![0.5] });
    assert_eq!((p.matrix_entry(0, 1), p.matrix_entry(1, 0)), (3.0, 4.0));
    // Old header: d=2, n_c=1, storage 2, 2 x 2 (Drucker-Prager).
    let old = sparse_text("2\n1\n2\n2\n2\n", body, "5 6\n0.5\n0.7\n");
    let p = SiconosProblem::parse(&old).unwrap();
    assert_eq!(
        p.model,
        SiconosModel::DruckerPrager {
            eta: vec![0.5],
            theta: vec![0.7]
        }
    );
    assert_eq!(p.q, vec![5.0, 6.0]);
}

#[test]
fn trailing_whitespace_and_crlf_are_accepted() {
    let t = DENSE_NEW.replace('\n', "\r\n") + "  \n\n\t\n";
    check_dense_1_to_9(&SiconosProblem::parse(&t).unwrap());
}

// ---------------------------------------------------------------- bad inputs

/// Parses `t`, expects an error whose message starts with `line {line}:`
/// and contains `needle`.
fn bad(t: &str, line: usize, needle: &str) {
    let err = match SiconosProblem::parse(t) {
        Ok(p) => panic!("accepted bad input (expected error at line {line}): {p:?}"),
        Err(e) => e,
    };
    let msg = err.to_string();
    assert!(
        msg.starts_with(&format!("line {line}:")),
        "wrong line in `{msg}` (want {line})"
    );
    assert!(msg.contains(needle), "`{msg}` lacks `{needle}`");
}

/// Replaces the `k`-th (1-based) line of `t`.
fn with_line(t: &str, k: usize, new: &str) -> String {
    t.lines()
        .enumerate()
        .map(|(i, l)| if i + 1 == k { new } else { l })
        .collect::<Vec<_>>()
        .join("\n")
        + "\n"
}

#[test]
fn empty_and_truncated_inputs() {
    bad("", 1, "unexpected end of input");
    bad("  \n", 1, "cone dimension");
    bad("3\n1\n1\n0\n3\n3\n3\t3\n1 2 3\n4 5 6\n", 9, "(0, 2)");
    let footing = text("plasticity_2d_footing_1.dat");
    let cut: String = footing.lines().take(11).collect::<Vec<_>>().join("\n");
    bad(&cut, 11, "eta[0] of 1");
    let sparse = text("plasticity_2d_example1.dat");
    let cut: String = sparse.lines().take(12).collect::<Vec<_>>().join("\n");
    bad(&cut, 12, "row index of triplet 3 of 9");
    let cut: String = sparse.lines().take(8).collect::<Vec<_>>().join("\n");
    bad(&cut, 8, "CSparse size line");
}

#[test]
fn every_prefix_of_small_files_errors_cleanly() {
    for name in [
        "plasticity_2d_footing_1.dat",
        "plasticity_2d_example1.dat",
        "plasticity_2d_vonmises_example1.dat",
    ] {
        let t = text(name);
        let trimmed = t.trim_end();
        let last_token_start = trimmed.rfind(|c: char| c.is_ascii_whitespace()).unwrap() + 1;
        for len in 0..t.len() {
            let r = SiconosProblem::parse(&t[..len]);
            if len <= last_token_start {
                let e = r.expect_err("prefix lacking the last token must fail");
                assert!(e.to_string().starts_with("line "), "{name}[..{len}]: {e}");
            }
        }
    }
}

#[test]
fn non_numeric_tokens() {
    bad(&DENSE_NEW.replace("4 5 6", "4 x 6"), 9, "found `x`");
    bad(
        &DENSE_NEW.replace("3\n1\n1", "3.0\n1\n1"),
        1,
        "cone dimension",
    );
    bad(&DENSE_NEW.replace("10 20 30", "10 20 1e"), 11, "q[2] of 3");
    bad(&with_line(DENSE_NEW, 12, "0.5x"), 12, "eta[0]");
}

#[test]
fn wrong_sizes() {
    // Row count 4 for n = 3.
    bad(
        &with_line(DENSE_NEW, 5, "4"),
        5,
        "row count 3 (= d * n_c = 3 * 1)",
    );
    bad(&with_line(DENSE_NEW, 6, "2"), 6, "column count 3");
    bad(
        &with_line(DENSE_NEW, 7, "3\t4"),
        7,
        "repeated dense column count 3",
    );
    // n != d * n_c: two cones declared, 3x3 matrix, data for one cone: line 2 is wrong.
    bad(
        &with_line(DENSE_NEW, 2, "2"),
        2,
        "declares n_c = 2 cones, so n = d * n_c = 3 * 2 = 6, but the matrix (line 5) is 3 by 3 \
         and the 14 numbers after its header fit n_c = 1 (n = 3)",
    );
    bad(&with_line(DENSE_NEW, 1, "0"), 1, "cone dimension d >= 2");
    bad(&with_line(DENSE_NEW, 2, "0"), 2, "n_c >= 1");
    // Triplet size line disagreeing with n, and a short q.
    let t = sparse_text(
        "3\n1\n1\n2\n3\n3\n",
        &TRIPLETS.replace("3-by-3", "4-by-4"),
        "1 2 3\n1\n1\n",
    );
    bad(&t, 9, "triplet: 3-by-3");
    let t = sparse_text("3\n1\n1\n2\n3\n3\n", TRIPLETS, "1 2\n");
    bad(&t, 15, "q[2] of 3");
}

/// A wrong size line is reported as such, on the line that the numbers after the header
/// contradict, never as a token out of place further on (the old header read with `n_c`
/// wrong used to give "line 3: expected model type 1 (Drucker-Prager) or 2 (von Mises),
/// found `0`").
#[test]
fn wrong_size_lines_are_named() {
    // The old header (no model line), 10 cones declared as 11.
    let old = text("plasticity_2d_footing_10.dat");
    bad(
        &with_line(&old, 2, "11"),
        2,
        "declares n_c = 11 cones, so n = d * n_c = 3 * 11 = 33, but the matrix (line 4) is \
         30 by 30 and the 950 numbers after its header fit n_c = 10 (n = 30)",
    );
    // The cone dimension wrong instead (old header): 6 * 10 = 60 for a 30 x 30 matrix.
    bad(
        &with_line(&old, 1, "6"),
        1,
        "declares the cone dimension d = 6, so n = d * n_c = 6 * 10 = 60, but the matrix \
         (line 4) is 30 by 30 and the 950 numbers after its header fit d = 3",
    );
    // Both matrix size lines wrong (new header): the data fits n = d * n_c = 3.
    let footing = text("plasticity_2d_footing_1.dat");
    let t = with_line(&with_line(&footing, 5, "4"), 6, "4");
    bad(
        &with_line(&t, 7, "4\t4"),
        5,
        "declares a 4-by-4 matrix, but lines 1-2 declare n = d * n_c = 3 * 1 = 3, and the 14 \
         numbers after the matrix header fit n = 3",
    );
    // A sparse file (triplets) with n_c wrong, and one whose data fits no size.
    let sparse = text("plasticity_2d_example1.dat");
    bad(
        &with_line(&sparse, 2, "4"),
        2,
        "declares n_c = 4 cones, so n = d * n_c = 3 * 4 = 12, but the matrix (line 5) is 9 by 9 \
         and the 51 numbers after its header fit n_c = 3 (n = 9)",
    );
    let cut = sparse.lines().take(18).collect::<Vec<_>>().join("\n");
    bad(
        &with_line(&cut, 2, "4"),
        5,
        "declares a 9-by-9 matrix, but lines 1-2 declare n = d * n_c = 3 * 4 = 12; the 36 \
         numbers after the matrix header fit neither (51 for n = 9, 56 for n = 12)",
    );
    // CSC storage, n_c wrong.
    let csc = "3\n1\n2\n2\n3\n3\n2\n".to_string()
        + BANNER
        + "\n3-by-3, nzmax: 1 nnz: 1, 1-norm: 9\n    col 0 : locations 0 to 0\n      0 : 4\n    \
           col 1 : locations 1 to 0\n    col 2 : locations 1 to 0\n0 0 0\n2\n";
    bad(
        &csc.replacen("3\n1\n", "3\n2\n", 1),
        2,
        "declares n_c = 2 cones",
    );
}

/// A file's parse error names the file, then the line.
#[test]
fn parse_errors_name_the_file() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"));
    let p = dir.join("wrong_n_c.dat");
    std::fs::write(
        &p,
        with_line(&text("plasticity_2d_footing_10.dat"), 2, "11"),
    )
    .unwrap();
    let err = SiconosProblem::from_path(&p).unwrap_err();
    let msg = err.to_string();
    assert!(
        msg.starts_with(&format!("{}: line 2: declares n_c = 11", p.display())),
        "{msg}"
    );
    assert!(matches!(err.in_text(), SiconosError::Size { line: 2, .. }));
}

#[test]
fn huge_or_overflowing_sizes_do_not_allocate_or_panic() {
    // 10^9 x 10^9 declared, almost no data: must fail at end of input.
    let t = "2\n500000000\n1\n0\n1000000000\n1000000000\n1000000000\t1000000000\n1 2\n";
    bad(t, 8, "unexpected end of input");
    // n * n overflows usize.
    let big = 1usize << 33;
    let t = format!("2\n{}\n1\n0\n{big}\n{big}\n{big}\t{big}\n1\n", big / 2);
    bad(&t, 7, "square fits");
    // d * n_c overflows usize.
    let t = format!("{big}\n{big}\n1\n0\n");
    bad(&t, 2, "fits in usize");
    // A huge nnz with no triplets.
    let t = sparse_text(
        "3\n1\n1\n2\n3\n3\n",
        "triplet: 3-by-3, nzmax: 99999999999 nnz: 99999999999\n",
        "",
    );
    bad(&t, 9, "unexpected end of input");
}

#[test]
fn triplet_index_out_of_range_or_malformed() {
    let hdr = "3\n1\n1\n2\n3\n3\n";
    bad(
        &sparse_text(
            hdr,
            &TRIPLETS.replace("2 1 : -4", "3 1 : -4"),
            "1 2 3\n1\n1\n",
        ),
        12,
        "row index of triplet 2 of 5 in 0..3",
    );
    bad(
        &sparse_text(
            hdr,
            &TRIPLETS.replace("2 1 : -4", "2 7 : -4"),
            "1 2 3\n1\n1\n",
        ),
        12,
        "column index",
    );
    bad(
        &sparse_text(
            hdr,
            &TRIPLETS.replace("2 1 : -4", "-1 1 : -4"),
            "1 2 3\n1\n1\n",
        ),
        12,
        "found `-1`",
    );
    bad(
        &sparse_text(
            hdr,
            &TRIPLETS.replace("2 1 : -4", "2 1 = -4"),
            "1 2 3\n1\n1\n",
        ),
        12,
        "`:`",
    );
    // Missing banner, unknown origin, nnz > nzmax.
    let no_banner = format!("{hdr}1\n{TRIPLETS}1 2 3\n1\n1\n");
    bad(&no_banner, 8, "CSparse Version");
    bad(
        &sparse_text(hdr, TRIPLETS, "1 2 3\n1\n1\n").replacen("3\n1\nCSparse", "3\n3\nCSparse", 1),
        7,
        "sparse origin",
    );
    bad(
        &sparse_text(
            hdr,
            &TRIPLETS.replace("nzmax: 8", "nzmax: 4"),
            "1 2 3\n1\n1\n",
        ),
        9,
        "nnz",
    );
}

#[test]
fn nan_and_infinity_rejected_everywhere() {
    bad(&DENSE_NEW.replace("4 5 6", "4 NaN 6"), 9, "finite");
    bad(&DENSE_NEW.replace("4 5 6", "4 inf 6"), 9, "finite");
    bad(&DENSE_NEW.replace("10 20 30", "10 nan 30"), 11, "q[1]");
    bad(&with_line(DENSE_NEW, 12, "nan"), 12, "eta[0]");
    bad(&with_line(DENSE_NEW, 13, "-inf"), 13, "theta[0]");
    let hdr = "3\n1\n1\n2\n3\n3\n";
    bad(
        &sparse_text(hdr, &TRIPLETS.replace(": -4", ": nan"), "1 2 3\n1\n1\n"),
        12,
        "value of triplet 2",
    );
}

#[test]
fn negative_or_non_finite_parameters() {
    bad(
        &with_line(DENSE_NEW, 12, "-0.5"),
        12,
        "eta[0] of 1 (finite, >= 0)",
    );
    bad(&with_line(DENSE_NEW, 12, "infinity"), 12, "eta[0]");
    let vm = "3\n1\n2\n0\n3\n3\n3\t3\n1 2 3\n4 5 6\n7 8 9\n10 20 30\n";
    bad(&format!("{vm}-1.5\n"), 12, "sigma_y[0] of 1 (finite, >= 0)");
    bad(&format!("{vm}NaN\n"), 12, "sigma_y[0]");
    // A negative theta is allowed (only finiteness is required).
    let p = SiconosProblem::parse(&with_line(DENSE_NEW, 13, "-0.2")).unwrap();
    assert_eq!(
        p.model,
        SiconosModel::DruckerPrager {
            eta: vec![0.5],
            theta: vec![-0.2]
        }
    );
}

#[test]
fn unknown_storage_and_model() {
    bad(
        &with_line(DENSE_NEW, 4, "1"),
        4,
        "storage id 0 (dense) or 2 (sparse)",
    );
    bad(&with_line(DENSE_NEW, 4, "7"), 4, "found `7`");
    bad(
        &with_line(DENSE_NEW, 3, "3"),
        3,
        "model type 1 (Drucker-Prager) or 2 (von Mises)",
    );
    bad(&with_line(DENSE_NEW, 3, "0"), 3, "model type");
    bad(&with_line(DENSE_OLD, 3, "5"), 3, "model type");
}

#[test]
fn trailing_garbage_rejected() {
    bad(
        &format!("{DENSE_NEW}foo\n"),
        14,
        "end of input after the model parameters, found `foo`",
    );
    bad(&format!("{DENSE_NEW}\n\n  0\n"), 16, "found `0`");
    // A von Mises file with a theta line left over.
    let vm = "3\n1\n2\n0\n3\n3\n3\t3\n1 2 3\n4 5 6\n7 8 9\n10 20 30\n0.5\n0.1\n";
    bad(vm, 13, "found `0.1`");
}

#[test]
fn missing_file_is_io_error_naming_the_path() {
    let p = path("no_such_file.dat");
    let err = SiconosProblem::from_path(&p).unwrap_err();
    assert!(matches!(err, SiconosError::Io { .. }));
    assert!(err.to_string().contains("no_such_file.dat"), "{err}");
}
