use faer::sparse::{SparseColMat, Triplet};
use faer::Mat;
use nalgebra::{SMatrix, SVector};
use rayon::prelude::*;

use crate::error::invalid;
use crate::point_share::PointShare;
use crate::SolveError;

/// `W = S + h² B M⁻¹ Bᵀ` kept in factors: per-point compliance blocks `S_i` (already
/// multiplied by the point's volume), `B` (stress rows × free velocity columns, rows
/// weighted by the volume, so that `Bᵀσ` is the internal force), the lumped mass `M`
/// (diagonal, one entry per free velocity) and the time step `h`.
#[derive(Debug, Clone)]
pub struct Structured<const D: usize> {
    pub compliance: Vec<SMatrix<f64, D, D>>,
    pub b: SparseColMat<usize, f64>,
    pub lumped_mass: Vec<f64>,
    pub h: f64,
}

/// The operator `W` of `z = Wσ + q`.
#[derive(Debug, Clone)]
pub enum Operator<const D: usize> {
    Dense(Mat<f64>),
    Sparse(SparseColMat<usize, f64>),
    Structured(Structured<D>),
}

/// The most velocity columns a point's product gathers on the stack (a 3D P2
/// tetrahedron's point touches 30); larger points (a 3D MPM particle's 81) gather as they
/// go.
const LOCAL_DOFS: usize = 32;

/// Per-point dense pieces of a structured `B`: the velocity columns a point touches and
/// its D × n_i block, so that `Bu`, `Bᵀσ` and `Bᵀ C B` run point by point.
#[derive(Debug, Clone)]
pub(crate) struct PointBlocks<const D: usize> {
    pub dof_ptr: Vec<usize>,
    pub dofs: Vec<usize>,
    /// Row-major `D × n_i` per point, concatenated.
    pub values: Vec<f64>,
    /// For each velocity dof, the (point, position in the point's `dofs`) pairs that touch
    /// it, in point order: `Bᵀσ` is summed per dof in that fixed order, by any thread.
    by_dof_ptr: Vec<usize>,
    /// The point of each entry, and its D values of `B` (a transposed copy of `values`,
    /// contiguous so that the gather streams through it).
    by_dof_point: Vec<usize>,
    by_dof_values: Vec<f64>,
}

impl<const D: usize> PointBlocks<D> {
    pub(crate) fn new(b: &SparseColMat<usize, f64>, n_points: usize) -> Self {
        // Transpose to rows: for each point, gather (column, local row, value).
        let mut per_point: Vec<Vec<(usize, usize, f64)>> = vec![Vec::new(); n_points];
        let col_ptr = b.symbolic().col_ptr();
        let row_idx = b.symbolic().row_idx();
        let val = b.val();
        for j in 0..b.ncols() {
            for k in col_ptr[j]..col_ptr[j + 1] {
                let r = row_idx[k];
                per_point[r / D].push((j, r % D, val[k]));
            }
        }
        let mut dof_ptr = vec![0];
        let mut dofs = Vec::new();
        let mut values = Vec::new();
        for entries in per_point {
            let mut cols: Vec<usize> = entries.iter().map(|e| e.0).collect();
            cols.sort_unstable();
            cols.dedup();
            let n_i = cols.len();
            let mut local = vec![0.0; D * n_i];
            for (j, row, v) in entries {
                let a = cols.binary_search(&j).unwrap_or(0);
                local[row * n_i + a] += v;
            }
            dofs.extend_from_slice(&cols);
            values.extend_from_slice(&local);
            dof_ptr.push(dofs.len());
        }
        let n_dofs = b.ncols();
        let mut by_dof_ptr = vec![0usize; n_dofs + 1];
        for &j in &dofs {
            by_dof_ptr[j + 1] += 1;
        }
        for j in 0..n_dofs {
            by_dof_ptr[j + 1] += by_dof_ptr[j];
        }
        let mut next = by_dof_ptr.clone();
        let mut by_dof_point = vec![0; dofs.len()];
        let mut by_dof_values = vec![0.0; D * dofs.len()];
        for i in 0..n_points {
            let (start, end) = (dof_ptr[i], dof_ptr[i + 1]);
            let n_i = end - start;
            for (a, &j) in dofs[start..end].iter().enumerate() {
                let e = next[j];
                by_dof_point[e] = i;
                for r in 0..D {
                    by_dof_values[D * e + r] = values[D * start + r * n_i + a];
                }
                next[j] += 1;
            }
        }
        Self {
            dof_ptr,
            dofs,
            values,
            by_dof_ptr,
            by_dof_point,
            by_dof_values,
        }
    }

