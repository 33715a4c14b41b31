//! Reader for the Siconos plasticity test-problem text format
//! (`numerics/src/Plasticity/test/data/*.dat` in the Siconos project).
//!
//! # Conventions
//!
//! * All indices are 0-based; line numbers in errors are 1-based.
//! * The problem unknowns are grouped per cone: cone `i` owns entries
//!   `d*i .. d*(i+1)` of `R`, `v` and `q`; component 0 is the cone axis,
//!   components `1..d` the deviatoric part `T`.
//! * Values are returned exactly as stored in the file (no rescaling, no
//!   unit conversion; the Siconos files are dimensionless).
//!
//! # Layout (as written by Siconos `plasticity_printInFile`)
//!
//! ```text
//! d                 cone dimension
//! n_c               number of cones
//! model_type        1 = Drucker-Prager, 2 = von Mises   (absent in old files)
//! storage           NumericsMatrix storage id: 0 = dense, 2 = sparse
//! size0             rows (= n = d * n_c)
//! size1             columns (= n)
//! -- dense (0): --
//! size0<TAB>size1   sizes repeated
//! n*n values        column-major (the file's k-th value is entry (k % n, k / n))
//! -- sparse (2): --
//! origin            NumericsSparseMatrix origin: 1 = triplet, 2 = CSC
//! CSparse Version ...               (banner line, ignored)
//! triplet: m-by-n, nzmax: X nnz: Y  (then Y lines "row col : value")
//!   or, for CSC: m-by-n, nzmax: X nnz: Y, 1-norm: Z
//!                (then per column "col j : locations a to b" + "row : value")
//! -- then --
//! q                 n values
//! eta   | sigma_y   n_c values
//! theta             n_c values (Drucker-Prager only)
//! ```
//!
//! Old files (written by the former `plasticity2D_printInFile`, e.g.
//! `plasticity_2d_footing_10.dat`) have no `model_type` line and are always
//! Drucker-Prager. They are recognised by token structure, not file name.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::str::{Lines, SplitAsciiWhitespace};

/// One reduced problem: find R, v with v = W R + q and, per cone i,
/// R_i = P_K(R_i - rho (v_i0 + theta_i |v_iT|, v_iT)).
///
/// `K_i` is the Drucker-Prager cone of slope `eta_i` (or the von Mises
/// cylinder of radius `sigma_y,i`); see [`SiconosModel`].
#[derive(Debug, Clone, PartialEq)]
pub struct SiconosProblem {
    /// Components per cone, `d` (3 in all shipped files).
    pub cone_dimension: usize,
    /// Number of cones, `n_c`.
    pub n_cones: usize,
    /// The `n x n` matrix `W` (Siconos calls it `M`), `n = d * n_c`.
    pub matrix: SiconosMatrix,
    /// The vector `q`, length `n`.
    pub q: Vec<f64>,
    /// Yield model and its per-cone parameters.
    pub model: SiconosModel,
}

/// Storage of the problem matrix, as found in the file.
#[derive(Debug, Clone, PartialEq)]
pub enum SiconosMatrix {
    /// Row-major n*n values (converted from the file's column-major order).
    Dense { n: usize, values: Vec<f64> },
    /// Triplets (row, col, value) as stored; duplicates are summed by consumers.
    Sparse {
        n: usize,
        triplets: Vec<(usize, usize, f64)>,
    },
}

/// Per-cone model parameters (each vector has length `n_c`).
#[derive(Debug, Clone, PartialEq)]
pub enum SiconosModel {
    /// Cone `|R_T| <= eta_i R_0` with flow coupling `theta_i`
    /// (`theta_i = 0`: associative). `eta_i >= 0`; `theta_i` any finite value.
    DruckerPrager { eta: Vec<f64>, theta: Vec<f64> },
    /// Cylinder `|R_T| <= sigma_y,i` (axis component free), `sigma_y,i >= 0`.
    VonMises { sigma_y: Vec<f64> },
}

