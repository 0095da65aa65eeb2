//! Four-lane f64 arithmetic for the collision's per-mode update, with one portable and one AVX
//! implementation that give bit-identical results.
//!
//! Every operation is a lane-wise IEEE-754 add or multiply (never a fused multiply–add), and sums across
//! lanes are taken in one fixed order, so which implementation runs changes the speed and never a digit of
//! a result: a bag recorded on one machine replays bit-exactly on another.

/// Number of lanes in a group.
pub(crate) const LANES: usize = 4;

/// One group of [`LANES`] values as stored in memory.
pub(crate) type Lanes = [f64; LANES];

/// Lane-wise arithmetic on a group held in registers.
pub(crate) trait Lane4: Copy {
    /// Loads a group.
    fn load(x: &Lanes) -> Self;
    /// Stores the group.
    fn store(self, x: &mut Lanes);
    /// All lanes set to `x`.
    fn splat(x: f64) -> Self;
    /// Lane-wise sum.
    fn add(self, other: Self) -> Self;
    /// Lane-wise product.
    fn mul(self, other: Self) -> Self;
    /// Sum across lanes, as (l0 + l1) + (l2 + l3).
    fn sum(self) -> f64;
}

/// The portable implementation (plain arrays; the compiler vectorises what it can).
#[derive(Clone, Copy)]
pub(crate) struct Portable(Lanes);

impl Lane4 for Portable {
    #[inline(always)]
    fn load(x: &Lanes) -> Self {
        Portable(*x)
    }
    #[inline(always)]
    fn store(self, x: &mut Lanes) {
        *x = self.0;
    }
    #[inline(always)]
    fn splat(x: f64) -> Self {
        Portable([x; LANES])
    }
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        let (a, b) = (self.0, o.0);
        Portable([a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3]])
    }
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        let (a, b) = (self.0, o.0);
        Portable([a[0] * b[0], a[1] * b[1], a[2] * b[2], a[3] * b[3]])
    }
    #[inline(always)]
    fn sum(self) -> f64 {
        let a = self.0;
        (a[0] + a[1]) + (a[2] + a[3])
    }
}

#[cfg(target_arch = "x86_64")]
pub(crate) use avx::Avx;

#[cfg(target_arch = "x86_64")]
mod avx {
    use super::{Lane4, Lanes};
    use std::arch::x86_64::{
        __m256d, _mm256_add_pd, _mm256_castpd256_pd128, _mm256_extractf128_pd, _mm256_loadu_pd, _mm256_mul_pd,
        _mm256_set1_pd, _mm256_storeu_pd, _mm_add_pd, _mm_add_sd, _mm_cvtsd_f64, _mm_unpackhi_pd,
    };

    /// The AVX implementation: one 256-bit register per group.
    ///
    /// Invariant: values of this type exist only inside code that runs after `is_x86_feature_detected!("avx")`
    /// (or a stronger feature) returned true, i.e. inside `#[target_feature(enable = "avx2")]` functions
    /// that are called only after that check. Every `unsafe` block below relies on it.
    #[derive(Clone, Copy)]
    pub(crate) struct Avx(__m256d);

    impl Lane4 for Avx {
        #[inline(always)]
        fn load(x: &Lanes) -> Self {
            // SAFETY: AVX is available (type invariant); `x` is 4 readable f64s (unaligned load).
            Avx(unsafe { _mm256_loadu_pd(x.as_ptr()) })
        }
        #[inline(always)]
        fn store(self, x: &mut Lanes) {
            // SAFETY: AVX is available (type invariant); `x` is 4 writable f64s (unaligned store).
            unsafe { _mm256_storeu_pd(x.as_mut_ptr(), self.0) }
        }
        #[inline(always)]
        fn splat(x: f64) -> Self {
            // SAFETY: AVX is available (type invariant).
            Avx(unsafe { _mm256_set1_pd(x) })
        }
        #[inline(always)]
        fn add(self, o: Self) -> Self {
            // SAFETY: AVX is available (type invariant).
            Avx(unsafe { _mm256_add_pd(self.0, o.0) })
        }
        #[inline(always)]
        fn mul(self, o: Self) -> Self {
            // SAFETY: AVX is available (type invariant).
            Avx(unsafe { _mm256_mul_pd(self.0, o.0) })
        }
        #[inline(always)]
        fn sum(self) -> f64 {
            // (l0 + l1) + (l2 + l3), the same order as `Portable::sum`.
            // SAFETY: AVX is available (type invariant); the SSE2 parts are baseline on x86_64.
            unsafe {
                let low = _mm256_castpd256_pd128(self.0);
                let high = _mm256_extractf128_pd::<1>(self.0);
                let low_sum = _mm_add_sd(low, _mm_unpackhi_pd(low, low));
                let high_sum = _mm_add_sd(high, _mm_unpackhi_pd(high, high));
                _mm_cvtsd_f64(_mm_add_pd(low_sum, high_sum))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ops<V: Lane4>(a: &Lanes, b: &Lanes) -> (Lanes, f64) {
        let (x, y) = (V::load(a), V::load(b));
        let mut out = [0.0; LANES];
        x.mul(y).add(V::splat(0.1)).store(&mut out);
        (out, x.add(y).sum())
    }

    #[test]
    fn portable_sums_in_the_documented_order() {
        // 1e16 + 1 rounds away unless the small lanes are added to each other first.
        let (_, sum) = ops::<Portable>(&[1e16, -1e16, 1.0, 1.0], &[0.0; 4]);
        assert_eq!(sum, 2.0);
    }

    #[cfg(target_arch = "x86_64")]
    #[test]
    fn avx_gives_the_same_bits_as_portable() {
        if !std::is_x86_feature_detected!("avx2") {
            eprintln!("no AVX2 on this CPU: nothing to compare");
            return;
        }
        #[target_feature(enable = "avx2")]
        fn with_avx(a: &Lanes, b: &Lanes) -> (Lanes, f64) {
            ops::<Avx>(a, b)
        }
        let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x as f64 / u64::MAX as f64 - 0.5) * 10f64.powi((x % 40) as i32 - 20)
        };
        for _ in 0..10_000 {
            let a = [next(), next(), next(), next()];
            let b = [next(), next(), next(), next()];
            // SAFETY: AVX2 was detected above.
            let fast = unsafe { with_avx(&a, &b) };
            let slow = ops::<Portable>(&a, &b);
            assert_eq!(fast.0.map(f64::to_bits), slow.0.map(f64::to_bits));
            assert_eq!(fast.1.to_bits(), slow.1.to_bits());
        }
    }
}