    pub(crate) fn point(&self, i: usize) -> (&[usize], &[f64]) {
        let (a, b) = (self.dof_ptr[i], self.dof_ptr[i + 1]);
        (&self.dofs[a..b], &self.values[D * a..D * b])
    }

    /// `(B u)_i` for one point.
    #[inline]
    pub(crate) fn apply_point(&self, i: usize, u: &[f64]) -> SVector<f64, D> {
        let (dofs, vals) = self.point(i);
        let n_i = dofs.len();
        // The point's entries of `u` gathered once, not once per stress row; each row's
        // sum keeps its order (the same bits).
        if n_i > LOCAL_DOFS {
            return SVector::from_fn(|r, _| (0..n_i).map(|a| vals[r * n_i + a] * u[dofs[a]]).sum());
        }
        let mut local = [0.0; LOCAL_DOFS];
        for (x, &j) in local.iter_mut().zip(dofs) {
            *x = u[j];
        }
        let local = &local[..n_i];
        SVector::from_fn(|r, _| {
            vals[r * n_i..(r + 1) * n_i]
                .iter()
                .zip(local)
                .map(|(v, x)| v * x)
                .sum()
        })
    }

    /// Keeps only the points `owned` marks in `Bᵀ` ([`Self::add_transpose`]): a rank of a
    /// distributed solve sums its own points' terms (`PointShare`).
    pub(crate) fn keep_points(&mut self, owned: &[bool]) {
        let mut ptr = vec![0usize; self.by_dof_ptr.len()];
        let (mut points, mut values) = (Vec::new(), Vec::new());
        for j in 0..self.by_dof_ptr.len() - 1 {
            for e in self.by_dof_ptr[j]..self.by_dof_ptr[j + 1] {
                let i = self.by_dof_point[e];
                if owned[i] {
                    points.push(i);
                    values.extend_from_slice(&self.by_dof_values[D * e..D * e + D]);
                }
            }
            ptr[j + 1] = points.len();
        }
        self.by_dof_ptr = ptr;
        self.by_dof_point = points;
        self.by_dof_values = values;
    }

    /// `out += Bᵀ s` for a flat `s`: each `out[j]` adds its points' terms in point order,
    /// so the sums do not depend on `parallel` or the thread count.
    pub(crate) fn add_transpose(&self, s: &[f64], out: &mut [f64], parallel: bool) {
        let one = |(j, o): (usize, &mut f64)| {
            let mut acc = *o;
            for e in self.by_dof_ptr[j]..self.by_dof_ptr[j + 1] {
                let i = self.by_dof_point[e];
                let vals = &self.by_dof_values[D * e..D * e + D];
                acc += (0..D).map(|r| vals[r] * s[D * i + r]).sum::<f64>();
            }
            *o = acc;
        };
        if parallel {
            out.par_iter_mut()
                .enumerate()
                .with_min_len(1024)
                .for_each(one);
        } else {
            out.iter_mut().enumerate().for_each(one);
        }
    }
}

impl<const D: usize> Operator<D> {
    /// Side length of `W`.
    pub fn size(&self) -> usize {
        match self {
            Operator::Dense(m) => m.nrows(),
            Operator::Sparse(m) => m.nrows(),
            Operator::Structured(s) => D * s.compliance.len(),
        }
    }

