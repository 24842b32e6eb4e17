//! The directional light (Mitsuba 3's `directional`): parallel light arriving from infinitely
//! far away along `direction`, carrying irradiance E (W/m²) on a surface facing it.

use crate::light::{LightSample, RefPoint};
use glam::Vec3;
use radiometry::Rgb;

/// A directional light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionalLight {
    /// Unit direction the light travels in (from the light into the scene).
    pub direction: Vec3,
    /// Irradiance on a surface perpendicular to `direction`, W/m² per channel.
    pub irradiance: Rgb,
}

impl DirectionalLight {
    /// The one direction towards the light (−direction), with E as its radiance-equivalent.
    pub fn sample(&self, r: &RefPoint) -> Option<LightSample> {
        let wi = -self.direction;
        Some(LightSample {
            wi,
            dist: f32::INFINITY,
            p: r.p + wi,
            li: self.irradiance,
            pdf: 1.0,
            delta: true,
            shape: None,
        })
    }
}
