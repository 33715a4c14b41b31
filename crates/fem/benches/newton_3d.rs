//! Memory and speed of the 3D Newton iteration (issue 25, item 3): a square footing on a
//! block of P2 tetrahedra, against one elastic Cholesky factorization and solve of the same
//! mesh, and the fill of the factor under AMD (faer's, what talus-ssn uses) and under
//! nested dissection (METIS, feature `metis`).
//!
//! ```text
//!        y = 0: rough rigid footing [0, 0.25]² ↓ 1 mm/s, 20 kPa on the rest of the top
//!   x = 0, z = 0: symmetry (rollers); x = 1, z = 1: rollers; y = −1: fixed
//!        soil: Drucker-Prager φ = 27°, c = 2 kPa, E = 1 GPa, ν = 0.3, ρ = 2000 kg/m³,
//!        outer-cone fit, K₀ = 0.546 at rest, gravity; h = 1e-2 s
//! ```
//!
//! A quarter of the footing of `scenes/footing.toml` turned into a square one: the block
//! `[0, 1] × [−1, 0] × [0, 1]` m cut into `NX × NY × NZ` uniform cells of 6 P2 tetrahedra
//! each (`TetrahedralMesh::block`). Two flows: `lu`, the paper's non-associative soil
//! (tan θ = tan φ / 2: the no-pivot LU of the velocity-sized Newton matrix), and `llt`,
//! associative (θ = φ: Cholesky). The model is stepped `TALUS_3D_BENCH_STEPS` steps (default
//! 4) from its K₀ state with `StepSettings::fem()` (the footing then pushes 40 µm into the
//! soil: the points under its edges are on the cone); then, interleaved and as in
//! `crates/talus/benches/step.rs`:
//! - `newton iteration`: a `Solver` on the operator and `q` of the next step with
//!   `max_iterations = 1` and no line search, from σₙ + (σₙ − σₙ₋₁): residual, local
//!   blocks, Schur assembly, numeric factorization and solve, direction check, residual;
//! - `cholesky`: the baseline, `SupernodalCholesky` (faer's supernodal LLᵀ, AMD, symbolic
//!   analysis once) of the elastic `K = M + h² Σ Bᵢᵀ Sᵢ⁻¹ Bᵢ` (the Newton matrix's pattern),
//!   numeric factorization and one solve;
//! - `lu on K`: talus-ssn's no-pivot LU of the same `K`, factorization and solve;
//! - `evaluation`: `Solver::residual_at` (`z = Wσ + q` and the natural map).
//!
//! Each is the median of `TALUS_3D_BENCH_REPEATS` runs (default 9 below 30k free dofs, 5
//! below 100k, 3 above). The stepper's own figure is printed too: its Newton solves' wall
//! time over the loading steps divided by their iterations (elastic predictor, line search
//! and failed attempts included).
//!
//! The orderings: the same elastic `K`, symbolic analysis with faer's AMD
//! (`SymmetricOrdering::Amd`) or with METIS' nested dissection (`METIS_NodeND`, default
//! options, on the graph of `K`; passed to faer as `SymmetricOrdering::Custom`), then the
//! numeric supernodal Cholesky and one solve (median of the repeats) and the solve's
//! relative residual. Reported: `nnz(L)` (the supernodal factor's stored values, what
//! `SupernodalCholesky::factor_nnz` counts) and the multiply-adds `Σ_j c_j (c_j + 1) / 2`
//! of its columns (`c_j` entries below the diagonal). Without the feature only AMD runs.
//! `nnz(W)`: the stored lower triangle of `W = S + h² B M⁻¹ Bᵀ` (its size is 6 × the
//! stress points) as `Operator::to_sparse` would store it (each point's full 6 × 6 `S`
//! block, and `B Bᵀ`'s pattern), counted without building it.
//!
//! Every (size, flow) and (size, ordering) runs in its own child process (this binary with
//! `--child`), so that each peak resident memory (`VmHWM`) is its own.
//!
//! Sizes: `TALUS_3D_BENCH_SIZES`, comma-separated `NXxNYxNZ` (default `4x4x4,8x8x8`, under
//! a minute; `12x14x12` has about 50k free dofs, `20x21x20` 200k, `24x28x24` 330k).
//! `TALUS_3D_BENCH_PARTS`: any of `newton`, `ordering`, `krylov` (default
//! `newton,ordering`); `krylov` compares whole Newton solves, direct against GMRES on a
//! reused factorization (`krylov_child`, `docs/krylov.md`), under AMD or, with
//! `TALUS_3D_BENCH_ND=1` and `--features metis`, nested dissection.
//!
//! Run with `cargo bench -p talus-fem --bench newton_3d` (AMD only), or with
//! `--features metis` for nested dissection (METIS is built from source by `metis-sys`).
use std::collections::BTreeMap;
use std::process::{Command, Stdio};
use std::sync::Arc;
use std::time::Instant;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky,
    SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::{SparseColMat, SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par, Side};
use nalgebra::{SMatrix, SVector};
use talus_bipotential::{ConeFit, DruckerPrager, DruckerPragerParameters};
use talus_engine::{StepSettings, Stepper};
use talus_fem::{Assembly, Constraint, DofMap, ElementOrder, Model, State, TetrahedralMesh};
use talus_ssn::factorization::{
    SupernodalCholesky, SymbolicSymmetricPatternLu, SymmetricPatternLu, DEFAULT_PIVOT_TOLERANCE,
};
use talus_ssn::krylov::{Gmres, GmresWorkspace};
use talus_ssn::{Krylov, NewtonSolve, Ordering, Precision, Settings, SolveError, Solver};

const D: usize = 6;
/// The paper's step (s), footing velocity (m/s, downward), soil density (kg/m³).
const H: f64 = 1e-2;
const VELOCITY: f64 = 1e-3;
const DENSITY: f64 = 2e3;
const SURCHARGE: f64 = 20e3;
/// Jaky, 1 − sin 27°.
const K0: f64 = 0.546;
/// Half-width of the square footing (m): the quarter model's footing is [0, B]².
const B: f64 = 0.25;
const PHI: f64 = 27.0;
/// atan(tan 27° / 2): the paper's non-associative soil.
const THETA_PAPER: f64 = 14.2906;

/// On a worker of rayon's pool, as `talus run` solves (`talus_ssn::on_pool`).
fn main() {
    talus_ssn::on_pool(bench);
}

