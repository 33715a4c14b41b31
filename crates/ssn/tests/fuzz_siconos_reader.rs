//! Fuzzing of the Siconos `.dat` reader (`talus reduced FILE`): mutated shipped files and
//! generated problems. The reader returns a problem or an error and never panics; a problem
//! it returns is consistent (sizes `n = d * n_c`, finite numbers, indices in range) and
//! turns into a reduced system without panicking.
//! `TALUS_FUZZ_CASES` / `TALUS_FUZZ_SCALE` raise the case count (`cargo xtask fuzz`);
//! `docs/scenes.md`, 'Fuzzing'.
use std::panic::{catch_unwind, AssertUnwindSafe};

use proptest::prelude::*;
use talus_ssn::reduced_system_from_siconos;
use talus_ssn::siconos::{SiconosMatrix, SiconosModel, SiconosProblem};

#[path = "common/mutations.rs"]
mod mutations;
use mutations::{apply, cases, fuzz, mutated, Outcome};

const DATA: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../data/siconos-plasticity/"
);

/// The shipped files small enough to parse in microseconds (the 3 MB footings add nothing
/// the 30 kB one, with the old header, does not have), and a CSC matrix, which no shipped
/// file uses.
fn seeds() -> Vec<Vec<u8>> {
    let mut seeds: Vec<Vec<u8>> = [
        "plasticity_2d_footing_1.dat",
        "plasticity_2d_footing_10.dat",
        "plasticity_2d_example1.dat",
        "plasticity_2d_example1_theta0.dat",
        "plasticity_2d_vonmises_example1.dat",
    ]
    .iter()
    .map(|name| std::fs::read(format!("{DATA}{name}")).expect("shipped .dat file"))
    .collect();
    seeds.push(
        "3\n1\n2\n2\n3\n3\n2\nCSparse Version 4.4.1, June 20, 2024.\n\
         3-by-3, nzmax: 3 nnz: 3, 1-norm: 9\n    col 0 : locations 0 to 1\n      0 : 4\n      \
         2 : -5\n    col 1 : locations 2 to 1\n    col 2 : locations 2 to 2\n      1 : 7\n\
         0 0 0\n2\n"
            .as_bytes()
            .to_vec(),
    );
    seeds
}

/// Checks what the reader promises of a problem it returned.
fn consistent(p: &SiconosProblem) -> Result<(), String> {
    let (d, nc) = (p.cone_dimension, p.n_cones);
    if d < 2 || nc == 0 {
        return Err(format!("d = {d}, n_c = {nc}"));
    }
    let n = d * nc;
    let finite = |v: &[f64], what: &str| match v.iter().find(|x| !x.is_finite()) {
        Some(x) => Err(format!("{what} holds {x}")),
        None => Ok(()),
    };
    match &p.matrix {
        SiconosMatrix::Dense { n: m, values } => {
            if *m != n || values.len() != n * n {
                return Err(format!("dense {m} x {m}, {} values, n = {n}", values.len()));
            }
            finite(values, "W")?;
        }
        SiconosMatrix::Sparse { n: m, triplets } => {
            if *m != n {
                return Err(format!("sparse {m} x {m}, n = {n}"));
            }
            if let Some(t) = triplets
                .iter()
                .find(|t| t.0 >= n || t.1 >= n || !t.2.is_finite())
            {
                return Err(format!("triplet {t:?} for n = {n}"));
            }
        }
    }
    if p.q.len() != n {
        return Err(format!("q has {} values, n = {n}", p.q.len()));
    }
    finite(&p.q, "q")?;
    let nonnegative = |v: &[f64], what: &str| {
        if v.len() != nc {
            return Err(format!("{what} has {} values, n_c = {nc}", v.len()));
        }
        match v.iter().find(|x| !(x.is_finite() && **x >= 0.0)) {
            Some(x) => Err(format!("{what} holds {x}")),
            None => Ok(()),
        }
    };
    match &p.model {
        SiconosModel::DruckerPrager { eta, theta } => {
            nonnegative(eta, "eta")?;
            if theta.len() != nc {
                return Err(format!("theta has {} values", theta.len()));
            }
            finite(theta, "theta")?;
        }
        SiconosModel::VonMises { sigma_y } => nonnegative(sigma_y, "sigma_y")?,
    }
    // The path of `talus reduced`: building the reduced system returns Ok or an error.
    if d == 3 {
        catch_unwind(AssertUnwindSafe(|| {
            let _ = reduced_system_from_siconos::<3>(p);
        }))
        .map_err(|_| "reduced_system_from_siconos panicked on a problem the reader accepted")?;
    }
    Ok(())
}

