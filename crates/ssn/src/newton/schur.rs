use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use nalgebra::SMatrix;
use rayon::prelude::*;
use talus_bipotential::NaturalMapLinearization;

use super::owned_assembly::OwnedAssembly;
use super::partition::group_owners;
use super::schur_factor::{Factorized, LuChoice, SchurFactor};
use super::schur_pattern::{block_len, point_groups, schur_pattern, SchurPattern};
use crate::factorization::Ordering;
use crate::krylov::{Gmres, GmresError, GmresWorkspace, Verdict, PROJECT_AFTER};
use crate::local_lu::LocalLu;
use crate::norm::inf_norm;
use crate::operator::{block, PointBlocks, Structured};
use crate::point_share::PointShare;
use crate::FactorRanks;
use crate::Krylov;

/// The velocity-sized Newton system (`docs/derivations.md`, 'The Schur step'):
/// `(M + h² Bᵀ C B) u = Bᵀ A⁻¹ r`, `d = A⁻¹ r − h² C B u`,
/// with per point `A_i = I − D_i + ρ_i G_i S_i` and `C_i = ρ_i A_i⁻¹ G_i`.
/// The pattern of K is that of `Bᵀ B` plus the diagonal: fixed, factored symbolically once.
/// Points with the same dofs (one element's Gauss points) are summed before the scatter.
pub(crate) struct SchurSystem<const D: usize> {
    symmetric: bool,
    symbolic: SymbolicSparseColMat<usize>,
    /// The contributions of `new`'s enumeration (masses, then each point group's
    /// `h² Σᵢ Bᵢᵀ Cᵢ Bᵢ` entries) that sum into each CSC value, in enumeration order
    /// (CSR-like: `gather[p]` for value `p`). Each value is summed by one thread in that
    /// fixed order: the matrix is the same whatever the thread count. Empty, as
    /// `csc_values`, when `owned` assembles this rank's share only.
    gather_ptr: Vec<usize>,
    gather: Vec<u32>,
    /// Points sharing their dofs (`schur_pattern::point_groups`).
    group_ptr: Vec<usize>,
    /// Start of group g's entries in `contributions` (masses first).
    group_entries: Vec<usize>,
    contributions: Vec<f64>,
    csc_values: Vec<f64>,
    factorization: SchurFactor,
    /// This rank's share of the assembly when MUMPS factorizes `K` over the MPI ranks
    /// (then `csc_values` stay unused).
    owned: Option<OwnedAssembly>,
    local_c: Vec<SMatrix<f64, D, D>>,
    rhs: Vec<f64>,
    a_inv_r: Vec<f64>,
    /// The Krylov path's state (`NewtonSolve::Krylov`); untouched by the direct path.
    krylov: KrylovState,
}

/// GMRES on `K` preconditioned by the last factorization (`docs/krylov.md`).
#[derive(Default)]
struct KrylovState {
    /// The last GMRES solve needed more than `degraded_iterations`: refactorize next time.
    degraded: bool,
    workspace: Option<GmresWorkspace>,
    /// `u` of GMRES, then copied into `rhs`.
    u: Vec<f64>,
    /// Per point `h² Cᵢ Bᵢ x` (the product with `K`).
    points: Vec<f64>,
    /// `M⁻¹ e` (the stress residual of a velocity residual `e`).
    velocity: Vec<f64>,
    counts: SchurCounts,
}

/// What the Schur system did since the counts were last taken.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub(crate) struct SchurCounts {
    pub(crate) factorizations: usize,
    pub(crate) krylov_iterations: usize,
    pub(crate) krylov_failures: usize,
}

/// Ask for a GMRES direction on the last factorization, to `‖J_F d − r‖∞ ≤ η ‖r‖∞`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct KrylovRequest {
    pub(crate) settings: Krylov,
    pub(crate) forcing: f64,
}

/// Why the Schur path could not give a direction this step.
pub(crate) enum SchurFailure {
    /// A local block `A_i` is singular: use the stress-sized system.
    SingularBlock(usize),
    Factorization(String),
}

