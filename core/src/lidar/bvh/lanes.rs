//! Four f32 lanes: SSE on x86-64 (always present there), plain arrays
//! elsewhere. Only what the box tests need (a ray's four child boxes, or
//! four rays of a packet against one box).

#[cfg(target_arch = "x86_64")]
mod imp {
    // SAFETY (every `unsafe` below): SSE and SSE2 are part of the x86-64
    // baseline, so these intrinsics are always available; none of them
    // touches memory except `_mm_storeu_ps`, whose target is a local array.
    use std::arch::x86_64::{
        __m128, _mm_and_ps, _mm_andnot_ps, _mm_cmple_ps, _mm_cmplt_ps, _mm_max_ps, _mm_min_ps,
        _mm_movemask_ps, _mm_mul_ps, _mm_or_ps, _mm_set_ps, _mm_set1_ps, _mm_storeu_ps, _mm_sub_ps,
    };

    /// Four lanes in one SSE register.
    #[derive(Clone, Copy)]
    pub(crate) struct F4(__m128);

    impl F4 {
        #[inline(always)]
        pub fn load(a: &[f32; 4]) -> Self {
            Self(unsafe { _mm_set_ps(a[3], a[2], a[1], a[0]) })
        }
        #[inline(always)]
        pub fn splat(x: f32) -> Self {
            Self(unsafe { _mm_set1_ps(x) })
        }
        #[inline(always)]
        pub fn sub(self, o: Self) -> Self {
            Self(unsafe { _mm_sub_ps(self.0, o.0) })
        }
        #[inline(always)]
        pub fn mul(self, o: Self) -> Self {
            Self(unsafe { _mm_mul_ps(self.0, o.0) })
        }
        #[inline(always)]
        pub fn min(self, o: Self) -> Self {
            Self(unsafe { _mm_min_ps(self.0, o.0) })
        }
        #[inline(always)]
        pub fn max(self, o: Self) -> Self {
            Self(unsafe { _mm_max_ps(self.0, o.0) })
        }
        /// Bit `i` set where lane `i` of `self` ≤ that of `o`.
        #[inline(always)]
        pub fn le_mask(self, o: Self) -> u32 {
            unsafe { _mm_movemask_ps(_mm_cmple_ps(self.0, o.0)) as u32 }
        }
        /// All-ones lanes where `self` ≤ `o`, zero elsewhere.
        #[inline(always)]
        pub fn le(self, o: Self) -> Self {
            Self(unsafe { _mm_cmple_ps(self.0, o.0) })
        }
        /// All-ones lanes where `self` < `o`, zero elsewhere.
        #[inline(always)]
        pub fn lt(self, o: Self) -> Self {
            Self(unsafe { _mm_cmplt_ps(self.0, o.0) })
        }
        /// Bit `i` set where lane `i` of a comparison result is all ones.
        #[inline(always)]
        pub fn mask(self) -> u32 {
            unsafe { _mm_movemask_ps(self.0) as u32 }
        }
        /// `a` where lane `i` of the comparison result `self` is set, else `b`.
        #[inline(always)]
        pub fn select(self, a: Self, b: Self) -> Self {
            Self(unsafe { _mm_or_ps(_mm_and_ps(self.0, a.0), _mm_andnot_ps(self.0, b.0)) })
        }
        #[inline(always)]
        pub fn to_array(self) -> [f32; 4] {
            let mut out = [0.0; 4];
            unsafe { _mm_storeu_ps(out.as_mut_ptr(), self.0) };
            out
        }
    }
}

#[cfg(not(target_arch = "x86_64"))]
mod imp {
    /// Four lanes as a plain array.
    #[derive(Clone, Copy)]
    pub(crate) struct F4([f32; 4]);

    impl F4 {
        #[inline(always)]
        pub fn load(a: &[f32; 4]) -> Self {
            Self(*a)
        }
        #[inline(always)]
        pub fn splat(x: f32) -> Self {
            Self([x; 4])
        }
        #[inline(always)]
        pub fn sub(self, o: Self) -> Self {
            Self(std::array::from_fn(|i| self.0[i] - o.0[i]))
        }
        #[inline(always)]
        pub fn mul(self, o: Self) -> Self {
            Self(std::array::from_fn(|i| self.0[i] * o.0[i]))
        }
        #[inline(always)]
        pub fn min(self, o: Self) -> Self {
            Self(std::array::from_fn(|i| {
                if self.0[i] < o.0[i] {
                    self.0[i]
                } else {
                    o.0[i]
                }
            }))
        }
        #[inline(always)]
        pub fn max(self, o: Self) -> Self {
            Self(std::array::from_fn(|i| {
                if self.0[i] > o.0[i] {
                    self.0[i]
                } else {
                    o.0[i]
                }
            }))
        }
        #[inline(always)]
        pub fn le_mask(self, o: Self) -> u32 {
            (0..4).fold(0, |m, i| m | (u32::from(self.0[i] <= o.0[i]) << i))
        }
        #[inline(always)]
        fn cmp(self, o: Self, f: impl Fn(f32, f32) -> bool) -> Self {
            Self(std::array::from_fn(|i| {
                f32::from_bits(if f(self.0[i], o.0[i]) { u32::MAX } else { 0 })
            }))
        }
        #[inline(always)]
        pub fn le(self, o: Self) -> Self {
            self.cmp(o, |a, b| a <= b)
        }
        #[inline(always)]
        pub fn lt(self, o: Self) -> Self {
            self.cmp(o, |a, b| a < b)
        }
        #[inline(always)]
        pub fn mask(self) -> u32 {
            (0..4).fold(0, |m, i| m | (u32::from(self.0[i].to_bits() != 0) << i))
        }
        #[inline(always)]
        pub fn select(self, a: Self, b: Self) -> Self {
            Self(std::array::from_fn(|i| {
                if self.0[i].to_bits() != 0 {
                    a.0[i]
                } else {
                    b.0[i]
                }
            }))
        }
        #[inline(always)]
        pub fn to_array(self) -> [f32; 4] {
            self.0
        }
    }
}

pub(crate) use imp::F4;
