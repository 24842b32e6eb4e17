//! The diffuse area light: a shape emitting radiance L(uv) from the side its shading normal
//! faces, like Mitsuba's `area` emitter (one-sided; `flip_normals` moves it to the other side).
//! The radiance may be a texture over the shape's uv.

use crate::light::{LightSample, RefPoint};
use crate::shape::Geometry;
use crate::texture::Texture;
use glam::{Vec2, Vec3};
use radiometry::Rgb;

/// Radiance over one shape of the scene.
#[derive(Clone, Debug)]
pub struct AreaLight {
    /// The shape's index in the scene.
    pub shape: usize,
    /// Emitted radiance, W/(m²·sr), over the shape's uv.
    pub radiance: Texture,
}

impl AreaLight {
    /// Radiance leaving a point with shading normal `n` and coordinates `uv` in direction `w`
    /// (unit, away from the surface).
    #[inline]
    pub fn emitted(&self, n: Vec3, uv: Vec2, w: Vec3) -> Rgb {
        if n.dot(w) > 0.0 {
            self.radiance.eval(uv)
        } else {
            Rgb::ZERO
        }
    }

    /// A point on the shape seen from `r`.
    pub fn sample(&self, geometry: &Geometry, r: &RefPoint, uc: f32, u: Vec2) -> Option<LightSample> {
        // Only a textured radiance reads the point's uv.
        let s = geometry.sample(r.p, uc, u, !matches!(self.radiance, Texture::Constant(_)))?;
        let delta = s.p - r.p;
        let dist = delta.length();
        let wi = delta / dist;
        let li = self.emitted(s.ns, s.uv, -wi);
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
