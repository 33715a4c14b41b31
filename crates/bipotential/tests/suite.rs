//! The integration tests of `talus-bipotential`, one module per file of `tests/`, built as one
//! test binary to save the link of one binary per file (README, 'Development'). Run one
//! file's tests with `cargo test --release -p talus-bipotential --test suite <file>::`; a new file
//! of `tests/` is added here (`autotests = false` in Cargo.toml).
mod common;

mod flow_rule;
mod material;
mod relaxation;
mod validation;
