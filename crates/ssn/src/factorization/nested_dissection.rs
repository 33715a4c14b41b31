//! A nested-dissection ordering of a symmetric pattern by level structures (George & Liu,
//! *Computer Solution of Large Sparse Positive Definite Systems*, 1981, ch. 8): a part is
//! split by the middle level of a breadth-first search from a pseudo-peripheral vertex,
//! its two sides are ordered first and the separator last, down to small parts ordered
//! by reverse Cuthill-McKee. On the 2D meshes of a footing its separators are short
//! lines across the mesh, where minimum degree leaves long fronts
//! (`docs/performance.md`, "The factorization").
//!
//! Deterministic: every choice depends on the pattern only.

/// Parts this small (vertices) are not split further.
const LEAF: usize = 4;

/// `perm_fwd[new] = old` for the graph of `adjacency` (CSR: the neighbours of `v` are
/// `adj[xadj[v]..xadj[v + 1]]`, symmetric, without `v` itself).
pub(crate) fn nested_dissection(xadj: &[usize], adj: &[usize]) -> Vec<usize> {
    let n = xadj.len().saturating_sub(1);
    let mut g = Graph {
        xadj,
        adj,
        stamp: vec![0; n],
        level: vec![usize::MAX; n],
        current: 0,
    };
    let mut order = Vec::with_capacity(n);
    // Explicit stack: `Part(vertices)` is split, `Emit(vertices)` is appended as is.
    let mut stack = vec![Task::Part((0..n).collect::<Vec<_>>())];
    while let Some(task) = stack.pop() {
        match task {
            Task::Emit(vs) => order.extend(vs),
            Task::Part(vs) if vs.len() <= LEAF => order.extend(g.reverse_cuthill_mckee(&vs)),
            Task::Part(vs) => match g.split(&vs) {
                // Pushed in reverse: side a, then side b, then the separator.
                Some((a, b, s)) => {
                    stack.push(Task::Emit(s));
                    stack.push(Task::Part(b));
                    stack.push(Task::Part(a));
                }
                None => order.extend(g.reverse_cuthill_mckee(&vs)),
            },
        }
    }
    order
}

enum Task {
    Part(Vec<usize>),
    Emit(Vec<usize>),
}

struct Graph<'a> {
    xadj: &'a [usize],
    adj: &'a [usize],
    /// `stamp[v] == current`: `v` is in the part being worked on.
    stamp: Vec<usize>,
    level: Vec<usize>,
    current: usize,
}