/// Why a file could not be read. Every parse error names the 1-based line,
/// what was expected and what was found.
#[derive(Debug, thiserror::Error)]
pub enum SiconosError {
    /// The file could not be read.
    #[error("cannot read Siconos problem {}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A token had the wrong form or an invalid value.
    #[error("line {line}: expected {expected}, found `{found}`")]
    Invalid {
        line: usize,
        expected: String,
        found: String,
    },
    /// The input ended before the problem was complete.
    #[error("line {line}: unexpected end of input, expected {expected}")]
    UnexpectedEof { line: usize, expected: String },
    /// Non-whitespace text after the last model parameter.
    #[error("line {line}: expected end of input after the model parameters, found `{found}`")]
    TrailingData { line: usize, found: String },
}

impl SiconosProblem {
    /// Reads and parses a `.dat` file.
    pub fn from_path(path: &Path) -> Result<Self, SiconosError> {
        let text = std::fs::read_to_string(path).map_err(|source| SiconosError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Self::parse(&text)
    }

    /// Parses the text of a `.dat` file (either header variant).
    pub fn parse(text: &str) -> Result<Self, SiconosError> {
        Parser::new(text).problem()
    }

    /// Problem size `n = d * n_c`.
    pub fn n(&self) -> usize {
        self.cone_dimension * self.n_cones
    }

    /// entry (i, j) regardless of storage (sums duplicate triplets); used by tests
    ///
    /// Panics if `i >= n` or `j >= n` (caller error, like slice indexing).
    pub fn matrix_entry(&self, i: usize, j: usize) -> f64 {
        let n = self.n();
        assert!(
            i < n && j < n,
            "matrix_entry({i}, {j}) out of range for n = {n}"
        );
        match &self.matrix {
            SiconosMatrix::Dense { n, values } => values[i * n + j],
            SiconosMatrix::Sparse { triplets, .. } => triplets
                .iter()
                .filter(|&&(r, c, _)| r == i && c == j)
                .map(|&(_, _, v)| v)
                .sum(),
        }
    }
}

/// Storage ids of Siconos `NM_types` (1 = sparse-block is not supported).
const STORAGE_DENSE: usize = 0;
const STORAGE_SPARSE: usize = 2;
/// `NumericsSparseOrigin`: 1 = triplet (COO), 2 = CSC.
const ORIGIN_TRIPLET: usize = 1;
const ORIGIN_CSC: usize = 2;

#[derive(Clone, Copy)]
struct Token<'a> {
    line: usize,
    text: &'a str,
}

/// Whitespace tokenizer that keeps 1-based line numbers and can also hand
/// out whole lines (the CSparse dump is line-oriented).
#[derive(Clone)]
struct Lexer<'a> {
    lines: Lines<'a>,
    /// Number of the line `words` comes from (0 before the first line).
    line: usize,
    words: SplitAsciiWhitespace<'a>,
}

impl<'a> Lexer<'a> {
    fn new(text: &'a str) -> Self {
        Lexer {
            lines: text.lines(),
            line: 0,
            words: "".split_ascii_whitespace(),
        }
    }

    fn next_token(&mut self) -> Option<Token<'a>> {
        loop {
            if let Some(text) = self.words.next() {
                return Some(Token {
                    line: self.line,
                    text,
                });
            }
            let l = self.lines.next()?;
            self.line += 1;
            self.words = l.split_ascii_whitespace();
        }
    }

    /// Remaining tokens of the current line (empty if none).
    fn rest_of_line(&mut self) -> Vec<Token<'a>> {
        let line = self.line;
        self.words
            .by_ref()
            .map(|text| Token { line, text })
            .collect()
    }

    /// Next whole line as (number, tokens), dropping what is left of the
    /// current one.
    fn next_line(&mut self) -> Option<(usize, Vec<&'a str>)> {
        let l = self.lines.next()?;
        self.line += 1;
        self.words = "".split_ascii_whitespace();
        Some((self.line, l.split_ascii_whitespace().collect()))
    }
}