fn bench() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) == Some("--child") {
        let cells = args.get(2).and_then(|s| parse_cells(s));
        match (args.get(1).map(String::as_str), cells, args.get(3)) {
            (Some("newton"), Some(cells), Some(flow)) => newton_child(cells, flow == "llt"),
            (Some("ordering"), Some(cells), Some(ordering)) => ordering_child(cells, ordering),
            (Some("krylov"), Some(cells), Some(flow)) => krylov_child(cells, flow == "llt"),
            _ => {
                eprintln!("usage: --child newton|ordering|krylov NXxNYxNZ lu|llt|amd|nd");
                std::process::exit(2);
            }
        }
        return;
    }
    let sizes = std::env::var("TALUS_3D_BENCH_SIZES").unwrap_or_else(|_| "4x4x4,8x8x8".into());
    let parts = std::env::var("TALUS_3D_BENCH_PARTS").unwrap_or_else(|_| "newton,ordering".into());
    let exe = std::env::current_exe().expect("own path");
    let mut failed = false;
    let mut newton_rows = Vec::new();
    let mut ordering_rows = Vec::new();
    let mut krylov_rows = Vec::new();
    let mut ratios = Vec::new();
    let mut projections = Vec::new();
    println!("load before: {}", load());
    for cells in sizes.split(',').filter(|s| !s.is_empty()) {
        if parse_cells(cells).is_none() {
            eprintln!("TALUS_3D_BENCH_SIZES: `{cells}` is not NXxNYxNZ");
            std::process::exit(2);
        }
        let run = |kind: &str, what: &str| -> Option<BTreeMap<String, String>> {
            let started = Instant::now();
            eprintln!("== {cells} {kind} {what} (load {})", load());
            let out = Command::new(&exe)
                .args(["--child", kind, cells, what])
                .stderr(Stdio::inherit())
                .output();
            match out {
                Ok(out) if out.status.success() => {
                    let text = String::from_utf8_lossy(&out.stdout).into_owned();
                    for line in text.lines().filter(|l| !l.starts_with("RESULT ")) {
                        println!("  {cells} {what}: {line}");
                    }
                    let mut map =
                        text.lines()
                            .find_map(|l| l.strip_prefix("RESULT "))
                            .map(|l| {
                                l.split_whitespace()
                                    .filter_map(|kv| kv.split_once('='))
                                    .map(|(k, v)| (k.to_string(), v.to_string()))
                                    .collect::<BTreeMap<_, _>>()
                            })?;
                    map.insert(
                        "wall".into(),
                        format!("{:.1}", started.elapsed().as_secs_f64()),
                    );
                    Some(map)
                }
                Ok(out) => {
                    eprintln!("{cells} {kind} {what}: child failed ({})", out.status);
                    None
                }
                Err(e) => {
                    eprintln!("{cells} {kind} {what}: child not started: {e}");
                    None
                }
            }
        };
        let mut newton = BTreeMap::new();
        if parts.contains("newton") {
            for flow in ["lu", "llt"] {
                match run("newton", flow) {
                    Some(r) => {
                        newton_rows.push(newton_row(cells, flow, &r));
                        ratios.push(format!(
                            "ratio 3d {flow} {cells}: newton iteration / cholesky {}, lu on K / cholesky {}",
                            r["ratio_iteration"], r["ratio_lu"]
                        ));
                        newton.insert(flow, r);
                    }
                    None => failed = true,
                }
            }
        }
        if parts.contains("krylov") {
            for flow in ["lu", "llt"] {
                match run("krylov", flow) {
                    Some(r) => krylov_rows.push(krylov_row(cells, flow, &r)),
                    None => failed = true,
                }
            }
        }
        let mut orderings = BTreeMap::new();
        if parts.contains("ordering") {
            let names: &[&str] = if cfg!(feature = "metis") {
                &["amd", "nd"]
            } else {
                &["amd"]
            };
            for &ordering in names {
                match run("ordering", ordering) {
                    Some(r) => {
                        ordering_rows.push(ordering_row(cells, ordering, &r));
                        orderings.insert(ordering, r);
                    }
                    None => failed = true,
                }
            }
        }
        // With nested dissection the Newton iteration's factorization would cost what the
        // orderings' Cholesky times say: the iteration's other work is unchanged.
        if let (Some(amd), Some(nd)) = (orderings.get("amd"), orderings.get("nd")) {
            let f = |m: &BTreeMap<String, String>, k: &str| m[k].parse::<f64>().unwrap_or(f64::NAN);
            let speedup = f(nd, "factor_s") / f(amd, "factor_s");
            for (flow, r) in &newton {
                let (it, ch, lu) = (f(r, "iteration_s"), f(r, "cholesky_s"), f(r, "lu_s"));
                let factor = if *flow == "llt" { ch } else { lu };
                if factor.is_nan() {
                    // No `lu on K` at this size (TALUS_3D_BENCH_LU_ON_K): no share to scale.
                    continue;
                }
                let it_nd = it - factor + factor * speedup;
                projections.push(format!(
                    "projected 3d {flow} {cells} with METIS: factorization × {speedup:.2}; newton iteration {:.3} s, / cholesky (AMD) {:.2}, / cholesky (ND) {:.2}",
                    it_nd,
                    it_nd / ch,
                    it_nd / (ch * speedup)
                ));
            }
        }
    }
    println!("load after: {}", load());
    if !newton_rows.is_empty() {
        println!("\nNewton iteration against one elastic Cholesky factorization and solve (AMD), medians");
        println!("| cells | flow | tets | free dofs | W size (6·points) | nnz(K) lower | nnz(L) AMD | LU fill (L+U) | steps: Newton its (failed) | plastic points | stepper s/it | newton iteration s | cholesky s | lu on K s | evaluation s | it / cholesky | lu / cholesky | peak MiB, run | peak MiB, bench |");
        println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
        for r in &newton_rows {
            println!("{r}");
        }
        for r in &ratios {
            println!("{r}");
        }
    }
    if !ordering_rows.is_empty() {
        println!(
            "\nThe elastic K's Cholesky under each ordering (faer supernodal, one thread), medians"
        );
        println!("| cells | free dofs | W size | nnz(W) lower | nnz(K) lower | ordering | ordering s | symbolic s | nnz(L) | multiply-adds | factor s | solve s | residual | peak MiB |");
        println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
        for r in &ordering_rows {
            println!("{r}");
        }
        for p in &projections {
            println!("{p}");
        }
    }
    if !krylov_rows.is_empty() {
        println!("\nWhole Newton solves of the last steps, direct against GMRES on a reused factorization (NewtonSolve::Krylov), same q and start, alternating order; seconds are CPU seconds of the process");
        println!("| cells | flow | free dofs | factor MiB | steps | direct s | krylov s | krylov / direct | Newton its direct / krylov | factorizations direct / krylov | GMRES solves | GMRES its per Newton it | GMRES MiB | max Δσ/‖σ‖ | peak MiB | elastic K: GMRES its, f64 / f32 factor | factor MiB f64 / f32 | f32 solver: factor MiB | f32 s | f32 / direct | f32 Newton its | f32 factorizations | GMRES its per Newton it |");
        println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
        for r in &krylov_rows {
            println!("{r}");
        }
    }
    if failed {
        std::process::exit(1);
    }
}

fn newton_row(cells: &str, flow: &str, r: &BTreeMap<String, String>) -> String {
    let g = |k: &str| r.get(k).map(String::as_str).unwrap_or("?");
    format!(
        "| {cells} | {flow} | {} | {} | {} | {} | {} | {} | {} ({}) | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
        g("tets"),
        g("free_dofs"),
        g("w_size"),
        g("k_nnz"),
        g("cholesky_fill"),
        g("lu_fill"),
        g("newton_its"),
        g("failed_its"),
        g("plastic_points"),
        g("stepper_s_per_it"),
        g("iteration_s"),
        g("cholesky_s"),
        g("lu_s"),
        g("evaluation_s"),
        g("ratio_iteration"),
        g("ratio_lu"),
        g("peak_run_mib"),
        g("peak_mib"),
    )
}

