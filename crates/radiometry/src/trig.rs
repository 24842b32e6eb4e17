//! sin πx and cos πx together, by polynomials. x is reduced to r = x − k/2 ∈ [−¼, ¼], k the
//! integer nearest 2x (r exact, by Sterbenz's lemma, for |x| < 2²¹); then sin πr = r·S(r²) and
//! cos πr = 1 + r²·C(r²), each with four coefficients, minimax fits (reweighted least squares,
//! done once in f64) within 1e-8 of the exact values, and k's quarter turn rotates the pair.
//! After f32 rounding: within 2 ulp (the test sweeps [−2, 2]); exact at multiples of ½.
//!
//! Samplers turn a uniform number into an angle, 2πu or πv: passing x = 2u skips rounding
//! 2π·u (up to 2.4e-7 rad), and the code has no call and no branch, so a loop over sixteen
//! lanes vectorizes; libm's `sincosf` was a call per sample, 2–3 % of a render's time.

/// sin πr / r as a polynomial in r², r ∈ [0, ¼].
const S: [f32; 4] = [std::f32::consts::PI, -5.167_708, 2.549_767_5, -0.589_080_04];
/// (cos πr − 1) / r² as a polynomial in r², r ∈ [0, ¼].
const C: [f32; 4] = [-4.934_802, 4.058_710_6, -1.335_138, 0.232_126_77];
/// 1.5·2²³: adding and subtracting it rounds an f32 of magnitude below 2²² to an integer.
const ROUND: f32 = 12_582_912.0;

/// (sin πr, cos πr) for |r| ≤ ¼.
#[inline(always)]
pub fn sin_cos_pi_quarter(r: f32) -> (f32, f32) {
    let r2 = r * r;
    let s = r * (S[0] + r2 * (S[1] + r2 * (S[2] + r2 * S[3])));
    let c = 1.0 + r2 * (C[0] + r2 * (C[1] + r2 * (C[2] + r2 * C[3])));
    (s, c)
}

/// (sin πx, cos πx) for |x| < 2²¹ (NaN beyond ±∞ and for NaN).
#[inline(always)]
pub fn sin_cos_pi(x: f32) -> (f32, f32) {
    let k = (2.0 * x + ROUND) - ROUND;
    let (s, c) = sin_cos_pi_quarter(x - 0.5 * k);
    // The quarter turns: k = 1 maps (s, c) to (c, −s), k = 2 to (−s, −c).
    let q = k as i32;
    let (s, c) = if q & 1 != 0 { (c, -s) } else { (s, c) };
    if q & 2 != 0 {
        (-s, -c)
    } else {
        (s, c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Distance in units in the last place of `exact` rounded to f32.
    fn ulps(got: f32, exact: f64) -> f64 {
        let e = exact as f32;
        let ulp = (f32::from_bits(e.abs().to_bits() + 1) - e.abs()) as f64;
        (got as f64 - exact).abs() / ulp
    }

    #[test]
    fn is_within_two_ulp_of_the_exact_values() {
        let n = 1 << 20;
        let (mut worst_s, mut worst_c) = (0.0f64, 0.0f64);
        for i in 0..=n {
            let x = -2.0 + 4.0 * i as f32 / n as f32;
            let (s, c) = sin_cos_pi(x);
            let a = std::f64::consts::PI * x as f64;
            // Near a zero an ulp is tiny: there the absolute error counts (f32 has 2^-24 of 1).
            let (es, ec) = (a.sin(), a.cos());
            worst_s = worst_s.max(ulps(s, es).min((s as f64 - es).abs() / 2f64.powi(-24)));
            worst_c = worst_c.max(ulps(c, ec).min((c as f64 - ec).abs() / 2f64.powi(-24)));
        }
        assert!(worst_s <= 2.0 && worst_c <= 2.0, "sin {worst_s} ulp, cos {worst_c} ulp");
    }

    #[test]
    fn is_exact_at_half_turns_and_nan_outside() {
        for (k, (s, c)) in [(0.0, 1.0), (1.0, 0.0), (0.0, -1.0), (-1.0, 0.0), (0.0, 1.0)].into_iter().enumerate() {
            let (gs, gc) = sin_cos_pi(0.5 * k as f32);
            assert_eq!((gs, gc), (s, c), "x = {}", 0.5 * k as f32);
            let (gs, gc) = sin_cos_pi(-0.5 * k as f32);
            assert_eq!((gs, gc), (-s, c), "x = {}", -0.5 * k as f32);
        }
        for x in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            let (s, c) = sin_cos_pi(x);
            assert!(s.is_nan() && c.is_nan(), "{x}");
        }
    }
}
