//! The matrix `W` of a Siconos problem: dense column-major, or a CSparse dump (triplet or
//! CSC).
use std::fmt::Write as _;

use super::lexer::{invalid, line_invalid, Token};
use super::parser::Parser;
use super::{
    SiconosError, SiconosMatrix, ORIGIN_CSC, ORIGIN_TRIPLET, STORAGE_DENSE, STORAGE_SPARSE,
};

impl<'a> Parser<'a> {
    pub(super) fn matrix(
        &mut self,
        n: usize,
        d: usize,
        nc: usize,
    ) -> Result<SiconosMatrix, SiconosError> {
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

    pub(super) fn dense(&mut self, n: usize) -> Result<SiconosMatrix, SiconosError> {
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
    pub(super) fn expect_dense(
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

    pub(super) fn sparse(&mut self, n: usize) -> Result<SiconosMatrix, SiconosError> {
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
    pub(super) fn csc(
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

    pub(super) fn line(&mut self, what: &str) -> Result<(usize, Vec<&'a str>), SiconosError> {
        self.lex
            .next_line()
            .ok_or_else(|| SiconosError::UnexpectedEof {
                line: self.last_line,
                expected: what.to_string(),
            })
    }

    pub(super) fn index(&mut self, what: &str, n: usize) -> Result<usize, SiconosError> {
        let tok = self.expect(what)?;
        match tok.text.parse::<usize>() {
            Ok(i) if i < n => Ok(i),
            _ => Err(invalid(tok, format!("{what} in 0..{n}"))),
        }
    }

    pub(super) fn colon(&mut self, what: &str) -> Result<(), SiconosError> {
        let tok = self.expect(what)?;
        if tok.text == ":" {
            Ok(())
        } else {
            Err(invalid(tok, what))
        }
    }

    /// Parses `triplet: m-by-n, nzmax: X nnz: Y` (or the CSC form without
    /// `triplet:` and with `, 1-norm: Z`) and returns Y.
    pub(super) fn csparse_header(
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