fn ordering_row(cells: &str, ordering: &str, r: &BTreeMap<String, String>) -> String {
    let g = |k: &str| r.get(k).map(String::as_str).unwrap_or("?");
    format!(
        "| {cells} | {} | {} | {} | {} | {ordering} | {} | {} | {} | {} | {} | {} | {} | {} |",
        g("free_dofs"),
        g("w_size"),
        g("w_nnz"),
        g("k_nnz"),
        g("ordering_s"),
        g("symbolic_s"),
        g("factor_nnz"),
        g("multiply_adds"),
        g("factor_s"),
        g("solve_s"),
        g("residual"),
        g("peak_mib"),
    )
}

fn parse_cells(s: &str) -> Option<[usize; 3]> {
    let v: Vec<usize> = s
        .split('x')
        .map(|c| c.parse().ok())
        .collect::<Option<_>>()?;
    (v.len() == 3 && v.iter().all(|&c| c > 0)).then(|| [v[0], v[1], v[2]])
}

/// The load average (1, 5, 15 min).
fn load() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "?".into())
}

/// Peak resident memory of this process (MiB), `VmHWM` of `/proc/self/status`.
fn peak_mib() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find_map(|l| l.strip_prefix("VmHWM:"))
                .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok())
        })
        .map_or(f64::NAN, |kb| kb / 1024.0)
}

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn repeats(n_free: usize) -> usize {
    if let Some(r) = std::env::var("TALUS_3D_BENCH_REPEATS")
        .ok()
        .and_then(|s| s.parse::<usize>().ok())
    {
        return r.max(1);
    }
    if n_free < 30_000 {
        9
    } else if n_free < 100_000 {
        5
    } else {
        3
    }
}

/// The footing's velocity (m/s): `TALUS_3D_BENCH_VELOCITY`, default 1 mm/s.
fn velocity() -> f64 {
    std::env::var("TALUS_3D_BENCH_VELOCITY")
        .ok()
        .and_then(|s| s.parse::<f64>().ok())
        .unwrap_or(VELOCITY)
}

fn soil(theta: f64) -> DruckerPrager {
    DruckerPrager::try_new(DruckerPragerParameters {
        young_modulus: 1e9,
        poisson_ratio: 0.3,
        friction_angle: PHI,
        cohesion: 2e3,
        dilatancy_angle: theta,
        cone_fit: ConeFit::OuterCone,
    })
    .expect("the footing's soil")
}

/// Uniform grid lines of `[a, b]` in `n` cells.
fn uniform(a: f64, b: f64, n: usize) -> Vec<f64> {
    (0..=n).map(|i| a + (b - a) * i as f64 / n as f64).collect()
}

/// The quarter square footing on `cells` of P2 tetrahedra, and its K₀ state at rest.
fn footing(cells: [usize; 3], theta: f64) -> (Model<6>, State<6>) {
    let mesh = TetrahedralMesh::block(
        &uniform(0.0, 1.0, cells[0]),
        &uniform(-1.0, 0.0, cells[1]),
        &uniform(0.0, 1.0, cells[2]),
        ElementOrder::P2,
    )
    .expect("a block mesh");
    let under = |x: &[f64; 3]| x[0] <= B + 1e-9 && x[2] <= B + 1e-9;
    let footing: Vec<usize> = mesh.node_sets["top"]
        .iter()
        .copied()
        .filter(|&n| under(&mesh.nodes[n]))
        .collect();
    let set = |name: &str| mesh.node_sets[name].clone();
    let dofs = DofMap::with_components(
        mesh.nodes.len(),
        3,
        &[
            (set("bottom"), Constraint::Fixed),
            (set("left"), Constraint::FixX),
            (set("right"), Constraint::FixX),
            (set("back"), Constraint::FixZ),
            (set("front"), Constraint::FixZ),
            (footing.clone(), Constraint::Fixed),
        ],
    )
    .expect("a dof map");
    let assembly = Assembly::<6>::new(&mesh, &dofs, DENSITY).expect("an assembly");
    let weight = assembly
        .body_force(DENSITY, [0.0, -9.81, 0.0])
        .expect("the weight");
    // The surcharge on the top faces beside the footing.
    let beside: Vec<_> = mesh.face_sets["top"]
        .iter()
        .filter(|f| !f.nodes.iter().all(|&n| under(&mesh.nodes[n])))
        .cloned()
        .collect();
    let surcharge = assembly
        .pressure(&mesh, &beside, SURCHARGE)
        .expect("the surcharge");
    let points = assembly.gauss_points.clone();
    let mut model = Model::new(mesh, assembly, soil(theta));
    model.add_load(weight, None);
    model.add_load(surcharge, None);
    for &n in &footing {
        for comp in 0..3 {
            let j = model
                .assembly
                .dofs()
                .prescribed(n, comp)
                .expect("a footing dof");
            model.reaction_dofs.push((j, comp));
        }
        let j = model
            .assembly
            .dofs()
            .prescribed(n, 1)
            .expect("a footing dof");
        model.prescribed_velocity[j] = -velocity();
    }
    let dofs = model.assembly.dofs();
    let mut state = State::at_rest(
        model.n_points(),
        dofs.n_free(),
        dofs.n_prescribed(),
        model.mesh.nodes.len(),
    );
    for (p, x) in points.iter().enumerate() {
        let vertical = -(SURCHARGE + DENSITY * 9.81 * (0.0 - x[1]));
        let s = [K0 * vertical, vertical, K0 * vertical, 0.0, 0.0, 0.0];
        state.sigma[D * p..D * p + D].copy_from_slice(&s);
    }
    (model, state)
}

/// The elements' dof lists and per-point `B` blocks: each element's points (consecutive in
/// the assembly) share one sorted list of free dofs; `blocks[p]` is point `p`'s `D × m`
/// row-major block on its element's list.
struct Elements {
    point_ptr: Vec<usize>,
    dofs: Vec<Vec<usize>>,
    blocks: Vec<Vec<f64>>,
}

fn elements(model: &Model<6>) -> Elements {
    let asm = &model.assembly;
    // Bᵀ in CSC: column D p + k holds row k of point p.
    let bt = asm.b_free.as_ref().transpose().to_col_major().expect("Bᵀ");
    let (cp, ri, v) = (bt.symbolic().col_ptr(), bt.symbolic().row_idx(), bt.val());
    let mut point_ptr = vec![0];
    for p in 1..asm.n_points() {
        if asm.gauss_element[p] != asm.gauss_element[p - 1] {
            point_ptr.push(p);
        }
    }
    point_ptr.push(asm.n_points());
    let mut dofs = Vec::with_capacity(point_ptr.len() - 1);
    let mut blocks = Vec::with_capacity(asm.n_points());
    for w in point_ptr.windows(2) {
        let mut list: Vec<usize> = (D * w[0]..D * w[1])
            .flat_map(|col| ri[cp[col]..cp[col + 1]].iter().copied())
            .collect();
        list.sort_unstable();
        list.dedup();
        let m = list.len();
        for p in w[0]..w[1] {
            let mut b = vec![0.0; D * m];
            for k in 0..D {
                for e in cp[D * p + k]..cp[D * p + k + 1] {
                    let a = list.binary_search(&ri[e]).expect("an element dof");
                    b[k * m + a] += v[e];
                }
            }
            blocks.push(b);
        }
        dofs.push(list);
    }
    Elements {
        point_ptr,
        dofs,
        blocks,
    }
}

