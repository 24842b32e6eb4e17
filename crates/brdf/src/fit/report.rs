//! The text of a fit: one model's parameters with their standard errors, and the ranked table
//! of `--all` (Ngan et al.'s per-material table).

use super::Fit;
use std::fmt::Write as _;

/// An RGB triple as `r,g,b` with `digits` decimals.
fn rgb(v: &[f64; 3], digits: usize) -> String {
    format!("{:.d$},{:.d$},{:.d$}", v[0], v[1], v[2], d = digits)
}

/// The parameters as `gonio` model options that rebuild the fitted model, e.g.
/// `ward --alpha 0.1 --ks 0.2,0.2,0.2 --diffuse 0.5,0.4,0.3`. GGX and Beckmann carry the constant
/// Fresnel k_s as `--reflectance` (clamped to its range [0, 1]); Cook-Torrance has no registry
/// parameter for it, so its options rebuild the lobe with F = 1 and `describe` prints k_s.
pub fn options(fit: &Fit) -> String {
    let mut s = fit.model.name().to_string();
    for (k, v) in fit.model.registry_shape_params(fit.shape) {
        let _ = write!(s, " --{k} {v}");
    }
    match fit.model {
        super::FitModel::Ward | super::FitModel::BlinnPhong => {
            let _ = write!(s, " --ks {}", rgb(&fit.ks, 5));
        }
        super::FitModel::Ggx | super::FitModel::Beckmann => {
            let _ = write!(s, " --reflectance {}", rgb(&fit.ks.map(|k| k.clamp(0.0, 1.0)), 5));
        }
        super::FitModel::CookTorrance => {}
    }
    let _ = write!(s, " --diffuse {}", rgb(&fit.diffuse, 5));
    s
}

/// A multi-line report of one fit.
pub fn describe(fit: &Fit) -> String {
    let e = &fit.std_err;
    let mut s = String::new();
    let _ = writeln!(s, "model        {}", fit.model.name());
    let _ = writeln!(s, "{:<12} {:.6} ± {:.2e}", fit.model.shape_name(), fit.shape, e[0]);
    let ks_doc = match fit.model {
        super::FitModel::Ward | super::FitModel::BlinnPhong => "ks",
        _ => "ks (=F)",
    };
    let _ = writeln!(s, "{:<12} {}  ± {:.1e},{:.1e},{:.1e}", ks_doc, rgb(&fit.ks, 5), e[4], e[5], e[6]);
    let _ = writeln!(s, "{:<12} {}  ± {:.1e},{:.1e},{:.1e}", "diffuse", rgb(&fit.diffuse, 5), e[1], e[2], e[3]);
    let _ = writeln!(
        s,
        "error        {:.5e} 1/sr (Ngan et al., ρ·cosθi RMS), relative {:.4}",
        fit.error, fit.relative_error
    );
    let _ = writeln!(
        s,
        "search       {} LM iterations{}",
        fit.iterations,
        if fit.converged { "" } else { " (best start did not meet a tolerance)" }
    );
    let _ = writeln!(s, "as options   {}", options(fit));
    s
}

/// The ranked table of several fits (best first as given).
pub fn table(fits: &[Fit]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:>4}  {:<22} {:>12} {:>9}  {:>10}  {:<20} {:<20}",
        "rank", "model", "error (1/sr)", "relative", "shape", "ks", "diffuse"
    );
    for (i, f) in fits.iter().enumerate() {
        let _ = writeln!(
            s,
            "{:>4}  {:<22} {:>12.5e} {:>9.4}  {:>4}={:<8.4} {:<20} {:<20}",
            i + 1,
            f.model.name(),
            f.error,
            f.relative_error,
            f.model.shape_name(),
            f.shape,
            rgb(&f.ks, 4),
            rgb(&f.diffuse, 4)
        );
    }
    s
}