impl Graph<'_> {
    fn neighbours(&self, v: usize) -> &[usize] {
        &self.adj[self.xadj[v]..self.xadj[v + 1]]
    }

    fn enter(&mut self, vs: &[usize]) {
        self.current += 1;
        for &v in vs {
            self.stamp[v] = self.current;
        }
    }

    /// Breadth-first levels from `root` inside the current part: the vertices in visiting
    /// order and where each level starts (with a final end marker).
    fn levels(&mut self, root: usize, visit: &mut Vec<usize>, starts: &mut Vec<usize>) {
        visit.clear();
        starts.clear();
        let part = self.current;
        // A fresh sub-stamp marks visited vertices: stamp them past the part's value.
        self.current += 1;
        let seen = self.current;
        visit.push(root);
        self.stamp[root] = seen;
        let mut begin = 0;
        while begin < visit.len() {
            starts.push(begin);
            let end = visit.len();
            for i in begin..end {
                let v = visit[i];
                for k in self.xadj[v]..self.xadj[v + 1] {
                    let w = self.adj[k];
                    if self.stamp[w] == part {
                        self.stamp[w] = seen;
                        visit.push(w);
                    }
                }
            }
            begin = end;
        }
        starts.push(visit.len());
        // Back to the part's stamp for the next search.
        for &v in visit.iter() {
            self.stamp[v] = part;
        }
        self.current = part;
    }

    /// Splits `vs` into two sides and a separator, or `None` when the part is too shallow
    /// to split. A disconnected part is split into a component and the rest, with an
    /// empty separator.
    fn split(&mut self, vs: &[usize]) -> Option<(Vec<usize>, Vec<usize>, Vec<usize>)> {
        self.enter(vs);
        let (mut visit, mut starts) = (Vec::new(), Vec::new());
        let degree = |g: &Self, v: usize| {
            g.neighbours(v)
                .iter()
                .filter(|&&w| g.stamp[w] == g.current)
                .count()
        };
        // Pseudo-peripheral root: from the part's first vertex, move to a least-degree
        // vertex of the last level while the depth grows.
        let mut root = vs[0];
        self.levels(root, &mut visit, &mut starts);
        if visit.len() < vs.len() {
            let component = visit.clone();
            self.enter(&component);
            let rest: Vec<usize> = vs
                .iter()
                .copied()
                .filter(|&v| self.stamp[v] != self.current)
                .collect();
            return Some((component, rest, Vec::new()));
        }
        for _ in 0..8 {
            let depth = starts.len();
            let last = &visit[starts[depth - 2]..starts[depth - 1]];
            let candidate = *last
                .iter()
                .min_by_key(|&&v| (degree(self, v), v))
                .expect("a level is not empty");
            self.levels(candidate, &mut visit, &mut starts);
            if starts.len() <= depth {
                self.levels(root, &mut visit, &mut starts);
                break;
            }
            root = candidate;
        }
        let n_levels = starts.len() - 1;
        if n_levels < 3 {
            return None;
        }
        // The smallest level that leaves each side at least a third of the part (the
        // middle level by count if none does), never the first or the last.
        let total = vs.len();
        let balanced = |l: usize| 3 * starts[l] >= total && 3 * (total - starts[l + 1]) >= total;
        let middle = (1..n_levels - 1)
            .find(|&l| 2 * starts[l + 1] > total)
            .unwrap_or(n_levels - 2);
        let m = (1..n_levels - 1)
            .filter(|&l| balanced(l))
            .min_by_key(|&l| (starts[l + 1] - starts[l], l.abs_diff(middle)))
            .unwrap_or(middle);
        for l in 0..n_levels {
            for &v in &visit[starts[l]..starts[l + 1]] {
                self.level[v] = l;
            }
        }
        let a: Vec<usize> = visit[..starts[m]].to_vec();
        let mut a = a;
        let mut s = Vec::new();
        // A separator vertex with no neighbour beyond it does not separate: it joins a.
        for &v in &visit[starts[m]..starts[m + 1]] {
            let touches_b = self
                .neighbours(v)
                .iter()
                .any(|&w| self.stamp[w] == self.current && self.level[w] == m + 1);
            if touches_b {
                s.push(v);
            } else {
                a.push(v);
            }
        }
        let b: Vec<usize> = visit[starts[m + 1]..].to_vec();
        Some((a, b, s))
    }

    /// Reverse Cuthill-McKee inside the part `vs` (each component from a
    /// pseudo-peripheral vertex, neighbours by increasing degree).
    fn reverse_cuthill_mckee(&mut self, vs: &[usize]) -> Vec<usize> {
        self.enter(vs);
        let part = self.current;
        let mut out: Vec<usize> = Vec::with_capacity(vs.len());
        let (mut visit, mut starts) = (Vec::new(), Vec::new());
        for &start in vs {
            if self.stamp[start] != part {
                continue; // already ordered
            }
            self.levels(start, &mut visit, &mut starts);
            let last = visit[starts[starts.len() - 2]];
            let from = out.len();
            out.push(last);
            self.stamp[last] = usize::MAX;
            let mut head = from;
            while head < out.len() {
                let v = out[head];
                head += 1;
                let mut next: Vec<usize> = self
                    .neighbours(v)
                    .iter()
                    .copied()
                    .filter(|&w| self.stamp[w] == part)
                    .collect();
                let deg = |w: usize| self.neighbours(w).len();
                next.sort_by_key(|&w| (deg(w), w));
                for w in next {
                    self.stamp[w] = usize::MAX;
                    out.push(w);
                }
            }
        }
        out.reverse();
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 5-point grid graph of `nx × ny` vertices.
    fn grid(nx: usize, ny: usize) -> (Vec<usize>, Vec<usize>) {
        let mut xadj = vec![0];
        let mut adj = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                if i > 0 {
                    adj.push(j * nx + i - 1);
                }
                if i + 1 < nx {
                    adj.push(j * nx + i + 1);
                }
                if j > 0 {
                    adj.push((j - 1) * nx + i);
                }
                if j + 1 < ny {
                    adj.push((j + 1) * nx + i);
                }
                xadj.push(adj.len());
            }
        }
        (xadj, adj)
    }

    #[test]
    fn is_a_permutation_of_a_grid_and_of_a_disconnected_graph() {
        for (nx, ny) in [(1, 1), (3, 1), (40, 30), (129, 7)] {
            let (xadj, adj) = grid(nx, ny);
            let mut p = nested_dissection(&xadj, &adj);
            p.sort_unstable();
            assert_eq!(p, (0..nx * ny).collect::<Vec<_>>(), "{nx}×{ny}");
        }
        // Two grids side by side, no edge between them.
        let (x1, a1) = grid(20, 20);
        let mut xadj = x1.clone();
        let mut adj = a1.clone();
        let off = 400;
        for k in 1..x1.len() {
            xadj.push(x1[k] + a1.len());
        }
        adj.extend(a1.iter().map(|v| v + off));
        let mut p = nested_dissection(&xadj, &adj);
        p.sort_unstable();
        assert_eq!(p, (0..800).collect::<Vec<_>>());
    }

    #[test]
    fn the_top_separator_of_a_grid_separates() {
        // The last vertices of the order are the top separator: removing them leaves no
        // edge between the two sides ordered before them.
        let (nx, ny) = (60, 40);
        let (xadj, adj) = grid(nx, ny);
        let p = nested_dissection(&xadj, &adj);
        let mut g = Graph {
            xadj: &xadj,
            adj: &adj,
            stamp: vec![0; nx * ny],
            level: vec![usize::MAX; nx * ny],
            current: 0,
        };
        let all: Vec<usize> = (0..nx * ny).collect();
        let (a, b, s) = g.split(&all).expect("splits");
        assert_eq!(a.len() + b.len() + s.len(), nx * ny);
        assert!(
            s.len() <= 2 * nx.max(ny),
            "separator of {} vertices",
            s.len()
        );
        let side: Vec<u8> = {
            let mut side = vec![0u8; nx * ny];
            a.iter().for_each(|&v| side[v] = 1);
            b.iter().for_each(|&v| side[v] = 2);
            side
        };
        for &v in &a {
            for &w in &adj[xadj[v]..xadj[v + 1]] {
                assert_ne!(side[w], 2, "edge {v}–{w} crosses the separator");
            }
        }
        assert_eq!(&p[p.len() - s.len()..], &s[..]);
    }
}

