//! The diffuse area light: a shape emitting constant radiance L from its front side (the
//! side its normal points to), like Mitsuba's `area` emitter.

use crate::light::{LightSample, RefPoint};
use crate::shape::Geometry;
use glam::{Vec2, Vec3};
use radiometry::Rgb;

/// Constant radiance on one shape of the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AreaLight {
    /// The shape's index in the scene.
    pub shape: usize,
    /// Emitted radiance, W/(m²·sr).
    pub radiance: Rgb,
}

impl AreaLight {
    /// Radiance leaving a point with normal `n` in direction `w` (unit, away from the surface).
    #[inline]
    pub fn emitted(&self, n: Vec3, w: Vec3) -> Rgb {
        if n.dot(w) > 0.0 {
            self.radiance
        } else {
            Rgb::ZERO
        }
    }

    /// A point on the shape seen from `r`.
    pub fn sample(&self, geometry: &Geometry, r: &RefPoint, uc: f32, u: Vec2) -> Option<LightSample> {
        let s = geometry.sample(r.p, uc, u)?;
        let delta = s.p - r.p;
        let dist = delta.length();
        let wi = delta / dist;
        let li = self.emitted(s.n, -wi);
        (!li.is_black() && dist > 0.0 && s.pdf > 0.0).then_some(LightSample {
            wi,
            dist,
            p: s.p,
            li,
            pdf: s.pdf,
            delta: false,
            shape: Some(self.shape),
        })
    }
}
