//! CIE 1931 colour matching, the D65 illuminant, and the reduction of a sampled spectrum to linear
//! sRGB (Rec.709 primaries) that Mitsuba 3's RGB variants apply to a `<spectrum>` given as
//! wavelength:value pairs or an `.spd` file.
//!
//! With the spectrum s(λ) interpolated linearly between its samples (and zero outside them), the
//! 5 nm tables below interpolated linearly, and w_i = 360 + 470 i/999 nm for i = 0..999:
//!
//!   XYZ = (470/1000) / 106.7502594 · Σ_i s(w_i) (x̄, ȳ, z̄)(w_i) · [D65(w_i)/98.9974175],   RGB = M · XYZ,
//!
//! M the XYZ → linear sRGB matrix. The normalisation is this same sum over ȳ, so that a unit
//! emission spectrum has luminance 1. The bracketed illuminant weights a reflectance (the colour a
//! white-lit surface shows; a unit reflectance comes out (0.99899, 0.99887, 0.99880), as in
//! Mitsuba) and an unbounded quantity such as a conductor's η, but not an emission spectrum.
//! A reflectance is clamped to [0, 1]; the rest only to ≥ 0.
//! Sources: CIE 15:2004, *Colorimetry*, Tables T.1 and T.4; Mitsuba 3, `src/core/spectrum.cpp`
//! (`spectrum_list_to_srgb`), for the sum rule and its constants.

/// CIE 1931 2° colour-matching functions, 360..=830 nm every 5 nm (CIE 15:2004 table).
#[rustfmt::skip]
pub const CIE_X: [f64; 95] = [
    0.0001299, 0.0002321, 0.0004149, 0.0007416, 0.001368, 0.002236, 0.004243, 0.00765, 0.01431, 0.02319, 0.04351,
    0.07763, 0.13438, 0.21477, 0.2839, 0.3285, 0.34828, 0.34806, 0.3362, 0.3187, 0.2908, 0.2511, 0.19536, 0.1421,
    0.09564, 0.05795001, 0.03201, 0.0147, 0.0049, 0.0024, 0.0093, 0.0291, 0.06327, 0.1096, 0.1655, 0.2257499,
    0.2904, 0.3597, 0.4334499, 0.5120501, 0.5945, 0.6784, 0.7621, 0.8425, 0.9163, 0.9786, 1.0263, 1.0567, 1.0622,
    1.0456, 1.0026, 0.9384, 0.8544499, 0.7514, 0.6424, 0.5419, 0.4479, 0.3608, 0.2835, 0.2187, 0.1649, 0.1212,
    0.0874, 0.0636, 0.04677, 0.0329, 0.0227, 0.01584, 0.01135916, 0.008110916, 0.005790346, 0.004109457,
    0.002899327, 0.00204919, 0.001439971, 0.0009999493, 0.0006900786, 0.0004760213, 0.0003323011, 0.0002348261,
    0.0001661505, 0.000117413, 0.00008307527, 0.00005870652, 0.00004150994, 0.00002935326, 0.00002067383,
    0.00001455977, 0.00001025398, 0.000007221456, 0.000005085868, 0.000003581652, 0.000002522525, 0.000001776509,
    0.000001251141,
];
#[rustfmt::skip]
pub const CIE_Y: [f64; 95] = [
    0.000003917, 0.000006965, 0.00001239, 0.00002202, 0.000039, 0.000064, 0.00012, 0.000217, 0.000396, 0.00064,
    0.00121, 0.00218, 0.004, 0.0073, 0.0116, 0.01684, 0.023, 0.0298, 0.038, 0.048, 0.06, 0.0739, 0.09098, 0.1126,
    0.13902, 0.1693, 0.20802, 0.2586, 0.323, 0.4073, 0.503, 0.6082, 0.71, 0.7932, 0.862, 0.9148501, 0.954, 0.9803,
    0.9949501, 1.0, 0.995, 0.9786, 0.952, 0.9154, 0.87, 0.8163, 0.757, 0.6949, 0.631, 0.5668, 0.503, 0.4412, 0.381,
    0.321, 0.265, 0.217, 0.175, 0.1382, 0.107, 0.0816, 0.061, 0.04458, 0.032, 0.0232, 0.017, 0.01192, 0.00821,
    0.005723, 0.004102, 0.002929, 0.002091, 0.001484, 0.001047, 0.00074, 0.00052, 0.0003611, 0.0002492, 0.0001719,
    0.00012, 0.0000848, 0.00006, 0.0000424, 0.00003, 0.0000212, 0.00001499, 0.0000106, 0.0000074657, 0.0000052578,
    0.0000037029, 0.0000026078, 0.0000018366, 0.0000012934, 0.00000091093, 0.00000064153, 0.00000045181,
];
#[rustfmt::skip]
pub const CIE_Z: [f64; 95] = [
    0.0006061, 0.001086, 0.001946, 0.003486, 0.006450001, 0.01054999, 0.02005001, 0.03621, 0.06785001, 0.1102,
    0.2074, 0.3713, 0.6456, 1.0390501, 1.3856, 1.62296, 1.74706, 1.7826, 1.77211, 1.7441, 1.6692, 1.5281, 1.28764,
    1.0419, 0.8129501, 0.6162, 0.46518, 0.3533, 0.272, 0.2123, 0.1582, 0.1117, 0.07824999, 0.05725001, 0.04216,
    0.02984, 0.0203, 0.0134, 0.008749999, 0.005749999, 0.0039, 0.002749999, 0.0021, 0.0018, 0.001650001, 0.0014,
    0.0011, 0.001, 0.0008, 0.0006, 0.00034, 0.00024, 0.00019, 0.0001, 0.00004999999, 0.00003, 0.00002, 0.00001, 0.0,
    0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
    0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
];

