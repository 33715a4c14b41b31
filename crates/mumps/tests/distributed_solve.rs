//! MUMPS through the handle on 1 and 2 ranks, against closed forms. Outside `mpirun` this
//! program relaunches itself under `mpirun -np 1` and `-np 2` and fails if either fails.
//!
//! The matrices: the 1D convection–diffusion operator `tridiag(−1 − c, 2 + s, −1 + c)` and,
//! for inertia, the symmetric `tridiag(−1, 2 − s, −1)`, whose eigenvalues are
//! `2 − s − 2 cos(kπ/(n+1))`, k = 1..n (Golub & Van Loan, 4th ed., §4.8): the number of
//! negative ones is the LDLᵀ's negative pivots (Sylvester's law of inertia) and fixes the
//! determinant's sign.
//!
//! On rank 0 alone (`Placement::Host`): the same solutions, the same figures on every rank,
//! and a 40 000-unknown 5-point operator factorized twice and solved twice to the same
//! bits (over two ranks MUMPS does not repeat them: `docs/distributed.md`,
//! 'Reproducibility').
#[path = "common/five_point.rs"]
mod five_point;

use std::process::ExitCode;

use five_point::{bits_hash, five_point_entries, five_point_rhs};
use talus_mumps::{Mumps, Placement, Symmetry};

const N: usize = 400;

/// Entries of a tridiagonal matrix `(lower, diagonal, upper)`; rows split between ranks
/// by blocks, the diagonal of the row at each block boundary given in two halves (one
/// per neighbouring rank) so that MUMPS' summing of duplicates is exercised.
fn local_entries(
    rank: usize,
    size: usize,
    (lower, diagonal, upper): (f64, f64, f64),
    triangle: bool,
) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
    let (mut rows, mut cols, mut vals) = (Vec::new(), Vec::new(), Vec::new());
    let block = N.div_ceil(size);
    let (first, last) = (rank * block, ((rank + 1) * block).min(N));
    for i in first..last {
        let boundary = i == first && rank > 0;
        let half = if boundary || (i + 1 == last && rank + 1 < size) {
            0.5
        } else {
            1.0
        };
        rows.push(i);
        cols.push(i);
        vals.push(half * diagonal);
        if i > 0 {
            rows.push(i);
            cols.push(i - 1);
            vals.push(lower);
        }
        if i + 1 < N && !triangle {
            rows.push(i);
            cols.push(i + 1);
            vals.push(upper);
        }
    }
    // The other half of the boundary diagonals.
    if rank + 1 < size {
        rows.push(last);
        cols.push(last);
        vals.push(0.5 * diagonal);
    }
    if rank > 0 {
        rows.push(first - 1);
        cols.push(first - 1);
        vals.push(0.5 * diagonal);
    }
    (rows, cols, vals)
}

fn tridiagonal_product((lower, diagonal, upper): (f64, f64, f64), x: &[f64]) -> Vec<f64> {
    (0..N)
        .map(|i| {
            let mut y = diagonal * x[i];
            if i > 0 {
                y += lower * x[i - 1];
            }
            if i + 1 < N {
                y += upper * x[i + 1];
            }
            y
        })
        .collect()
}

fn relative_error(x: &[f64], y: &[f64]) -> f64 {
    let d = x
        .iter()
        .zip(y)
        .map(|(a, b)| (a - b).powi(2))
        .sum::<f64>()
        .sqrt();
    d / y.iter().map(|b| b * b).sum::<f64>().sqrt()
}

/// Rank 0 reports every check; another rank only its failures.
fn check(name: &str, ok: bool, detail: String, failures: &mut usize) {
    let rank0 = std::env::var("OMPI_COMM_WORLD_RANK").map_or(true, |r| r == "0");
    if rank0 || !ok {
        eprintln!("{} {name}: {detail}", if ok { "ok" } else { "FAILED" });
    }
    if !ok {
        *failures += 1;
    }
}

/// MUMPS analysed and factorized on this rank's `entries`, over all ranks.
fn factorized(
    symmetry: Symmetry,
    determinant: bool,
    entries: &(Vec<usize>, Vec<usize>, Vec<f64>),
) -> Mumps {
    factorized_on(Placement::AllRanks, symmetry, determinant, entries)
}

