//! Sixteen rays at once: the lane type of ray packets, and the instruction set their kernels
//! are compiled for, chosen at run time.
//!
//! A kernel is written once on [`F16`], whose operations are loops over sixteen `f32`s that
//! the compiler turns into vector instructions, and compiled three times on x86_64: for
//! AVX-512 (one register per operation), AVX2 (two) and the SSE2 every x86_64 CPU has (four;
//! NEON on aarch64). [`Simd::detect`] picks the widest the CPU runs. The lanes round exactly as
//! scalar code does (no fused multiply-adds, IEEE division), so every instruction set gives
//! the same image bit for bit; [`Simd::Scalar`] turns packets off altogether.

// Lane loops index several arrays in step: the form the vectoriser reads best.
#![allow(clippy::needless_range_loop)]

use std::ops::{Add, Div, Mul, Sub};

/// Lanes of a packet.
pub const LANES: usize = 16;

/// How ray queries run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Simd {
    /// One ray at a time, no packets.
    Scalar,
    /// Packets on the instructions every CPU of the architecture has (SSE2; NEON on aarch64).
    Sse2,
    /// Packets on AVX2 and FMA.
    Avx2,
    /// Packets on AVX-512 (F, VL, BW, DQ).
    Avx512,
}

impl Simd {
    /// Every choice, by its name.
    pub const ALL: [(&'static str, Simd); 4] =
        [("scalar", Simd::Scalar), ("sse2", Simd::Sse2), ("avx2", Simd::Avx2), ("avx512", Simd::Avx512)];

    /// The name `--simd` and `GONIO_SIMD` take.
    pub fn name(self) -> &'static str {
        Self::ALL.iter().find(|(_, s)| *s == self).map_or("scalar", |(n, _)| n)
    }

    /// The choice named `name` ("auto" is [`detect`](Self::detect)), when this CPU runs it.
    pub fn parse(name: &str) -> Result<Simd, String> {
        if name == "auto" {
            return Ok(Simd::best());
        }
        let names = || Self::ALL.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", ");
        let s = Self::ALL
            .iter()
            .find(|(n, _)| *n == name)
            .map(|&(_, s)| s)
            .ok_or_else(|| format!("unknown SIMD choice '{name}'; accepted: auto, {}", names()))?;
        if !s.available() {
            return Err(format!("this CPU cannot run '{name}'; best available: {}", Simd::best().name()));
        }
        Ok(s)
    }

    /// [`parse`](Self::parse), with "auto" meaning [`detect`](Self::detect) (`GONIO_SIMD`
    /// first): the command line's reading.
    pub fn parse_arg(name: &str) -> Result<Simd, String> {
        if name == "auto" {
            return Ok(Simd::detect());
        }
        Simd::parse(name)
    }

    /// True when this CPU runs it. Asked at every dispatched ray query, so the features are
    /// detected once and kept as one bit per choice (perf, Cornell box: the feature tests took
    /// 1.2 % of the render).
    #[inline]
    pub fn available(self) -> bool {
        static BITS: std::sync::atomic::AtomicU8 = std::sync::atomic::AtomicU8::new(0);
        const DETECTED: u8 = 1 << 7;
        let mut bits = BITS.load(std::sync::atomic::Ordering::Relaxed);
        if bits & DETECTED == 0 {
            bits = Self::ALL.iter().fold(DETECTED, |b, &(_, s)| b | (s.detected() as u8) << s as u8);
            BITS.store(bits, std::sync::atomic::Ordering::Relaxed);
        }
        bits >> self as u8 & 1 != 0
    }

    /// Whether the CPU has the features, asked of the CPU.
    #[cold]
    fn detected(self) -> bool {
        match self {
            Simd::Scalar | Simd::Sse2 => true,
            #[cfg(target_arch = "x86_64")]
            Simd::Avx2 => is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma"),
            #[cfg(target_arch = "x86_64")]
            Simd::Avx512 => {
                is_x86_feature_detected!("avx512f")
                    && is_x86_feature_detected!("avx512vl")
                    && is_x86_feature_detected!("avx512bw")
                    && is_x86_feature_detected!("avx512dq")
            }
            #[cfg(not(target_arch = "x86_64"))]
            Simd::Avx2 | Simd::Avx512 => false,
        }
    }

    /// The widest this CPU runs.
    pub fn best() -> Simd {
        [Simd::Avx512, Simd::Avx2].into_iter().find(|s| s.available()).unwrap_or(Simd::Sse2)
    }