impl<const D: usize> SchurSystem<D> {
    pub(crate) fn new(
        structured: &Structured<D>,
        blocks: &PointBlocks<D>,
        symmetric: bool,
        ordering: Ordering,
        single: bool,
        distributed: Option<FactorRanks>,
    ) -> Result<Self, String> {
        let n_v = structured.lumped_mass.len();
        let n_points = structured.compliance.len();
        let group_ptr = point_groups(blocks);
        let SchurPattern {
            symbolic,
            positions,
        } = schur_pattern(n_v, blocks, &group_ptr, symmetric)?;
        let row_idx = symbolic.row_idx();
        let count = u32::try_from(positions.len())
            .map_err(|_| format!("{} Schur contributions exceed u32", positions.len()))?;
        // Counting sort of the contributions by destination, stable: enumeration order kept.
        // Not on a rank of a distributed factorization: it sums only its own entries
        // (`OwnedAssembly`), never the whole `K`.
        let (mut gather_ptr, mut gather) = (Vec::new(), Vec::new());
        if distributed.is_none() {
            gather_ptr = vec![0usize; row_idx.len() + 1];
            for &p in &positions {
                gather_ptr[p + 1] += 1;
            }
            for p in 0..row_idx.len() {
                gather_ptr[p + 1] += gather_ptr[p];
            }
            let mut next = gather_ptr.clone();
            gather = vec![0u32; positions.len()];
            for (k, &p) in (0..count).zip(&positions) {
                gather[next[p]] = k;
                next[p] += 1;
            }
        }
        let n_groups = group_ptr.len().saturating_sub(1);
        let mut group_entries = Vec::with_capacity(n_groups + 1);
        group_entries.push(n_v);
        for g in 0..n_groups {
            let m = blocks.point(group_ptr[g]).0.len();
            group_entries.push(group_entries[g] + block_len(m, symmetric));
        }
        let nnz = row_idx.len();
        let (factorization, owned) = if let Some(ranks) = distributed {
            let (rank, size) = SchurFactor::world()?;
            let start = std::time::Instant::now();
            let owners = group_owners(symbolic.as_ref(), blocks, &group_ptr, size)?;
            let partition_seconds = start.elapsed().as_secs_f64();
            let owned = OwnedAssembly::new(
                rank,
                &owners,
                &group_entries,
                &positions,
                symbolic.col_ptr(),
                row_idx,
            );
            tracing::debug!(
                rank,
                groups = owned.groups.len(),
                of_groups = n_groups,
                entries = owned.rows.len(),
                of_entries = nnz,
                partition_seconds,
                "this rank's share of K's assembly"
            );
            let factor = SchurFactor::distributed(n_v, &owned.rows, &owned.cols, symmetric, ranks)?;
            (factor, Some(owned))
        } else {
            let factor = SchurFactor::analyse(symbolic.as_ref(), symmetric, ordering, single)?;
            (factor, None)
        };
        Ok(Self {
            symmetric,
            symbolic,
            gather_ptr,
            gather,
            contributions: vec![0.0; group_entries[n_groups]],
            group_ptr,
            group_entries,
            csc_values: if owned.is_some() {
                Vec::new()
            } else {
                vec![0.0; nnz]
            },
            factorization,
            owned,
            local_c: vec![SMatrix::zeros(); n_points],
            rhs: vec![0.0; n_v],
            a_inv_r: vec![0.0; D * n_points],
            krylov: KrylovState::default(),
        })
    }

    /// The points this rank owns when MUMPS factorizes `K` over the ranks: those of the
    /// groups whose share of `K` it assembles.
    pub(crate) fn point_share(&self) -> Result<Option<PointShare>, String> {
        let Some(owned) = &self.owned else {
            return Ok(None);
        };
        let (rank, size) = SchurFactor::world()?;
        Ok(Some(PointShare::new(
            &self.group_ptr,
            &owned.owners,
            rank,
            size,
        )))
    }

    /// The counts since the last call, reset.
    pub(crate) fn take_counts(&mut self) -> SchurCounts {
        std::mem::take(&mut self.krylov.counts)
    }

    /// Stored entries of the factors.
    pub(crate) fn factor_nnz(&self) -> usize {
        self.factorization.factor_nnz()
    }