/// The dof graph of the footing's P2 meshes, for the tests of the orderings.
#[cfg(test)]
pub(crate) mod test_meshes {
    /// Dof graph of a P2 mesh of `nx × ny` cells, 2 triangles each, 2 dofs per node.
    pub(crate) fn p2_graph(nx: usize, ny: usize) -> (Vec<usize>, Vec<usize>) {
        let (mx, my) = (2 * nx + 1, 2 * ny + 1);
        let node = |i: usize, j: usize| j * mx + i;
        let mut elements = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let (i2, j2) = (2 * i, 2 * j);
                elements.push([
                    node(i2, j2),
                    node(i2 + 2, j2),
                    node(i2 + 2, j2 + 2),
                    node(i2 + 1, j2),
                    node(i2 + 2, j2 + 1),
                    node(i2 + 1, j2 + 1),
                ]);
                elements.push([
                    node(i2, j2),
                    node(i2 + 2, j2 + 2),
                    node(i2, j2 + 2),
                    node(i2 + 1, j2 + 1),
                    node(i2 + 1, j2 + 2),
                    node(i2, j2 + 1),
                ]);
            }
        }
        let n = 2 * mx * my;
        let mut nb: Vec<Vec<usize>> = vec![Vec::new(); n];
        for e in &elements {
            for &a in e {
                for &b in e {
                    for da in 0..2 {
                        for db in 0..2 {
                            let (u, v) = (2 * a + da, 2 * b + db);
                            if u != v {
                                nb[u].push(v);
                            }
                        }
                    }
                }
            }
        }
        let mut xadj = vec![0];
        let mut adj = Vec::new();
        for l in &mut nb {
            l.sort_unstable();
            l.dedup();
            adj.extend_from_slice(l);
            xadj.push(adj.len());
        }
        (xadj, adj)
    }
}

#[cfg(test)]
mod measure {
    use super::test_meshes::p2_graph;
    use super::*;
    use faer::perm::PermRef;
    use faer::sparse::linalg::cholesky::{
        factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholeskyRaw, SymmetricOrdering,
    };
    use faer::sparse::linalg::SupernodalThreshold;
    use faer::sparse::{Pair, SymbolicSparseColMat};
    use faer::Side;