/// The elastic `K = M + h² Σ Bᵢᵀ Sᵢ⁻¹ Bᵢ` on the Newton matrix's pattern (that of
/// `M + Bᵀ B`), its lower triangle if `lower`, assembled element by element.
fn elastic_matrix(
    model: &Model<6>,
    el: &Elements,
    h: f64,
    lower: bool,
) -> SparseColMat<usize, f64> {
    let asm = &model.assembly;
    let n = asm.lumped_mass_free.len();
    let mut ptr = vec![0usize; n + 1];
    for list in &el.dofs {
        for &j in list {
            ptr[j + 1] += 1;
        }
    }
    for j in 0..n {
        ptr[j + 1] += ptr[j];
    }
    let mut next = ptr.clone();
    let mut of_dof = vec![0usize; ptr[n]];
    for (g, list) in el.dofs.iter().enumerate() {
        for &j in list {
            of_dof[next[j]] = g;
            next[j] += 1;
        }
    }
    let mut mark = vec![usize::MAX; n];
    let mut col_ptr = Vec::with_capacity(n + 1);
    col_ptr.push(0);
    let mut row_idx = Vec::new();
    for j in 0..n {
        let start = row_idx.len();
        mark[j] = j;
        row_idx.push(j);
        for &g in &of_dof[ptr[j]..ptr[j + 1]] {
            for &r in &el.dofs[g] {
                if (!lower || r >= j) && mark[r] != j {
                    mark[r] = j;
                    row_idx.push(r);
                }
            }
        }
        row_idx[start..].sort_unstable();
        col_ptr.push(row_idx.len());
    }
    drop((of_dof, next, ptr, mark));
    let mut values = vec![0.0; row_idx.len()];
    let at = |r: usize, c: usize| -> usize {
        col_ptr[c]
            + row_idx[col_ptr[c]..col_ptr[c + 1]]
                .binary_search(&r)
                .expect("in the pattern")
    };
    for (j, m) in asm.lumped_mass_free.iter().enumerate() {
        values[at(j, j)] += m;
    }
    let compliance = model.compliance_blocks();
    let mut local = Vec::new();
    for (g, list) in el.dofs.iter().enumerate() {
        let m = list.len();
        local.clear();
        local.resize(m * m, 0.0);
        let points = el.point_ptr[g]..el.point_ptr[g + 1];
        for (s, b) in compliance[points.clone()].iter().zip(&el.blocks[points]) {
            let c: SMatrix<f64, D, D> = s.try_inverse().expect("S invertible") * (h * h);
            for a in 0..m {
                let cb = c * SVector::<f64, D>::from_fn(|k, _| b[k * m + a]);
                for bb in 0..m {
                    local[bb * m + a] += (0..D).map(|k| cb[k] * b[k * m + bb]).sum::<f64>();
                }
            }
        }
        for (b, &col) in list.iter().enumerate() {
            for (a, &row) in list.iter().enumerate() {
                if lower && row < col {
                    continue;
                }
                values[at(row, col)] += local[b * m + a];
            }
        }
    }
    let symbolic = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
    SparseColMat::new(symbolic, values)
}

/// Stored entries of the lower triangle of `W = S + h² B M⁻¹ Bᵀ` as `Operator::to_sparse`
/// builds it: each point's 6 × 6 block of `S`, and `(r, r')` wherever rows `r` and `r'` of
/// `B` share a column.
fn w_lower_nnz(model: &Model<6>) -> u64 {
    let b = &model.assembly.b_free;
    let bt = b.as_ref().transpose().to_col_major().expect("Bᵀ");
    let (bcp, bri) = (b.symbolic().col_ptr(), b.symbolic().row_idx());
    let (tcp, tri) = (bt.symbolic().col_ptr(), bt.symbolic().row_idx());
    let rows = b.nrows();
    let mut mark = vec![u32::MAX; rows];
    let mut count = 0u64;
    for r in 0..rows {
        let tag = r as u32;
        // The point's own S block, up to the diagonal.
        let own = &mut mark[D * (r / D)..=r];
        own.fill(tag);
        count += own.len() as u64;
        for &j in &tri[tcp[r]..tcp[r + 1]] {
            // B's rows are sorted in each column: stop past the diagonal.
            for &r2 in &bri[bcp[j]..bcp[j + 1]] {
                if r2 > r {
                    break;
                }
                if mark[r2] != tag {
                    mark[r2] = tag;
                    count += 1;
                }
            }
        }
    }
    count
}

/// `nnz(L)` as stored, and the multiply-adds `Σ_j c_j (c_j + 1) / 2` of the factor's
/// columns (`c_j` entries below the diagonal).
fn factor_stats(symbolic: &SymbolicCholesky<usize>) -> (usize, f64) {
    let mut flops = 0.0;
    match symbolic.raw() {
        SymbolicCholeskyRaw::Supernodal(s) => {
            for k in 0..s.n_supernodes() {
                let (b, e) = (s.supernode_begin()[k], s.supernode_end()[k]);
                let m = s.supernode(k).pattern().len();
                for j in b..e {
                    let c = (e - j - 1 + m) as f64;
                    flops += c * (c + 1.0) / 2.0;
                }
            }
        }
        SymbolicCholeskyRaw::Simplicial(s) => {
            let cp = s.col_ptr();
            for j in 0..s.ncols() {
                let c = (cp[j + 1] - cp[j]).saturating_sub(1) as f64;
                flops += c * (c + 1.0) / 2.0;
            }
        }
    }
    (symbolic.len_val(), flops)
}

