//! The isotropic point light: intensity I in W/sr, so the irradiance at distance r on a
//! surface tilted by θ is E = I cos θ / r² (inverse-square law).

use crate::light::{LightSample, RefPoint};
use glam::Vec3;
use radiometry::Rgb;

/// A point light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLight {
    /// Position.
    pub position: Vec3,
    /// Radiant intensity in W/sr per channel.
    pub intensity: Rgb,
}

impl PointLight {
    /// The one direction towards the light, with the incident radiance-equivalent I/r².
    pub fn sample(&self, r: &RefPoint) -> Option<LightSample> {
        let delta = self.position - r.p;
        let dist2 = delta.length_squared();
        if !dist2.is_finite() || dist2 <= 0.0 {
            return None;
        }
        let dist = dist2.sqrt();
        let li = self.intensity / dist2;
        li.is_finite().then_some(LightSample {
            wi: delta / dist,
            dist,
            p: self.position,
            li,
            pdf: 1.0,
            delta: true,
            shape: None,
        })
    }
}