/// XYZ → linear sRGB (Rec.709 primaries, D65 white).
#[rustfmt::skip]
pub const XYZ_TO_SRGB: [[f64; 3]; 3] =
    [[3.240479, -1.537150, -0.498535], [-0.969256, 1.875991, 0.041556], [0.055648, -0.204043, 1.057311]];

/// The CIE standard illuminant D65, relative spectral power (100 at 560 nm), 360..=830 nm every
/// 5 nm (CIE 15:2004, Table T.1).
#[rustfmt::skip]
pub const D65: [f64; 95] = [
    46.6383, 49.3637, 52.0891, 51.0323, 49.9755, 52.3118, 54.6482, 68.7015, 82.7549, 87.1204, 91.486, 92.4589,
    93.4318, 90.057, 86.6823, 95.7736, 104.865, 110.936, 117.008, 117.41, 117.812, 116.336, 114.861, 115.392, 115.923,
    112.367, 108.811, 109.082, 109.354, 108.578, 107.802, 106.296, 104.79, 106.239, 107.689, 106.047, 104.405,
    104.225, 104.046, 102.023, 100.0, 98.1671, 96.3342, 96.0611, 95.788, 92.2368, 88.6856, 89.3459, 90.0062, 89.8026,
    89.5991, 88.6489, 87.6987, 85.4936, 83.2886, 83.4939, 83.6992, 81.863, 80.0268, 80.1207, 80.2146, 81.2462,
    82.2778, 80.281, 78.2842, 74.0027, 69.7213, 70.6652, 71.6091, 72.979, 74.349, 67.9765, 61.604, 65.7448, 69.8856,
    72.4863, 75.087, 69.3398, 63.5927, 55.0054, 46.4182, 56.6118, 66.8054, 65.0941, 63.3828, 63.8434, 64.304, 61.8779,
    59.4519, 55.7054, 51.959, 54.6998, 57.4406, 58.8765, 60.3125,
];

/// The wavelength range of the tables, nm.
pub const LAMBDA_MIN: f64 = 360.0;
/// The wavelength range of the tables, nm.
pub const LAMBDA_MAX: f64 = 830.0;

/// Σ ȳ(w_i) · 470/1000 over the sum's wavelengths: the luminance of a unit spectrum before
/// normalisation (Mitsuba's `MI_CIE_Y_NORMALIZATION` is its inverse).
const Y_INTEGRAL: f64 = 106.75025939941406;
/// D65 scaled so that Σ D65·ȳ matches Σ ȳ (Mitsuba's `MI_CIE_D65_NORMALIZATION` inverse).
const D65_SCALE: f64 = 98.99741751876255;
/// Samples of the sum.
const STEPS: usize = 1000;

