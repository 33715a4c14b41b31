//! The two precisions a factor is stored in: f64, and f32 for the preconditioner of the
//! Krylov path (`docs/krylov.md`, 'A single-precision factor'), whose factorization costs
//! about half (twice the SIMD width, half the memory traffic).
use faer::traits::RealField;

/// A real scalar the supernodal factorizations work in. The input matrix and right-hand
/// sides stay f64; they are rounded on the way in and widened on the way out.
pub trait Real: RealField + Copy + Send + Sync + std::ops::Neg<Output = Self> + 'static {
    const ZERO: Self;
    const ONE: Self;
    fn from_f64(v: f64) -> Self;
    fn to_f64(self) -> f64;
    fn sqrt(self) -> Self;
    fn is_finite(self) -> bool;
}

macro_rules! real {
    ($t:ty) => {
        impl Real for $t {
            const ZERO: Self = 0.0;
            const ONE: Self = 1.0;
            #[inline(always)]
            fn from_f64(v: f64) -> Self {
                v as $t
            }
            #[inline(always)]
            fn to_f64(self) -> f64 {
                self as f64
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                <$t>::sqrt(self)
            }
            #[inline(always)]
            fn is_finite(self) -> bool {
                <$t>::is_finite(self)
            }
        }
    };
}

real!(f32);
real!(f64);