fn read(text: &[u8]) -> Result<Outcome, String> {
    match SiconosProblem::parse(&String::from_utf8_lossy(text)) {
        Ok(p) => consistent(&p).map(|()| Outcome::Read),
        Err(e) => Ok(Outcome::Refused(e.to_string())),
    }
}

/// Mutated shipped files.
#[test]
fn mutated_files_are_read_or_refused_never_panic() {
    let seeds = seeds();
    fuzz(
        "siconos .dat (mutated files)",
        cases(20_000),
        mutated(seeds.len()),
        |(seed, mutations)| read(&apply(&seeds[*seed], mutations)),
    );
}

// ------------------------------------------------------------------ generated problems

/// A problem as generated, and how to write it.
#[derive(Debug, Clone)]
struct Generated {
    d: usize,
    nc: usize,
    /// Old header (no model line; Drucker-Prager only).
    old: bool,
    /// 0 dense, 1 triplet, 2 CSC.
    storage: u8,
    /// Row-major n x n (dense), or the entries (row, col, value) in file order.
    dense: Vec<f64>,
    entries: Vec<(usize, usize, f64)>,
    q: Vec<f64>,
    /// Drucker-Prager (eta, theta) or von Mises (sigma_y, empty).
    params: (Vec<f64>, Vec<f64>),
    von_mises: bool,
    /// Spelling of the numbers: 0 `{:e}`, 1 `{:.17e}` with padding, 2 `{}`.
    spelling: u8,
    crlf: bool,
}

fn value() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -1e3f64..1e3,
        1 => Just(0.0),
        1 => Just(-0.0),
        1 => Just(1e300),
        1 => Just(-1e-300),
        1 => Just(f64::MIN_POSITIVE / 4.0),
        1 => any::<f64>().prop_filter("finite", |v| v.is_finite()),
    ]
}

fn generated() -> impl Strategy<Value = Generated> {
    (2usize..=4, 1usize..=4, any::<bool>(), 0u8..3, any::<bool>())
        .prop_flat_map(|(d, nc, old, storage, von_mises)| {
            let n = d * nc;
            let von_mises = von_mises && !old;
            (
                Just((d, nc, old, storage, von_mises)),
                proptest::collection::vec(value(), n * n),
                proptest::collection::vec((0..n, 0..n, value()), 0..=2 * n),
                proptest::collection::vec(value(), n),
                proptest::collection::vec(value().prop_map(f64::abs), nc),
                proptest::collection::vec(value(), if von_mises { 0 } else { nc }),
                0u8..3,
                any::<bool>(),
            )
        })
        .prop_map(
            |((d, nc, old, storage, von_mises), dense, mut entries, q, p0, p1, spelling, crlf)| {
                if storage == 2 {
                    // CSC: by column, no repeated (row, col) within the file's order rules.
                    entries.sort_by_key(|e| (e.1, e.0));
                    entries.dedup_by_key(|e| (e.1, e.0));
                }
                Generated {
                    d,
                    nc,
                    old,
                    storage,
                    dense,
                    entries,
                    q,
                    params: (p0, p1),
                    von_mises,
                    spelling,
                    crlf,
                }
            },
        )
}

impl Generated {
    fn num(&self, v: f64) -> String {
        match self.spelling {
            0 => format!("{v:e}"),
            1 => format!(" {v:.17e} "),
            _ => format!("{v}"),
        }
    }