fn newton_child(cells: [usize; 3], associative: bool) {
    let t = Instant::now();
    let theta = if associative { PHI } else { THETA_PAPER };
    let (model, mut state) = footing(cells, theta);
    let asm = &model.assembly;
    let n_free = asm.lumped_mass_free.len();
    eprintln!(
        "{} nodes, {} tets, {} free dofs, {} points; model built in {:.2} s (load {}); peak {:.0} MiB",
        model.mesh.nodes.len(),
        model.mesh.tetrahedra.len(),
        n_free,
        asm.n_points(),
        t.elapsed().as_secs_f64(),
        load(),
        peak_mib()
    );
    let steps = std::env::var("TALUS_3D_BENCH_STEPS")
        .ok()
        .and_then(|s| s.parse::<usize>().ok())
        .unwrap_or(4);
    let dp = model.materials[0].drucker_prager().expect("Drucker-Prager");
    let on_cone = |sigma: &[f64]| {
        sigma
            .chunks_exact(D)
            .filter(|s| dp.yield_function(&SVector::<f64, D>::from_column_slice(s)) > -1e-3)
            .count()
    };
    let mut stepper = Stepper::new(&model, StepSettings::fem());
    let mut previous = state.sigma.clone();
    let (mut its, mut failed_its, mut solve_seconds) = (0, 0, 0.0);
    let mut per_step = Vec::new();
    for step in 1..=steps {
        previous.clone_from(&state.sigma);
        let r = stepper
            .advance(&mut state, H)
            .unwrap_or_else(|e| panic!("step {step} failed: {e}"));
        its += r.newton_iterations;
        failed_its += r.failed_newton_iterations;
        solve_seconds += r.solve_seconds;
        per_step.push(format!(
            "{}{}{} in {:.2} s ({} on the cone)",
            r.newton_iterations,
            if r.failed_newton_iterations > 0 {
                format!("+{} failed", r.failed_newton_iterations)
            } else {
                String::new()
            },
            if r.substeps > 1 {
                format!(" ({} sub-steps)", r.substeps)
            } else {
                String::new()
            },
            r.seconds,
            on_cone(&state.sigma)
        ));
    }
    drop(stepper);
    let plastic = on_cone(&state.sigma);
    // The run's own peak: model, stepper, its solver and factor (nothing of the baseline).
    let peak_run = peak_mib();
    eprintln!(
        "{steps} steps, Newton iterations per step: {}; {plastic} of {} points on the cone (load {}); peak {peak_run:.0} MiB",
        per_step.join(", "),
        asm.n_points(),
        load(),
    );

    let mut one = StepSettings::fem().solver;
    one.max_iterations = 1;
    one.line_search = None;
    let t = Instant::now();
    let system = model.reduced_system(H).expect("W");
    let mut solver = Some(Solver::new(system, one).expect("solver"));
    let setup = t.elapsed().as_secs_f64();
    let q = model.reduced_rhs(&state, H);
    if let Some(s) = solver.as_mut() {
        s.set_q(q).expect("q of the next step");
    }
    let start: Vec<f64> = state
        .sigma
        .iter()
        .zip(&previous)
        .map(|(s, p)| s + (s - p))
        .collect();
    drop(previous);
    // Interleaved (a change of the machine's load touches every figure alike) unless the
    // Newton solver's LU and the baseline's Cholesky together would not fit: at 200k free
    // dofs the non-associative solver alone holds 14 GB. Then the Newton iterations run
    // first, and the baseline after the solver is dropped.
    let interleave = match std::env::var("TALUS_3D_BENCH_INTERLEAVE").as_deref() {
        Ok("1") => true,
        Ok("0") => false,
        _ => n_free <= 100_000 || associative,
    };
    // The LU of the elastic K (its share of a non-associative iteration) doubles the memory
    // of the factors: by default only up to 100k free dofs.
    let lu_on_k = match std::env::var("TALUS_3D_BENCH_LU_ON_K").as_deref() {
        Ok("1") => true,
        Ok("0") => false,
        _ => n_free <= 100_000,
    };
    let repeats = repeats(n_free);
    let (mut iteration, mut cholesky, mut lu_times, mut evaluation) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let newton = |solver: &mut Solver<D>, iteration: &mut Vec<f64>, evaluation: &mut Vec<f64>| {
        let mut sigma = start.clone();
        let t = Instant::now();
        match solver.solve(&mut sigma) {
            Err(SolveError::NotConverged(r)) => {
                assert_eq!((r.iterations, r.schur_steps), (1, 1), "{r:?}");
                assert_eq!(r.pivoting_fallbacks, 0, "{r:?}");
            }
            other => panic!("expected one iteration, got {other:?}"),
        }
        iteration.push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        solver.residual_at(&start).expect("evaluation");
        evaluation.push(t.elapsed().as_secs_f64());
    };
    if !interleave {
        let mut s = solver.take().expect("the solver");
        for _ in 0..repeats {
            newton(&mut s, &mut iteration, &mut evaluation);
        }
        eprintln!(
            "newton iterations (s): {:?}, then the solver dropped; peak {:.0} MiB (load {})",
            iteration,
            peak_mib(),
            load()
        );
    }
    let t = Instant::now();
    let el = elements(&model);
    let lower = elastic_matrix(&model, &el, H, true);
    let full = elastic_matrix(&model, &el, H, false);
    drop(el);
    let assembly_s = t.elapsed().as_secs_f64();
    let rhs: Vec<f64> = (0..n_free).map(|i| 1.0 + (i % 7) as f64).collect();
    let t = Instant::now();
    let mut llt = SupernodalCholesky::try_new(lower.symbolic()).expect("symbolic");
    let llt_symbolic = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let lu_symbolic =
        Arc::new(SymbolicSymmetricPatternLu::try_new(full.symbolic()).expect("LU symbolic"));
    let lu_symbolic_s = t.elapsed().as_secs_f64();
    let lu_fill = lu_symbolic.factor_nnz();
    let mut lu = lu_on_k.then(|| (SymmetricPatternLu::new(lu_symbolic), full));
    eprintln!(
        "Solver::new {setup:.2} s (its Schur analysis), elastic K assembled in {assembly_s:.2} s, Cholesky symbolic {llt_symbolic:.2} s, LU symbolic {lu_symbolic_s:.2} s; {} (load {})",
        if interleave { "interleaved" } else { "baseline after the Newton iterations" },
        load()
    );
    for _ in 0..repeats {
        if let Some(s) = solver.as_mut() {
            newton(s, &mut iteration, &mut evaluation);
        }

        let t = Instant::now();
        llt.factorize(lower.as_ref()).expect("K is SPD");
        let mut x = rhs.clone();
        llt.solve_in_place(&mut x);
        cholesky.push(t.elapsed().as_secs_f64());

        if let Some((lu, full)) = lu.as_mut() {
            let t = Instant::now();
            lu.factorize(full.val(), DEFAULT_PIVOT_TOLERANCE)
                .expect("K is SPD: no pivot breaks down");
            let mut x = rhs.clone();
            lu.solve_in_place(&mut x);
            lu_times.push(t.elapsed().as_secs_f64());
        }
    }
    let (it, ch, lu_t, ev) = (
        median(iteration.clone()),
        median(cholesky.clone()),
        median(lu_times.clone()),
        median(evaluation),
    );
    let fmt = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x:.3}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    eprintln!(
        "runs (s): newton iteration [{}], cholesky [{}], lu on K [{}] (load {})",
        fmt(&iteration),
        fmt(&cholesky),
        fmt(&lu_times),
        load()
    );
    println!(
        "RESULT tets={} free_dofs={n_free} w_size={} k_nnz={} cholesky_fill={} lu_fill={lu_fill} newton_its={its} failed_its={failed_its} plastic_points={plastic} stepper_s_per_it={:.3} iteration_s={it:.4} cholesky_s={ch:.4} lu_s={lu_t:.4} evaluation_s={ev:.4} ratio_iteration={:.2} ratio_lu={:.2} repeats={repeats} interleaved={interleave} peak_run_mib={peak_run:.0} peak_mib={:.0}",
        model.mesh.tetrahedra.len(),
        D * asm.n_points(),
        lower.val().len(),
        llt.factor_nnz(),
        solve_seconds / (its + failed_its).max(1) as f64,
        it / ch,
        lu_t / ch,
        peak_mib()
    );
}

