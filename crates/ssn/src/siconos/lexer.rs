//! The whitespace tokenizer of the Siconos format, with 1-based line numbers, and the
//! checks on single tokens.
use std::str::{Lines, SplitAsciiWhitespace};

use super::SiconosError;

#[derive(Clone, Copy)]
pub(super) struct Token<'a> {
    pub(super) line: usize,
    pub(super) text: &'a str,
}

/// Whitespace tokenizer that keeps 1-based line numbers and can also hand
/// out whole lines (the CSparse dump is line-oriented).
#[derive(Clone)]
pub(super) struct Lexer<'a> {
    pub(super) lines: Lines<'a>,
    /// Number of the line `words` comes from (0 before the first line).
    pub(super) line: usize,
    pub(super) words: SplitAsciiWhitespace<'a>,
}

impl<'a> Lexer<'a> {
    pub(super) fn new(text: &'a str) -> Self {
        Lexer {
            lines: text.lines(),
            line: 0,
            words: "".split_ascii_whitespace(),
        }
    }

    pub(super) fn next_token(&mut self) -> Option<Token<'a>> {
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
    pub(super) fn rest_of_line(&mut self) -> Vec<Token<'a>> {
        let line = self.line;
        self.words
            .by_ref()
            .map(|text| Token { line, text })
            .collect()
    }

    /// Next whole line as (number, tokens), dropping what is left of the
    /// current one.
    pub(super) fn next_line(&mut self) -> Option<(usize, Vec<&'a str>)> {
        let l = self.lines.next()?;
        self.line += 1;
        self.words = "".split_ascii_whitespace();
        Some((self.line, l.split_ascii_whitespace().collect()))
    }
}

/// Quote at most 40 characters of an offending token.
pub(super) fn shown(s: &str) -> String {
    if s.chars().count() <= 40 {
        s.to_string()
    } else {
        let mut out: String = s.chars().take(40).collect();
        out.push_str("...");
        out
    }
}

pub(super) fn invalid(tok: Token<'_>, expected: impl Into<String>) -> SiconosError {
    SiconosError::Invalid {
        line: tok.line,
        expected: expected.into(),
        found: shown(tok.text),
    }
}

pub(super) fn parse_usize(tok: Token<'_>, what: &str) -> Result<usize, SiconosError> {
    tok.text
        .parse::<usize>()
        .map_err(|_| invalid(tok, format!("{what} (a non-negative integer)")))
}

pub(super) fn parse_finite(tok: Token<'_>, what: &str) -> Result<f64, SiconosError> {
    match tok.text.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(invalid(tok, format!("{what} (a finite number)"))),
    }
}

pub(super) fn line_invalid(line: usize, words: &[&str], expected: &str) -> SiconosError {
    SiconosError::Invalid {
        line,
        expected: expected.to_string(),
        found: shown(&words.join(" ")),
    }
}
