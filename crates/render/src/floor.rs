//! floor (and ceil) without a call: on the baseline x86-64 instruction set (SSE2, no `roundss`)
//! `f32::floor` is a call to libm's floorf, which the texture lookups made four times per sample
//! (2 % of the textured scene's instructions), and `f64::ceil`/`floor` are calls too, four per
//! film splat. Truncation through an integer and a correction give the library's values.

/// ⌊x⌋, equal to `x.floor()` for every f32, signed zeros, infinities and NaN included.
#[inline(always)]
pub fn floor(x: f32) -> f32 {
    // From 2²³ on every f32 is an integer; ±∞ and NaN are their own floor.
    if x.abs() >= 8_388_608.0 || x.is_nan() {
        return x;
    }
    let t = x as i32 as f32;
    // The sign of x: −0 stays −0, and a negative x never floors to +0.
    (if t > x { t - 1.0 } else { t }).copysign(x)
}

/// ⌈x⌉ as an integer, for |x| < 2⁶³.
#[inline(always)]
pub fn ceil_i64(x: f64) -> i64 {
    let t = x as i64;
    t + ((t as f64) < x) as i64
}

/// ⌊x⌋ as an integer, for |x| < 2⁶³.
#[inline(always)]
pub fn floor_i64(x: f64) -> i64 {
    let t = x as i64;
    t - ((t as f64) > x) as i64
}

#[cfg(test)]
mod tests {
    use super::{ceil_i64, floor, floor_i64};

    #[test]
    fn integer_ceil_and_floor_match_the_library() {
        for k in -40_000..40_000 {
            // Integers, halves and values a rounding away from an integer.
            for x in [k as f64 / 16.0, k as f64 / 16.0 + 1e-12, k as f64 / 16.0 - 1e-12] {
                assert_eq!((ceil_i64(x), floor_i64(x)), (x.ceil() as i64, x.floor() as i64), "{x}");
            }
        }
    }

    #[test]
    fn equals_the_library_floor_bit_for_bit() {
        let same = |x: f32| {
            let (a, b) = (floor(x), x.floor());
            assert!(a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()), "floor({x:e}) = {a:e}, not {b:e}");
        };
        for x in [0.0, -0.0, 0.5, -0.5, 1.0, -1.0, 1.5, -1.5, 8_388_607.5, -8_388_607.5, 8_388_608.0, -8_388_609.0] {
            same(x);
        }
        for x in [f32::INFINITY, f32::NEG_INFINITY, f32::NAN, f32::MAX, f32::MIN, f32::MIN_POSITIVE, -f32::MIN_POSITIVE]
        {
            same(x);
        }
        // Every bit pattern of a sweep over the whole range, and next to every integer up to 2¹².
        for bits in (0..u32::MAX).step_by(9_973) {
            same(f32::from_bits(bits));
        }
        for i in -4096..4096 {
            let x = i as f32;
            for y in [x, x.next_up(), x.next_down()] {
                same(y);
            }
        }
    }
}