fn ordering_child(cells: [usize; 3], ordering: &str) {
    let t = Instant::now();
    let (model, _) = footing(cells, THETA_PAPER);
    let n_free = model.assembly.lumped_mass_free.len();
    let el = elements(&model);
    let lower = elastic_matrix(&model, &el, H, true);
    drop(el);
    eprintln!(
        "model and elastic K in {:.2} s (load {})",
        t.elapsed().as_secs_f64(),
        load()
    );
    // nnz(W) once per size, in the AMD child.
    let w_nnz = if ordering == "amd" {
        let t = Instant::now();
        let c = w_lower_nnz(&model);
        eprintln!("nnz(W) lower counted in {:.2} s", t.elapsed().as_secs_f64());
        c.to_string()
    } else {
        "-".to_string()
    };
    let params = CholeskySymbolicParams::default();
    let (symbolic, ordering_s, symbolic_s) = match ordering {
        "amd" => {
            let t = Instant::now();
            let s = factorize_symbolic_cholesky(
                lower.symbolic(),
                Side::Lower,
                SymmetricOrdering::Amd,
                params,
            )
            .expect("symbolic");
            // faer's AMD is inside the symbolic analysis.
            (s, f64::NAN, t.elapsed().as_secs_f64())
        }
        "nd" => nested_dissection(&lower, params),
        other => {
            eprintln!("unknown ordering `{other}` (amd, nd)");
            std::process::exit(2);
        }
    };
    let (factor_nnz, flops) = factor_stats(&symbolic);
    let mut values = vec![0.0; symbolic.len_val()];
    let mut factor_mem = MemBuffer::try_new(
        symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
    )
    .expect("factor scratch");
    let mut solve_mem = MemBuffer::try_new(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq))
        .expect("solve scratch");
    let rhs: Vec<f64> = (0..n_free).map(|i| 1.0 + (i % 7) as f64).collect();
    let (mut factor_t, mut solve_t) = (Vec::new(), Vec::new());
    let mut x = rhs.clone();
    // Symbolic only: the fill and the flops of sizes too large to factorize here.
    let numeric = std::env::var("TALUS_3D_BENCH_SYMBOLIC_ONLY").as_deref() != Ok("1");
    for _ in 0..if numeric { repeats(n_free) } else { 0 } {
        let t = Instant::now();
        symbolic
            .factorize_numeric_llt::<f64>(
                &mut values,
                lower.as_ref(),
                Side::Lower,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut factor_mem),
                Default::default(),
            )
            .expect("K is SPD");
        factor_t.push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        x.copy_from_slice(&rhs);
        LltRef::new(&symbolic, &values).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(&mut x, n_free, 1),
            Par::Seq,
            MemStack::new(&mut solve_mem),
        );
        solve_t.push(t.elapsed().as_secs_f64());
    }
    let residual = if numeric {
        relative_residual(lower.as_ref(), &x, &rhs)
    } else {
        f64::NAN
    };
    eprintln!(
        "factorizations (s): [{}] (load {})",
        factor_t
            .iter()
            .map(|x| format!("{x:.3}"))
            .collect::<Vec<_>>()
            .join(" "),
        load()
    );
    println!(
        "RESULT free_dofs={n_free} w_size={} w_nnz={w_nnz} k_nnz={} ordering_s={} symbolic_s={symbolic_s:.3} factor_nnz={factor_nnz} multiply_adds={flops:.3e} factor_s={:.4} solve_s={:.4} residual={residual:.1e} peak_mib={:.0}",
        D * model.n_points(),
        lower.val().len(),
        if ordering_s.is_nan() {
            "in_symbolic".to_string()
        } else {
            format!("{ordering_s:.3}")
        },
        median(factor_t),
        median(solve_t),
        peak_mib()
    );
}

/// `‖K x − b‖∞ / ‖b‖∞` for `K` given by its lower triangle.
fn relative_residual(lower: SparseColMatRef<'_, usize, f64>, x: &[f64], b: &[f64]) -> f64 {
    let (cp, ri, v) = (
        lower.symbolic().col_ptr(),
        lower.symbolic().row_idx(),
        lower.val(),
    );
    let mut r: Vec<f64> = b.iter().map(|b| -b).collect();
    for j in 0..lower.ncols() {
        for k in cp[j]..cp[j + 1] {
            let i = ri[k];
            r[i] += v[k] * x[j];
            if i != j {
                r[j] += v[k] * x[i];
            }
        }
    }
    let norm = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    norm(&r) / norm(b)
}

/// METIS' nested dissection of the graph of `K` (talus-ssn's
/// `factorization::nested_dissection`, the one implementation), handed to faer's symbolic
/// Cholesky as a custom ordering: the symbolic factor, the ordering's and the symbolic
/// analysis' seconds.
#[cfg(feature = "metis")]
fn nested_dissection(
    lower: &SparseColMat<usize, f64>,
    params: CholeskySymbolicParams<'_>,
) -> (SymbolicCholesky<usize>, f64, f64) {
    let t = Instant::now();
    let n = lower.nrows();
    let (fwd, inv) =
        talus_ssn::factorization::nested_dissection(lower.symbolic()).expect("METIS_NodeND");
    let ordering_s = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let symbolic = factorize_symbolic_cholesky(
        lower.symbolic(),
        Side::Lower,
        SymmetricOrdering::Custom(faer::perm::PermRef::new_checked(&fwd, &inv, n)),
        params,
    )
    .expect("symbolic");
    (symbolic, ordering_s, t.elapsed().as_secs_f64())
}

#[cfg(not(feature = "metis"))]
fn nested_dissection(
    _: &SparseColMat<usize, f64>,
    _: CholeskySymbolicParams<'_>,
) -> (SymbolicCholesky<usize>, f64, f64) {
    eprintln!("nested dissection needs `--features metis`");
    std::process::exit(2);
}