    fn cost(xadj: &[usize], adj: &[usize], perm: Option<&[usize]>) -> (usize, f64) {
        let n = xadj.len() - 1;
        let mut pairs: Vec<Pair<usize, usize>> = (0..n).map(|j| Pair::new(j, j)).collect();
        for v in 0..n {
            for &w in &adj[xadj[v]..xadj[v + 1]] {
                if w < v {
                    pairs.push(Pair::new(v, w));
                }
            }
        }
        let (lower, _) = SymbolicSparseColMat::try_new_from_indices(n, n, &pairs).unwrap();
        let inv: Vec<usize>;
        let ordering = match perm {
            None => SymmetricOrdering::Amd,
            Some(p) => {
                let mut i = vec![0; n];
                for (new, &old) in p.iter().enumerate() {
                    i[old] = new;
                }
                inv = i;
                SymmetricOrdering::Custom(PermRef::new_checked(p, &inv, n))
            }
        };
        let chol = factorize_symbolic_cholesky(
            lower.as_ref(),
            Side::Lower,
            ordering,
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
                ..Default::default()
            },
        )
        .unwrap();
        let SymbolicCholeskyRaw::Supernodal(sn) = chol.raw() else {
            panic!()
        };
        let mut nnz = 0;
        let mut flops = 0.0;
        let begin = sn.supernode_begin();
        for s in 0..sn.n_supernodes() {
            let c = (if s + 1 < sn.n_supernodes() {
                begin[s + 1]
            } else {
                n
            }) - begin[s];
            let r = sn.supernode(s).pattern().len();
            nnz += c * (c + 1) / 2 + c * r;
            // column j of the supernode has (c − j + r) entries below the diagonal
            for j in 0..c {
                let below = (c - j - 1 + r) as f64;
                flops += below * below;
            }
        }
        (nnz, flops)
    }

    /// Median of 3 numeric supernodal LLᵀ of a diagonally dominant matrix on the pattern.
    fn numeric_llt_seconds(xadj: &[usize], adj: &[usize], perm: Option<&[usize]>) -> f64 {
        use faer::dyn_stack::{MemBuffer, MemStack};
        use faer::sparse::{SparseColMat, Triplet};
        let n = xadj.len() - 1;
        let mut t = Vec::new();
        for v in 0..n {
            t.push(Triplet::new(v, v, 100.0));
            for &w in &adj[xadj[v]..xadj[v + 1]] {
                if w > v {
                    t.push(Triplet::new(w, v, -1.0 / (1.0 + (v + w) as f64 % 7.0)));
                }
            }
        }
        let a = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &t).unwrap();
        let inv: Vec<usize>;
        let ordering = match perm {
            None => SymmetricOrdering::Amd,
            Some(p) => {
                let mut i = vec![0; n];
                for (new, &old) in p.iter().enumerate() {
                    i[old] = new;
                }
                inv = i;
                SymmetricOrdering::Custom(PermRef::new_checked(p, &inv, n))
            }
        };
        let sym =
            factorize_symbolic_cholesky(a.symbolic(), Side::Lower, ordering, Default::default())
                .unwrap();
        let mut values = vec![0.0; sym.len_val()];
        let mut mem = MemBuffer::new(
            sym.factorize_numeric_llt_scratch::<f64>(faer::Par::Seq, Default::default()),
        );
        let mut times: Vec<f64> = (0..3)
            .map(|_| {
                let start = std::time::Instant::now();
                sym.factorize_numeric_llt::<f64>(
                    &mut values,
                    a.as_ref(),
                    Side::Lower,
                    Default::default(),
                    faer::Par::Seq,
                    MemStack::new(&mut mem),
                    Default::default(),
                )
                .unwrap();
                start.elapsed().as_secs_f64()
            })
            .collect();
        times.sort_by(f64::total_cmp);
        times[1]
    }

    #[test]
    #[ignore = "measurement: cargo test --release -p talus-ssn nested_dissection -- --ignored --nocapture"]
    fn fill_against_amd() {
        for (nx, ny) in [(32, 14), (104, 48), (208, 96), (320, 156)] {
            let (xadj, adj) = p2_graph(nx, ny);
            let t = std::time::Instant::now();
            let amd = cost(&xadj, &adj, None);
            let ta = t.elapsed().as_secs_f64();
            let t = std::time::Instant::now();
            let p = nested_dissection(&xadj, &adj);
            let tnd = t.elapsed().as_secs_f64();
            let nd = cost(&xadj, &adj, Some(&p));
            let (t_amd, t_nd) = (
                numeric_llt_seconds(&xadj, &adj, None),
                numeric_llt_seconds(&xadj, &adj, Some(&p)),
            );
            println!("{nx}x{ny} numeric LLT (faer, one thread): AMD {t_amd:.3} s, ND {t_nd:.3} s, ratio {:.3}", t_nd / t_amd);
            println!(
                "{nx}x{ny} n={} AMD nnz(L) {:.3}M flops {:.3}G ({ta:.2}s) | ND nnz {:.3}M flops {:.3}G (order {tnd:.2}s) | ratio nnz {:.3} flops {:.3}",
                xadj.len() - 1,
                amd.0 as f64 * 1e-6,
                amd.1 * 1e-9,
                nd.0 as f64 * 1e-6,
                nd.1 * 1e-9,
                nd.0 as f64 / amd.0 as f64,
                nd.1 / amd.1
            );
        }
    }
}
