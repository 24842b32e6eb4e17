//! Mitsuba 3's `null`: a surface light passes straight through (wi = −wo, weight 1), as if it
//! were not there; it bounds a medium or carries an area light without reflecting.
//! Source: Mitsuba 3, `src/bsdfs/null.cpp` (behaviour only).

use crate::model::{Brdf, BrdfSample, Claims};
use crate::params::{ParamError, ParamSource, ParamSpec};
use crate::registry::{by_value, ModelSpec};
use radiometry::{Rgb, Vec2, Vec3};

/// The invisible surface.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Null;

impl Brdf for Null {
    fn eval(&self, _wi: Vec3, _wo: Vec3) -> Rgb {
        Rgb::ZERO
    }

    fn pdf(&self, _wi: Vec3, _wo: Vec3) -> f32 {
        0.0
    }

    fn sample(&self, wo: Vec3, _uc: f32, _u: Vec2) -> Option<BrdfSample> {
        (wo.z != 0.0).then_some(BrdfSample { wi: -wo, pdf: 1.0, weight: Rgb::ONE, delta: true, eta: 1.0 })
    }

    fn claims(&self) -> Claims {
        Claims::PLAUSIBLE
    }

    fn has_delta(&self) -> bool {
        true
    }

    fn delta_only(&self) -> bool {
        true
    }

    fn transmits(&self) -> bool {
        true
    }
}

fn params() -> Vec<ParamSpec> {
    Vec::new()
}

fn make(_p: &dyn ParamSource) -> Result<Null, ParamError> {
    Ok(Null)
}

/// Registry entry.
pub const SPEC: ModelSpec = ModelSpec {
    name: "null",
    summary: "Mitsuba's null: light passes straight through (a medium's boundary, a bare emitter)",
    reference: "Mitsuba 3 null",
    params,
    build: by_value!(make),
    showcase: &[],
};