    pub(crate) fn validate(&self) -> Result<(), SolveError> {
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        match self {
            Operator::Dense(m) => {
                if m.nrows() != m.ncols() {
                    return Err(invalid(
                        "W",
                        format!("dense W is {}×{}, not square", m.nrows(), m.ncols()),
                    ));
                }
                for j in 0..m.ncols() {
                    if !(0..m.nrows()).all(|i| m[(i, j)].is_finite()) {
                        return Err(invalid("W", format!("non-finite entry in column {j}")));
                    }
                }
            }
            Operator::Sparse(m) => {
                if m.nrows() != m.ncols() {
                    return Err(invalid(
                        "W",
                        format!("sparse W is {}×{}, not square", m.nrows(), m.ncols()),
                    ));
                }
                if !finite(m.val()) {
                    return Err(invalid("W", "non-finite entry"));
                }
            }
            Operator::Structured(s) => {
                if !(s.h.is_finite() && s.h > 0.0) {
                    return Err(invalid(
                        "h",
                        format!("time step {} must be finite and > 0", s.h),
                    ));
                }
                if s.b.nrows() != D * s.compliance.len() {
                    return Err(invalid(
                        "B",
                        format!(
                            "B has {} rows for {} points of {D} components",
                            s.b.nrows(),
                            s.compliance.len()
                        ),
                    ));
                }
                if s.b.ncols() != s.lumped_mass.len() {
                    return Err(invalid(
                        "lumped_mass",
                        format!(
                            "{} masses for {} velocity columns of B",
                            s.lumped_mass.len(),
                            s.b.ncols()
                        ),
                    ));
                }
                if let Some((j, m)) = s
                    .lumped_mass
                    .iter()
                    .enumerate()
                    .find(|(_, m)| !(m.is_finite() && **m > 0.0))
                {
                    return Err(invalid(
                        "lumped_mass",
                        format!("mass {m} at velocity {j} must be finite and > 0"),
                    ));
                }
                if !finite(s.b.val()) {
                    return Err(invalid("B", "non-finite entry"));
                }
                if let Some(i) = s
                    .compliance
                    .iter()
                    .position(|c| !c.iter().all(|x| x.is_finite()))
                {
                    return Err(invalid(
                        "compliance",
                        format!("non-finite block at point {i}"),
                    ));
                }
            }
        }
        Ok(())
    }

    /// The diagonal of `W`.
    pub(crate) fn diagonal(&self) -> Vec<f64> {
        match self {
            Operator::Dense(m) => (0..m.nrows()).map(|i| m[(i, i)]).collect(),
            Operator::Sparse(m) => {
                let mut d = vec![0.0; m.nrows()];
                let (cp, ri, v) = (m.symbolic().col_ptr(), m.symbolic().row_idx(), m.val());
                for j in 0..m.ncols() {
                    for k in cp[j]..cp[j + 1] {
                        if ri[k] == j {
                            d[j] += v[k];
                        }
                    }
                }
                d
            }
            Operator::Structured(s) => {
                let mut d: Vec<f64> = s
                    .compliance
                    .iter()
                    .flat_map(|c| (0..D).map(|k| c[(k, k)]))
                    .collect();
                let (cp, ri, v) = (
                    s.b.symbolic().col_ptr(),
                    s.b.symbolic().row_idx(),
                    s.b.val(),
                );
                for j in 0..s.b.ncols() {
                    for k in cp[j]..cp[j + 1] {
                        d[ri[k]] += s.h * s.h * v[k] * v[k] / s.lumped_mass[j];
                    }
                }
                d
            }
        }
    }

    /// `W` as a sparse matrix (for the stress-sized Newton system).
    pub(crate) fn to_sparse(&self) -> SparseColMat<usize, f64> {
        let n = self.size();
        let mut triplets = Vec::new();
        match self {
            Operator::Dense(m) => {
                for j in 0..n {
                    for i in 0..n {
                        if m[(i, j)] != 0.0 {
                            triplets.push(Triplet::new(i, j, m[(i, j)]));
                        }
                    }
                }
            }
            Operator::Sparse(m) => return m.clone(),
            Operator::Structured(s) => {
                for (p, c) in s.compliance.iter().enumerate() {
                    for a in 0..D {
                        for b in 0..D {
                            triplets.push(Triplet::new(D * p + a, D * p + b, c[(a, b)]));
                        }
                    }
                }
                let (cp, ri, v) = (
                    s.b.symbolic().col_ptr(),
                    s.b.symbolic().row_idx(),
                    s.b.val(),
                );
                for j in 0..s.b.ncols() {
                    let w = s.h * s.h / s.lumped_mass[j];
                    for k in cp[j]..cp[j + 1] {
                        for l in cp[j]..cp[j + 1] {
                            triplets.push(Triplet::new(ri[k], ri[l], w * v[k] * v[l]));
                        }
                    }
                }
            }
        }
        SparseColMat::try_new_from_triplets(n, n, &triplets)
            .expect("indices are within the operator's size")
    }
}

