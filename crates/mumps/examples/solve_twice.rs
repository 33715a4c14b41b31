//! Does MUMPS give the same bits twice? `mpirun -np N target/release/examples/solve_twice`
//! factorizes a 40 000-unknown unsymmetric 5-point operator (every entry handed by one
//! rank, so no duplicate is summed between ranks) twice, solves the same right-hand side
//! twice with each factorization, and prints a hash of each solution's bits
//! (`docs/distributed.md`, 'Reproducibility'). On one rank the four are equal; on two
//! ranks (Debian's MUMPS 5.5.1) they differ between solves of the same factors, and from
//! run to run: MUMPS' parallel solve adds its contributions in the order its messages
//! arrive.
use talus_mumps::{Mumps, Symmetry};

fn main() {
    let _universe = mpi::initialize().expect("MPI initializes once");
    let (rank, size) = talus_mumps::world().expect("MPI is initialized");
    let m = 200;
    let n = m * m;
    let (mut rows, mut cols, mut values) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..m {
        for j in 0..m {
            let k = i * m + j;
            if k % size != rank {
                continue;
            }
            let mut push = |c: usize, v: f64| {
                rows.push(k);
                cols.push(c);
                values.push(v);
            };
            push(k, 4.3 + (k % 7) as f64 * 0.01);
            if i > 0 {
                push(k - m, -1.1);
            }
            if i + 1 < m {
                push(k + m, -0.9);
            }
            if j > 0 {
                push(k - 1, -1.05);
            }
            if j + 1 < m {
                push(k + 1, -0.95);
            }
        }
    }
    let mut mumps = Mumps::new(Symmetry::Unsymmetric, false).expect("MUMPS starts");
    mumps.analyse(n, &rows, &cols).expect("analysis");
    let hash = |x: &[f64]| x.iter().fold(0u64, |h, y| h.rotate_left(5) ^ y.to_bits());
    for factorization in 0..2 {
        mumps.factorize(&values).expect("factorization");
        for solve in 0..2 {
            let mut x: Vec<f64> = (0..n).map(|k| 1.0 + (k % 13) as f64).collect();
            mumps.solve(&mut x).expect("solve");
            if rank == 0 {
                println!(
                    "factorization {factorization}, solve {solve}: {:016x}",
                    hash(&x)
                );
            }
        }
    }
}