    /// Bytes of the stored factors and of the GMRES workspace.
    pub(crate) fn memory(&self) -> (usize, usize) {
        (
            self.factorization.factor_bytes(),
            self.krylov.workspace.as_ref().map_or(0, |w| w.bytes()),
        )
    }

    /// The held factorization belongs to another operator: the next request factorizes,
    /// as in a new system.
    pub(crate) fn forget_factor(&mut self) {
        self.krylov.degraded = true;
    }

    /// A reused factorization's direction failed the accuracy check: the next request
    /// refactorizes.
    pub(crate) fn mark_degraded(&mut self) {
        self.krylov.degraded = true;
        self.krylov.counts.krylov_failures += 1;
    }

    /// Writes the direction into `d`: by GMRES on the last factorization when `krylov`
    /// asks for it and a fresh one is held, otherwise (or when GMRES misses its
    /// tolerance) factorizing K with `choice` (Cholesky if symmetric).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn solve(
        &mut self,
        structured: &Structured<D>,
        blocks: &PointBlocks<D>,
        lin: &[NaturalMapLinearization<D>],
        rho: &[f64],
        r: &[f64],
        d: &mut [f64],
        choice: LuChoice,
        krylov: Option<KrylovRequest>,
        share: Option<&PointShare>,
        parallel: bool,
    ) -> Result<Factorized, SchurFailure> {
        let h2 = structured.h * structured.h;
        // Per point and independent: spread over threads when `parallel` (the results do
        // not depend on it); the first singular block in point order is reported. A rank
        // of a distributed solve works on its own points; the others' `A⁻¹r` stay 0.
        let symmetric = self.symmetric;
        let owned = share.map(PointShare::owned);
        let one = |i: usize, c: &mut SMatrix<f64, D, D>, ar: &mut [f64]| -> bool {
            if owned.is_some_and(|o| !o[i]) {
                ar.fill(0.0);
                return true;
            }
            let g = lin[i].coupling * rho[i];
            let a = SMatrix::<f64, D, D>::identity() - lin[i].projection_jacobian
                + g * structured.compliance[i];
            let Some(lu) = LocalLu::factor(&a) else {
                return false;
            };
            *c = lu.solve_matrix(&g);
            if symmetric {
                *c = (*c + c.transpose()) * 0.5;
            }
            ar.copy_from_slice(lu.solve(&block::<D>(r, i)).as_slice());
            true
        };
        let regular: Vec<bool> = if parallel {
            self.local_c
                .par_iter_mut()
                .zip(self.a_inv_r.par_chunks_mut(D))
                .enumerate()
                .with_min_len(64)
                .map(|(i, (c, ar))| one(i, c, ar))
                .collect()
        } else {
            self.local_c
                .iter_mut()
                .zip(self.a_inv_r.chunks_mut(D))
                .enumerate()
                .map(|(i, (c, ar))| one(i, c, ar))
                .collect()
        };
        let mut singular = regular.iter().position(|ok| !ok);
        if let Some(share) = share {
            singular = share.first(singular);
        }
        if let Some(i) = singular {
            return Err(SchurFailure::SingularBlock(i));
        }
        schur_rhs(&self.a_inv_r, blocks, share, parallel, &mut self.rhs);
        let reused = match krylov {
            Some(request)
                if request.settings.reuse
                    && self.factorization.ready()
                    && !self.krylov.degraded =>
            {
                self.gmres(structured, blocks, lin, rho, r, request, parallel, false)
            }
            _ => None,
        };
        let used = match reused {
            Some(used) => used,
            None if self.factorization.single() => {
                // A fresh f32 factor, then GMRES with it; the f64 factorization only if
                // that misses the tolerance.
                self.assemble(structured, blocks, parallel);
                let k = SparseColMatRef::new(self.symbolic.as_ref(), &self.csc_values);
                self.krylov.counts.factorizations += 1;
                self.krylov.degraded = false;
                let fresh = match (krylov, self.factorization.factorize_single(k)) {
                    (Some(request), Ok(())) => {
                        self.gmres(structured, blocks, lin, rho, r, request, parallel, true)
                    }
                    (_, Err(e)) => {
                        tracing::debug!(error = %e, "f32 Cholesky failed");
                        None
                    }
                    (None, Ok(())) => None,
                };
                match fresh {
                    Some(used) => used,
                    None => {
                        tracing::debug!("f32 factor insufficient: f64 Cholesky this iteration");
                        let k = SparseColMatRef::new(self.symbolic.as_ref(), &self.csc_values);
                        self.krylov.counts.factorizations += 1;
                        self.factorization
                            .solve(k, &mut self.rhs, choice)
                            .map_err(SchurFailure::Factorization)?
                    }
                }
            }
            None if self.owned.is_some() => {
                let mut owned = self.owned.take().expect("checked by the guard");
                self.fill_contributions(structured, blocks, Some(&owned.groups), parallel);
                owned.sum(&self.contributions);
                let owned = self.owned.insert(owned);
                self.krylov.counts.factorizations += 1;
                self.factorization
                    .solve_distributed(&owned.values, &mut self.rhs)
                    .map_err(SchurFailure::Factorization)?
            }
            None => {
                self.assemble(structured, blocks, parallel);
                let k = SparseColMatRef::new(self.symbolic.as_ref(), &self.csc_values);
                let result = self.factorization.solve(k, &mut self.rhs, choice);
                // A refused no-pivot LU is followed by the pivoting one: two.
                self.krylov.counts.factorizations += match (&result, choice) {
                    (Ok(Factorized::PivotingLu), LuChoice::NoPivot { .. }) => 2,
                    _ => 1,
                };
                self.krylov.degraded = false;
                result.map_err(SchurFailure::Factorization)?
            }
        };
        let u = &self.rhs;
        let (local_c, a_inv_r) = (&self.local_c, &self.a_inv_r);
        let back = |(i, di): (usize, &mut [f64])| {
            if owned.is_some_and(|o| !o[i]) {
                di.fill(0.0);
                return;
            }
            let v = block::<D>(a_inv_r, i) - local_c[i] * blocks.apply_point(i, u) * h2;
            di.copy_from_slice(v.as_slice());
        };
        if parallel {
            d.par_chunks_mut(D)
                .enumerate()
                .with_min_len(64)
                .for_each(back);
        } else {
            d.chunks_mut(D).enumerate().for_each(back);
        }
        Ok(used)
    }

    /// The normwise backward error `‖b − K u‖∞ / (‖K‖∞ ‖u‖∞ + ‖b‖∞)` of the last direct
    /// solve of the full `K` (the LU path; Rigal & Gaches 1967, Higham 2002, 'Accuracy and
    /// Stability of Numerical Algorithms', Thm. 7.1). Near round-off, `u` is as good as
    /// any factorization of `K`, with row exchanges or not, can give. Only after a solve
    /// that returned [`Factorized::NoPivotLu`]: `K` is then assembled in full and `u` is
    /// in `rhs`; `b` is formed again from `A⁻¹r` (rare: an inaccurate direction). NaN if
    /// `r`, `K` or `u` holds one, which no `≤` test accepts.
    pub(crate) fn backward_error(
        &self,
        blocks: &PointBlocks<D>,
        share: Option<&PointShare>,
        parallel: bool,
    ) -> f64 {
        // r = b − K u in place of b, and the row sums of |K|, column by column.
        let mut r = vec![0.0; self.rhs.len()];
        schur_rhs(&self.a_inv_r, blocks, share, parallel, &mut r);
        let b_norm = inf_norm(&r);
        let k = SparseColMatRef::new(self.symbolic.as_ref(), &self.csc_values);
        let (col_ptr, row_idx, val) = (k.col_ptr(), k.row_idx(), k.val());
        let u = &self.rhs;
        let mut rows = vec![0.0f64; u.len()];
        for (j, &uj) in u.iter().enumerate() {
            for p in col_ptr[j]..col_ptr[j + 1] {
                let (i, v) = (row_idx[p], val[p]);
                r[i] -= v * uj;
                rows[i] += v.abs();
            }
        }
        let scale = inf_norm(&rows) * inf_norm(u) + b_norm;
        if scale > 0.0 {
            inf_norm(&r) / scale
        } else {
            0.0
        }
    }

    /// `K`'s values (CSC) from this iteration's local `Cᵢ`: the contributions summed in a
    /// fixed order.
    fn assemble(&mut self, structured: &Structured<D>, blocks: &PointBlocks<D>, parallel: bool) {
        self.fill_contributions(structured, blocks, None, parallel);
        let (contributions, gather, gather_ptr) =
            (&self.contributions, &self.gather, &self.gather_ptr);
        let sum = |(p, out): (usize, &mut f64)| {
            let mut acc = 0.0;
            for &k in &gather[gather_ptr[p]..gather_ptr[p + 1]] {
                acc += contributions[k as usize];
            }
            *out = acc;
        };
        if parallel {
            self.csc_values
                .par_iter_mut()
                .enumerate()
                .with_min_len(4096)
                .for_each(sum);
        } else {
            self.csc_values.iter_mut().enumerate().for_each(sum);
        }
    }

    /// The masses and the contributions `h² Σᵢ Bᵢᵀ Cᵢ Bᵢ` of the point groups `groups`
    /// (ascending; `None`: all), in `contributions` (the other groups' are left as they
    /// were).
    fn fill_contributions(
        &mut self,
        structured: &Structured<D>,
        blocks: &PointBlocks<D>,
        groups: Option<&[usize]>,
        parallel: bool,
    ) {
        let h2 = structured.h * structured.h;
        let symmetric = self.symmetric;
        // The contributions in the order of `new` (masses, then h² Σᵢ Bᵢᵀ Cᵢ Bᵢ per group,
        // its points in order), each group's into its own slice, then each CSC value
        // summed from its list.
        let n_v = structured.lumped_mass.len();
        let (masses, mut rest) = self.contributions.split_at_mut(n_v);
        masses.copy_from_slice(&structured.lumped_mass);
        let n_groups = self.group_entries.len() - 1;
        let mut per_group = Vec::with_capacity(groups.map_or(n_groups, <[usize]>::len));
        let mut wanted = groups.map(|g| g.iter().peekable());
        for (g, w) in self.group_entries.windows(2).enumerate() {
            let (this, tail) = rest.split_at_mut(w[1] - w[0]);
            let take = match wanted.as_mut() {
                None => true,
                Some(list) => list.next_if_eq(&&g).is_some(),
            };
            if take {
                per_group.push((g, this));
            }
            rest = tail;
        }
        let group_ptr = &self.group_ptr;
        let local_c = &self.local_c;
        // Each point adds h² Bᵢᵀ (Cᵢ Bᵢ) to its group's m × m block, row a of the block as
        // Σ_k h² B[k, a] · (C B)[k, :]: contiguous rows, so the inner loop vectorizes.
        // The symmetric case keeps only `dofs[a] ≥ dofs[b]`, packed from a scratch block.
        let fill = |scratch: &mut Vec<f64>, (g, out): &mut (usize, &mut [f64])| {
            let g = *g;
            let m = blocks.point(group_ptr[g]).0.len();
            scratch.clear();
            scratch.resize(D * m + if symmetric { m * m } else { 0 }, 0.0);
            let (cb, full) = scratch.split_at_mut(D * m);
            let block: &mut [f64] = if symmetric {
                full
            } else {
                out.fill(0.0);
                out
            };
            let points = group_ptr[g]..group_ptr[g + 1];
            for (c, i) in local_c[points.clone()].iter().zip(points) {
                add_point_block::<D>(c, blocks.point(i).1, m, h2, cb, block);
            }
            if symmetric {
                let dofs = blocks.point(group_ptr[g]).0;
                let mut pos = 0;
                for a in 0..m {
                    for b in 0..m {
                        if dofs[a] >= dofs[b] {
                            out[pos] = full[a * m + b];
                            pos += 1;
                        }
                    }
                }
            }
        };
        if parallel {
            per_group
                .par_iter_mut()
                .with_min_len(64)
                .for_each_init(Vec::new, fill);
        } else {
            let mut scratch = Vec::new();
            per_group.iter_mut().for_each(|x| fill(&mut scratch, x));
        }
    }

    /// GMRES on `K u = b` (`b` in `rhs`, `u` left there), `K` applied matrix-free as
    /// `M u + h² Bᵀ (C (B u))`, or, when `assembled` (`csc_values` hold this iteration's
    /// `K`), by its stored values: a fraction of the memory traffic of the points' `B`
    /// and `Bᵀ`. Preconditioned by the last factorization. Accepted when the
    /// stress residual of the direction it gives, `‖J_F d − r‖∞ = ‖h² R G B M⁻¹ e‖∞` for
    /// the velocity residual `e = b − K u` (`docs/krylov.md`, 'Which residual'), is at
    /// most `η ‖r‖∞`. `None` (counted as a failure) when it is not reached within the cap.
    #[allow(clippy::too_many_arguments)]
    fn gmres(
        &mut self,
        structured: &Structured<D>,
        blocks: &PointBlocks<D>,
        lin: &[NaturalMapLinearization<D>],
        rho: &[f64],
        r: &[f64],
        request: KrylovRequest,
        parallel: bool,
        assembled: bool,
    ) -> Option<Factorized> {
        let clock = std::time::Instant::now();
        let h2 = structured.h * structured.h;
        let n_v = structured.lumped_mass.len();
        let n_points = self.local_c.len();
        let settings = request.settings;
        let state = &mut self.krylov;
        // (Re)built when absent or sized for another restart or dimension.
        let rebuild = match &state.workspace {
            Some(w) => !w.fits(n_v, settings.restart),
            None => true,
        };
        if rebuild {
            state.workspace = Some(GmresWorkspace::new(n_v, settings.restart));
        }
        state.u.clear();
        state.u.resize(n_v, 0.0);
        state.points.resize(D * n_points, 0.0);
        state.velocity.resize(n_v, 0.0);
        let KrylovState {
            workspace,
            u,
            points,
            velocity,
            counts,
            degraded,
        } = state;
        let workspace = workspace.as_mut().expect("just built");
        let (local_c, mass) = (&self.local_c, &structured.lumped_mass);
        let factorization = &mut self.factorization;
        // Only the f32 Cholesky's GMRES sees an assembled K: a lower triangle.
        debug_assert!(!assembled || self.symmetric);
        let k = SparseColMatRef::new(self.symbolic.as_ref(), &self.csc_values);
        let apply = |x: &[f64], y: &mut [f64]| {
            if assembled {
                return lower_product(k, x, y);
            }
            let one = |(i, t): (usize, &mut [f64])| {
                t.copy_from_slice((local_c[i] * blocks.apply_point(i, x) * h2).as_slice());
            };
            if parallel {
                points
                    .par_chunks_mut(D)
                    .enumerate()
                    .with_min_len(64)
                    .for_each(one);
            } else {
                points.chunks_mut(D).enumerate().for_each(one);
            }
            for ((y, m), x) in y.iter_mut().zip(mass).zip(x) {
                *y = m * x;
            }
            blocks.add_transpose(points, y, parallel);
        };
        // ‖h² ρᵢ Gᵢ Bᵢ M⁻¹ e‖∞ over the points; NaN counts as infinite.
        let stress_residual = |e: &[f64], velocity: &mut [f64]| -> f64 {
            for ((v, e), m) in velocity.iter_mut().zip(e).zip(mass) {
                *v = e / m;
            }
            let velocity = &*velocity;
            let one = |i: usize| -> f64 {
                let t = (lin[i].coupling * blocks.apply_point(i, velocity) * (h2 * rho[i])).amax();
                if t.is_nan() {
                    f64::INFINITY
                } else {
                    t
                }
            };
            if parallel {
                (0..n_points)
                    .into_par_iter()
                    .with_min_len(256)
                    .map(one)
                    .reduce(|| 0.0, f64::max)
            } else {
                (0..n_points).map(one).fold(0.0, f64::max)
            }
        };
        let allowed = request.forcing * r.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        // The first 2-norm target from b (u = 0, e = b): scaled to the stress residual.
        let b_norm = self.rhs.iter().map(|v| v * v).sum::<f64>().sqrt();
        let b_stress = stress_residual(&self.rhs, velocity);
        let target = if b_stress > 0.0 {
            0.5 * b_norm * allowed / b_stress
        } else {
            b_norm
        };
        let gmres = Gmres {
            restart: settings.restart,
            max_iterations: settings.max_iterations,
            project_after: PROJECT_AFTER,
        };
        let mut checks = 0;
        let result = gmres.solve(
            workspace,
            apply,
            |x: &mut [f64]| factorization.precondition(x),
            &self.rhs,
            u,
            target,
            |_, e| {
                checks += 1;
                let stress = stress_residual(e, velocity);
                if stress <= allowed {
                    Verdict::Accept
                } else {
                    let e_norm = e.iter().map(|v| v * v).sum::<f64>().sqrt();
                    Verdict::Continue {
                        target: 0.5 * e_norm * allowed / stress,
                    }
                }
            },
        );
        match result {
            Ok(solved) => {
                counts.krylov_iterations += solved.iterations;
                *degraded = solved.iterations > settings.degraded_iterations;
                tracing::debug!(
                    iterations = solved.iterations,
                    checks,
                    forcing = request.forcing,
                    seconds = clock.elapsed().as_secs_f64(),
                    "GMRES on the last factorization"
                );
                self.rhs.copy_from_slice(u);
                Some(Factorized::Reused {
                    iterations: solved.iterations,
                })
            }
            Err(error) => {
                let iterations = match error {
                    GmresError::NotConverged { iterations, .. }
                    | GmresError::NonFinite { iterations } => iterations,
                    GmresError::Settings => 0,
                };
                counts.krylov_iterations += iterations;
                counts.krylov_failures += 1;
                tracing::debug!(
                    %error,
                    forcing = request.forcing,
                    seconds = clock.elapsed().as_secs_f64(),
                    "GMRES missed its tolerance: refactorized"
                );
                None
            }
        }
    }
}

