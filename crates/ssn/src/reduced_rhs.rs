//! `q` of eq. 16, the one place both discretizations build it (`docs/derivations.md`, 'The
//! reduced system'): `q = −(S σₙ + B (h vₙ + h² M⁻¹ f) + h B_D v_D)`, with `B v` the
//! volume-weighted strain rate of the free velocities and `B_D v_D` that of the prescribed
//! ones, `f` and `v_D` those of the end of the step.
use faer::sparse::SparseColMat;

use crate::error::{invalid, SolveError};

/// The free velocities: `B` on them, and their velocity `vₙ` (m/s), external force `f`
/// (N/m) and lumped mass (kg/m).
pub struct FreeVelocities<'a> {
    pub b: &'a SparseColMat<usize, f64>,
    pub velocity: &'a [f64],
    pub force: &'a [f64],
    pub lumped_mass: &'a [f64],
}

/// The prescribed velocities `v_D` (m/s) and `B_D` on them.
pub struct PrescribedVelocities<'a> {
    pub b: &'a SparseColMat<usize, f64>,
    pub velocity: &'a [f64],
}

/// `q` for a step of `h` (s) from `s_sigma = S σₙ` (per point, flat).
pub fn reduced_rhs(
    h: f64,
    s_sigma: &[f64],
    free: &FreeVelocities,
    prescribed: &PrescribedVelocities,
) -> Result<Vec<f64>, SolveError> {
    let n = s_sigma.len();
    let n_free = free.b.ncols();
    if free.b.nrows() != n || prescribed.b.nrows() != n {
        return Err(invalid(
            "B",
            format!(
                "{} and {} rows for {n} stress components",
                free.b.nrows(),
                prescribed.b.nrows()
            ),
        ));
    }
    if [
        free.velocity.len(),
        free.force.len(),
        free.lumped_mass.len(),
    ] != [n_free; 3]
        || prescribed.velocity.len() != prescribed.b.ncols()
    {
        return Err(invalid(
            "velocities",
            format!(
                "lengths {}, {}, {} for {n_free} free columns, {} for {} prescribed",
                free.velocity.len(),
                free.force.len(),
                free.lumped_mass.len(),
                prescribed.velocity.len(),
                prescribed.b.ncols()
            ),
        ));
    }
    let mut q: Vec<f64> = s_sigma.iter().map(|s| -s).collect();
    let drive: Vec<f64> = free
        .velocity
        .iter()
        .zip(free.force)
        .zip(free.lumped_mass)
        .map(|((v, f), m)| -(h * v + h * h * f / m))
        .collect();
    add_mul(free.b, &drive, &mut q);
    let drive: Vec<f64> = prescribed.velocity.iter().map(|v| -h * v).collect();
    add_mul(prescribed.b, &drive, &mut q);
    Ok(q)
}

/// `y += A x`, column by column.
fn add_mul(a: &SparseColMat<usize, f64>, x: &[f64], y: &mut [f64]) {
    let (cp, ri, val) = (a.symbolic().col_ptr(), a.symbolic().row_idx(), a.val());
    for (j, xj) in x.iter().enumerate() {
        for k in cp[j]..cp[j + 1] {
            y[ri[k]] += val[k] * xj;
        }
    }
}