    /// The choice of the environment variable `GONIO_SIMD` when set to a valid one, else the
    /// widest this CPU runs (read once).
    pub fn detect() -> Simd {
        static CHOICE: std::sync::OnceLock<Simd> = std::sync::OnceLock::new();
        *CHOICE.get_or_init(|| {
            std::env::var("GONIO_SIMD").ok().and_then(|v| Simd::parse(&v).ok()).unwrap_or_else(Simd::best)
        })
    }
}

/// Calls the `#[inline(always)]` method `$this.$method(args)` compiled for the instruction set
/// `$simd` names: one copy per set is made here, the method inlined into a function with that
/// set's target features (`Scalar` runs the baseline copy). `$ty` is `$this`'s type. In the
/// form `$method::<AVX>(args)` the method takes a `const AVX: bool`, true in the AVX2 and
/// AVX-512 copies, so that it may call AVX intrinsics there.
macro_rules! dispatch {
    ($simd:expr, $this:ident: $ty:ty, $method:ident::<AVX>($($a:ident: $t:ty),*) -> $r:ty) => {
        $crate::simd::dispatch!(@copies $simd, $this: $ty, $method, [::<true>], [::<false>], ($($a: $t),*) -> $r)
    };
    ($simd:expr, $this:ident: $ty:ty, $method:ident($($a:ident: $t:ty),*) -> $r:ty) => {
        $crate::simd::dispatch!(@copies $simd, $this: $ty, $method, [], [], ($($a: $t),*) -> $r)
    };
    // The copies, the AVX2 and AVX-512 ones calling `$method $($wide)*`, the baseline one
    // `$method $($base)*`.
    (@copies $simd:expr, $this:ident: $ty:ty, $method:ident, [$($wide:tt)*], [$($base:tt)*],
        ($($a:ident: $t:ty),*) -> $r:ty) => {{
        #[cfg(target_arch = "x86_64")]
        {
            #[target_feature(enable = "avx512f,avx512vl,avx512bw,avx512dq,avx2,fma")]
            unsafe fn avx512(this: &$ty, $($a: $t),*) -> $r {
                this.$method $($wide)* ($($a),*)
            }
            #[target_feature(enable = "avx2,fma")]
            unsafe fn avx2(this: &$ty, $($a: $t),*) -> $r {
                this.$method $($wide)* ($($a),*)
            }
            match $simd {
                // SAFETY: the guards check that the CPU has the features (a cached flag test:
                // `Simd`'s variants can be named by anyone, so being given one proves nothing).
                s @ $crate::simd::Simd::Avx512 if s.available() => unsafe { avx512($this, $($a),*) },
                s @ $crate::simd::Simd::Avx2 if s.available() => unsafe { avx2($this, $($a),*) },
                _ => $this.$method $($base)* ($($a),*),
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            $this.$method $($base)* ($($a),*)
        }
    }};
}
pub(crate) use dispatch;

/// Sixteen `f32` lanes.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
pub struct F16(pub [f32; LANES]);

/// Sixteen lane flags, each all ones (set) or zero: the form vector compares produce, so that
/// masking and blending stay in vector registers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(C, align(64))]
pub struct M16(pub [i32; LANES]);

impl M16 {
    /// No lane set.
    pub const NONE: M16 = M16([0; LANES]);

    /// The lanes of bit mask `bits` (bit i: lane i).
    #[inline(always)]
    pub fn from_bits(bits: u32) -> M16 {
        let mut r = [0; LANES];
        for (i, r) in r.iter_mut().enumerate() {
            *r = -((bits >> i & 1) as i32);
        }
        M16(r)
    }

    /// As a bit mask (bit i: lane i).
    #[inline(always)]
    pub fn bits(self) -> u32 {
        let mut b = 0u32;
        for i in 0..LANES {
            b |= ((self.0[i] as u32) >> 31) << i;
        }
        b
    }

    /// [`bits`](Self::bits) in code compiled for AVX2 or AVX-512 when `AVX` (`dispatch!`'s
    /// `::<AVX>` form): two sign-bit gathers, where LLVM makes the loop of `bits` a chain of
    /// shifts and a ten-instruction OR reduction even with the mask in a mask register.
    #[inline(always)]
    pub fn bits_in<const AVX: bool>(self) -> u32 {
        #[cfg(target_arch = "x86_64")]
        if AVX {
            // SAFETY: `AVX` is set only in code compiled for AVX2 or AVX-512, which `dispatch!`
            // runs after checking that the CPU has them.
            return unsafe { self.bits_avx() };
        }
        self.bits()
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    #[inline]
    unsafe fn bits_avx(self) -> u32 {
        use std::arch::x86_64::*;
        // SAFETY: sixteen 32-bit lanes are two eight-lane AVX registers, bit for bit.
        let [lo, hi]: [__m256; 2] = unsafe { std::mem::transmute(self.0) };
        _mm256_movemask_ps(lo) as u32 | (_mm256_movemask_ps(hi) as u32) << 8
    }

    /// [`any`](Self::any), `AVX` as for [`bits_in`](Self::bits_in).
    #[inline(always)]
    pub fn any_in<const AVX: bool>(self) -> bool {
        self.bits_in::<AVX>() != 0
    }

    /// True when some lane is set.
    #[inline(always)]
    pub fn any(self) -> bool {
        self.0.iter().fold(0, |a, &b| a | b) != 0
    }

    #[inline(always)]
    fn zip(self, o: M16, f: impl Fn(i32, i32) -> i32) -> M16 {
        let mut r = [0; LANES];
        for i in 0..LANES {
            r[i] = f(self.0[i], o.0[i]);
        }
        M16(r)
    }

    /// Lanes set in both.
    #[inline(always)]
    pub fn and(self, o: M16) -> M16 {
        self.zip(o, |a, b| a & b)
    }

    /// Lanes set in either.
    #[inline(always)]
    pub fn or(self, o: M16) -> M16 {
        self.zip(o, |a, b| a | b)
    }

    /// Lanes set here and not in `o`.
    #[inline(always)]
    pub fn and_not(self, o: M16) -> M16 {
        self.zip(o, |a, b| a & !b)
    }

    /// `a`'s lanes where set, else `b`'s.
    #[inline(always)]
    pub fn select_u32(self, a: [u32; LANES], b: [u32; LANES]) -> [u32; LANES] {
        let mut r = [0; LANES];
        for i in 0..LANES {
            r[i] = (a[i] & self.0[i] as u32) | (b[i] & !self.0[i] as u32);
        }
        r
    }
}

impl F16 {
    /// `x` on every lane.
    #[inline(always)]
    pub fn splat(x: f32) -> Self {
        F16([x; LANES])
    }

    #[inline(always)]
    fn map2(self, o: F16, f: impl Fn(f32, f32) -> f32) -> F16 {
        let mut r = [0.0; LANES];
        for i in 0..LANES {
            r[i] = f(self.0[i], o.0[i]);
        }
        F16(r)
    }

    #[inline(always)]
    fn mask(self, o: F16, f: impl Fn(f32, f32) -> bool) -> M16 {
        let mut m = [0; LANES];
        for i in 0..LANES {
            m[i] = -(f(self.0[i], o.0[i]) as i32);
        }
        M16(m)
    }

    /// Lane-wise minimum (the second operand where either is NaN).
    #[inline(always)]
    pub fn min(self, o: F16) -> F16 {
        self.map2(o, |a, b| if a < b { a } else { b })
    }

    /// Lane-wise maximum (the second operand where either is NaN).
    #[inline(always)]
    pub fn max(self, o: F16) -> F16 {
        self.map2(o, |a, b| if a > b { a } else { b })
    }

    /// Lanes that are < `o`'s.
    #[inline(always)]
    pub fn lt(self, o: F16) -> M16 {
        self.mask(o, |a, b| a < b)
    }

    /// Lanes that are ≤ `o`'s.
    #[inline(always)]
    pub fn le(self, o: F16) -> M16 {
        self.mask(o, |a, b| a <= b)
    }

    /// Lanes that are > `o`'s.
    #[inline(always)]
    pub fn gt(self, o: F16) -> M16 {
        self.mask(o, |a, b| a > b)
    }

    /// Lanes of `a` where `mask` is set, else of `self`.
    #[inline(always)]
    pub fn blend(self, mask: M16, a: F16) -> F16 {
        let mut r = [0.0; LANES];
        for i in 0..LANES {
            let m = mask.0[i] as u32;
            r[i] = f32::from_bits((a.0[i].to_bits() & m) | (self.0[i].to_bits() & !m));
        }
        F16(r)
    }

    /// The smallest lane among those `mask` selects (+∞ for none).
    #[inline(always)]
    pub fn min_of(self, mask: M16) -> f32 {
        min_lanes(F16::splat(f32::INFINITY).blend(mask, self).0)
    }
}

/// The smallest of `L` lanes (a power of two), by halving: vector minima of register halves.
#[inline(always)]
pub fn min_lanes<const L: usize>(mut m: [f32; L]) -> f32 {
    let mut w = L / 2;
    while w > 0 {
        for i in 0..w {
            m[i] = if m[i + w] < m[i] { m[i + w] } else { m[i] };
        }
        w /= 2;
    }
    m[0]
}

macro_rules! lane_op {
    ($tr:ident, $f:ident, $op:tt) => {
        impl $tr for F16 {
            type Output = F16;
            #[inline(always)]
            fn $f(self, o: F16) -> F16 {
                self.map2(o, |a, b| a $op b)
            }
        }
    };
}
lane_op!(Add, add, +);
lane_op!(Sub, sub, -);
lane_op!(Mul, mul, *);
lane_op!(Div, div, /);

/// Lane-wise cross product of vectors held as x, y, z lanes (`F16`, glam's `Vec4`), in the
/// operand order of glam's `Vec3::cross`, so that each lane rounds as the scalar one does.
#[inline(always)]
pub fn cross<T: Copy + Mul<Output = T> + Sub<Output = T>>(a: &[T; 3], b: &[T; 3]) -> [T; 3] {
    [a[1] * b[2] - b[1] * a[2], a[2] * b[0] - b[2] * a[0], a[0] * b[1] - b[0] * a[1]]
}

/// Lane-wise dot product, in the summation order of glam's `Vec3::dot`.
#[inline(always)]
pub fn dot<T: Copy + Mul<Output = T> + Add<Output = T>>(a: &[T; 3], b: &[T; 3]) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Calls `f` with the index of every set bit of `mask`, lowest first.
#[inline(always)]
pub fn for_bits(mask: u32, mut f: impl FnMut(usize)) {
    for i in Bits(mask) {
        f(i);
    }
}

/// The indices of the set bits of a mask, lowest first: [`for_bits`] as an iterator, for loops
/// whose body must not be a closure (code compiled for an instruction set by `dispatch!`).
pub struct Bits(pub u32);

impl Iterator for Bits {
    type Item = usize;
    #[inline(always)]
    fn next(&mut self) -> Option<usize> {
        if self.0 == 0 {
            return None;
        }
        let i = self.0.trailing_zeros() as usize;
        self.0 &= self.0 - 1;
        Some(i)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn choices_parse_and_the_baseline_is_always_there() {
        assert_eq!(Simd::parse("sse2"), Ok(Simd::Sse2));
        assert_eq!(Simd::parse("scalar"), Ok(Simd::Scalar));
        assert_eq!(Simd::parse("auto"), Ok(Simd::best()));
        assert!(Simd::parse("avx9").unwrap_err().contains("accepted: auto, scalar, sse2, avx2, avx512"));
        for (name, s) in Simd::ALL {
            assert_eq!(s.name(), name);
        }
        assert!(Simd::best().available());
    }

    #[test]
    fn lanes_compute_what_scalars_do() {
        let a = F16(std::array::from_fn(|i| i as f32 - 5.0));
        let b = F16(std::array::from_fn(|i| (i as f32 * 0.7).sin()));
        for i in 0..LANES {
            let (x, y) = (a.0[i], b.0[i]);
            assert_eq!((a + b).0[i], x + y);
            assert_eq!((a - b).0[i], x - y);
            assert_eq!((a * b).0[i], x * y);
            assert_eq!((a / b).0[i], x / y);
            assert_eq!(a.min(b).0[i], x.min(y));
            assert_eq!(a.max(b).0[i], x.max(y));
            assert_eq!(a.lt(b).bits() >> i & 1 != 0, x < y);
        }
        assert_eq!(a.min_of(M16::from_bits(0b1010_0000_0000)), 4.0);
        assert_eq!(a.min_of(M16::NONE), f32::INFINITY);
        for bits in [0, 1, 0x8001, 0xffff, 0x1234] {
            let m = M16::from_bits(bits);
            assert_eq!((m.bits(), m.any()), (bits, bits != 0));
            assert_eq!(m.and(M16::from_bits(0xff)).bits(), bits & 0xff);
            assert_eq!(m.and_not(M16::from_bits(0xff)).bits(), bits & !0xff);
            assert_eq!(F16::splat(1.0).blend(m, F16::splat(2.0)).0[0], if bits & 1 != 0 { 2.0 } else { 1.0 });
        }
        if Simd::Avx2.available() {
            for bits in [0, 1, 0x8001, 0xffff, 0x1234, 0x0100] {
                let m = M16::from_bits(bits);
                assert_eq!((m.bits_in::<true>(), m.any_in::<true>()), (bits, bits != 0));
            }
        }
        let mut seen = Vec::new();
        for_bits(0b1001_0010, |i| seen.push(i));
        assert_eq!(seen, [1, 4, 7]);
    }
}
