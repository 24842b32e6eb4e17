//! The error function, its complement and its inverse in f32, for the Beckmann distribution's
//! masking term and visible-normal sampler.
//!
//! erfc(x) = t exp(−x² + P(t)), t = 1/(1 + x/2), x ≥ 0, P a degree-9 polynomial: Chebyshev
//! fitting of the remaining factor, fractional error < 1.2·10⁻⁷ for every x ≥ 0 (W. H. Press
//! et al., *Numerical Recipes*, 2nd ed., §6.2, `erfcc`); erfc(−x) = 2 − erfc(x) and
//! erf = 1 − erfc. In f32 (ε = 2⁻²⁴) the exponent's rounding grows with x², so erfc
//! is good to 1.2·10⁻⁷ + ε (8 + 3x²) relative, and erf to 2·10⁻⁷ absolute (for |x| < ½ its
//! Maclaurin series instead, good to f32 rounding relative; tests below).
//! erfinv(y): M. Giles, "Approximating the erfinv function", GPU Computing Gems Jade Edition,
//! 2011, single-precision version: with w = −ln(1 − y²), a degree-8 polynomial in w − 2.5 for
//! w < 5 and in √w − 3 beyond, times y; relative error ≈ 3·10⁻⁷ (tests below).

use std::f32::consts::FRAC_2_SQRT_PI;

/// erfc(x) for x ≥ 0 (the fit's domain).
#[inline]
fn erfc_nonneg(x: f32) -> f32 {
    let t = 1.0 / (1.0 + 0.5 * x);
    let p = -1.265_512_2
        + t * (1.000_023_7
            + t * (0.374_091_96
                + t * (0.096_784_18
                    + t * (-0.186_288_06
                        + t * (0.278_868_07
                            + t * (-1.135_204 + t * (1.488_515_9 + t * (-0.822_152_23 + t * 0.170_872_77))))))));
    t * (p - x * x).exp()
}

/// The complementary error function 1 − erf(x).
#[inline]
pub fn erfc(x: f32) -> f32 {
    if x >= 0.0 {
        erfc_nonneg(x)
    } else {
        2.0 - erfc_nonneg(-x)
    }
}

/// The error function (2/√π) ∫₀ˣ exp(−t²) dt.
#[inline]
pub fn erf(x: f32) -> f32 {
    if x.abs() < 0.5 {
        // Its Maclaurin series, whose next term is below 4·10⁻¹⁰ here: 1 − erfc would lose
        // the relative accuracy of small values.
        let x2 = x * x;
        let s = 1.0
            + x2 * (-1.0 / 3.0
                + x2 * (1.0 / 10.0 + x2 * (-1.0 / 42.0 + x2 * (1.0 / 216.0 + x2 * (-1.0 / 1320.0 + x2 / 9360.0)))));
        return FRAC_2_SQRT_PI * x * s;
    }
    let e = 1.0 - erfc_nonneg(x.abs());
    e.copysign(x)
}

/// Largest f32 below 1: erfinv stays finite (|x| ≤ 3.9) for every input.
const ONE_MINUS_ULP: f32 = 1.0 - f32::EPSILON / 2.0;

/// The inverse error function, for y ∈ [−1, 1] (±1 give the value at 1 − 2⁻²⁴, ±3.9).
#[inline]
pub fn erfinv(y: f32) -> f32 {
    let y = y.clamp(-ONE_MINUS_ULP, ONE_MINUS_ULP);
    let w = -((1.0 - y) * (1.0 + y)).ln();
    let p = if w < 5.0 {
        let w = w - 2.5;
        let p = 2.810_226_4e-8;
        let p = 3.432_739_4e-7 + p * w;
        let p = -3.523_387_7e-6 + p * w;
        let p = -4.391_506_5e-6 + p * w;
        let p = 0.000_218_580_87 + p * w;
        let p = -0.001_253_725 + p * w;
        let p = -0.004_177_681_6 + p * w;
        let p = 0.246_640_73 + p * w;
        1.501_409_4 + p * w
    } else {
        let w = w.sqrt() - 3.0;
        let p = -0.000_200_214_26;
        let p = 0.000_100_950_56 + p * w;
        let p = 0.001_349_343_2 + p * w;
        let p = -0.003_673_428_4 + p * w;
        let p = 0.005_739_507_7 + p * w;
        let p = -0.007_622_461_3 + p * w;
        let p = 0.009_438_870_5 + p * w;
        let p = 1.001_674 + p * w;
        2.832_976_8 + p * w
    };
    p * y
}