/// `block += h² Bᵀ C B` for one point, `B` the D × m row-major `bv`, `block` m × m
/// row-major; `cb` (D × m) is scratch for `C B`.
#[inline]
fn add_point_block<const D: usize>(
    c: &SMatrix<f64, D, D>,
    bv: &[f64],
    m: usize,
    h2: f64,
    cb: &mut [f64],
    block: &mut [f64],
) {
    if m == 0 {
        return; // a point whose dofs are all prescribed adds nothing to K
    }
    let (bv, cb, block) = (&bv[..D * m], &mut cb[..D * m], &mut block[..m * m]);
    for k in 0..D {
        let row = &mut cb[k * m..(k + 1) * m];
        row.fill(0.0);
        for l in 0..D {
            let ckl = c[(k, l)];
            for (x, &b) in row.iter_mut().zip(&bv[l * m..(l + 1) * m]) {
                *x += ckl * b;
            }
        }
    }
    for (a, out_row) in block.chunks_exact_mut(m).enumerate() {
        for k in 0..D {
            let s = h2 * bv[k * m + a];
            // B is half zeros (plane strain's zz row, a normal row's other-direction
            // columns): a zero adds nothing but signed zeros.
            if s == 0.0 {
                continue;
            }
            for (x, &y) in out_row.iter_mut().zip(&cb[k * m..(k + 1) * m]) {
                *x += s * y;
            }
        }
    }
}

/// The Schur right-hand side `b = Σᵢ Bᵢᵀ (A⁻¹r)ᵢ` into `out`, summed over the ranks when
/// the points are shared.
fn schur_rhs<const D: usize>(
    a_inv_r: &[f64],
    blocks: &PointBlocks<D>,
    share: Option<&PointShare>,
    parallel: bool,
    out: &mut [f64],
) {
    out.fill(0.0);
    blocks.add_transpose(a_inv_r, out, parallel);
    if let Some(share) = share {
        share.sum_velocity(out);
    }
}

/// `y = K x` for a symmetric `K` given by its lower triangle in CSC: one pass over the
/// stored values, in a fixed order.
fn lower_product(k: SparseColMatRef<'_, usize, f64>, x: &[f64], y: &mut [f64]) {
    y.fill(0.0);
    let (col_ptr, row_idx, val) = (k.col_ptr(), k.row_idx(), k.val());
    for (j, &xj) in x.iter().enumerate() {
        let mut below = 0.0;
        for p in col_ptr[j]..col_ptr[j + 1] {
            let (i, v) = (row_idx[p], val[p]);
            y[i] += v * xj;
            if i != j {
                below += v * x[i];
            }
        }
        y[j] += below;
    }
}
