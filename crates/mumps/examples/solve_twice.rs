//! Does MUMPS give the same bits twice? `mpirun -np N target/release/examples/solve_twice
//! [host]` factorizes a 40 000-unknown unsymmetric 5-point operator (every entry handed by
//! one rank, so no duplicate is summed between ranks) twice, solves the same right-hand
//! side twice with each factorization, and prints a hash of each solution's bits
//! (`docs/distributed.md`, 'Reproducibility'). On one rank the four are equal; on two
//! ranks (Debian's MUMPS 5.5.1) they differ between solves of the same factors, and from
//! run to run: MUMPS' parallel solve adds its contributions in the order its messages
//! arrive. With `host` (`Placement::Host`: MUMPS on rank 0 alone) they are equal on any
//! number of ranks.
#[path = "../tests/common/five_point.rs"]
mod five_point;

use five_point::{bits_hash, five_point_entries, five_point_rhs};
use talus_mumps::{Mumps, Placement, Symmetry};

fn main() {
    let _universe = mpi::initialize().expect("MPI initializes once");
    let (rank, size) = talus_mumps::world().expect("MPI is initialized");
    let placement = match std::env::args().nth(1).as_deref() {
        Some("host") => Placement::Host,
        _ => Placement::AllRanks,
    };
    let m = 200;
    let (rows, cols, values) = five_point_entries(m, rank, size);
    let mut mumps =
        Mumps::with_placement(Symmetry::Unsymmetric, false, placement).expect("MUMPS starts");
    mumps.analyse(m * m, &rows, &cols).expect("analysis");
    for factorization in 0..2 {
        mumps.factorize(&values).expect("factorization");
        for solve in 0..2 {
            let mut x = five_point_rhs(m * m);
            mumps.solve(&mut x).expect("solve");
            if rank == 0 {
                println!(
                    "{placement:?}, factorization {factorization}, solve {solve}: {:016x}",
                    bits_hash(&x)
                );
            }
        }
    }
}
