use nalgebra::{SMatrix, SVector};
use rayon::prelude::*;

use crate::{Projection, Projector};

/// How a batch is spread over threads. Results do not depend on it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Parallelism {
    /// One thread, in order.
    #[default]
    Sequential,
    /// Rayon's current thread pool.
    Rayon,
}

/// Points per rayon task: large enough to amortise scheduling for 3-6 component points.
const CHUNK: usize = 1024;

/// Projects `points[i]` onto `sets[i]` (or onto `sets[0]` for all points when `sets` has one
/// element), writing `out[i]` and, when given, the Clarke Jacobian `jacobians[i]`.
///
/// Each point is handled on its own with no reduction, so the output is bitwise identical
/// for any [`Parallelism`] and thread count.
///
/// # Panics
/// When `out` (or `jacobians`) is not as long as `points`, or `sets` is neither of length 1
/// nor of the length of `points`: these are programming errors, not data errors.
pub fn project_batch<S, const D: usize>(
    sets: &[S],
    points: &[SVector<f64, D>],
    out: &mut [Projection<D>],
    jacobians: Option<&mut [SMatrix<f64, D, D>]>,
    parallelism: Parallelism,
) where
    S: Projector<D> + Sync,
{
    assert_eq!(out.len(), points.len(), "output length must match points");
    assert!(
        sets.len() == 1 || sets.len() == points.len(),
        "sets must hold one set or one per point"
    );
    let set_of = |i: usize| if sets.len() == 1 { &sets[0] } else { &sets[i] };
    match jacobians {
        None => {
            let run = |(c, chunk): (usize, &mut [Projection<D>])| {
                for (k, o) in chunk.iter_mut().enumerate() {
                    let i = c * CHUNK + k;
                    *o = set_of(i).project(&points[i]);
                }
            };
            match parallelism {
                Parallelism::Sequential => out.chunks_mut(CHUNK).enumerate().for_each(run),
                Parallelism::Rayon => out.par_chunks_mut(CHUNK).enumerate().for_each(run),
            }
        }
        Some(jac) => {
            assert_eq!(jac.len(), points.len(), "jacobian length must match points");
            let run = |(c, (chunk, jchunk)): (
                usize,
                (&mut [Projection<D>], &mut [SMatrix<f64, D, D>]),
            )| {
                for (k, (o, j)) in chunk.iter_mut().zip(jchunk.iter_mut()).enumerate() {
                    let i = c * CHUNK + k;
                    (*o, *j) = set_of(i).project_with_jacobian(&points[i]);
                }
            };
            match parallelism {
                Parallelism::Sequential => out
                    .chunks_mut(CHUNK)
                    .zip(jac.chunks_mut(CHUNK))
                    .enumerate()
                    .for_each(run),
                Parallelism::Rayon => out
                    .par_chunks_mut(CHUNK)
                    .zip(jac.par_chunks_mut(CHUNK))
                    .enumerate()
                    .for_each(run),
            }
        }
    }
}
