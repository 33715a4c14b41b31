//! The f64 Cholesky of the associative Newton matrix (`docs/performance.md`, 'The
//! Cholesky on two threads'): `SymmetricPatternLlt` on one thread and on two against
//! faer's supernodal Cholesky (sequential, the factorization before it), on the pattern
//! of a 3D P1 stiffness (3 dofs per node, 27-point stencil, SPD values), under nested
//! dissection with `--features metis`, AMD without. Same factor bits on any thread count
//! (`tests/supernodal_llt.rs`); the figures are medians of 5, alternating, as ratios
//! against faer's in the same run.
//!
//! Sizes: `TALUS_LLT_BENCH_SIDES` (comma-separated grid sides, default `20,28`: 24k and
//! 66k unknowns, the second the size of the 3D slope `scenes/slope_3d_fine.msh`). Run with
//! `cargo bench -p talus-ssn --features metis --bench llt_threads`.
use std::sync::Arc;
use std::time::Instant;

use talus_ssn::factorization::{Ordering, SymbolicSymmetricPatternLu, SymmetricPatternLlt};
use talus_ssn::faer::dyn_stack::{MemBuffer, MemStack};
use talus_ssn::faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymmetricOrdering,
};
use talus_ssn::faer::sparse::{SparseColMat, Triplet};
use talus_ssn::faer::{Par, Side};

const REPEATS: usize = 5;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The lower triangle of a 3-dof 27-point stencil on an `m³` grid, symmetric values
/// (SplitMix64), diagonal twice the row's off-diagonal sum plus one.
fn stiffness_like(m: usize) -> SparseColMat<usize, f64> {
    let node = |i: usize, j: usize, k: usize| i + m * (j + m * k);
    let n = 3 * m * m * m;
    let mut state = 7u64;
    let mut next = || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let mut lower = Vec::new();
    let mut sum = vec![0.0; n];
    for k in 0..m {
        for j in 0..m {
            for i in 0..m {
                for dk in -1i64..=1 {
                    for dj in -1i64..=1 {
                        for di in -1i64..=1 {
                            let (ii, jj, kk) = (i as i64 + di, j as i64 + dj, k as i64 + dk);
                            let m = m as i64;
                            if ii < 0 || jj < 0 || kk < 0 || ii >= m || jj >= m || kk >= m {
                                continue;
                            }
                            let other = node(ii as usize, jj as usize, kk as usize);
                            for a in 0..3 {
                                for b in 0..3 {
                                    let (r, c) = (3 * node(i, j, k) + a, 3 * other + b);
                                    if r > c {
                                        let v = next();
                                        sum[r] += v.abs();
                                        sum[c] += v.abs();
                                        lower.push(Triplet::new(r, c, v));
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    for (r, s) in sum.iter().enumerate() {
        lower.push(Triplet::new(r, r, 2.0 * s + 1.0));
    }
    SparseColMat::try_new_from_triplets(n, n, &lower).expect("valid triplets")
}

fn main() {
    #[cfg(feature = "metis")]
    let (ordering, faer_ordering_name) = (Ordering::NestedDissection, "nested dissection");
    #[cfg(not(feature = "metis"))]
    let (ordering, faer_ordering_name) = (Ordering::Amd, "AMD");
    let sides = std::env::var("TALUS_LLT_BENCH_SIDES").unwrap_or_else(|_| "20,28".into());
    println!("ordering: {faer_ordering_name}");
    println!("| grid | unknowns | faer L | ours L | subtrees | faer ms | 1 thread ms | 2 threads ms | 1 / faer | 2 / faer |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for side in sides.split(',').filter(|s| !s.is_empty()) {
        let Ok(m) = side.trim().parse::<usize>() else {
            eprintln!("TALUS_LLT_BENCH_SIDES: `{side}` is not a grid side");
            std::process::exit(2);
        };
        let lower = stiffness_like(m);
        let n = lower.nrows();
        let ours = match SymbolicSymmetricPatternLu::try_new_with(lower.symbolic(), ordering) {
            Ok(s) => Arc::new(s),
            Err(e) => {
                eprintln!("{e}");
                std::process::exit(1);
            }
        };
        // faer's analysis under the same permutation.
        let perm = ours_permutation(&ours, n);
        let faer_symbolic = match factorize_symbolic_cholesky(
            lower.symbolic(),
            Side::Lower,
            SymmetricOrdering::Custom(perm.as_ref()),
            CholeskySymbolicParams::default(),
        ) {
            Ok(s) => s,
            Err(e) => {
                eprintln!("faer symbolic: {e:?}");
                std::process::exit(1);
            }
        };
        let mut faer_values = vec![0.0; faer_symbolic.len_val()];
        let mut scratch = MemBuffer::new(
            faer_symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
        );
        let mut llt = SymmetricPatternLlt::<f64>::new(Arc::clone(&ours));
        let pools: Vec<rayon::ThreadPool> = [1, 2]
            .iter()
            .map(|&t| {
                rayon::ThreadPoolBuilder::new()
                    .num_threads(t)
                    .build()
                    .unwrap_or_else(|e| panic!("thread pool: {e}"))
            })
            .collect();
        let mut times = [Vec::new(), Vec::new(), Vec::new()];
        for _ in 0..REPEATS {
            let start = Instant::now();
            if let Err(e) = faer_symbolic.factorize_numeric_llt::<f64>(
                &mut faer_values,
                lower.as_ref(),
                Side::Lower,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut scratch),
                Default::default(),
            ) {
                eprintln!("faer: {e:?}");
                std::process::exit(1);
            }
            times[0].push(start.elapsed().as_secs_f64() * 1e3);
            for (pool, t) in pools.iter().zip(times[1..].iter_mut()) {
                let start = Instant::now();
                if let Err(e) = pool.install(|| llt.factorize(lower.val())) {
                    eprintln!("{e}");
                    std::process::exit(1);
                }
                t.push(start.elapsed().as_secs_f64() * 1e3);
            }
        }
        let [f, one, two] = times.map(median);
        println!(
            "| {m}³ | {n} | {:.1} M | {:.1} M | {} | {f:.0} | {one:.0} | {two:.0} | {:.2} | {:.2} |",
            faer_values.len() as f64 / 1e6,
            llt.len_val() as f64 / 1e6,
            ours.parallel_subtrees(),
            one / f,
            two / f,
        );
    }
}

/// The fill-reducing permutation of `ours`, for faer's analysis.
fn ours_permutation(
    ours: &SymbolicSymmetricPatternLu,
    n: usize,
) -> talus_ssn::faer::perm::Perm<usize> {
    let fwd = ours.permutation().to_vec();
    let mut inv = vec![0; n];
    for (new, &old) in fwd.iter().enumerate() {
        inv[old] = new;
    }
    talus_ssn::faer::perm::Perm::new_checked(fwd.into_boxed_slice(), inv.into_boxed_slice(), n)
}