fn factorized_on(
    placement: Placement,
    symmetry: Symmetry,
    determinant: bool,
    (rows, cols, vals): &(Vec<usize>, Vec<usize>, Vec<f64>),
) -> Mumps {
    let mut m = Mumps::with_placement(symmetry, determinant, placement).expect("MUMPS starts");
    m.analyse(N, rows, cols).expect("analysis");
    m.factorize(vals).expect("factorization");
    m
}

/// The relative error of `m`'s solution of `A x = A exact` for the tridiagonal `matrix`.
fn solve_error(m: &mut Mumps, matrix: (f64, f64, f64), exact: &[f64]) -> f64 {
    let mut x = tridiagonal_product(matrix, exact);
    m.solve(&mut x).expect("solve");
    relative_error(&x, exact)
}

fn under_mpirun(rank: usize, size: usize) -> usize {
    let mut failures = 0;
    let exact: Vec<f64> = (0..N).map(|i| (0.1 * i as f64).sin() + 1.0).collect();

    // Unsymmetric LU, solved twice on the same factorization and refactorized.
    let convection = (-1.3, 2.01, -0.7);
    let entries = local_entries(rank, size, convection, false);
    let mut lu = factorized(Symmetry::Unsymmetric, true, &entries);
    let rhs = tridiagonal_product(convection, &exact);
    let mut x = rhs.clone();
    lu.solve(&mut x).expect("solve");
    let error = relative_error(&x, &exact);
    check(
        "unsymmetric LU solves A x = b",
        error < 1e-12,
        format!("relative error {error:.2e}"),
        &mut failures,
    );
    lu.factorize(&entries.2).expect("second factorization");
    let mut again = rhs.clone();
    lu.solve(&mut again).expect("second solve");
    check(
        "a second factorization gives the same bits",
        again
            .iter()
            .zip(&x)
            .all(|(a, b)| a.to_bits() == b.to_bits()),
        String::new(),
        &mut failures,
    );
    let stats = lu.statistics();
    check(
        "the determinant of a diagonally dominant tridiagonal matrix is positive",
        stats.determinant_sign == Some(1.0),
        format!("{stats:?}"),
        &mut failures,
    );
    check(
        "factor entries at least the matrix's",
        stats.factor_entries >= 3 * N as i64 - 2,
        format!("{}", stats.factor_entries),
        &mut failures,
    );

    // Symmetric indefinite LDLᵀ: inertia against the closed-form eigenvalues.
    // 93 negative eigenvalues: an odd count, so the determinant is negative.
    let shift = 0.51;
    let symmetric = (-1.0, 2.0 - shift, -1.0);
    let negative = negative_eigenvalues(shift);
    let entries = local_entries(rank, size, symmetric, true);
    let mut ldlt = factorized(Symmetry::Symmetric, true, &entries);
    let error = solve_error(&mut ldlt, symmetric, &exact);
    check(
        "symmetric LDLᵀ solves A x = b",
        error < 1e-10,
        format!("relative error {error:.2e}"),
        &mut failures,
    );
    let stats = ldlt.statistics();
    let sign = if negative.is_multiple_of(2) {
        1.0
    } else {
        -1.0
    };
    check(
        "LDLᵀ's negative pivots are the negative eigenvalues",
        stats.negative_pivots as usize == negative && stats.determinant_sign == Some(sign),
        format!(
            "{} negative pivots, {negative} negative eigenvalues, sign {:?}",
            stats.negative_pivots, stats.determinant_sign
        ),
        &mut failures,
    );
    // The unsymmetric LU of the same matrix (both triangles): the determinant's sign.
    let lu = factorized(
        Symmetry::Unsymmetric,
        true,
        &local_entries(rank, size, symmetric, false),
    );
    check(
        "the LU's determinant sign is (−1)^(negative eigenvalues)",
        lu.statistics().determinant_sign == Some(sign),
        format!("{:?} against {sign}", lu.statistics().determinant_sign),
        &mut failures,
    );

    // Positive definite LDLᵀ without pivoting.
    let spd = (-1.0, 2.0 + shift, -1.0);
    let entries = local_entries(rank, size, spd, true);
    let vals = &entries.2;
    let mut llt = factorized(Symmetry::PositiveDefinite, false, &entries);
    let error = solve_error(&mut llt, spd, &exact);
    check(
        "positive definite LDLᵀ solves A x = b",
        error < 1e-12,
        format!("relative error {error:.2e}"),
        &mut failures,
    );

    // Bad input is an error naming the field.
    let err = llt
        .factorize(&vals[..vals.len() - 1])
        .unwrap_err()
        .to_string();
    check(
        "a short value array is refused",
        err.starts_with("values = "),
        err,
        &mut failures,
    );
    let err = llt.analyse(N, &[N], &[0]).unwrap_err().to_string();
    check(
        "an index outside the matrix is refused",
        err.starts_with("rows/cols = "),
        err,
        &mut failures,
    );
    failures + on_host(rank, size, &exact)
}

