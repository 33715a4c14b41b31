//! A header whose sizes disagree (`n = d * n_c` against the matrix size lines), told as
//! such: the numbers that follow the header are counted to say which line is wrong, instead
//! of the strict parser stumbling later on a token out of place (with `n_c` wrong in an old
//! header, it would read the storage id as the model type).
use super::lexer::{Lexer, Token};
use super::parser::Parser;
use super::{SiconosError, ORIGIN_CSC, ORIGIN_TRIPLET, STORAGE_DENSE, STORAGE_SPARSE};

/// The header after `d` and `n_c`, as its tokens lay it out.
struct Layout<'a> {
    /// Per-cone parameters after `q`: 2 (Drucker-Prager: eta, theta) or 1 (von Mises).
    per_cone: u128,
    /// The matrix row count, and its value `m` (the column count equals it).
    rows: Token<'a>,
    m: usize,
    storage: Storage,
    /// The tokens after the matrix header (dense: after the repeated sizes; sparse: after
    /// the CSparse size line).
    rest: Lexer<'a>,
}

enum Storage {
    Dense,
    Triplet { nnz: u128 },
    Csc { nnz: u128 },
}

impl Layout<'_> {
    /// How many numbers follow the matrix header for size `s` and `c` cones.
    fn numbers(&self, s: usize, c: usize) -> u128 {
        let (s, c) = (s as u128, c as u128);
        let matrix = match self.storage {
            Storage::Dense => s * s,
            // `row col : value` per entry.
            Storage::Triplet { nnz } => 4 * nnz,
            // `col j : locations a to b` per column, `row : value` per entry.
            Storage::Csc { nnz } => 7 * s + 3 * nnz,
        };
        matrix + s + self.per_cone * c
    }
}

impl<'a> Parser<'a> {
    /// `Some` error when the header reads as a whole (model, storage, sizes) but its matrix
    /// size `m` is not `d * n_c`; `None` otherwise (the strict parser reports the rest).
    pub(super) fn misdeclared_size(
        &self,
        (d_tok, d): (Token<'a>, usize),
        (nc_tok, nc): (Token<'a>, usize),
    ) -> Option<SiconosError> {
        let n = d.checked_mul(nc)?;
        let layout = self.layout()?;
        let m = layout.m;
        if m == n {
            return None;
        }
        let found = layout.rest.clone().count_tokens();
        let fits = |s: usize, c: usize| layout.numbers(s, c) == found;
        let matrix_line = layout.rows.line;
        let declared = format!("n = d * n_c = {d} * {nc} = {n}");
        let (line, message) = if m % d == 0 && fits(m, m / d) {
            (
                nc_tok.line,
                format!(
                    "declares n_c = {nc} cones, so {declared}, but the matrix (line \
                     {matrix_line}) is {m} by {m} and the {found} numbers after its header fit \
                     n_c = {} (n = {m})",
                    m / d
                ),
            )
        } else if m % nc == 0 && m / nc >= 2 && fits(m, nc) {
            (
                d_tok.line,
                format!(
                    "declares the cone dimension d = {d}, so {declared}, but the matrix (line \
                     {matrix_line}) is {m} by {m} and the {found} numbers after its header fit \
                     d = {} (n = {m})",
                    m / nc
                ),
            )
        } else if fits(n, nc) {
            (
                matrix_line,
                format!(
                    "declares a {m}-by-{m} matrix, but lines {}-{} declare {declared}, and the \
                     {found} numbers after the matrix header fit n = {n}",
                    d_tok.line, nc_tok.line
                ),
            )
        } else {
            (
                matrix_line,
                format!(
                    "declares a {m}-by-{m} matrix, but lines {}-{} declare {declared}; the \
                     {found} numbers after the matrix header fit neither ({} for n = {m}, {} \
                     for n = {n})",
                    d_tok.line,
                    nc_tok.line,
                    layout.numbers(m, m / d),
                    layout.numbers(n, nc)
                ),
            )
        };
        Some(SiconosError::Size { line, message })
    }

    /// The header as laid out by the new writer (`model storage m m`) or the old one
    /// (`storage m m`), with the matrix header that follows; `None` if neither reads.
    fn layout(&self) -> Option<Layout<'a>> {
        let mut lex = self.lex.clone();
        let toks: Vec<Token<'a>> = std::iter::from_fn(|| lex.next_token()).take(6).collect();
        let num = |k: usize| toks.get(k).and_then(|t| t.text.parse::<usize>().ok());
        let per_cone = match toks.first().map(|t| t.text) {
            Some("1") => Some(2),
            Some("2") => Some(1),
            _ => None,
        };
        // New layout first: `model storage m m`, then the old `storage m m`.
        let new = per_cone.map(|p| (p, 1));
        [new, Some((2, 0))]
            .into_iter()
            .flatten()
            .find_map(|(per_cone, at)| {
                let storage = num(at).filter(|s| matches!(*s, STORAGE_DENSE | STORAGE_SPARSE))?;
                let m = num(at + 1).filter(|&m| num(at + 2) == Some(m))?;
                let mut rest = self.lex.clone();
                let storage = if storage == STORAGE_DENSE {
                    if num(at + 3) != Some(m) || num(at + 4) != Some(m) {
                        return None;
                    }
                    rest.skip_tokens(at + 5);
                    Storage::Dense
                } else {
                    let origin =
                        num(at + 3).filter(|o| matches!(*o, ORIGIN_TRIPLET | ORIGIN_CSC))?;
                    rest.skip_tokens(at + 4);
                    let banner = rest.next_line()?.1;
                    if banner.first() != Some(&"CSparse") {
                        return None;
                    }
                    let (_, size) = rest.next_line()?;
                    let at = size.iter().position(|w| *w == "nnz:")?;
                    let nnz = size
                        .get(at + 1)?
                        .trim_end_matches(',')
                        .parse::<u128>()
                        .ok()?;
                    if origin == ORIGIN_TRIPLET {
                        Storage::Triplet { nnz }
                    } else {
                        Storage::Csc { nnz }
                    }
                };
                Some(Layout {
                    per_cone,
                    rows: toks[at + 1],
                    m,
                    storage,
                    rest,
                })
            })
    }
}

impl Lexer<'_> {
    fn skip_tokens(&mut self, k: usize) {
        for _ in 0..k {
            self.next_token();
        }
    }

    fn count_tokens(mut self) -> u128 {
        let mut count = 0;
        while self.next_token().is_some() {
            count += 1;
        }
        count
    }
}
