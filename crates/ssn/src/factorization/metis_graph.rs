//! The graph METIS takes of a square sparse pattern (cargo feature `metis`), and the two
//! things asked of it: a nested-dissection ordering (`ordering.rs`) and a k-way partition
//! (the ranks' shares of `K`'s assembly, `docs/distributed.md`, 'What runs where').
use faer::sparse::SymbolicSparseColMatRef;
use metis_sys::{idx_t, METIS_SetDefaultOptions, METIS_NOPTIONS};

use super::symbolic_error::SymbolicError;

/// The symmetric closure of a pattern without its diagonal, in METIS' compressed rows.
pub(crate) struct MetisGraph {
    xadj: Vec<idx_t>,
    adjncy: Vec<idx_t>,
}

/// METIS' `idx_t`s as indices, each checked below `n` (`what` in the message).
fn below(v: Vec<idx_t>, n: usize, what: &str) -> Result<Vec<usize>, SymbolicError> {
    v.into_iter()
        .map(|p| {
            usize::try_from(p)
                .ok()
                .filter(|&p| p < n)
                .ok_or_else(|| SymbolicError::new(format!("METIS returned {what} {p}")))
        })
        .collect()
}

fn too_large(what: &str) -> SymbolicError {
    SymbolicError::new(format!("{what} exceeds METIS' indices"))
}

impl MetisGraph {
    /// The graph of a square pattern (either triangle, or both).
    pub(crate) fn of_pattern(
        pattern: SymbolicSparseColMatRef<'_, usize>,
    ) -> Result<Self, SymbolicError> {
        let n = pattern.nrows();
        if pattern.ncols() != n {
            return Err(SymbolicError::new(format!(
                "the graph of a {}×{} pattern",
                n,
                pattern.ncols()
            )));
        }
        let (cp, ri) = (pattern.col_ptr(), pattern.row_idx());
        // Both directions of every off-diagonal entry, then each list sorted and
        // deduplicated: METIS wants a symmetric graph without self loops or repeated edges.
        let mut degree = vec![0usize; n + 1];
        for j in 0..n {
            for &i in &ri[cp[j]..cp[j + 1]] {
                if i != j {
                    degree[i + 1] += 1;
                    degree[j + 1] += 1;
                }
            }
        }
        for j in 0..n {
            degree[j + 1] += degree[j];
        }
        let mut next = degree.clone();
        let mut adjacency = vec![0usize; degree[n]];
        for j in 0..n {
            for &i in &ri[cp[j]..cp[j + 1]] {
                if i != j {
                    adjacency[next[i]] = j;
                    next[i] += 1;
                    adjacency[next[j]] = i;
                    next[j] += 1;
                }
            }
        }
        drop(next);
        let mut xadj: Vec<idx_t> = Vec::with_capacity(n + 1);
        let mut adjncy: Vec<idx_t> = Vec::with_capacity(adjacency.len());
        xadj.push(0);
        for j in 0..n {
            let list = &mut adjacency[degree[j]..degree[j + 1]];
            list.sort_unstable();
            let mut last = usize::MAX;
            for &i in list.iter() {
                if i != last {
                    adjncy.push(idx_t::try_from(i).map_err(|_| too_large("a vertex"))?);
                    last = i;
                }
            }
            xadj.push(idx_t::try_from(adjncy.len()).map_err(|_| too_large("the edge count"))?);
        }
        Ok(Self { xadj, adjncy })
    }

    fn order(&self) -> Result<idx_t, SymbolicError> {
        idx_t::try_from(self.xadj.len() - 1).map_err(|_| too_large("the order"))
    }

    /// METIS' nested dissection (`METIS_NodeND`, default options): `(perm, iperm)`, row
    /// i of the permuted matrix being row `perm[i]` of the input.
    pub(crate) fn nested_dissection(&mut self) -> Result<(Vec<usize>, Vec<usize>), SymbolicError> {
        let n = self.xadj.len() - 1;
        let mut nvtxs = self.order()?;
        let mut options = [0 as idx_t; METIS_NOPTIONS as usize];
        let (mut perm, mut iperm) = (vec![0 as idx_t; n], vec![0 as idx_t; n]);
        // SAFETY: xadj (n + 1 entries) and adjncy (xadj[n]) describe a symmetric graph
        // without self loops or repeated edges; perm and iperm have n entries; no weights.
        let status = unsafe {
            METIS_SetDefaultOptions(options.as_mut_ptr());
            metis_sys::METIS_NodeND(
                &mut nvtxs,
                self.xadj.as_mut_ptr(),
                self.adjncy.as_mut_ptr(),
                std::ptr::null_mut(),
                options.as_mut_ptr(),
                perm.as_mut_ptr(),
                iperm.as_mut_ptr(),
            )
        };
        if status != metis_sys::rstatus_et_METIS_OK {
            return Err(SymbolicError::new(format!(
                "METIS_NodeND returned {status}"
            )));
        }
        Ok((below(perm, n, "index")?, below(iperm, n, "index")?))
    }

    /// METIS' k-way partition into `parts` (`METIS_PartGraphKway`, default options: a
    /// fixed seed, so the same graph gives the same parts on every rank) balancing the
    /// vertices' `weights`; the part of each vertex.
    pub(crate) fn partition(
        &mut self,
        weights: &[usize],
        parts: usize,
    ) -> Result<Vec<usize>, SymbolicError> {
        let n = self.xadj.len() - 1;
        if weights.len() != n {
            return Err(SymbolicError::new(format!(
                "{} vertex weights for {n} vertices",
                weights.len()
            )));
        }
        if parts <= 1 || n == 0 {
            return Ok(vec![0; n]);
        }
        // A graph of a few vertices a part: split in order (METIS would print that it
        // cannot bisect it on standard output, every rank).
        if n < 4 * parts {
            return Ok((0..n).map(|v| v * parts / n).collect());
        }
        let mut vwgt = weights
            .iter()
            .map(|&w| idx_t::try_from(w).map_err(|_| too_large("a vertex weight")))
            .collect::<Result<Vec<_>, _>>()?;
        let mut nvtxs = self.order()?;
        let mut ncon: idx_t = 1;
        let mut nparts = idx_t::try_from(parts).map_err(|_| too_large("the parts"))?;
        let mut options = [0 as idx_t; METIS_NOPTIONS as usize];
        let mut cut: idx_t = 0;
        let mut part = vec![0 as idx_t; n];
        // SAFETY: the graph as in `nested_dissection`; vwgt and part have n entries; one
        // balance constraint; no edge or size weights, default imbalance targets.
        let status = unsafe {
            METIS_SetDefaultOptions(options.as_mut_ptr());
            metis_sys::METIS_PartGraphKway(
                &mut nvtxs,
                &mut ncon,
                self.xadj.as_mut_ptr(),
                self.adjncy.as_mut_ptr(),
                vwgt.as_mut_ptr(),
                std::ptr::null_mut(),
                std::ptr::null_mut(),
                &mut nparts,
                std::ptr::null_mut(),
                std::ptr::null_mut(),
                options.as_mut_ptr(),
                &mut cut,
                part.as_mut_ptr(),
            )
        };
        if status != metis_sys::rstatus_et_METIS_OK {
            return Err(SymbolicError::new(format!(
                "METIS_PartGraphKway returned {status}"
            )));
        }
        below(part, parts, "part")
    }
}
