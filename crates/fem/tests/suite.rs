//! The integration tests of `talus-fem`, one module per file of `tests/`, built as one
//! test binary to save the link of one binary per file (README, 'Development'). Run one
//! file's tests with `cargo test --release -p talus-fem --test suite <file>::`; a new file
//! of `tests/` is added here (`autotests = false` in Cargo.toml).
mod common;
#[path = "common/gmsh_layers.rs"]
mod gmsh_layers;
mod solid3d;

mod axisymmetric;
mod block_mesh;
mod dofs_and_sets;
mod elastic_step;
mod excavation;
mod extrude;
mod face_loads;
mod fuzz_msh_reader;
mod gmsh_element_sets;
mod gmsh_reader;
mod graded_coordinates;
mod halved_retry_predictor;
mod lame_sphere;
mod loads;
mod msh_tetrahedra;
mod no_pivot_lu_footing;
mod operators;
mod patch_test;
mod patch_test_3d;
mod point_densities;
mod pressure;
mod tetrahedra;
mod to_p2;
mod triaxial_cube;
mod varying_loads;