/// Direct against Krylov-reuse Newton solves (`docs/krylov.md`): the model is stepped
/// `TALUS_3D_BENCH_STEPS` steps by the engine (direct); before each of the last
/// `TALUS_3D_BENCH_REPLAY` (default 3) steps, that step's whole Newton solve (its `q`, from
/// σₙ + (σₙ − σₙ₋₁), to the FEM tolerance) is solved by two more solvers kept across the
/// steps, one `NewtonSolve::Direct`, one `NewtonSolve::Krylov` (its factorization carried
/// from step to step), in alternating order. Then (associative flow only) the elastic `K`
/// preconditioned by its own Cholesky factor stored in f32 or f64: GMRES iterations to a
/// relative residual of 1e-12, and the factor's bytes.
fn krylov_child(cells: [usize; 3], associative: bool) {
    let theta = if associative { PHI } else { THETA_PAPER };
    let (model, mut state) = footing(cells, theta);
    let n_free = model.assembly.lumped_mass_free.len();
    let steps = std::env::var("TALUS_3D_BENCH_STEPS")
        .ok()
        .and_then(|s| s.parse::<usize>().ok())
        .unwrap_or(4);
    let replay = std::env::var("TALUS_3D_BENCH_REPLAY")
        .ok()
        .and_then(|s| s.parse::<usize>().ok())
        .unwrap_or(3)
        .min(steps);
    let ordering = if std::env::var("TALUS_3D_BENCH_ND").as_deref() == Ok("1") {
        nd_ordering()
    } else {
        Ordering::Amd
    };
    let direct_settings = Settings {
        ordering,
        ..StepSettings::fem().solver
    };
    let krylov_settings = Settings {
        newton_solve: NewtonSolve::Krylov(Krylov::DEFAULT),
        ..direct_settings
    };
    let system = model.reduced_system(H).expect("W");
    let mut direct = Solver::new(system.clone(), direct_settings).expect("solver");
    let mut krylov = Solver::new(system.clone(), krylov_settings).expect("solver");
    // Associative flow: a third solver whose Cholesky factor is stored in f32.
    let mut single = associative.then(|| {
        let settings = Settings {
            newton_solve: NewtonSolve::Krylov(Krylov {
                precision: Precision::Single,
                ..Krylov::DEFAULT
            }),
            ..direct_settings
        };
        Solver::new(system, settings).expect("solver")
    });
    let (mut t_single, mut single_totals, mut single_diff) = (Vec::new(), [0usize; 4], 0.0f64);
    let mut single_bytes = 0;
    let factor_nnz = direct.factor_nnz().unwrap_or(0);
    let mut stepper = Stepper::new(&model, StepSettings::fem());
    let mut previous: Option<Vec<f64>> = None;
    let (mut t_direct, mut t_krylov) = (Vec::new(), Vec::new());
    let mut totals = [0usize; 7]; // its direct, its krylov, fact direct, fact krylov, solves, gmres its, failures
    let mut max_diff: f64 = 0.0;
    for step in 1..=steps {
        if step > steps - replay {
            let q = model.reduced_rhs(&state, H);
            direct.set_q(q.clone()).expect("q");
            krylov.set_q(q).expect("q");
            let start: Vec<f64> = match &previous {
                Some(p) => state
                    .sigma
                    .iter()
                    .zip(p)
                    .map(|(s, p)| s + (s - p))
                    .collect(),
                None => state.sigma.clone(),
            };
            let mut single_runs = Vec::new();
            // CPU seconds of the process (all threads): less disturbed than wall time by
            // the other jobs of a shared machine.
            let run = |solver: &mut Solver<D>| {
                let mut sigma = start.clone();
                let t = cpu_seconds();
                let r = match solver.solve(&mut sigma) {
                    Ok(r) => r,
                    Err(SolveError::NotConverged(r)) => *r,
                    Err(e) => panic!("step {step}: {e}"),
                };
                (sigma, r, cpu_seconds() - t)
            };
            if let Some(single) = single.as_mut() {
                single.set_q(model.reduced_rhs(&state, H)).expect("q");
                if step % 3 == 0 {
                    let (sc, rc, tc) = run(single);
                    single_runs.push((sc, rc, tc));
                }
            }
            let ((sa, ra, ta), (sb, rb, tb)) = if step % 2 == 0 {
                let a = run(&mut direct);
                (a, run(&mut krylov))
            } else {
                let b = run(&mut krylov);
                (run(&mut direct), b)
            };
            if let Some(single) = single.as_mut() {
                if step % 3 != 0 {
                    let (sc, rc, tc) = run(single);
                    single_runs.push((sc, rc, tc));
                }
            }
            for (sc, rc, tc) in single_runs.drain(..) {
                let scale = sa.iter().fold(1.0f64, |m, v| m.max(v.abs()));
                let d = sa
                    .iter()
                    .zip(&sc)
                    .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
                single_diff = single_diff.max(d / scale);
                eprintln!(
                    "step {step}: f32 factor {} its {tc:.2} s ({} factorizations, {} GMRES solves in {} its, {} failures, {})",
                    rc.iterations, rc.factorizations, rc.krylov_solves, rc.krylov_iterations, rc.krylov_failures, rc.status
                );
                t_single.push(tc);
                for (k, v) in [
                    rc.iterations,
                    rc.factorizations,
                    rc.krylov_iterations,
                    rc.krylov_failures,
                ]
                .into_iter()
                .enumerate()
                {
                    single_totals[k] += v;
                }
            }
            let scale = sa.iter().fold(1.0f64, |m, v| m.max(v.abs()));
            let diff = sa
                .iter()
                .zip(&sb)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            max_diff = max_diff.max(diff / scale);
            eprintln!(
                "step {step}: direct {} its {:.2} s ({} factorizations, {}), krylov {} its {:.2} s ({} factorizations, {} GMRES solves in {} its, {} failures, {}); |Δσ|/‖σ‖ {:.1e} (load {})",
                ra.iterations, ta, ra.factorizations, ra.status, rb.iterations, tb, rb.factorizations,
                rb.krylov_solves, rb.krylov_iterations, rb.krylov_failures, rb.status, diff / scale, load()
            );
            t_direct.push(ta);
            t_krylov.push(tb);
            for (k, v) in [
                ra.iterations,
                rb.iterations,
                ra.factorizations,
                rb.factorizations,
                rb.krylov_solves,
                rb.krylov_iterations,
                rb.krylov_failures,
            ]
            .into_iter()
            .enumerate()
            {
                totals[k] += v;
            }
        }
        previous = Some(state.sigma.clone());
        stepper
            .advance(&mut state, H)
            .unwrap_or_else(|e| panic!("step {step} failed: {e}"));
    }
    let direct_bytes = direct.factor_memory().map_or(0, |m| m.0);
    if let Some(s) = &single {
        single_bytes = s.factor_memory().map_or(0, |m| m.0);
    }
    drop((stepper, direct, krylov, single));
    let peak_solvers = peak_mib();
    let (sd, sk) = (t_direct.iter().sum::<f64>(), t_krylov.iter().sum::<f64>());
    let restart = Krylov::DEFAULT.restart;
    let gmres_mib = (8 * n_free * (2 * restart + 2)) as f64 / 1048576.0;
    // The single-precision preconditioner, on the elastic K.
    let (mut f64_its, mut f32_its, mut f32_factor_mib, mut f64_factor_mib) =
        (String::from("-"), String::from("-"), f64::NAN, f64::NAN);
    if associative {
        let el = elements(&model);
        let lower = elastic_matrix(&model, &el, H, true);
        drop(el);
        let symbolic = factorize_symbolic_cholesky(
            lower.symbolic(),
            Side::Lower,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams::default(),
        )
        .expect("symbolic");
        let rhs: Vec<f64> = (0..n_free).map(|i| 1.0 + (i % 7) as f64).collect();
        let apply = |x: &[f64], y: &mut [f64]| symmetric_product(lower.as_ref(), x, y);
        let gmres = Gmres {
            restart,
            max_iterations: 200,
            project_after: 0,
        };
        let mut ws = GmresWorkspace::new(n_free, restart);
        // f64 factor.
        {
            let mut values = vec![0.0f64; symbolic.len_val()];
            let mut mem = MemBuffer::new(
                symbolic
                    .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default())
                    .or(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq)),
            );
            symbolic
                .factorize_numeric_llt::<f64>(
                    &mut values,
                    lower.as_ref(),
                    Side::Lower,
                    Default::default(),
                    Par::Seq,
                    MemStack::new(&mut mem),
                    Default::default(),
                )
                .expect("SPD");
            f64_factor_mib = (8 * values.len()) as f64 / 1048576.0;
            let mut x = vec![0.0; n_free];
            let r = gmres.solve_relative(
                &mut ws,
                apply,
                |v: &mut [f64]| {
                    LltRef::new(&symbolic, &values).solve_in_place_with_conj(
                        Conj::No,
                        MatMut::from_column_major_slice_mut(v, n_free, 1),
                        Par::Seq,
                        MemStack::new(&mut mem),
                    )
                },
                &rhs,
                &mut x,
                1e-12,
            );
            f64_its = match r {
                Ok(s) => s.iterations.to_string(),
                Err(e) => format!("failed:{}", e.to_string().replace(' ', "_")),
            };
        }
        // f32 factor of the same K.
        {
            let lower32 = SparseColMat::<usize, f32>::new(
                lower.symbolic().to_owned().expect("pattern"),
                lower.val().iter().map(|&v| v as f32).collect(),
            );
            let mut values = vec![0.0f32; symbolic.len_val()];
            let mut mem = MemBuffer::new(
                symbolic
                    .factorize_numeric_llt_scratch::<f32>(Par::Seq, Default::default())
                    .or(symbolic.solve_in_place_scratch::<f32>(1, Par::Seq)),
            );
            let ok = symbolic
                .factorize_numeric_llt::<f32>(
                    &mut values,
                    lower32.as_ref(),
                    Side::Lower,
                    Default::default(),
                    Par::Seq,
                    MemStack::new(&mut mem),
                    Default::default(),
                )
                .is_ok();
            f32_factor_mib = (4 * values.len()) as f64 / 1048576.0;
            if ok {
                let mut single = vec![0.0f32; n_free];
                let mut x = vec![0.0; n_free];
                let r = gmres.solve_relative(
                    &mut ws,
                    apply,
                    |v: &mut [f64]| {
                        for (s, v) in single.iter_mut().zip(v.iter()) {
                            *s = *v as f32;
                        }
                        LltRef::new(&symbolic, &values).solve_in_place_with_conj(
                            Conj::No,
                            MatMut::from_column_major_slice_mut(&mut single, n_free, 1),
                            Par::Seq,
                            MemStack::new(&mut mem),
                        );
                        for (v, s) in v.iter_mut().zip(&single) {
                            *v = *s as f64;
                        }
                    },
                    &rhs,
                    &mut x,
                    1e-12,
                );
                f32_its = match r {
                    Ok(s) => s.iterations.to_string(),
                    Err(e) => format!("failed:{}", e.to_string().replace(' ', "_")),
                };
            } else {
                f32_its = "not_positive_definite".into();
            }
        }
    }
    println!(
        "RESULT free_dofs={n_free} factor_nnz={factor_nnz} factor_mib={:.0} replayed={} direct_s={sd:.3} krylov_s={sk:.3} ratio={:.3} its_direct={} its_krylov={} factorizations_direct={} factorizations_krylov={} gmres_solves={} gmres_its={} gmres_failures={} gmres_per_newton={:.2} gmres_mib={gmres_mib:.1} max_rel_diff={max_diff:.1e} direct_factor_mib={:.0} single_factor_mib={:.0} single_s={:.3} single_ratio={:.3} single_its={} single_factorizations={} single_gmres_its={} single_failures={} single_gmres_per_newton={:.2} single_max_rel_diff={single_diff:.1e} peak_solvers_mib={peak_solvers:.0} elastic_f64_its={f64_its} elastic_f32_its={f32_its} factor_f64_mib={f64_factor_mib:.0} factor_f32_mib={f32_factor_mib:.0} peak_mib={:.0}",
        (8 * factor_nnz) as f64 / 1048576.0,
        t_direct.len(),
        sk / sd,
        totals[0], totals[1], totals[2], totals[3], totals[4], totals[5], totals[6],
        totals[5] as f64 / totals[1].max(1) as f64,
        direct_bytes as f64 / 1048576.0,
        single_bytes as f64 / 1048576.0,
        t_single.iter().sum::<f64>(),
        t_single.iter().sum::<f64>() / sd,
        single_totals[0],
        single_totals[1],
        single_totals[2],
        single_totals[3],
        single_totals[2] as f64 / single_totals[0].max(1) as f64,
        peak_mib()
    );
}

