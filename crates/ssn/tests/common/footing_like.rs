//! A small plane-strain footing as a structured reduced problem `W = S + h² B M⁻¹ Bᵀ`
//! (no talus-fem: P1 triangles written out here). The block `[0, 1] × [−1, 0]` m, a rough
//! rigid footing on `x ≤ 0.25` of the top pushed down at a prescribed velocity, rollers on
//! the sides, the base fixed, gravity; Drucker-Prager soil (Mandel vectors, D = 4).
#![allow(dead_code)]

use nalgebra::SMatrix;
use talus_bipotential::{ConeFit, DruckerPrager, DruckerPragerParameters};
use talus_ssn::faer::sparse::{SparseColMat, Triplet};
use talus_ssn::{
    reduced_rhs, FreeVelocities, Operator, PrescribedVelocities, ReducedSystem, Structured,
};

pub const D: usize = 4;
const DENSITY: f64 = 2000.0;
const GRAVITY: f64 = 10.0;

pub struct FootingLike {
    pub problem: ReducedSystem<D>,
    pub h: f64,
    compliance: Vec<SMatrix<f64, D, D>>,
    b_free: SparseColMat<usize, f64>,
    b_prescribed: SparseColMat<usize, f64>,
    force: Vec<f64>,
    mass: Vec<f64>,
}

enum Dof {
    Free(usize),
    /// Index among the prescribed dofs, and its velocity per unit footing speed.
    Prescribed(usize, f64),
    Fixed,
}

impl FootingLike {
    /// `nx × ny` cells of two triangles; `dilatancy` in degrees (30 = associative).
    pub fn new(nx: usize, ny: usize, dilatancy: f64, h: f64) -> Self {
        Self::with_young_modulus(nx, ny, dilatancy, h, 1e7)
    }

