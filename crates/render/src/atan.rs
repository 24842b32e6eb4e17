//! atan2 by a polynomial: atan t ≈ t·P(t²) on t = min(|x|,|y|)/max(|x|,|y|) ∈ [0, 1], then the
//! octant identities atan(1/t) = π/2 − atan t and atan(−t) = −atan t, and π − θ for x < 0.
//! P has 8 coefficients, a minimax fit (Lawson's reweighted least squares, done once in
//! f64) of degree 15 in t: error ≤ 3.8e-8 rad, ≤ 1.7e-7 rad with f32 rounding (evaluated
//! by Estrin's scheme), plus ½ ulp for rounding the angle — within about 1 ulp of libm's
//! atan2f, and several times cheaper (no call, no branch on the octant, a short dependency
//! chain), which matters in the environment-map lookup.

use std::f32::consts::{FRAC_PI_2, PI};

/// atan t / t as a polynomial in s = t², for t ∈ [0, 1].
const P: [f32; 8] = [
    0.999_999_34,
    -0.333_298_6,
    0.199_465_66,
    -0.139_086_29,
    0.096_421_96,
    -0.055_912_3,
    0.021_862_939,
    -0.004_054_561_7,
];

/// π/2 − FRAC_PI_2 (f32).
const FRAC_PI_2_LO: f32 = -4.371_139e-8;
/// π − PI (f32).
const PI_LO: f32 = -8.742_278e-8;

/// atan2(y, x) in [−π, π], within 2e-7 rad + ½ ulp of the exact angle; ±0 for (±0, x ≥ 0).
#[inline(always)]
pub fn atan2(y: f32, x: f32) -> f32 {
    let (ax, ay) = (x.abs(), y.abs());
    // Selects rather than branches: the octant of a ray direction is not predictable.
    let swap = ay > ax;
    let (lo, hi) = if swap { (ax, ay) } else { (ay, ax) };
    let t = lo / if hi > f32::MIN_POSITIVE { hi } else { f32::MIN_POSITIVE };
    // Estrin's scheme: pairs, then pairs of pairs, a shorter dependency chain than Horner's.
    let s = t * t;
    let (s2, s4) = (s * s, s * s * (s * s));
    let (q0, q1, q2, q3) = (P[0] + P[1] * s, P[2] + P[3] * s, P[4] + P[5] * s, P[6] + P[7] * s);
    let p = (q0 + q1 * s2) + (q2 + q3 * s2) * s4;
    // The angle is base ± atan t, with base 0, π/2 or π. f32 π/2 and π are off by 4.4e-8
    // and 8.7e-8: their remainders go into the small term first, so the sum rounds once.
    let left = x < 0.0;
    let a = f32::from_bits((t * p).to_bits() ^ (((swap != left) as u32) << 31));
    let (base, rest) = if swap {
        (FRAC_PI_2, FRAC_PI_2_LO)
    } else if left {
        (PI, PI_LO)
    } else {
        (0.0, 0.0)
    };
    (base + (a + rest)).copysign(y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_exact_angle_everywhere() {
        // Every direction around the circle (and radii from tiny to huge), against f64.
        let mut worst = 0.0f64;
        for k in 0..200_000 {
            let phi = -std::f64::consts::PI + 2.0 * std::f64::consts::PI * (k as f64 + 0.5) / 200_000.0;
            for r in [1e-30f64, 1e-3, 1.0, 1e20] {
                let (y, x) = ((r * phi.sin()) as f32, (r * phi.cos()) as f32);
                let exact = (y as f64).atan2(x as f64);
                // The polynomial's error, beyond the ½ ulp that rounding the angle to f32 costs.
                let bits = (exact.abs() as f32).to_bits();
                let half_ulp = (f32::from_bits(bits + 1) - f32::from_bits(bits)) as f64 / 2.0;
                worst = worst.max((atan2(y, x) as f64 - exact).abs() - half_ulp);
            }
        }
        assert!(worst < 2e-7, "{worst}");
        // Axes and signed zeros, as libm.
        assert_eq!(atan2(0.0, 1.0), 0.0);
        assert_eq!(atan2(1.0, 0.0), FRAC_PI_2);
        assert_eq!(atan2(-1.0, 0.0), -FRAC_PI_2);
        assert_eq!(atan2(0.0, -1.0), PI);
        assert_eq!(atan2(-0.0, -1.0), -PI);
        assert_eq!(atan2(0.0, 0.0), 0.0);
        assert!((atan2(1.0, 1.0) - std::f32::consts::FRAC_PI_4).abs() < 1e-7);
    }
}
