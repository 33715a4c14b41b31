//! Projections per second on one core: `project_batch` (Sequential) over 100,000 points
//! spread evenly and at random over the three regions of a Drucker-Prager-like cone
//! (axis −e, apex on e, η = 0.4), for D = 3, 4 and 6, with and without the Jacobian.
//!
//! Run with `cargo bench -p talus-cone --bench projection`; divan prints items/s.

use std::f64::consts::{FRAC_PI_2, PI};

use divan::counter::ItemsCount;
use divan::{black_box, Bencher};
use talus_cone::{
    project_batch, Parallelism, Projection, Projector, Region, SMatrix, SVector, SecondOrderCone,
};

fn main() {
    divan::main();
}

const N: usize = 100_000;
const ETA: f64 = 0.4;

/// 64-bit LCG (Knuth's MMIX constants): fixed data without extra dependencies.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The cone and N points: region chosen at random (a third each), angle uniform within the
/// region in a random meridian plane, distance to the apex log-uniform in [1e-2, 1e2].
fn data<const D: usize>() -> (SecondOrderCone<D>, Vec<SVector<f64, D>>) {
    let mut rng = Lcg(0x7A1u64 + D as u64);
    let mut e = SVector::<f64, D>::zeros();
    for k in 0..3 {
        e[k] = 1.0 / 3f64.sqrt();
    }
    let cone = SecondOrderCone::try_new(-e, e * 2.0, ETA).unwrap();
    let n = *cone.axis();
    let alpha = ETA.atan();
    let points: Vec<_> = (0..N)
        .map(|_| {
            let (lo, hi) = match (rng.next() * 3.0) as usize {
                0 => (0.0, alpha),
                1 => (alpha, alpha + FRAC_PI_2),
                _ => (alpha + FRAC_PI_2, PI),
            };
            let theta = lo + (hi - lo) * rng.next();
            let mut t = SVector::<f64, D>::from_fn(|_, _| rng.next() - 0.5);
            t -= n * n.dot(&t);
            t.normalize_mut();
            let m = 10f64.powf(4.0 * rng.next() - 2.0);
            cone.apex() + (n * theta.cos() + t * theta.sin()) * m
        })
        .collect();
    let mut counts = [0usize; 3];
    for p in &points {
        counts[cone.project(p).region as usize] += 1;
    }
    assert!(counts.iter().all(|&c| c > N / 4), "region mix {counts:?}");
    (cone, points)
}

fn blank<const D: usize>() -> Projection<D> {
    Projection {
        point: SVector::zeros(),
        region: Region::Interior,
    }
}

#[divan::bench(consts = [3, 4, 6], sample_count = 50)]
fn project<const D: usize>(bencher: Bencher) {
    let (cone, points) = data::<D>();
    let sets = [cone];
    let mut out = vec![blank::<D>(); N];
    bencher.counter(ItemsCount::new(N)).bench_local(|| {
        project_batch(
            black_box(&sets),
            black_box(&points),
            &mut out,
            None,
            Parallelism::Sequential,
        );
        black_box(&out);
    });
}

#[divan::bench(consts = [3, 4, 6], sample_count = 50)]
fn project_with_jacobian<const D: usize>(bencher: Bencher) {
    let (cone, points) = data::<D>();
    let sets = [cone];
    let mut out = vec![blank::<D>(); N];
    let mut jac = vec![SMatrix::<f64, D, D>::zeros(); N];
    bencher.counter(ItemsCount::new(N)).bench_local(|| {
        project_batch(
            black_box(&sets),
            black_box(&points),
            &mut out,
            Some(&mut jac),
            Parallelism::Sequential,
        );
        black_box((&out, &jac));
    });
}