    /// As [`new`](Self::new) with Young's modulus `young` (Pa).
    pub fn with_young_modulus(nx: usize, ny: usize, dilatancy: f64, h: f64, young: f64) -> Self {
        let soil = DruckerPrager::try_new(DruckerPragerParameters {
            young_modulus: young,
            poisson_ratio: 0.3,
            friction_angle: 30.0,
            cohesion: 1e3,
            dilatancy_angle: dilatancy,
            cone_fit: ConeFit::PlaneStrain,
        })
        .expect("soil");
        let node = |i: usize, j: usize| j * (nx + 1) + i;
        let xy = |n: usize| {
            let (i, j) = (n % (nx + 1), n / (nx + 1));
            (i as f64 / nx as f64, -(j as f64) / ny as f64)
        };
        let n_nodes = (nx + 1) * (ny + 1);
        let (mut n_free, mut n_prescribed) = (0, 0);
        let mut dofs = Vec::with_capacity(2 * n_nodes);
        for n in 0..n_nodes {
            let (i, j) = (n % (nx + 1), n / (nx + 1));
            let (x, _) = xy(n);
            for c in 0..2 {
                let dof = if j == ny || (c == 0 && (i == 0 || i == nx)) {
                    Dof::Fixed
                } else if j == 0 && x <= 0.25 + 1e-12 {
                    n_prescribed += 1;
                    Dof::Prescribed(n_prescribed - 1, if c == 1 { -1.0 } else { 0.0 })
                } else {
                    n_free += 1;
                    Dof::Free(n_free - 1)
                };
                dofs.push(dof);
            }
        }
        let mut triangles = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let (a, b, c, d) = (
                    node(i, j),
                    node(i + 1, j),
                    node(i + 1, j + 1),
                    node(i, j + 1),
                );
                triangles.push([a, b, c]);
                triangles.push([a, c, d]);
            }
        }
        let (mut free_t, mut prescribed_t) = (Vec::new(), Vec::new());
        let mut mass = vec![0.0; n_free];
        let mut force = vec![0.0; n_free];
        let mut compliance = Vec::new();
        let s = soil.compliance::<D>();
        let root2 = 2f64.sqrt();
        for (p, t) in triangles.iter().enumerate() {
            let [(x0, y0), (x1, y1), (x2, y2)] = [xy(t[0]), xy(t[1]), xy(t[2])];
            let det = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0);
            let area = det.abs() / 2.0;
            // ∇N_a of the linear shape functions.
            let grads = [
                ((y1 - y2) / det, (x2 - x1) / det),
                ((y2 - y0) / det, (x0 - x2) / det),
                ((y0 - y1) / det, (x1 - x0) / det),
            ];
            compliance.push(s * area);
            for (a, &(gx, gy)) in grads.iter().enumerate() {
                // Rows xx, yy, zz, √2 xy of the volume-weighted strain rate.
                let rows_x = [(0, gx), (3, gy / root2)];
                let rows_y = [(1, gy), (3, gx / root2)];
                for (c, rows) in [(0, rows_x), (1, rows_y)] {
                    let entries = rows.iter().map(|&(r, v)| (D * p + r, area * v));
                    match dofs[2 * t[a] + c] {
                        Dof::Free(k) => {
                            mass[k] += DENSITY * area / 3.0;
                            if c == 1 {
                                force[k] -= DENSITY * GRAVITY * area / 3.0;
                            }
                            free_t.extend(entries.map(|(r, v)| Triplet::new(r, k, v)));
                        }
                        Dof::Prescribed(k, _) => {
                            prescribed_t.extend(entries.map(|(r, v)| Triplet::new(r, k, v)))
                        }
                        Dof::Fixed => {}
                    }
                }
            }
        }
        let n_points = triangles.len();
        let b_free = SparseColMat::try_new_from_triplets(D * n_points, n_free, &free_t).expect("B");
        let b_prescribed =
            SparseColMat::try_new_from_triplets(D * n_points, n_prescribed, &prescribed_t)
                .expect("B_D");
        let op = Operator::Structured(Structured {
            compliance: compliance.clone(),
            b: b_free.clone(),
            lumped_mass: mass.clone(),
            h,
        });
        let rules = vec![soil.flow_rule::<D>(); n_points];
        let problem = ReducedSystem::try_new(op, vec![0.0; D * n_points], rules).expect("problem");
        Self {
            problem,
            h,
            compliance,
            b_free,
            b_prescribed,
            force,
            mass,
        }
    }

    /// `q` of a step from `sigma` (at rest, free velocities 0) with the footing moving
    /// down at `speed` (m/s).
    pub fn q(&self, sigma: &[f64], speed: f64) -> Vec<f64> {
        let s_sigma: Vec<f64> = sigma
            .chunks_exact(D)
            .zip(&self.compliance)
            .flat_map(|(s, c)| {
                let v = c * nalgebra::SVector::<f64, D>::from_column_slice(s);
                v.iter().copied().collect::<Vec<_>>()
            })
            .collect();
        let prescribed = vec![-speed; self.b_prescribed.ncols()];
        // Only the vertical prescribed dofs move: every other column is ux of the footing
        // (its nodes are numbered x then y, both prescribed).
        let prescribed: Vec<f64> = prescribed
            .iter()
            .enumerate()
            .map(|(k, v)| if k % 2 == 1 { *v } else { 0.0 })
            .collect();
        reduced_rhs(
            self.h,
            &s_sigma,
            &FreeVelocities {
                b: &self.b_free,
                velocity: &vec![0.0; self.mass.len()],
                force: &self.force,
                lumped_mass: &self.mass,
            },
            &PrescribedVelocities {
                b: &self.b_prescribed,
                velocity: &prescribed,
            },
        )
        .expect("q")
    }
}

/// The FEM settings with the Krylov reuse of factorizations (`docs/krylov.md`).
pub fn krylov() -> talus_ssn::Settings {
    talus_ssn::Settings {
        newton_solve: talus_ssn::NewtonSolve::Krylov(talus_ssn::Krylov::DEFAULT),
        ..talus_ssn::Settings::fem()
    }
}

/// `solver.solve(sigma)`'s report; a solve that does not converge stops the caller.
pub fn solve(solver: &mut talus_ssn::Solver<D>, sigma: &mut [f64]) -> talus_ssn::Report {
    match solver.solve(sigma) {
        Ok(r) => r,
        Err(talus_ssn::SolveError::NotConverged(r)) => panic!("not converged: {r:?}"),
        Err(e) => panic!("{e}"),
    }
}