struct Parser<'a> {
    lex: Lexer<'a>,
    /// Line reported for an unexpected end of input.
    last_line: usize,
    /// Upper bound on how many numbers the input can still hold, so a
    /// corrupt size cannot trigger a huge allocation.
    max_numbers: usize,
}

/// Quote at most 40 characters of an offending token.
fn shown(s: &str) -> String {
    if s.chars().count() <= 40 {
        s.to_string()
    } else {
        let mut out: String = s.chars().take(40).collect();
        out.push_str("...");
        out
    }
}

fn invalid(tok: Token<'_>, expected: impl Into<String>) -> SiconosError {
    SiconosError::Invalid {
        line: tok.line,
        expected: expected.into(),
        found: shown(tok.text),
    }
}

fn parse_usize(tok: Token<'_>, what: &str) -> Result<usize, SiconosError> {
    tok.text
        .parse::<usize>()
        .map_err(|_| invalid(tok, format!("{what} (a non-negative integer)")))
}

fn parse_finite(tok: Token<'_>, what: &str) -> Result<f64, SiconosError> {
    match tok.text.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(invalid(tok, format!("{what} (a finite number)"))),
    }
}

/// Header layout, decided before strict parsing.
#[derive(Debug, PartialEq)]
enum Header {
    /// d, n_c, model_type, storage, ...
    WithModel,
    /// d, n_c, storage, ... (old Plasticity2D writer, Drucker-Prager)
    Old,
}

impl<'a> Parser<'a> {
    fn new(text: &'a str) -> Self {
        Parser {
            lex: Lexer::new(text),
            last_line: text.lines().count().max(1),
            max_numbers: text.len() / 2 + 1,
        }
    }