#[cfg(test)]
mod tests {
    use super::*;
    use statrs::function::erf as reference;

    #[test]
    fn erfc_relative_error() {
        // The fit's 1.2e-7, the f32 rounding of Horner's rule in t (a few ε = 2⁻²⁴) and of the
        // exponent −x² + P, which grows as ε x² (measured: 6ε + 2ε x²; bound 8ε + 3ε x²).
        let mut worst = 0.0f64;
        for i in 0..=200_000 {
            let x = (-3.0 + 13.0 * i as f64 / 200_000.0) as f32;
            let want = reference::erfc(x as f64);
            if want < 1e-37 {
                continue;
            }
            let got = erfc(x) as f64;
            let rel = (got - want).abs() / want;
            let x = x as f64;
            let eps = f32::EPSILON as f64 / 2.0;
            let bound = 1.2e-7 + eps * (8.0 + 3.0 * x * x);
            assert!(rel <= bound, "erfc({x}) = {got} vs {want}: relative error {rel:.2e} > {bound:.2e}");
            worst = worst.max(rel / bound);
        }
        println!("erfc: worst error / bound = {worst:.3}");
    }

    #[test]
    fn erf_absolute_error() {
        let mut worst = 0.0f64;
        for i in 0..=20_000 {
            let x = -6.0 + 12.0 * i as f64 / 20_000.0;
            let err = (erf(x as f32) as f64 - reference::erf(x)).abs();
            worst = worst.max(err);
        }
        println!("erf: max absolute error {worst:.2e}");
        assert!(worst < 2e-7, "{worst}");
        assert_eq!(erf(0.0), 0.0);
        assert_eq!(erf(f32::INFINITY), 1.0);
        assert_eq!(erf(f32::NEG_INFINITY), -1.0);
    }

    #[test]
    fn erfinv_relative_error_and_range() {
        // Against the f64 inverse at the f32 inputs: the approximation's own error, away from 0
        // where both are exactly 0, and up to the last f32 below 1.
        let mut worst = 0.0f64;
        let mut check = |y: f32| {
            let want = reference::erf_inv(y as f64);
            let got = erfinv(y) as f64;
            let rel = (got - want).abs() / want.abs().max(1e-30);
            worst = worst.max(rel);
        };
        for i in 1..100_000 {
            check(i as f32 / 100_000.0);
            check(-(i as f32) / 100_000.0);
        }
        for k in 1..24 {
            check(1.0 - (0.5f32).powi(k));
        }
        check(ONE_MINUS_ULP);
        println!("erfinv: max relative error {worst:.2e}");
        assert!(worst < 5e-7, "{worst}");
        // The ends stay finite.
        for y in [-1.0f32, 1.0, 2.0, -2.0] {
            let x = erfinv(y);
            assert!(x.is_finite() && x.abs() < 4.0, "{y}: {x}");
        }
        assert_eq!(erfinv(0.0), 0.0);
    }

    #[test]
    fn erfinv_inverts_erf() {
        for i in -400..=400 {
            let x = i as f32 / 100.0;
            let back = erfinv(erf(x));
            // d erfinv / dy = (√π/2) e^{x²}: erf's 2e-7 absolute error, magnified.
            let tol = 3e-7 * 0.886_226_9 * (x * x).exp() + 1e-6 * x.abs();
            assert!((back - x).abs() <= tol, "{x}: {back} (tolerance {tol})");
        }
    }
}
