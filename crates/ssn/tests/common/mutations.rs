//! Byte- and line-level mutations of valid seed files, and the harness that feeds them to a
//! reader: the fuzz tests of the three readers users give files to (`fuzz_siconos_reader.rs`
//! here, `crates/fem/tests/fuzz_msh_reader.rs`, `crates/talus/tests/fuzz_scene_reader.rs`,
//! which include this file by path; `docs/scenes.md`, 'Fuzzing').
//!
//! A case is a seed and up to [`MAX_MUTATIONS`] mutations applied in turn. The reader runs
//! under `catch_unwind`: a panic fails the property with the input that caused it, shrunk.
//! `TALUS_FUZZ_CASES` sets the number of cases, `TALUS_FUZZ_SCALE` multiplies the defaults
//! (`cargo xtask fuzz` raises them); each test
//! prints one line `fuzz <reader>: <cases> cases (<read> read, <refused> refused), 0 panics,
//! <seconds> s` that `cargo xtask fuzz` reports.
#![allow(dead_code)] // each fuzz test uses its own part

use std::cell::Cell;
use std::fmt;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::Instant;

use proptest::prelude::*;
use proptest::sample::{select, Index};
use proptest::test_runner::{Config, RngSeed, TestCaseError, TestRunner};

/// Mutations applied to one seed, at most.
pub const MAX_MUTATIONS: usize = 4;

/// Numbers that break readers: zeros, signs, overflow and underflow of f64, NaN and
/// infinities in the spellings of Rust, TOML and C, integers at and past the limits of
/// u32/i64/u64, and small sizes that shift a count by one.
pub const EXTREMES: &[&str] = &[
    "0",
    "-0",
    "-1",
    "1",
    "2",
    "3",
    "4",
    "6",
    "1000000",
    "0.5",
    "-0.5",
    "1e300",
    "-1e300",
    "1e-300",
    "4.9e-324",
    "1e999",
    "NaN",
    "nan",
    "inf",
    "-inf",
    "+inf",
    "infinity",
    "2147483647",
    "4294967296",
    "9223372036854775807",
    "-9223372036854775808",
    "18446744073709551615",
    "18446744073709551616",
    "99999999999999999999999999",
];

/// One edit of a file.
#[derive(Clone)]
pub enum Mutation {
    DeleteLine(Index),
    DuplicateLine(Index),
    SwapLines(Index, Index),
    /// Replace the k-th number (a run of `[0-9.eE+-]` holding a digit) by the text.
    ReplaceNumber(Index, String),
    /// Delete the k-th number.
    DeleteNumber(Index),
    TruncateAt(Index),
    InsertBytes(Index, Vec<u8>),
    SetByte(Index, u8),
}

impl fmt::Debug for Mutation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let i = |x: &Index| x.index(1 << 20);
        match self {
            Mutation::DeleteLine(a) => write!(f, "DeleteLine({})", i(a)),
            Mutation::DuplicateLine(a) => write!(f, "DuplicateLine({})", i(a)),
            Mutation::SwapLines(a, b) => write!(f, "SwapLines({}, {})", i(a), i(b)),
            Mutation::ReplaceNumber(a, s) => write!(f, "ReplaceNumber({}, {s:?})", i(a)),
            Mutation::DeleteNumber(a) => write!(f, "DeleteNumber({})", i(a)),
            Mutation::TruncateAt(a) => write!(f, "TruncateAt({})", i(a)),
            Mutation::InsertBytes(a, b) => {
                write!(f, "InsertBytes({}, {:?})", i(a), String::from_utf8_lossy(b))
            }
            Mutation::SetByte(a, b) => write!(f, "SetByte({}, {b:#04x})", i(a)),
        }
    }
}

/// A replacement number: an extreme, a random float in several spellings, or a small
/// integer (sizes, counts, indices, tags).
pub fn number() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => select(EXTREMES).prop_map(str::to_string),
        2 => (0u64..64).prop_map(|v| v.to_string()),
        1 => any::<i64>().prop_map(|v| v.to_string()),
        1 => any::<f64>().prop_map(|v| format!("{v:e}")),
        1 => (-1e6f64..1e6).prop_map(|v| format!("{v}")),
    ]
}

