//! The `tabulated` model: ρ(wi, wo) = a gonio-reflectometer table (see `tabulated` for the text
//! format), multilinearly interpolated on its θi × φi × θo × φo grid. Sampling draws from the
//! same per-θo piecewise-constant tables of ρ·cos θi mixed with cosine sampling as `merl`;
//! those tables assume isotropy, so for anisotropic data they are only a proposal (`pdf` and
//! `sample` still agree, and the cosine part reaches every direction).
//!
//! Claims nothing: a measured table need not be reciprocal, isotropic or energy conserving
//! (`check` measures all three).

use super::{open_filename, TableSampler, Tabulated};
use crate::model::{same_upper_hemisphere, Brdf, BrdfSample, Claims};
use crate::params::{ParamError, ParamSource, ParamSpec};
use crate::registry::ModelSpec;
use radiometry::{Rgb, Vec2, Vec3};
use std::sync::Arc;

/// A measured BRDF read from a tabulated text file.
#[derive(Clone, Debug)]
pub struct TabulatedBrdf {
    /// The measurements.
    pub table: Arc<Tabulated>,
    sampler: Arc<TableSampler>,
}

impl TabulatedBrdf {
    /// A model of `table`, its sampler built from the sum of the three channels.
    pub fn new(table: Tabulated) -> Self {
        let sampler = TableSampler::build(&|wi, wo| {
            let c = table.lookup(wi, wo);
            c.0[0] + c.0[1] + c.0[2]
        });
        TabulatedBrdf { table: Arc::new(table), sampler: Arc::new(sampler) }
    }
}

impl Brdf for TabulatedBrdf {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if !same_upper_hemisphere(wi, wo) {
            return Rgb::ZERO;
        }
        self.table.lookup(wi, wo)
    }

    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        self.sampler.pdf(wi, wo)
    }

    fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BrdfSample> {
        self.sampler.sample_brdf(self, wo, uc, u)
    }

    fn claims(&self) -> Claims {
        Claims { reciprocal: false, energy_conserving: false, isotropic: false }
    }
}

fn params() -> Vec<ParamSpec> {
    vec![ParamSpec::path(
        "filename",
        "the tabulated text file (θi, φi, θo, φo, r, g, b per line; `gonio measure` writes it)",
    )]
}

fn build(p: &dyn ParamSource) -> Result<Box<dyn Brdf>, ParamError> {
    let table = open_filename(p, "tabulated", "FILE.csv (a tabulated BRDF file)", "tabulated", Tabulated::read)?;
    Ok(Box::new(TabulatedBrdf::new(table)))
}

/// Registry entry.
pub const SPEC: ModelSpec = ModelSpec {
    name: "tabulated",
    summary: "measured BRDF from a tabulated gonio-reflectometer text file, interpolated",
    reference: "gonio's tabulated text format (`gonio measure MODEL -o FILE.csv` writes it)",
    params,
    build: crate::registry::boxed!(build),
    showcase: &[],
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::measured::tabulated::{uniform_phi, uniform_theta};

    #[test]
    fn reads_back_what_it_was_measured_from_and_samples_consistently() {
        let lambert = crate::build("lambert", &[("albedo", "0.6")]).unwrap();
        let t = Tabulated::from_brdf(&*lambert, uniform_theta(9), vec![0.0], uniform_theta(9), uniform_phi(12));
        let m = TabulatedBrdf::new(t);
        let (wi, wo) = (Vec3::new(0.3, 0.1, 0.948_683), Vec3::new(-0.5, 0.2, 0.842_615));
        let want = 0.6 / std::f32::consts::PI;
        assert!((m.eval(wi.normalize(), wo.normalize()).0[1] - want).abs() < 1e-5);
        let s = m.sample(wo.normalize(), 0.3, Vec2::new(0.4, 0.7)).unwrap();
        assert!((s.pdf - m.pdf(s.wi, wo.normalize())).abs() <= 1e-5 * s.pdf);
    }

    #[test]
    fn a_missing_file_is_an_error_naming_the_parameter() {
        let e = crate::build("tabulated", &[]).unwrap_err().to_string();
        assert!(e.contains("--filename"), "{e}");
        let e = crate::build("tabulated", &[("filename", "/nonexistent/x.csv")]).unwrap_err().to_string();
        assert!(e.contains("filename") && e.contains("x.csv"), "{e}");
    }
}
