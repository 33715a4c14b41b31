//! The Krylov reuse in 2D against the direct path (`docs/krylov.md`, 'Where it pays'):
//! the plane-strain footing's steps solved both ways, alternating, with the seconds,
//! Newton iterations, factorizations and GMRES iterations of each and their ratio, in one
//! run. `cargo bench -p talus-ssn --bench krylov_footing`; `TALUS_2D_KRYLOV_CELLS=NXxNY`
//! (default 160x120).
#[path = "../tests/common/footing_like.rs"]
mod footing_like;

use footing_like::{krylov, solve, FootingLike};
use talus_ssn::{Settings, Solver};

/// On a worker of rayon's pool, as `talus run` solves (`talus_ssn::on_pool`).
fn main() {
    talus_ssn::on_pool(bench);
}

fn bench() {
    let cells = std::env::var("TALUS_2D_KRYLOV_CELLS").unwrap_or_else(|_| "160x120".into());
    let (nx, ny) = cells
        .split_once('x')
        .and_then(|(a, b)| Some((a.parse().ok()?, b.parse().ok()?)))
        .expect("NXxNY");
    for dilatancy in [30.0, 10.0] {
        let footing = FootingLike::new(nx, ny, dilatancy, 1e-2);
        let n = footing.problem.operator().size();
        let mut direct = Solver::new(footing.problem.clone(), Settings::fem()).unwrap();
        let mut reuse = Solver::new(footing.problem.clone(), krylov()).unwrap();
        let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
        let (mut ta, mut tb, mut fa, mut fb, mut g, mut ia, mut ib) = (0.0, 0.0, 0, 0, 0, 0, 0);
        for step in 0..8 {
            direct.set_q(footing.q(&a, 0.01)).unwrap();
            reuse.set_q(footing.q(&b, 0.01)).unwrap();
            let (ra, rb) = if step % 2 == 0 {
                let ra = solve(&mut direct, &mut a);
                (ra, solve(&mut reuse, &mut b))
            } else {
                let rb = solve(&mut reuse, &mut b);
                (solve(&mut direct, &mut a), rb)
            };
            ta += ra.seconds;
            tb += rb.seconds;
            fa += ra.factorizations;
            fb += rb.factorizations;
            g += rb.krylov_iterations;
            ia += ra.iterations;
            ib += rb.iterations;
        }
        eprintln!(
            "2D {nx}×{ny} ({} velocity dofs), θ = {dilatancy}: direct {ta:.2} s ({ia} its, {fa} factorizations), krylov {tb:.2} s ({ib} its, {fb} factorizations, {g} GMRES its): ratio {:.2}",
            match footing.problem.operator() {
                talus_ssn::Operator::Structured(s) => s.lumped_mass.len(),
                _ => 0,
            },
            tb / ta
        );
    }
}
