//! The integration tests of `talus-ssn`, one module per file of `tests/`, built as one
//! test binary to save the link of one binary per file (README, 'Development'). Run one
//! file's tests with `cargo test --release -p talus-ssn --test suite <file>::`; a new file
//! of `tests/` is added here (`autotests = false` in Cargo.toml).

mod clarabel_agreement;
#[path = "common/footing_like.rs"]
mod footing_like;
mod fuzz_siconos_reader;
#[path = "common/grid_matrix.rs"]
mod grid_matrix;
mod krylov_gmres;
mod krylov_newton;
mod krylov_siconos;
mod ordering;
mod relaxation_one_point;
mod replace_problem;
mod round_off_floor;
mod schur_step;
mod siconos_reader;
mod siconos_suite;
mod solver_contract;
mod supernodal_cholesky;
mod supernodal_llt;
mod symmetric_pattern_lu;
