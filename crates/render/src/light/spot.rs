//! The spot light (Mitsuba 3's `spot`): a point light at the origin of its `to_world` frame
//! shining along local +z with intensity I(θ) = I₀·s(θ)·T(uv), where θ is the angle from the
//! axis and s = 1 inside `beam_width`, 0 beyond `cutoff_angle`, and falls linearly in θ
//! between. An optional texture T is projected over the cone: a local direction (x, y, z)
//! reads uv = (½ + ½ (x/z)/tan(cutoff), ½ + ½ (y/z)/tan(cutoff)), Mitsuba's projection.

use crate::light::{LightSample, PointLight, RefPoint};
use crate::texture::Texture;
use glam::{Mat3, Vec2, Vec3};
use radiometry::Rgb;

/// A spot light.
#[derive(Clone, Debug)]
pub struct SpotLight {
    /// Position.
    pub position: Vec3,
    /// Unit axis the light shines along.
    pub axis: Vec3,
    /// Intensity on the axis, W/sr per channel.
    pub intensity: Rgb,
    /// Half-angle beyond which nothing is emitted, radians.
    pub cutoff: f32,
    /// Half-angle within which the full intensity is emitted, radians (≤ cutoff).
    pub beam_width: f32,
    /// A texture projected over the cone, and the light's frame (world → local).
    pub texture: Option<(Texture, Mat3)>,
}

impl SpotLight {
    /// The falloff s(θ) ∈ [0, 1] for a unit direction `d` leaving the light.
    pub fn falloff(&self, d: Vec3) -> f32 {
        let theta = d.dot(self.axis).clamp(-1.0, 1.0).acos();
        if theta >= self.cutoff {
            0.0
        } else if theta <= self.beam_width {
            1.0
        } else {
            // beam_width < θ < cutoff here, so the width is > 0.
            ((self.cutoff - theta) / (self.cutoff - self.beam_width)).clamp(0.0, 1.0)
        }
    }

    /// The one direction towards the light, with the incident radiance-equivalent I(θ)/r².
    pub fn sample(&self, r: &RefPoint) -> Option<LightSample> {
        let mut sample = PointLight { position: self.position, intensity: self.intensity }.sample(r)?;
        let s = self.falloff(-sample.wi);
        if s <= 0.0 {
            return None;
        }
        sample.li *= s;
        if let Some((t, to_local)) = &self.texture {
            let d = *to_local * -sample.wi;
            let k = 0.5 / self.cutoff.tan();
            sample.li = sample.li * t.eval(Vec2::new(0.5 + k * d.x / d.z, 0.5 + k * d.y / d.z));
        }
        Some(sample)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn falloff_and_inverse_square() {
        let l = SpotLight {
            position: Vec3::new(0.0, 2.0, 0.0),
            axis: -Vec3::Y,
            intensity: Rgb::splat(8.0),
            cutoff: 30f32.to_radians(),
            beam_width: 20f32.to_radians(),
            texture: None,
        };
        let below = l.sample(&RefPoint { p: Vec3::ZERO, n: Some(Vec3::Y) }).unwrap();
        assert!(below.delta && below.wi == Vec3::Y && below.li == Rgb::splat(2.0));
        // 25° off the axis: halfway through the transition.
        let t = 25f32.to_radians();
        assert!((l.falloff(Vec3::new(t.sin(), -t.cos(), 0.0)) - 0.5).abs() < 1e-5);
        let t = 31f32.to_radians();
        let outside = Vec3::new(2.0 * t.tan(), 0.0, 0.0);
        assert!(l.sample(&RefPoint { p: outside, n: None }).is_none());
        assert_eq!(l.falloff(Vec3::Y), 0.0);
    }
}
