//! The no-pivot LU on one thread and on two (`docs/performance.md`, 'The factorization'):
//! disjoint subtrees of the elimination tree in parallel, the top's large blocks through
//! faer's threads. Same factors bit for bit (`tests/symmetric_pattern_lu.rs`); the figure
//! is the ratio of the medians, measured in one run, alternating.
//!
//! Sizes: `TALUS_LU_BENCH_SIZES` (comma-separated grid sides, default `100,200,300`: 20k,
//! 80k and 180k unknowns). Run with `cargo bench -p talus-ssn --bench lu_threads`.
use std::sync::Arc;
use std::time::Instant;

use talus_ssn::factorization::{
    SymbolicSymmetricPatternLu, SymmetricPatternLu, DEFAULT_PIVOT_TOLERANCE,
};

#[path = "../tests/common/grid_matrix.rs"]
mod grid_matrix;

const REPEATS: usize = 7;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let sizes = std::env::var("TALUS_LU_BENCH_SIZES").unwrap_or_else(|_| "100,200,300".into());
    println!("| grid | unknowns | LU fill | subtrees | 1 thread ms | 2 threads ms | 2 / 1 |");
    println!("|---|---|---|---|---|---|---|");
    for side in sizes.split(',').filter(|s| !s.is_empty()) {
        let Ok(m) = side.trim().parse::<usize>() else {
            eprintln!("TALUS_LU_BENCH_SIZES: `{side}` is not a grid side");
            std::process::exit(2);
        };
        let a = grid_matrix::grid_matrix(m, m, 1.0, 3);
        let symbolic = match SymbolicSymmetricPatternLu::try_new(a.symbolic()) {
            Ok(s) => Arc::new(s),
            Err(e) => {
                eprintln!("{e}");
                std::process::exit(1);
            }
        };
        let pools: Vec<rayon::ThreadPool> = [1, 2]
            .iter()
            .map(|&t| {
                rayon::ThreadPoolBuilder::new()
                    .num_threads(t)
                    .build()
                    .unwrap_or_else(|e| panic!("thread pool: {e}"))
            })
            .collect();
        let mut lu = SymmetricPatternLu::new(Arc::clone(&symbolic));
        let mut times = [Vec::new(), Vec::new()];
        for _ in 0..REPEATS {
            for (pool, t) in pools.iter().zip(times.iter_mut()) {
                let start = Instant::now();
                if let Err(e) = pool.install(|| lu.factorize(a.val(), DEFAULT_PIVOT_TOLERANCE)) {
                    eprintln!("{e}");
                    std::process::exit(1);
                }
                t.push(start.elapsed().as_secs_f64() * 1e3);
            }
        }
        let [one, two] = times.map(median);
        println!(
            "| {m}×{m} | {} | {} | {} | {one:.1} | {two:.1} | {:.2} |",
            a.nrows(),
            symbolic.factor_nnz(),
            symbolic.parallel_subtrees(),
            two / one
        );
    }
}
