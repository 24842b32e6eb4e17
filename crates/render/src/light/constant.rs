//! A constant environment: radiance L from every direction. Seen from a surface, only the
//! hemisphere above its shading normal can reflect light (BRDFs reflect, not transmit), so
//! directions are drawn cosine-weighted about that normal; with no normal, uniformly.

use crate::light::{LightSample, RefPoint};
use glam::{Vec2, Vec3};
use radiometry::warp::{cosine_hemisphere, cosine_hemisphere_pdf, uniform_sphere, uniform_sphere_pdf};
use radiometry::{Frame, Rgb};

/// Constant radiance from the whole sphere of directions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConstantEnv {
    /// Radiance, W/(m²·sr).
    pub radiance: Rgb,
}

impl ConstantEnv {
    /// A direction towards the environment.
    pub fn sample(&self, r: &RefPoint, u: Vec2) -> Option<LightSample> {
        let (wi, pdf) = match r.n {
            Some(n) => {
                let w = cosine_hemisphere(u);
                (Frame::from_normal(n).to_world(w), cosine_hemisphere_pdf(w.z))
            }
            None => (uniform_sphere(u), uniform_sphere_pdf()),
        };
        (pdf > 0.0).then_some(LightSample {
            wi,
            dist: f32::INFINITY,
            p: r.p + wi,
            li: self.radiance,
            pdf,
            delta: false,
            shape: None,
        })
    }

    /// The density of `sample` for direction `wi`.
    pub fn pdf(&self, r: &RefPoint, wi: Vec3) -> f32 {
        match r.n {
            Some(n) => cosine_hemisphere_pdf(n.dot(wi)),
            None => uniform_sphere_pdf(),
        }
    }
}
