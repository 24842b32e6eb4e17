//! The micro-surface gonio-reflectometer against theory: the synthesised surface has Gaussian
//! slopes of the requested RMS, mirror facets lose no energy, a Beckmann fit recovers the RMS
//! slope, and the measured table is reciprocal within its counting noise.

use brdf::fit::{fit, tabulated_samples, FitModel};
use brdf::lambert::Lambert;
use brdf::measured::heightfield::HeightField;
use brdf::measured::microsurface::{Beam, Facet, MeasureOptions, Microsurface};
use brdf::measured::tabulated::{uniform_phi, uniform_theta};
use radiometry::Rgb;
use statrs::distribution::{ChiSquared, ContinuousCDF};

/// Mean and standard error of the mean of independent replicates.
fn mean_se(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let m = x.iter().sum::<f64>() / n;
    let var = x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (n - 1.0);
    (m, (var / n).sqrt())
}

#[test]
fn the_height_field_has_gaussian_slopes_of_the_requested_rms() {
    let s = 0.3;
    // Statistics within one field are correlated over a few cells, so the standard errors come
    // from independent fields (seeds), not from the triangle count.
    let (mut ratio_x, mut inside, mut kurt) = (Vec::new(), Vec::new(), Vec::new());
    for seed in 0..8 {
        let f = HeightField::gaussian(128, 3.0, s, seed);
        assert!((f.rms_slope() - s).abs() < 1e-9, "scaled to the requested RMS slope");
        let sl = f.slopes();
        let n = sl.len() as f64;
        // Beckmann: each component has variance m²/2, and |slope|²/m² is Exp(1), so
        // P(|slope| < m) = 1 − 1/e and ⟨|slope|⁴⟩/m⁴ = 2.
        ratio_x.push(sl.iter().map(|v| v[0] * v[0]).sum::<f64>() / n / (s * s / 2.0));
        inside.push(sl.iter().filter(|v| v[0] * v[0] + v[1] * v[1] < s * s).count() as f64 / n);
        kurt.push(sl.iter().map(|v| (v[0] * v[0] + v[1] * v[1]).powi(2)).sum::<f64>() / n / s.powi(4));
    }
    for (name, x, expect) in
        [("<sx²>/(m²/2)", &ratio_x, 1.0), ("P(|s|<m)", &inside, 1.0 - (-1.0f64).exp()), ("<|s|⁴>/m⁴", &kurt, 2.0)]
    {
        let (m, se) = mean_se(x);
        eprintln!("{name}: {m:.4} ± {se:.4} (theory {expect:.4})");
        assert!((m - expect).abs() < 4.0 * se, "{name} = {m} ± {se}, expected {expect}");
    }
}

#[test]
fn mirror_facets_lose_no_energy() {
    let ms = Microsurface::gaussian(0.5, 128, 3.0, 11, Facet::Mirror);
    let opts = MeasureOptions { rays: 100_000, seed: 5, ..Default::default() };
    let thetas = vec![0.0, 30.0, 60.0, 80.0];
    let m = ms.measure(thetas.clone(), vec![0.0], uniform_theta(18), uniform_phi(36), &opts);
    for (t, b) in thetas.iter().zip(&m.balance) {
        eprintln!("θi {t}: {b:?}");
        // Every ray escapes but those the bounce limit or a numerical crack drops, which the
        // balance counts; a mirror reflects all, so nothing else may go missing.
        let total = b.escaped[0] + b.truncated[0] + b.lost[0];
        assert!((total - 1.0).abs() < 1e-9, "{total}");
        assert!(b.truncated[0] + b.lost[0] < 1e-4, "{b:?}");
        assert!(b.mean_bounces >= 1.0);
    }
    // The table holds the escaped flux outside the grazing ring: Σ ρ̂ Ω⊥ = escaped − unbinned,
    // with Ω⊥ = Δφ (sin²θ₁ − sin²θ₀)/2 of the cells centred on θ = 5°k, φ = 10°j.
    let s2 = |d: f64| d.to_radians().sin().powi(2);
    for (a, b) in m.balance.iter().enumerate() {
        let mut sum = 0.0;
        for k in 0..18 {
            let omega = 0.5 * (s2(5.0 * k as f64 + 2.5) - s2((5.0 * k as f64 - 2.5).max(0.0))) * 10f64.to_radians();
            for j in 0..36 {
                sum += m.table.values[(a * 18 + k) * 36 + j][0] as f64 * omega;
            }
        }
        assert!((sum - (b.escaped[0] - b.unbinned[0])).abs() < 1e-5, "{sum} vs {b:?}");
    }
}

