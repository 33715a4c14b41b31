//! The strict parser of a Siconos problem: header, `q` and the per-cone parameters; the
//! matrix in `matrix.rs`.
use super::lexer::{invalid, parse_finite, parse_usize, shown, Lexer, Token};
use super::{SiconosError, SiconosModel, SiconosProblem, STORAGE_DENSE, STORAGE_SPARSE};

pub(super) struct Parser<'a> {
    pub(super) lex: Lexer<'a>,
    /// Line reported for an unexpected end of input.
    pub(super) last_line: usize,
    /// Upper bound on how many numbers the input can still hold, so a
    /// corrupt size cannot trigger a huge allocation.
    pub(super) max_numbers: usize,
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
    pub(super) fn new(text: &'a str) -> Self {
        Parser {
            lex: Lexer::new(text),
            last_line: text.lines().count().max(1),
            max_numbers: text.len() / 2 + 1,
        }
    }

    pub(super) fn expect(&mut self, what: &str) -> Result<Token<'a>, SiconosError> {
        self.lex
            .next_token()
            .ok_or_else(|| SiconosError::UnexpectedEof {
                line: self.last_line,
                expected: what.to_string(),
            })
    }

    pub(super) fn usize(&mut self, what: &str) -> Result<(Token<'a>, usize), SiconosError> {
        let tok = self.expect(what)?;
        Ok((tok, parse_usize(tok, what)?))
    }

    pub(super) fn finite(&mut self, what: &str) -> Result<f64, SiconosError> {
        let tok = self.expect(what)?;
        parse_finite(tok, what)
    }

    /// An exact integer value, e.g. a repeated size.
    pub(super) fn exact(&mut self, what: &str, want: usize) -> Result<(), SiconosError> {
        let tok = self.expect(what)?;
        match tok.text.parse::<usize>() {
            Ok(v) if v == want => Ok(()),
            _ => Err(invalid(tok, what)),
        }
    }

    pub(super) fn vector(&mut self, len: usize, what: &str) -> Result<Vec<f64>, SiconosError> {
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

    pub(super) fn problem(mut self) -> Result<SiconosProblem, SiconosError> {
        let header = self.detect_header();
        let (d_tok, d) = self.usize("cone dimension d")?;
        if d < 2 {
            return Err(invalid(d_tok, "cone dimension d >= 2"));
        }
        let (tok, n_cones) = self.usize("number of cones n_c")?;
        if n_cones == 0 {
            return Err(invalid(tok, "number of cones n_c >= 1"));
        }
        let n = d
            .checked_mul(n_cones)
            .ok_or_else(|| invalid(tok, "n_c such that d * n_c fits in usize"))?;
        if let Some(e) = self.misdeclared_size((d_tok, d), (tok, n_cones)) {
            return Err(e);
        }

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

    pub(super) fn nonnegative(&mut self, len: usize, what: &str) -> Result<Vec<f64>, SiconosError> {
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
}