    fn text(&self) -> String {
        let n = self.d * self.nc;
        let mut t = format!("{}\n{}\n", self.d, self.nc);
        if !self.old {
            t += if self.von_mises { "2\n" } else { "1\n" };
        }
        let storage = if self.storage == 0 { 0 } else { 2 };
        t += &format!("{storage}\n{n}\n{n}\n");
        let banner = "CSparse Version 4.4.1, June 20, 2024.  Copyright (c) Timothy A. Davis\n";
        match self.storage {
            0 => {
                t += &format!("{n}\t{n}\n");
                for j in 0..n {
                    for i in 0..n {
                        t += &self.num(self.dense[i * n + j]);
                        t += " ";
                    }
                    t += "\n";
                }
            }
            1 => {
                let nnz = self.entries.len();
                t += &format!(
                    "1\n{banner}triplet: {n}-by-{n}, nzmax: {} nnz: {nnz}\n",
                    nnz + 3
                );
                for &(i, j, v) in &self.entries {
                    t += &format!("    {i} {j} : {}\n", self.num(v));
                }
            }
            _ => {
                let nnz = self.entries.len();
                t += &format!("2\n{banner}{n}-by-{n}, nzmax: {nnz} nnz: {nnz}, 1-norm: 1\n");
                let mut p = 0;
                for j in 0..n {
                    let end = p + self.entries[p..].iter().take_while(|e| e.1 == j).count();
                    t += &format!("    col {j} : locations {p} to {}\n", end as i64 - 1);
                    for &(i, _, v) in &self.entries[p..end] {
                        t += &format!("      {i} : {}\n", self.num(v));
                    }
                    p = end;
                }
            }
        }
        let line = |v: &[f64]| v.iter().map(|&x| self.num(x)).collect::<Vec<_>>().join(" ") + "\n";
        t += &line(&self.q);
        t += &line(&self.params.0);
        if !self.von_mises {
            t += &line(&self.params.1);
        }
        if self.crlf {
            t = t.replace('\n', "\r\n");
        }
        t
    }

    /// The problem the text must read back as.
    fn problem(&self) -> SiconosProblem {
        let n = self.d * self.nc;
        let matrix = match self.storage {
            0 => SiconosMatrix::Dense {
                n,
                values: self.dense.clone(),
            },
            _ => SiconosMatrix::Sparse {
                n,
                triplets: self.entries.clone(),
            },
        };
        let model = if self.von_mises {
            SiconosModel::VonMises {
                sigma_y: self.params.0.clone(),
            }
        } else {
            SiconosModel::DruckerPrager {
                eta: self.params.0.clone(),
                theta: self.params.1.clone(),
            }
        };
        SiconosProblem {
            cone_dimension: self.d,
            n_cones: self.nc,
            matrix,
            q: self.q.clone(),
            model,
        }
    }
}

/// Generated problems of every layout (both headers, dense, triplet and CSC storage, both
/// models) read back exactly, bit for bit (`-0.0` and subnormals included).
#[test]
fn generated_problems_read_back_exactly() {
    fuzz("siconos .dat (generated)", cases(5_000), generated(), |g| {
        let text = g.text();
        let read = SiconosProblem::parse(&text)
            .map_err(|e| format!("refused a valid problem: {e}\n{text}"))?;
        let want = g.problem();
        let bits = |p: &SiconosProblem| format!("{p:?}");
        // Debug prints -0.0 and every f64 exactly.
        if bits(&read) != bits(&want) {
            return Err(format!("read {read:?}\nwant {want:?}\nfrom\n{text}"));
        }
        consistent(&read)?;
        Ok(Outcome::Read)
    });
}

/// The generated files, mutated: a second family of seeds, with every layout.
#[test]
fn mutated_generated_problems_never_panic() {
    fuzz(
        "siconos .dat (generated, mutated)",
        cases(10_000),
        (
            generated(),
            proptest::collection::vec(mutations::mutation(), 1..=mutations::MAX_MUTATIONS),
        ),
        |(g, m)| read(&apply(g.text().as_bytes(), m)),
    );
}