/// Bytes worth inserting: separators and comment marks of the three formats, quotes,
/// brackets, non-ASCII text, NUL and control bytes, or anything.
pub fn insertion() -> impl Strategy<Value = Vec<u8>> {
    prop_oneof![
        select(
            &[
                " ",
                "\n",
                "\t",
                "\r\n",
                "#",
                "=",
                "[",
                "]",
                "[[",
                "{",
                "}",
                "\"",
                "'",
                ",",
                ":",
                "$",
                "-",
                ".",
                "é",
                "\u{feff}",
                "\0",
                "\\",
                "$EndNodes\n",
                "$Nodes\n",
                "[mesh]\n",
                "[grid]\n",
                "col",
                "CSparse",
            ][..]
        )
        .prop_map(|s| s.as_bytes().to_vec()),
        proptest::collection::vec(any::<u8>(), 1..8),
    ]
}

pub fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        2 => any::<Index>().prop_map(Mutation::DeleteLine),
        2 => any::<Index>().prop_map(Mutation::DuplicateLine),
        1 => (any::<Index>(), any::<Index>()).prop_map(|(a, b)| Mutation::SwapLines(a, b)),
        6 => (any::<Index>(), number()).prop_map(|(a, s)| Mutation::ReplaceNumber(a, s)),
        1 => any::<Index>().prop_map(Mutation::DeleteNumber),
        1 => any::<Index>().prop_map(Mutation::TruncateAt),
        2 => (any::<Index>(), insertion()).prop_map(|(a, b)| Mutation::InsertBytes(a, b)),
        1 => (any::<Index>(), any::<u8>()).prop_map(|(a, b)| Mutation::SetByte(a, b)),
    ]
}

/// A seed (by index into the caller's list) and its mutations.
pub fn mutated(seeds: usize) -> impl Strategy<Value = (usize, Vec<Mutation>)> {
    (
        0..seeds,
        proptest::collection::vec(mutation(), 1..=MAX_MUTATIONS),
    )
}

/// Byte ranges of the lines of `b`, each with its `\n`.
fn lines(b: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = 0;
    for (i, &c) in b.iter().enumerate() {
        if c == b'\n' {
            out.push((start, i + 1));
            start = i + 1;
        }
    }
    if start < b.len() {
        out.push((start, b.len()));
    }
    out
}

/// Byte ranges of the numbers of `b`: runs of `[0-9.eE+-]` holding a digit.
fn numbers(b: &[u8]) -> Vec<(usize, usize)> {
    let is_num = |c: u8| c.is_ascii_digit() || matches!(c, b'.' | b'e' | b'E' | b'+' | b'-');
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if is_num(b[i]) {
            let start = i;
            while i < b.len() && is_num(b[i]) {
                i += 1;
            }
            if b[start..i].iter().any(u8::is_ascii_digit) {
                out.push((start, i));
            }
        } else {
            i += 1;
        }
    }
    out
}

fn splice(b: &mut Vec<u8>, (start, end): (usize, usize), with: &[u8]) {
    b.splice(start..end, with.iter().copied());
}

impl Mutation {
    pub fn apply(&self, b: &mut Vec<u8>) {
        match self {
            Mutation::DeleteLine(k) => {
                let l = lines(b);
                if !l.is_empty() {
                    splice(b, l[k.index(l.len())], b"");
                }
            }
            Mutation::DuplicateLine(k) => {
                let l = lines(b);
                if !l.is_empty() {
                    let (s, e) = l[k.index(l.len())];
                    let mut line = b[s..e].to_vec();
                    if line.last() != Some(&b'\n') {
                        line.insert(0, b'\n');
                    }
                    splice(b, (e, e), &line);
                }
            }
            Mutation::SwapLines(x, y) => {
                let l = lines(b);
                if l.len() >= 2 {
                    let (mut i, mut j) = (x.index(l.len()), y.index(l.len()));
                    if i > j {
                        std::mem::swap(&mut i, &mut j);
                    }
                    if i != j {
                        let (a, c) = (b[l[i].0..l[i].1].to_vec(), b[l[j].0..l[j].1].to_vec());
                        splice(b, l[j], &a);
                        splice(b, l[i], &c);
                    }
                }
            }
            Mutation::ReplaceNumber(k, text) => {
                let n = numbers(b);
                if !n.is_empty() {
                    splice(b, n[k.index(n.len())], text.as_bytes());
                }
            }
            Mutation::DeleteNumber(k) => {
                let n = numbers(b);
                if !n.is_empty() {
                    splice(b, n[k.index(n.len())], b"");
                }
            }
            Mutation::TruncateAt(k) => {
                let at = k.index(b.len() + 1);
                b.truncate(at);
            }
            Mutation::InsertBytes(k, bytes) => {
                let at = k.index(b.len() + 1);
                splice(b, (at, at), bytes);
            }
            Mutation::SetByte(k, v) => {
                if !b.is_empty() {
                    let at = k.index(b.len());
                    b[at] = *v;
                }
            }
        }
    }
}