    fn expect(&mut self, what: &str) -> Result<Token<'a>, SiconosError> {
        self.lex
            .next_token()
            .ok_or_else(|| SiconosError::UnexpectedEof {
                line: self.last_line,
                expected: what.to_string(),
            })
    }

    fn usize(&mut self, what: &str) -> Result<(Token<'a>, usize), SiconosError> {
        let tok = self.expect(what)?;
        Ok((tok, parse_usize(tok, what)?))
    }

    fn finite(&mut self, what: &str) -> Result<f64, SiconosError> {
        let tok = self.expect(what)?;
        parse_finite(tok, what)
    }

    /// An exact integer value, e.g. a repeated size.
    fn exact(&mut self, what: &str, want: usize) -> Result<(), SiconosError> {
        let tok = self.expect(what)?;
        match tok.text.parse::<usize>() {
            Ok(v) if v == want => Ok(()),
            _ => Err(invalid(tok, what)),
        }
    }

    fn vector(&mut self, len: usize, what: &str) -> Result<Vec<f64>, SiconosError> {
        let mut out = Vec::with_capacity(len.min(self.max_numbers));
        for k in 0..len {
            out.push(self.finite(&format!("{what}[{k}] of {len}"))?);
        }
        Ok(out)
    }

    /// Decides the header variant from token structure. Old layout iff
    /// tokens 3..=5 read `storage n n` with storage 0 or 2 and the matrix
    /// that follows starts as expected (`n n` again for dense, an origin then
    /// the `CSparse` banner for sparse). The new layout can only look like
    /// `x n n` when n = 2 and storage 2, and then token 7 is the origin, not
    /// `CSparse`, so the two are never confused.
    fn detect_header(&self) -> Header {
        let mut lex = self.lex.clone();
        let toks: Vec<&str> = std::iter::from_fn(|| lex.next_token())
            .take(7)
            .map(|t| t.text)
            .collect();
        let num = |k: usize| toks.get(k).and_then(|s| s.parse::<usize>().ok());
        let n = match (num(0), num(1)) {
            (Some(d), Some(nc)) => d.checked_mul(nc),
            _ => None,
        };
        let Some(n) = n.filter(|&n| n > 0) else {
            return Header::WithModel;
        };
        if num(3) != Some(n) || num(4) != Some(n) {
            return Header::WithModel;
        }
        let old = match num(2) {
            Some(STORAGE_DENSE) => num(5) == Some(n) && num(6) == Some(n),
            Some(STORAGE_SPARSE) => num(5).is_some() && toks.get(6) == Some(&"CSparse"),
            _ => false,
        };
        if old {
            Header::Old
        } else {
            Header::WithModel
        }
    }

    fn problem(mut self) -> Result<SiconosProblem, SiconosError> {
        let header = self.detect_header();
        let (tok, d) = self.usize("cone dimension d")?;
        if d < 2 {
            return Err(invalid(tok, "cone dimension d >= 2"));
        }
        let (tok, n_cones) = self.usize("number of cones n_c")?;
        if n_cones == 0 {
            return Err(invalid(tok, "number of cones n_c >= 1"));
        }
        let n = d
            .checked_mul(n_cones)
            .ok_or_else(|| invalid(tok, "n_c such that d * n_c fits in usize"))?;

        // Siconos PlasticityModelType: 1 = Drucker-Prager, 2 = von Mises.
        let von_mises = match header {
            Header::Old => false,
            Header::WithModel => {
                let what = "model type 1 (Drucker-Prager) or 2 (von Mises)";
                let tok = self.expect(what)?;
                match tok.text {
                    "1" => false,
                    "2" => true,
                    _ => return Err(invalid(tok, what)),
                }
            }
        };

        let matrix = self.matrix(n, d, n_cones)?;
        let q = self.vector(n, "q")?;

        let model = if von_mises {
            let sigma_y = self.nonnegative(n_cones, "sigma_y")?;
            SiconosModel::VonMises { sigma_y }
        } else {
            let eta = self.nonnegative(n_cones, "eta")?;
            let theta = self.vector(n_cones, "theta")?;
            SiconosModel::DruckerPrager { eta, theta }
        };

        if let Some(tok) = self.lex.next_token() {
            return Err(SiconosError::TrailingData {
                line: tok.line,
                found: shown(tok.text),
            });
        }
        Ok(SiconosProblem {
            cone_dimension: d,
            n_cones,
            matrix,
            q,
            model,
        })
    }

    fn nonnegative(&mut self, len: usize, what: &str) -> Result<Vec<f64>, SiconosError> {
        let mut out = Vec::with_capacity(len.min(self.max_numbers));
        for k in 0..len {
            let label = format!("{what}[{k}] of {len} (finite, >= 0)");
            let tok = self.expect(&label)?;
            match tok.text.parse::<f64>() {
                Ok(v) if v.is_finite() && v >= 0.0 => out.push(v),
                _ => return Err(invalid(tok, label)),
            }
        }
        Ok(out)
    }

    fn matrix(&mut self, n: usize, d: usize, nc: usize) -> Result<SiconosMatrix, SiconosError> {
        let what = "matrix storage id 0 (dense) or 2 (sparse)";
        let tok = self.expect(what)?;
        let storage = match tok.text.parse::<usize>() {
            Ok(s @ (STORAGE_DENSE | STORAGE_SPARSE)) => s,
            _ => return Err(invalid(tok, what)),
        };
        let size = format!("{n} (= d * n_c = {d} * {nc})");
        self.exact(&format!("matrix row count {size}"), n)?;
        self.exact(&format!("matrix column count {size}"), n)?;
        if storage == STORAGE_DENSE {
            self.dense(n)
        } else {
            self.sparse(n)
        }
    }

    fn dense(&mut self, n: usize) -> Result<SiconosMatrix, SiconosError> {
        // NM_write_in_file repeats "size0<TAB>size1" before the values.
        self.exact(&format!("repeated dense row count {n}"), n)?;
        self.exact(&format!("repeated dense column count {n}"), n)?;
        let nn = n.checked_mul(n).ok_or_else(|| SiconosError::Invalid {
            line: self.lex.line,
            expected: "a matrix size whose square fits in usize".into(),
            found: n.to_string(),
        })?;
        let mut col_major = Vec::with_capacity(nn.min(self.max_numbers));
        let mut label = String::new();
        for k in 0..nn {
            let tok = self.expect_dense(&mut label, k, n)?;
            match tok.text.parse::<f64>() {
                Ok(v) if v.is_finite() => col_major.push(v),
                _ => {
                    dense_label(&mut label, k, n);
                    return Err(invalid(tok, format!("{label} (a finite number)")));
                }
            }
        }
        // Siconos dense storage is column-major: value k is entry (k % n, k / n).
        let mut values = vec![0.0; nn];
        for (k, v) in col_major.into_iter().enumerate() {
            values[(k % n) * n + k / n] = v;
        }
        Ok(SiconosMatrix::Dense { n, values })
    }

    /// Like `expect`, but builds the label only on failure (hot loop).
    fn expect_dense(
        &mut self,
        label: &mut String,
        k: usize,
        n: usize,
    ) -> Result<Token<'a>, SiconosError> {
        match self.lex.next_token() {
            Some(t) => Ok(t),
            None => {
                dense_label(label, k, n);
                Err(SiconosError::UnexpectedEof {
                    line: self.last_line,
                    expected: label.clone(),
                })
            }
        }
    }

    fn sparse(&mut self, n: usize) -> Result<SiconosMatrix, SiconosError> {
        let what = "sparse origin 1 (triplet) or 2 (CSC)";
        let tok = self.expect(what)?;
        let origin = match tok.text.parse::<usize>() {
            Ok(o @ (ORIGIN_TRIPLET | ORIGIN_CSC)) => o,
            _ => return Err(invalid(tok, what)),
        };
        if let Some(extra) = self.lex.rest_of_line().first() {
            return Err(invalid(*extra, "end of line after the sparse origin"));
        }
        // CSparseMatrix_new_from_file skips the "CSparse Version" banner.
        let banner = "the `CSparse Version ...` banner line";
        let (line, words) = self.line(banner)?;
        if words.first() != Some(&"CSparse") {
            return Err(line_invalid(line, &words, banner));
        }
        let (line, words) = self.line("the CSparse size line")?;
        let nnz = self.csparse_header(line, &words, n, origin)?;
        let mut triplets = Vec::with_capacity(nnz.min(self.max_numbers / 4));
        if origin == ORIGIN_TRIPLET {
            for p in 0..nnz {
                let row = self.index(&format!("row index of triplet {p} of {nnz}"), n)?;
                let col = self.index(&format!("column index of triplet {p} of {nnz}"), n)?;
                self.colon(&format!("`:` in triplet {p} of {nnz}"))?;
                let v = self.finite(&format!("value of triplet {p} of {nnz}"))?;
                triplets.push((row, col, v));
            }
        } else {
            self.csc(n, nnz, &mut triplets)?;
        }
        Ok(SiconosMatrix::Sparse { n, triplets })
    }

    /// CSC dump: per column `col j : locations a to b`, then `row : value`.
    fn csc(
        &mut self,
        n: usize,
        nnz: usize,
        triplets: &mut Vec<(usize, usize, f64)>,
    ) -> Result<(), SiconosError> {
        let mut next = 0usize;
        for j in 0..n {
            let head = format!("`col {j} : locations {next} to ...`");
            let tok = self.expect(&head)?;
            if tok.text != "col" {
                return Err(invalid(tok, head));
            }
            self.exact(&format!("column number {j}"), j)?;
            self.colon(&format!("`:` after column number {j}"))?;
            let tok = self.expect(&head)?;
            if tok.text != "locations" {
                return Err(invalid(tok, head));
            }
            self.exact(&format!("first location {next} of column {j}"), next)?;
            let tok = self.expect(&head)?;
            if tok.text != "to" {
                return Err(invalid(tok, head));
            }
            // "to a-1" marks an empty column; CSparse prints it as a signed integer.
            let tok = self.expect(&format!("last location of column {j}"))?;
            let end = match tok.text.parse::<i128>() {
                Ok(b) if b + 1 >= next as i128 && b < nnz as i128 => (b + 1) as usize,
                _ => {
                    return Err(invalid(
                        tok,
                        format!("last location of column {j} in {}..{nnz}", next as i128 - 1),
                    ))
                }
            };
            for p in next..end {
                let row = self.index(&format!("row index of entry {p} of {nnz}"), n)?;
                self.colon(&format!("`:` in entry {p} of {nnz}"))?;
                let v = self.finite(&format!("value of entry {p} of {nnz}"))?;
                triplets.push((row, j, v));
            }
            next = end;
        }
        if next != nnz {
            return Err(SiconosError::Invalid {
                line: self.lex.line,
                expected: format!("{nnz} CSC entries (from the size line)"),
                found: next.to_string(),
            });
        }
        Ok(())
    }

    fn line(&mut self, what: &str) -> Result<(usize, Vec<&'a str>), SiconosError> {
        self.lex
            .next_line()
            .ok_or_else(|| SiconosError::UnexpectedEof {
                line: self.last_line,
                expected: what.to_string(),
            })
    }

    fn index(&mut self, what: &str, n: usize) -> Result<usize, SiconosError> {
        let tok = self.expect(what)?;
        match tok.text.parse::<usize>() {
            Ok(i) if i < n => Ok(i),
            _ => Err(invalid(tok, format!("{what} in 0..{n}"))),
        }
    }

    fn colon(&mut self, what: &str) -> Result<(), SiconosError> {
        let tok = self.expect(what)?;
        if tok.text == ":" {
            Ok(())
        } else {
            Err(invalid(tok, what))
        }
    }

    /// Parses `triplet: m-by-n, nzmax: X nnz: Y` (or the CSC form without
    /// `triplet:` and with `, 1-norm: Z`) and returns Y.
    fn csparse_header(
        &self,
        line: usize,
        words: &[&str],
        n: usize,
        origin: usize,
    ) -> Result<usize, SiconosError> {
        let triplet = origin == ORIGIN_TRIPLET;
        let expected = if triplet {
            format!("`triplet: {n}-by-{n}, nzmax: <count> nnz: <count>`")
        } else {
            format!("`{n}-by-{n}, nzmax: <count> nnz: <count>, 1-norm: <value>`")
        };
        let err = || line_invalid(line, words, &expected);
        let w = if triplet {
            match words.split_first() {
                Some((&"triplet:", rest)) => rest,
                _ => return Err(err()),
            }
        } else {
            words
        };
        let size = format!("{n}-by-{n},");
        if w.len() < 5 || w[0] != size || w[1] != "nzmax:" || w[3] != "nnz:" {
            return Err(err());
        }
        let nzmax = w[2].parse::<usize>().map_err(|_| err())?;
        let nnz_text = w[4].strip_suffix(',').unwrap_or(w[4]);
        let nnz = nnz_text.parse::<usize>().map_err(|_| err())?;
        // Triplet: nnz <= nzmax (allocation). CSC: "1-norm: Z" follows.
        let tail_ok = if triplet {
            w.len() == 5 && nnz <= nzmax
        } else {
            w.len() == 7 && w[4].ends_with(',') && w[5] == "1-norm:"
        };
        if !tail_ok {
            return Err(err());
        }
        Ok(nnz)
    }
}

fn dense_label(label: &mut String, k: usize, n: usize) {
    label.clear();
    let _ = write!(
        label,
        "dense matrix value {k} of {} (entry ({}, {}), column-major)",
        n * n,
        k % n,
        k / n
    );
}

fn line_invalid(line: usize, words: &[&str], expected: &str) -> SiconosError {
    SiconosError::Invalid {
        line,
        expected: expected.to_string(),
        found: shown(&words.join(" ")),
    }
}