/// Point `i` of a flat vector of D-blocks.
#[inline]
pub(crate) fn block<const D: usize>(v: &[f64], i: usize) -> SVector<f64, D> {
    SVector::from_column_slice(&v[D * i..D * i + D])
}

/// `z = Wσ + q` (or `Wσ` without `q`) into `z` (flat vectors of length `D × points`); `scratch` holds the
/// velocity-sized intermediate of the structured form. `parallel` spreads the structured
/// form over threads without changing any sum. With a `share` (structured only, `blocks`
/// kept to its points) the ranks' `Bᵀσ` are summed and `z` is computed at this rank's
/// points only.
#[allow(clippy::too_many_arguments)]
pub(crate) fn apply<const D: usize>(
    op: &Operator<D>,
    blocks: Option<&PointBlocks<D>>,
    sigma: &[f64],
    q: Option<&[f64]>,
    z: &mut [f64],
    scratch: &mut Vec<f64>,
    share: Option<&PointShare>,
    parallel: bool,
) {
    match q {
        Some(q) => z.copy_from_slice(q),
        None => z.fill(0.0),
    }
    match op {
        Operator::Dense(m) => {
            for (j, s) in sigma.iter().enumerate() {
                if *s != 0.0 {
                    for (i, zi) in z.iter_mut().enumerate() {
                        *zi += m[(i, j)] * s;
                    }
                }
            }
        }
        Operator::Sparse(m) => {
            let (cp, ri, v) = (m.symbolic().col_ptr(), m.symbolic().row_idx(), m.val());
            for (j, s) in sigma.iter().enumerate() {
                for k in cp[j]..cp[j + 1] {
                    z[ri[k]] += v[k] * s;
                }
            }
        }
        Operator::Structured(s) => {
            let blocks = blocks.expect("structured operators carry point blocks");
            scratch.clear();
            scratch.resize(s.lumped_mass.len(), 0.0);
            blocks.add_transpose(sigma, scratch, parallel);
            if let Some(share) = share {
                share.sum_velocity(scratch);
            }
            let h2 = s.h * s.h;
            for (u, m) in scratch.iter_mut().zip(&s.lumped_mass) {
                *u *= h2 / m;
            }
            let scratch = &*scratch;
            let owned = share.map(PointShare::owned);
            let one = |(i, zi): (usize, &mut [f64])| {
                if owned.is_some_and(|o| !o[i]) {
                    return;
                }
                let v = s.compliance[i] * block::<D>(sigma, i) + blocks.apply_point(i, scratch);
                for r in 0..D {
                    zi[r] += v[r];
                }
            };
            if parallel {
                z.par_chunks_mut(D)
                    .enumerate()
                    .with_min_len(64)
                    .for_each(one);
            } else {
                z.chunks_mut(D).enumerate().for_each(one);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A `B` of 3 points × D = 4 rows over 7 columns with the zeros of a plane-strain
    /// triangle (zz row empty, normal rows on alternate columns) and one stored zero.
    fn plane_strain_like() -> SparseColMat<usize, f64> {
        let mut t = Vec::new();
        for p in 0..3 {
            for c in p..p + 5 {
                let v = 1.0 + (7 * p + 3 * c) as f64 / 10.0;
                t.push(Triplet::new(4 * p + c % 2, c, v));
                t.push(Triplet::new(4 * p + 2, c, -v / 2.0));
            }
        }
        t.push(Triplet::new(3, 0, 0.0));
        SparseColMat::try_new_from_triplets(12, 7, &t).unwrap()
    }

    /// `Bᵀ s` and `(B u)_i` from `B`'s stored entries, the points `owned` only.
    fn by_entries(b: &SparseColMat<usize, f64>, s: &[f64], owned: &[bool]) -> Vec<f64> {
        let (cp, ri, v) = (b.symbolic().col_ptr(), b.symbolic().row_idx(), b.val());
        (0..b.ncols())
            .map(|j| {
                (cp[j]..cp[j + 1])
                    .filter(|&k| owned[ri[k] / 4])
                    .map(|k| v[k] * s[ri[k]])
                    .sum()
            })
            .collect()
    }

    /// `(B u)_i` is, bit for bit, the sum over the point's columns in order with `u`
    /// gathered per row (the product before the gather was hoisted).
    fn assert_same_bits_as_gathering_per_row(blocks: &PointBlocks<4>, i: usize, u: &[f64]) {
        let (dofs, vals) = blocks.point(i);
        let n_i = dofs.len();
        let bu = blocks.apply_point(i, u);
        for r in 0..4 {
            let e: f64 = (0..n_i).map(|a| vals[r * n_i + a] * u[dofs[a]]).sum();
            assert_eq!(bu[r].to_bits(), e.to_bits(), "point {i} row {r}");
        }
    }

    #[test]
    fn a_point_wider_than_the_stack_gather_keeps_the_same_product() {
        // One point over 40 columns (more than LOCAL_DOFS), one over 12.
        let mut t = Vec::new();
        for c in 0..40 {
            for r in 0..4 {
                t.push(Triplet::new(r, c, ((3 * c + r) % 7) as f64 - 2.5));
            }
        }
        for c in 0..12 {
            t.push(Triplet::new(4 + c % 3, c, 0.1 * c as f64 + 1.0));
        }
        let b = SparseColMat::try_new_from_triplets(8, 40, &t).unwrap();
        let blocks = PointBlocks::<4>::new(&b, 2);
        assert!(blocks.point(0).0.len() > LOCAL_DOFS);
        let u: Vec<f64> = (0..40).map(|j| (j as f64 * 0.7).sin()).collect();
        for i in 0..2 {
            assert_same_bits_as_gathering_per_row(&blocks, i, &u);
            assert_point_matches_dense(&blocks, &b, i, &u, 1e-13);
        }
    }

    /// `B u` of point `i` against the dense rows of `b`, to `tol` absolute.
    fn assert_point_matches_dense(
        blocks: &PointBlocks<4>,
        b: &SparseColMat<usize, f64>,
        i: usize,
        u: &[f64],
        tol: f64,
    ) {
        let dense = b.to_dense();
        let bu = blocks.apply_point(i, u);
        for r in 0..4 {
            let e: f64 = (0..u.len()).map(|j| dense[(4 * i + r, j)] * u[j]).sum();
            assert!((bu[r] - e).abs() <= tol, "point {i} row {r}: {} {e}", bu[r]);
        }
    }

    #[test]
    fn products_with_b_match_its_stored_entries() {
        let b = plane_strain_like();
        let s: Vec<f64> = (0..12).map(|k| (k as f64 - 5.5) * 0.37).collect();
        let u: Vec<f64> = (0..7).map(|j| 1.0 / (j as f64 + 1.5)).collect();
        let mut blocks = PointBlocks::<4>::new(&b, 3);
        for parallel in [false, true] {
            let mut out = vec![0.0; 7];
            blocks.add_transpose(&s, &mut out, parallel);
            let expected = by_entries(&b, &s, &[true; 3]);
            for (x, e) in out.iter().zip(&expected) {
                assert!(
                    (x - e).abs() <= 1e-14 * e.abs().max(1.0),
                    "{out:?} {expected:?}"
                );
            }
        }
        for i in 0..3 {
            assert_same_bits_as_gathering_per_row(&blocks, i, &u);
            assert_point_matches_dense(&blocks, &b, i, &u, 1e-14);
        }
        let owned = [true, false, true];
        blocks.keep_points(&owned);
        let mut out = vec![0.0; 7];
        blocks.add_transpose(&s, &mut out, false);
        let expected = by_entries(&b, &s, &owned);
        for (x, e) in out.iter().zip(&expected) {
            assert!(
                (x - e).abs() <= 1e-14 * e.abs().max(1.0),
                "{out:?} {expected:?}"
            );
        }
    }
}