/// The seed with the mutations applied.
pub fn apply(seed: &[u8], mutations: &[Mutation]) -> Vec<u8> {
    let mut b = seed.to_vec();
    for m in mutations {
        m.apply(&mut b);
    }
    b
}

/// Cases per property: `TALUS_FUZZ_CASES` if set, else `default` (sized so that each test
/// file takes a few seconds in release) times `TALUS_FUZZ_SCALE` (1 if unset; `cargo xtask
/// fuzz` sets 20).
pub fn cases(default: u32) -> u32 {
    let var = |name: &str| std::env::var(name).ok().and_then(|v| v.parse::<u32>().ok());
    var("TALUS_FUZZ_CASES")
        .unwrap_or_else(|| default.saturating_mul(var("TALUS_FUZZ_SCALE").unwrap_or(1)))
}

/// The same cases on every `cargo test` run, so that the suite passes or fails the same
/// way on every machine; fresh ones when asked for more (`TALUS_FUZZ_SCALE`,
/// `TALUS_FUZZ_CASES`: `cargo xtask fuzz`), which is where new inputs are looked for.
/// `TALUS_FUZZ_SEED` fixes the seed of such a run.
fn seed() -> RngSeed {
    let var = |name: &str| std::env::var(name).ok();
    match var("TALUS_FUZZ_SEED").and_then(|v| v.parse::<u64>().ok()) {
        Some(seed) => RngSeed::Fixed(seed),
        None if var("TALUS_FUZZ_SCALE").is_some() || var("TALUS_FUZZ_CASES").is_some() => {
            RngSeed::Random
        }
        None => RngSeed::Fixed(20_261_124),
    }
}

/// What a reader did with one input.
pub enum Outcome {
    /// Read, and the result passed the consistency checks.
    Read,
    /// Refused with an error (its message, which must not be empty).
    Refused(String),
    /// Valid, but too large to build within a fuzz case's budget (the reason).
    Skipped(String),
}

/// Runs `cases` inputs of `strategy` through `read` (under `catch_unwind`), failing on a
/// panic or a failed consistency check (`Err` of `read`), and prints the one-line tally.
pub fn fuzz<S>(
    reader: &str,
    cases: u32,
    strategy: S,
    read: impl Fn(&S::Value) -> Result<Outcome, String>,
) where
    S: Strategy,
    S::Value: fmt::Debug,
{
    let config = Config {
        cases,
        // Failures are reported with their input (and kept as regression tests by hand):
        // no files written into the source tree.
        failure_persistence: None,
        max_shrink_iters: 2048,
        rng_seed: seed(),
        ..Config::default()
    };
    let start = Instant::now();
    let (read_count, refused, skipped) = (Cell::new(0u64), Cell::new(0u64), Cell::new(0u64));
    let mut runner = TestRunner::new(config);
    let result = runner.run(&strategy, |input| {
        match catch_unwind(AssertUnwindSafe(|| read(&input))) {
            Err(panic) => {
                let what = panic
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_default();
                Err(TestCaseError::fail(format!(
                    "PANIC in the {reader} reader: {what}"
                )))
            }
            Ok(Err(inconsistent)) => Err(TestCaseError::fail(format!(
                "INCONSISTENT result of the {reader} reader: {inconsistent}"
            ))),
            Ok(Ok(Outcome::Read)) => {
                read_count.set(read_count.get() + 1);
                Ok(())
            }
            Ok(Ok(Outcome::Skipped(_))) => {
                skipped.set(skipped.get() + 1);
                Ok(())
            }
            Ok(Ok(Outcome::Refused(msg))) => {
                refused.set(refused.get() + 1);
                if msg.trim().is_empty() {
                    return Err(TestCaseError::fail("an error with an empty message"));
                }
                Ok(())
            }
        }
    });
    if let Err(e) = result {
        panic!("fuzz {reader}: {e}");
    }
    let skipped = match skipped.get() {
        0 => String::new(),
        k => format!(", {k} too large to build"),
    };
    println!(
        "fuzz {reader}: {cases} cases ({} read, {} refused{skipped}), 0 panics, {:.1} s",
        read_count.get(),
        refused.get(),
        start.elapsed().as_secs_f64()
    );
}
