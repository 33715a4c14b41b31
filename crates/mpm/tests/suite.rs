//! The integration tests of `talus-mpm`, one module per file of `tests/`, built as one
//! test binary to save the link of one binary per file (README, 'Development'). Run one
//! file's tests with `cargo test --release -p talus-mpm --test suite <file>::`; a new file
//! of `tests/` is added here (`autotests = false` in Cargo.toml).
mod sand_column;

mod elastic_column_gravity;
mod elastic_column_gravity_3d;
mod flip_blend;
mod friction_pass_reuse;
mod frictional_floor;
mod granular_collapse_3d;
mod materials;
mod pic_conservation;
mod pic_conservation_3d;
mod plane_strain_in_3d;
mod shape_functions;
mod shape_functions_3d;
mod step_control;
mod stress_rotation;
