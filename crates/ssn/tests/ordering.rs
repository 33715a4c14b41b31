//! The fill-reducing ordering setting (`Settings::ordering`, `factorization::Ordering`):
//! AMD by default; with the feature `metis`, nested dissection gives the same solutions
//! (to 1e-12 relative) and less fill on a 3D mesh.

use talus_ssn::{Ordering, Settings};

#[test]
fn amd_is_the_default() {
    assert_eq!(Ordering::default(), Ordering::Amd);
    for s in [Settings::default(), Settings::fem(), Settings::mpm()] {
        assert_eq!(s.ordering, Ordering::Amd);
    }
}

#[cfg(feature = "metis")]
mod nested_dissection {
    use crate::footing_like::FootingLike;
    use talus_ssn::factorization::{
        nested_dissection, SupernodalCholesky, SymbolicSymmetricPatternLu,
    };
    use talus_ssn::faer::sparse::{Pair, SymbolicSparseColMat};
    use talus_ssn::{Ordering, Settings, Solver};

    /// The lower-triangle pattern of a trilinear-hexahedron mesh of `n³` cells, 3 dofs
    /// per node: every pair of dofs of nodes sharing a cell.
    fn hexahedral_pattern(n: usize, lower: bool) -> SymbolicSparseColMat<usize> {
        let m = n + 1;
        let node = |i: usize, j: usize, k: usize| (k * m + j) * m + i;
        let mut pairs = Vec::new();
        for k in 0..n {
            for j in 0..n {
                for i in 0..n {
                    let mut nodes = Vec::new();
                    for (a, b, c) in (0..8).map(|v| (v & 1, (v >> 1) & 1, v >> 2)) {
                        nodes.push(node(i + a, j + b, k + c));
                    }
                    for &p in &nodes {
                        for &q in &nodes {
                            for (x, y) in (0..3).flat_map(|x| (0..3).map(move |y| (x, y))) {
                                let (r, c) = (3 * p + x, 3 * q + y);
                                if !lower || r >= c {
                                    pairs.push(Pair::new(r, c));
                                }
                            }
                        }
                    }
                }
            }
        }
        let dofs = 3 * m * m * m;
        SymbolicSparseColMat::try_new_from_indices(dofs, dofs, &pairs)
            .unwrap()
            .0
    }

    #[test]
    fn nested_dissection_is_a_permutation() {
        let pattern = hexahedral_pattern(6, false);
        let (fwd, inv) = nested_dissection(pattern.as_ref()).unwrap();
        assert_eq!(fwd.len(), pattern.nrows());
        for (new, &old) in fwd.iter().enumerate() {
            assert_eq!(inv[old], new);
        }
    }

    #[test]
    fn nested_dissection_lowers_the_fill_on_a_3d_mesh() {
        let lower = hexahedral_pattern(16, true);
        let full = hexahedral_pattern(16, false);
        let amd = SupernodalCholesky::try_new_with(lower.as_ref(), Ordering::Amd).unwrap();
        let nd =
            SupernodalCholesky::try_new_with(lower.as_ref(), Ordering::NestedDissection).unwrap();
        let lu_amd =
            SymbolicSymmetricPatternLu::try_new_with(full.as_ref(), Ordering::Amd).unwrap();
        let lu_nd =
            SymbolicSymmetricPatternLu::try_new_with(full.as_ref(), Ordering::NestedDissection)
                .unwrap();
        eprintln!(
            "16³ hexahedra, {} dofs: nnz(L) AMD {} ND {} ({:.2}×); LU fill AMD {} ND {} ({:.2}×)",
            lower.nrows(),
            amd.factor_nnz(),
            nd.factor_nnz(),
            nd.factor_nnz() as f64 / amd.factor_nnz() as f64,
            lu_amd.factor_nnz(),
            lu_nd.factor_nnz(),
            lu_nd.factor_nnz() as f64 / lu_amd.factor_nnz() as f64,
        );
        assert!(nd.factor_nnz() < amd.factor_nnz());
        assert!(lu_nd.factor_nnz() < lu_amd.factor_nnz());
    }

    /// Steps of the footing (Cholesky when associative, the no-pivot LU otherwise) under
    /// both orderings: the same σ to 1e-12 relative (rounding may change an iteration).
    /// Solved to 1e-14 so that the comparison measures the orderings, not the tolerance.
    #[test]
    fn same_solutions_under_both_orderings() {
        for (nx, ny, dilatancy) in [(16, 12, 30.0), (16, 12, 10.0), (32, 24, 10.0)] {
            let footing = FootingLike::new(nx, ny, dilatancy, 1e-2);
            let n = footing.problem.operator().size();
            // Solved to 1e-14 (near the round-off floor, `docs/solver.md`): at the default
            // 1e-12 two solutions of the non-associative footing differ by up to 1.4e-11,
            // the tolerance times the inverse Jacobian's norm, whatever the ordering.
            let settings = |ordering| Settings {
                ordering,
                tolerance: 1e-14,
                ..Settings::fem()
            };
            let mut amd = Solver::new(footing.problem.clone(), settings(Ordering::Amd)).unwrap();
            let mut nd = Solver::new(
                footing.problem.clone(),
                settings(Ordering::NestedDissection),
            )
            .unwrap();
            let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
            let mut worst: f64 = 0.0;
            let mut its = [0; 2];
            for _ in 0..4 {
                amd.set_q(footing.q(&a, 0.05)).unwrap();
                nd.set_q(footing.q(&b, 0.05)).unwrap();
                let ra = amd.solve(&mut a).unwrap();
                let rb = nd.solve(&mut b).unwrap();
                its[0] += ra.iterations;
                its[1] += rb.iterations;
                let scale = a.iter().fold(1.0f64, |m, v| m.max(v.abs()));
                let diff = a
                    .iter()
                    .zip(&b)
                    .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
                worst = worst.max(diff / scale);
            }
            eprintln!(
                "{nx}×{ny}, θ = {dilatancy}: |Δσ|/‖σ‖ = {worst:.1e}; Newton its {its:?}; factor nnz AMD {:?} ND {:?}",
                amd.factor_nnz(),
                nd.factor_nnz()
            );
            assert!(worst <= 1e-12, "{nx}×{ny} θ = {dilatancy}: {worst:e}");
        }
    }
}