/// What a spectrum describes, which decides its reduction to RGB.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SpectrumUse {
    /// A reflectance or transmittance: D65-weighted, clamped to [0, 1].
    Reflectance,
    /// An unbounded material constant (η, k): D65-weighted, clamped at 0.
    Unbounded,
    /// Emitted radiance or intensity: not weighted, clamped at 0.
    Emission,
}

/// Linear interpolation of a 5 nm table over 360..=830 nm; 0 outside.
fn table(t: &[f64; 95], lambda: f64) -> f64 {
    if !(LAMBDA_MIN..=LAMBDA_MAX).contains(&lambda) {
        return 0.0;
    }
    let x = (lambda - LAMBDA_MIN) * (94.0 / (LAMBDA_MAX - LAMBDA_MIN));
    let i = (x.floor() as usize).min(93);
    let f = x - i as f64;
    (1.0 - f) * t[i] + f * t[i + 1]
}

/// The CIE 1931 2° colour-matching functions (x̄, ȳ, z̄) at `lambda` nm (0 outside 360..=830).
pub fn xyz_bar(lambda: f64) -> [f64; 3] {
    [table(&CIE_X, lambda), table(&CIE_Y, lambda), table(&CIE_Z, lambda)]
}

/// XYZ to linear sRGB.
pub fn xyz_to_srgb(xyz: [f64; 3]) -> [f64; 3] {
    let m = XYZ_TO_SRGB;
    [0, 1, 2].map(|r| m[r][0] * xyz[0] + m[r][1] * xyz[1] + m[r][2] * xyz[2])
}

/// A spectrum sampled at strictly increasing `lambda` (nm), linearly interpolated between the
/// samples and zero outside them, reduced to linear sRGB for `usage` (see the module doc).
/// `lambda` and `values` have the same length, at least 2.
pub fn spectrum_to_srgb(lambda: &[f64], values: &[f64], usage: SpectrumUse) -> [f64; 3] {
    assert!(lambda.len() >= 2 && lambda.len() == values.len(), "a spectrum needs two or more (λ, value) pairs");
    let n = lambda.len();
    let mut xyz = [0.0f64; 3];
    for i in 0..STEPS {
        let w = LAMBDA_MIN + (i as f64 / (STEPS - 1) as f64) * (LAMBDA_MAX - LAMBDA_MIN);
        if w < lambda[0] || w > lambda[n - 1] {
            continue;
        }
        let k = lambda.partition_point(|&l| l <= w).clamp(1, n - 1) - 1;
        let v = ((w - lambda[k + 1]) * values[k] + (lambda[k] - w) * values[k + 1]) / (lambda[k] - lambda[k + 1]);
        let weight = if usage == SpectrumUse::Emission { 1.0 } else { table(&D65, w) / D65_SCALE };
        let cmf = xyz_bar(w);
        for c in 0..3 {
            xyz[c] += cmf[c] * v * weight;
        }
    }
    let scale = (LAMBDA_MAX - LAMBDA_MIN) / STEPS as f64 / Y_INTEGRAL;
    let rgb = xyz_to_srgb(xyz.map(|c| c * scale));
    match usage {
        SpectrumUse::Reflectance => rgb.map(|c| c.clamp(0.0, 1.0)),
        _ => rgb.map(|c| c.max(0.0)),
    }
}

