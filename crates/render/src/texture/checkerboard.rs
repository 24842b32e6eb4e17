//! Mitsuba 3's `checkerboard`: two textures alternating over the cells of the unit square,
//! after `to_uv`. With (u, v) = to_uv(uv) and the strict tests a = frac(u) > ½, b = frac(v) > ½,
//! `color0` is where a = b (so [0, ½]² holds color0) and `color1` elsewhere.
//!
//! Its one-number lookup (a real parameter, such as a roughness) is the other way round,
//! `color0` where a ≠ b: Mitsuba 3.9.1's `eval_1` swaps the colours, and a scene means what it
//! renders in Mitsuba.

use crate::floor::floor;
use crate::texture::{Texture, UvTransform};
use glam::Vec2;
use radiometry::Rgb;

/// A checkerboard of two textures.
#[derive(Clone, Debug)]
pub struct Checkerboard {
    /// The texture of the cells holding the origin.
    pub color0: Texture,
    /// The texture of the other cells.
    pub color1: Texture,
    /// The map applied to uv first.
    pub to_uv: UvTransform,
}

impl Checkerboard {
    /// True where `color0` shows.
    #[inline]
    fn even(&self, uv: Vec2) -> bool {
        let p = self.to_uv.apply(uv);
        let (a, b) = (p.x - floor(p.x) > 0.5, p.y - floor(p.y) > 0.5);
        a == b
    }

    /// The RGB value at `uv`.
    pub fn eval(&self, uv: Vec2) -> Rgb {
        if self.even(uv) {
            self.color0.eval(uv)
        } else {
            self.color1.eval(uv)
        }
    }

    /// The one-number value at `uv`, with Mitsuba's colours swapped (see the module doc).
    pub fn eval_1(&self, uv: Vec2) -> f32 {
        if self.even(uv) {
            self.color1.eval_1(uv)
        } else {
            self.color0.eval_1(uv)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Mat4, Vec3};

    #[test]
    fn cells_and_the_swapped_float_lookup_match_mitsuba() {
        // Mitsuba 3.9.1 defaults 0.4 / 0.2: (uv) → eval, eval_1.
        let c = Checkerboard {
            color0: Texture::Constant(Rgb::splat(0.4)),
            color1: Texture::Constant(Rgb::splat(0.2)),
            to_uv: UvTransform::IDENTITY,
        };
        let cases = [
            ((0.25, 0.25), 0.4, 0.2),
            ((0.75, 0.25), 0.2, 0.4),
            ((0.25, 0.75), 0.2, 0.4),
            ((0.75, 0.75), 0.4, 0.2),
            ((0.5, 0.5), 0.4, 0.2),
            ((0.5, 0.25), 0.4, 0.2),
            ((0.5000001, 0.25), 0.2, 0.4),
            ((0.0, 0.0), 0.4, 0.2),
            ((1.25, 0.25), 0.4, 0.2),
            ((-0.25, 0.25), 0.2, 0.4),
            ((-0.25, -0.25), 0.4, 0.2),
        ];
        for ((u, v), e, e1) in cases {
            let uv = Vec2::new(u, v);
            assert_eq!(c.eval(uv), Rgb::splat(e), "eval at {uv}");
            assert_eq!(c.eval_1(uv), e1, "eval_1 at {uv}");
        }
        let scaled = Checkerboard { to_uv: UvTransform::from_mat4(&Mat4::from_scale(Vec3::new(4.0, 4.0, 1.0))), ..c };
        assert_eq!(scaled.eval(Vec2::new(0.15, 0.05)), Rgb::splat(0.2));
    }
}
