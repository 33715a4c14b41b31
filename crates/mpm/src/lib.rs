//! The implicit material point method of Guillet et al. (2024), §3, on the same
//! semi-smooth Newton core as the finite elements: particles carry mass, momentum, volume,
//! stress, plastic strain and a material index ([`Mpm::with_materials`]); each step
//! transfers mass and momentum to a background grid (eq. 11), builds `B` at the particles
//! (rows weighted by the particle volume), the lumped grid mass `M` and `S = V_p S₀` (`S₀`
//! of the particle's material), solves `h z = Wσ + q` with talus-ssn (eqs. 12, 15–16),
//! then updates the particles with the PIC/FLIP blend of eqs. 13–14.
//!
//! Plane strain or 3D (`docs/3d-mpm.md`): every type is generic over the Mandel size `D`,
//! 4 by default (`(xx, yy, zz, √2 xy)`) or 6 (`(xx, yy, zz, √2 yz, √2 xz, √2 xy)`); SI
//! units, tension positive, y vertical.
//!
//! The crate builds each sub-step's reduced problem and applies its solution; the Newton
//! solves and the step control (halving, predictor) belong to talus-engine's `Stepper`,
//! which steps an [`Mpm`] as its `Discretization` ([`MpmStepper`] keeps the time). One
//! sub-step driven by hand:
//!
//! ```
//! use talus_bipotential::{ConeFit, DruckerPrager, DruckerPragerParameters};
//! use talus_mpm::{Grid, GridBoundary, Mpm, MpmSettings, Particles, ShapeFunction, Side, Wall, WallCondition};
//! use talus_ssn::{Settings, Solver};
//! let soil = DruckerPrager::try_new(DruckerPragerParameters {
//!     young_modulus: 1e7, poisson_ratio: 0.3, friction_angle: 30.0,
//!     cohesion: 0.0, dilatancy_angle: 0.0, cone_fit: ConeFit::PlaneStrain,
//! })?;
//! let grid = Grid::try_new([0.0, 0.0], 0.1, [10, 10], ShapeFunction::QuadraticBSpline)?;
//! let floor = Wall { side: Side::Bottom, condition: WallCondition::Friction { coefficient: 0.5 } };
//! let boundary = GridBoundary { walls: vec![floor], prescribed: vec![] };
//! let mpm = Mpm::try_new(grid, boundary, &soil, [0.0, -9.81], MpmSettings::default())?;
//! let mut sand = Particles::fill_rectangle([[0.0, 0.0], [0.2, 0.4]], 0.1, 2, 1800.0)?;
//! let (mut substep, system) = mpm.begin_substep(&sand, 1e-3)?;
//! let mut solver = Solver::new(system, Settings::default())?;
//! let mut sigma: Vec<f64> = sand.stress.as_flattened().to_vec();
//! loop {
//!     let report = solver.solve(&mut sigma)?;
//!     assert!(report.residual <= 1e-12 * report.scale);
//!     match substep.after_solve(&mpm, &sand, &sigma, solver.z())? {
//!         Some(next) => { solver.replace_problem(next)?; }
//!         None => break,
//!     }
//! }
//! substep.finish(&mpm, &mut sand, sigma)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
mod boundary;
mod contact;
mod dimension;
mod discretization;
mod error;
mod grid;
mod loads;
mod measure;
mod mpm;
mod particles;
mod probe;
mod programme;
mod reduced_problem;
mod settings;
mod shape;
mod side;
mod stepper;
mod substep;
pub mod transfer;

pub use boundary::{GridBoundary, PrescribedVelocity, Wall, WallCondition};
pub use dimension::{Dimension, Mandel, Vector};
pub use discretization::{GroupForces, MpmState, MpmStepReport};
pub use error::MpmError;
pub use grid::{Grid, Stencil};
pub use loads::SubstepLoads;
pub use measure::{front, kinetic_energy, radial_front, RunoutReference};
pub use mpm::Mpm;
pub use particles::Particles;
pub use probe::grid_value_at;
pub use programme::{MpmLoadProgramme, ProgrammedMpm, RampedSurfaceLoad};
pub use settings::MpmSettings;
pub use shape::ShapeFunction;
pub use side::Side;
pub use stepper::MpmStepper;
pub use substep::{Substep, SubstepStats};

// The README's example, compiled and run as a doctest (`cargo test --doc`).
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