/// Negative eigenvalues of `tridiag(−1, 2 − shift, −1)`: `2 − shift − 2 cos(kπ/(N+1)) < 0`.
fn negative_eigenvalues(shift: f64) -> usize {
    (1..=N)
        .filter(|&k| {
            2.0 - shift - 2.0 * (k as f64 * std::f64::consts::PI / (N as f64 + 1.0)).cos() < 0.0
        })
        .count()
}

/// `Placement::Host`: MUMPS on rank 0 alone, from every rank's entries.
fn on_host(rank: usize, size: usize, exact: &[f64]) -> usize {
    let mut failures = 0;
    // The LU of the convection operator, whose boundary diagonals two ranks share.
    let convection = (-1.3, 2.01, -0.7);
    let mut lu = factorized_on(
        Placement::Host,
        Symmetry::Unsymmetric,
        true,
        &local_entries(rank, size, convection, false),
    );
    let error = solve_error(&mut lu, convection, exact);
    check(
        "on the host: unsymmetric LU solves A x = b on every rank",
        error < 1e-12 && lu.factor_ranks() == 1,
        format!(
            "relative error {error:.2e}, {} factor ranks",
            lu.factor_ranks()
        ),
        &mut failures,
    );
    check(
        "on the host: every rank has the host's figures",
        lu.statistics().determinant_sign == Some(1.0) && lu.statistics().factor_entries > 0,
        format!("{:?}", lu.statistics()),
        &mut failures,
    );
    // Symmetric indefinite LDLᵀ: the inertia reaches every rank.
    let shift = 0.51;
    let symmetric = (-1.0, 2.0 - shift, -1.0);
    let ldlt = factorized_on(
        Placement::Host,
        Symmetry::Symmetric,
        true,
        &local_entries(rank, size, symmetric, true),
    );
    let negative = negative_eigenvalues(shift);
    check(
        "on the host: LDLᵀ's negative pivots are the negative eigenvalues on every rank",
        ldlt.statistics().negative_pivots as usize == negative,
        format!("{:?}, {negative} negative eigenvalues", ldlt.statistics()),
        &mut failures,
    );

    // The same bits from two factorizations and two solves of each.
    let m = 200;
    let (rows, cols, values) = five_point_entries(m, rank, size);
    let mut host =
        Mumps::with_placement(Symmetry::Unsymmetric, false, Placement::Host).expect("MUMPS");
    host.analyse(m * m, &rows, &cols).expect("analysis");
    let mut hashes = Vec::new();
    let mut x = Vec::new();
    for _ in 0..2 {
        host.factorize(&values).expect("factorization");
        for _ in 0..2 {
            x = five_point_rhs(m * m);
            host.solve(&mut x).expect("solve");
            hashes.push(bits_hash(&x));
        }
    }
    check(
        "on the host: two factorizations, two solves each, the same bits",
        hashes.iter().all(|&h| h == hashes[0]),
        format!("{hashes:016x?}"),
        &mut failures,
    );
    // And they solve the system: the residual of the whole operator.
    let (all_rows, all_cols, all_values) = five_point_entries(m, 0, 1);
    let mut residual = five_point_rhs(m * m);
    for ((&i, &j), &v) in all_rows.iter().zip(&all_cols).zip(&all_values) {
        residual[i] -= v * x[j];
    }
    let r = residual.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    check(
        "on the host: the 5-point solution's residual",
        r < 1e-10,
        format!("max residual {r:.2e}"),
        &mut failures,
    );
    failures
}

fn main() -> ExitCode {
    if let Some(code) = talus_mumps::relaunch_under_mpirun("distributed_solve", &[1, 2]) {
        return code;
    }
    let universe = mpi::initialize().expect("MPI initializes once");
    use mpi::traits::Communicator;
    let world = universe.world();
    let failures = under_mpirun(world.rank() as usize, world.size() as usize);
    if failures == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}