#[test]
fn white_lambert_facets_reflect_everything_and_grey_ones_absorb() {
    let white = Microsurface::gaussian(0.5, 128, 3.0, 2, Facet::Model(Box::new(Lambert { albedo: Rgb::ONE })));
    let opts = MeasureOptions { rays: 50_000, seed: 9, ..Default::default() };
    let m = white.measure(vec![45.0], vec![0.0], uniform_theta(9), uniform_phi(12), &opts);
    let b = m.balance[0];
    eprintln!("white: {b:?}");
    assert!((b.escaped[0] - 1.0).abs() < 1e-4, "{b:?}");
    // Grey facets of albedo a: each ray's weight is a^hits, so the albedo E[a^hits] lies below a
    // (some rays hit twice or more) and above a^E[hits] (Jensen: a^h is convex in h).
    let grey = Microsurface::gaussian(0.5, 128, 3.0, 2, Facet::Model(Box::new(Lambert { albedo: Rgb::splat(0.5) })));
    let g = grey.measure(vec![45.0], vec![0.0], uniform_theta(9), uniform_phi(12), &opts).balance[0];
    eprintln!("grey: {g:?}");
    assert!(g.escaped[0] < 0.5 && g.escaped[0] > 0.5f64.powf(g.mean_bounces), "{g:?}");
}

#[test]
fn beckmann_fit_recovers_the_rms_slope() {
    for (s, seed) in [(0.2, 7), (0.3, 8)] {
        let ms = Microsurface::gaussian(s, 256, 4.0, seed, Facet::Mirror);
        let opts = MeasureOptions { rays: 300_000, seed: 3, ..Default::default() };
        let m = ms.measure(vec![0.0, 15.0, 30.0, 45.0], vec![0.0], uniform_theta(18), uniform_phi(72), &opts);
        let f = fit(FitModel::Beckmann, &tabulated_samples(&m.table));
        eprintln!(
            "s = {s}: fitted m = {:.4} ± {:.4}, k_s = {:.3}, diffuse = {:.3}, relative error {:.3}",
            f.shape, f.std_err[0], f.ks[0], f.diffuse[0], f.relative_error
        );
        assert!((f.shape - s).abs() < 0.1 * s, "fitted m = {} for RMS slope {s}", f.shape);
    }
}

#[test]
fn the_measured_table_is_reciprocal_within_its_noise() {
    // Incident light fills each grid cell (Beam::Bin), so entry (A, B) estimates
    // ∫_A∫_B ρ cos cos / (Ω⊥(A) Ω⊥(B)), symmetric in A and B for a reciprocal surface.
    let ms = Microsurface::gaussian(0.35, 128, 3.0, 4, Facet::Mirror);
    let (th, ph) = (uniform_theta(6), uniform_phi(8));
    let opts = MeasureOptions { rays: 150_000, seed: 21, beam: Beam::Bin, threads: 0 };
    let m = ms.measure(th.clone(), ph.clone(), th.clone(), ph.clone(), &opts);
    let nd = th.len() * ph.len();
    let (mut chi2, mut k, mut worst) = (0.0, 0usize, 0.0f64);
    for a in 0..nd {
        for b in a + 1..nd {
            let (e1, e2) = (a * nd + b, b * nd + a);
            let (v1, v2) = (m.table.values[e1][0] as f64, m.table.values[e2][0] as f64);
            let (s1, s2) = (m.std_err[e1][0] as f64, m.std_err[e2][0] as f64);
            // Only pairs with ≥ 25 rays in each entry (count = (ρ/σ)² for unit weights), where
            // the counts are near enough normal for a χ² test.
            if s1 <= 0.0 || s2 <= 0.0 || (v1 / s1).powi(2) < 25.0 || (v2 / s2).powi(2) < 25.0 {
                continue;
            }
            let z = (v1 - v2) / (s1 * s1 + s2 * s2).sqrt();
            chi2 += z * z;
            worst = worst.max(z.abs());
            k += 1;
        }
    }
    let crit = ChiSquared::new(k as f64).unwrap().inverse_cdf(0.999);
    eprintln!("reciprocity: χ² = {chi2:.1} over {k} pairs (0.999 quantile {crit:.1}), worst |z| = {worst:.2}");
    assert!(k > 100, "too few pairs with counts: {k}");
    assert!(chi2 < crit, "χ² = {chi2} over {k} pairs exceeds {crit}");
}

#[test]
fn the_result_does_not_depend_on_the_thread_count() {
    let ms = Microsurface::gaussian(0.3, 64, 2.0, 1, Facet::Model(Box::new(Lambert { albedo: Rgb::splat(0.7) })));
    let run = |threads| {
        let opts = MeasureOptions { rays: 40_000, seed: 2, beam: Beam::Collimated, threads };
        ms.measure(vec![20.0], vec![0.0], uniform_theta(6), uniform_phi(8), &opts).table
    };
    assert_eq!(run(1), run(3));
}
