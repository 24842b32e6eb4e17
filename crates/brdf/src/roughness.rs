//! Roughness parameters shared by the rough models: `alpha`, and `alpha_u`/`alpha_v` for
//! anisotropy, where 0 means "same as alpha" (Mitsuba 3's names and convention).

use crate::params::{ParamError, ParamSource, ParamSpec};

/// Smallest accepted roughness, Mitsuba 3's floor: a texture that reads 0 gives this, and a
/// rough surface that smooth renders as Mitsuba renders it (lobes stay resolvable by f32
/// directions, 6e-8 rad apart).
pub const ALPHA_MIN: f64 = 1e-4;

/// The `alpha`, `alpha_u`, `alpha_v` parameter descriptions, with `alpha`'s default and doc.
pub fn params(default_alpha: f64, alpha_doc: &'static str) -> Vec<ParamSpec> {
    vec![
        ParamSpec::float("alpha", ALPHA_MIN, 1.0, default_alpha, alpha_doc),
        ParamSpec::float("alpha_u", 0.0, 1.0, 0.0, "roughness α_x along the tangent; 0 means alpha"),
        ParamSpec::float("alpha_v", 0.0, 1.0, 0.0, "roughness α_y along the bitangent; 0 means alpha"),
    ]
}

/// The resolved (α_x, α_y); an anisotropic value between 0 and `ALPHA_MIN` is an error.
pub fn from_params(p: &dyn ParamSource) -> Result<(f32, f32), ParamError> {
    let axis = |name: &'static str| {
        let v = p.float(name);
        if v == 0.0 {
            Ok(p.float("alpha"))
        } else if (v as f64) < ALPHA_MIN {
            Err(ParamError::Inconsistent(format!(
                "parameter '{name}': {v} is neither 0 (use alpha) nor at least {ALPHA_MIN}"
            )))
        } else {
            Ok(v)
        }
    };
    Ok((axis("alpha_u")?, axis("alpha_v")?))
}