/// `y = K x` for `K` given by its lower triangle.
fn symmetric_product(lower: SparseColMatRef<'_, usize, f64>, x: &[f64], y: &mut [f64]) {
    let (cp, ri, v) = (
        lower.symbolic().col_ptr(),
        lower.symbolic().row_idx(),
        lower.val(),
    );
    y.fill(0.0);
    for j in 0..lower.ncols() {
        let mut acc = 0.0;
        for k in cp[j]..cp[j + 1] {
            let i = ri[k];
            y[i] += v[k] * x[j];
            if i != j {
                acc += v[k] * x[i];
            }
        }
        y[j] += acc;
    }
}

fn krylov_row(cells: &str, flow: &str, r: &BTreeMap<String, String>) -> String {
    let g = |k: &str| r.get(k).map(String::as_str).unwrap_or("?");
    format!(
        "| {cells} | {flow} | {} | {} | {} | {} | {} | {} | {} / {} | {} / {} | {} ({} failed) | {} | {} | {} | {} | {} / {} | {} / {} | {} | {} | {} | {} | {} ({} failed) | {} |",
        g("free_dofs"),
        g("factor_mib"),
        g("replayed"),
        g("direct_s"),
        g("krylov_s"),
        g("ratio"),
        g("its_direct"),
        g("its_krylov"),
        g("factorizations_direct"),
        g("factorizations_krylov"),
        g("gmres_solves"),
        g("gmres_failures"),
        g("gmres_per_newton"),
        g("gmres_mib"),
        g("max_rel_diff"),
        g("peak_solvers_mib"),
        g("elastic_f64_its"),
        g("elastic_f32_its"),
        g("factor_f64_mib"),
        g("factor_f32_mib"),
        g("single_factor_mib"),
        g("single_s"),
        g("single_ratio"),
        g("single_its"),
        g("single_factorizations"),
        g("single_failures"),
        g("single_gmres_per_newton"),
    )
}

#[cfg(feature = "metis")]
fn nd_ordering() -> Ordering {
    Ordering::NestedDissection
}

#[cfg(not(feature = "metis"))]
fn nd_ordering() -> Ordering {
    eprintln!("TALUS_3D_BENCH_ND=1 needs `--features metis`");
    std::process::exit(2);
}

/// User + system CPU seconds of this process, all threads (`/proc/self/stat`, 100 Hz).
fn cpu_seconds() -> f64 {
    std::fs::read_to_string("/proc/self/stat")
        .ok()
        .and_then(|s| {
            // Fields after the command name (which may hold spaces) start at state (3).
            let rest = s.rsplit_once(')')?.1;
            let f: Vec<&str> = rest.split_whitespace().collect();
            let (u, k) = (
                f.get(11)?.parse::<f64>().ok()?,
                f.get(12)?.parse::<f64>().ok()?,
            );
            Some((u + k) / 100.0)
        })
        .unwrap_or(f64::NAN)
}