/// A constant spectrum of value `v` as RGB for `usage`: a reflectance keeps v in every channel
/// (Mitsuba's `uniform`), emission becomes the colour of a flat spectrum, v · M·(1, 1, 1).
pub fn uniform_to_srgb(v: f64, usage: SpectrumUse) -> [f64; 3] {
    match usage {
        SpectrumUse::Emission => xyz_to_srgb([v; 3]),
        _ => [v; 3],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
        (0..3).all(|c| (a[c] - b[c]).abs() <= tol * b[c].abs().max(1e-3))
    }

    /// The Cornell box's white wall, 400..=700 nm every 4 nm (Mitsuba's `cbox.xml`).
    #[rustfmt::skip]
    const CBOX_WHITE: [f64; 76] = [
        0.343, 0.445, 0.551, 0.624, 0.665, 0.687, 0.708, 0.723, 0.715, 0.71, 0.745, 0.758, 0.739, 0.767, 0.777, 0.765,
        0.751, 0.745, 0.748, 0.729, 0.745, 0.757, 0.753, 0.75, 0.746, 0.747, 0.735, 0.732, 0.739, 0.734, 0.725, 0.721,
        0.733, 0.725, 0.732, 0.743, 0.744, 0.748, 0.728, 0.716, 0.733, 0.726, 0.713, 0.74, 0.754, 0.764, 0.752, 0.736,
        0.734, 0.741, 0.74, 0.732, 0.745, 0.755, 0.751, 0.744, 0.731, 0.733, 0.744, 0.731, 0.712, 0.708, 0.729, 0.73,
        0.727, 0.707, 0.703, 0.729, 0.75, 0.76, 0.751, 0.739, 0.724, 0.73, 0.74, 0.737,
    ];

    #[test]
    fn reductions_match_mitsuba_rgb_variants() {
        // Reference values: Mitsuba 3.9.1 scalar_rgb, a diffuse reflectance and an area emitter's
        // radiance given the same <spectrum value="λ:v, ...">.
        use SpectrumUse::*;
        let lambda: Vec<f64> = (0..76).map(|i| 400.0 + 4.0 * i as f64).collect();
        assert!(close(spectrum_to_srgb(&lambda, &CBOX_WHITE, Reflectance), [0.735013, 0.7356246, 0.7362643], 2e-6));
        assert!(close(spectrum_to_srgb(&lambda, &CBOX_WHITE, Emission), [0.8853053, 0.6990085, 0.666026], 2e-6));
        let light = ([400.0, 500.0, 600.0, 700.0], [0.0, 8.0, 15.6, 18.4]);
        assert!(close(spectrum_to_srgb(&light.0, &light.1, Emission), [20.71084, 10.85463, 2.771152], 2e-6));
        assert_eq!(spectrum_to_srgb(&light.0, &light.1, Reflectance), [1.0; 3], "clamped");
        // A flat unit reflectance is not quite white under this rule, in Mitsuba too.
        assert!(close(
            spectrum_to_srgb(&[360.0, 830.0], &[1.0, 1.0], Reflectance),
            [0.9989852, 0.9988737, 0.9988016],
            2e-6
        ));
        assert!(close(
            spectrum_to_srgb(&[300.0, 900.0], &[1.0, 1.0], Emission),
            [1.204884, 0.9482282, 0.9092668],
            2e-6
        ));
        assert!(close(
            spectrum_to_srgb(&[400.0, 700.0], &[0.2, 0.4], Reflectance),
            [0.3598981, 0.2952424, 0.2261902],
            2e-6
        ));
        assert!(close(
            spectrum_to_srgb(&[500.0, 550.0, 600.0], &[0.1, 0.9, 0.1], Emission),
            [0.06253558, 0.5648484, 0.0],
            2e-6
        ));
        // A narrow band is out of gamut: the negative channel is clamped.
        assert!(close(spectrum_to_srgb(&[550.0, 560.0], &[1.0, 1.0], Reflectance), [0.01247926, 0.1371984, 0.0], 2e-6));
        assert!(close(uniform_to_srgb(0.5, Emission), [0.602397, 0.4741455, 0.454458], 2e-6));
        assert_eq!(uniform_to_srgb(0.5, Reflectance), [0.5; 3]);
    }

    #[test]
    fn tables_are_interpolated_between_nodes() {
        assert_eq!(xyz_bar(555.0)[1], CIE_Y[39]);
        assert!((xyz_bar(557.5)[1] - 0.5 * (CIE_Y[39] + CIE_Y[40])).abs() < 1e-15);
        assert_eq!(xyz_bar(359.0), [0.0; 3]);
        assert_eq!(xyz_bar(830.0)[0], CIE_X[94]);
    }
}
