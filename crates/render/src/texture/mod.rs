//! Textures: values that vary over a surface with its uv (Mitsuba 3's `bitmap` and
//! `checkerboard`), and constants. A texture gives an RGB value (`eval`) and, for real
//! parameters such as a roughness or an opacity, one number (`eval_1`): a bitmap's luminance
//! (or its one channel), a constant's channel mean, as Mitsuba's RGB variants read them.

pub mod bitmap;
pub mod checkerboard;

pub use bitmap::{decode, Bitmap, BitmapOptions, Decoded, FilterType, WrapMode};
pub use checkerboard::Checkerboard;

use glam::{Mat4, Vec2};
use radiometry::Rgb;
use std::sync::Arc;

/// Mitsuba's `to_uv`: an affine map of the plane, uv' = A·(u, v, 1), taken from a 4×4
/// transform's rows and columns 0, 1 and 3 (anything involving z is dropped).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvTransform {
    /// Rows of the 2×3 matrix.
    pub m: [[f32; 3]; 2],
}

impl UvTransform {
    /// The identity.
    pub const IDENTITY: UvTransform = UvTransform { m: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] };

    /// The uv map of a 4×4 transform.
    pub fn from_mat4(t: &Mat4) -> Self {
        let r = t.transpose(); // rows as columns
        let row = |i: usize| {
            let c = r.col(i);
            [c.x, c.y, c.w]
        };
        UvTransform { m: [row(0), row(1)] }
    }

    /// The transformed uv.
    #[inline]
    pub fn apply(&self, uv: Vec2) -> Vec2 {
        let [a, b] = self.m;
        Vec2::new(a[0] * uv.x + a[1] * uv.y + a[2], b[0] * uv.x + b[1] * uv.y + b[2])
    }

    /// True for the identity.
    #[inline]
    pub fn is_identity(&self) -> bool {
        *self == Self::IDENTITY
    }
}

/// A value over a surface.
#[derive(Clone, Debug)]
pub enum Texture {
    /// The same value everywhere.
    Constant(Rgb),
    /// An image.
    Bitmap(Arc<Bitmap>),
    /// Two textures in a checkerboard.
    Checkerboard(Arc<Checkerboard>),
}

impl Texture {
    /// Starts loading what a lookup at `uv` reads (an image's texels): a hint.
    #[inline]
    pub fn prefetch(&self, uv: Vec2) {
        if let Texture::Bitmap(b) = self {
            b.prefetch(uv);
        }
    }

    /// The RGB value at `uv`.
    #[inline]
    pub fn eval(&self, uv: Vec2) -> Rgb {
        match self {
            Texture::Constant(c) => *c,
            Texture::Bitmap(b) => b.eval(uv),
            Texture::Checkerboard(c) => c.eval(uv),
        }
    }

    /// The one-number value at `uv` (a real parameter's).
    #[inline]
    pub fn eval_1(&self, uv: Vec2) -> f32 {
        match self {
            Texture::Constant(c) => c.mean(),
            Texture::Bitmap(b) => b.eval_1(uv),
            Texture::Checkerboard(c) => c.eval_1(uv),
        }
    }

    /// The gradient of `eval_1` in uv (a bump map's height); None where a texture has none
    /// (a checkerboard), zero for constants and nearest-filtered bitmaps.
    pub fn eval_1_grad(&self, uv: Vec2) -> Option<Vec2> {
        match self {
            Texture::Constant(_) => Some(Vec2::ZERO),
            Texture::Bitmap(b) => Some(b.eval_1_grad(uv)),
            Texture::Checkerboard(_) => None,
        }
    }

    /// The mean of `eval` over the unit square of uv (the texture's value when the model is
    /// checked at load time).
    pub fn mean(&self) -> Rgb {
        match self {
            Texture::Constant(c) => *c,
            Texture::Bitmap(b) => b.mean(),
            Texture::Checkerboard(c) => (c.color0.mean() + c.color1.mean()) * 0.5,
        }
    }

    /// The smallest and largest channel values it can take, for range checks at load time.
    pub fn range(&self) -> (f32, f32) {
        match self {
            Texture::Constant(c) => (c.min_channel(), c.max_channel()),
            Texture::Bitmap(b) => b.range(),
            Texture::Checkerboard(c) => {
                let (a, b) = (c.color0.range(), c.color1.range());
                (a.0.min(b.0), a.1.max(b.1))
            }
        }
    }

    /// The value, when it is the same everywhere.
    pub fn constant(&self) -> Option<Rgb> {
        match self {
            Texture::Constant(c) => Some(*c),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn uv_transform_keeps_the_planar_part() {
        // Mitsuba: the rows and columns {0, 1, 3} of the 4×4; z terms are dropped.
        let m = Mat4::from_cols_array(&[1., 5., 9., 0., 2., 6., 10., 0., 3., 7., 11., 0., 4., 8., 12., 1.]);
        let t = UvTransform::from_mat4(&m);
        assert_eq!(t.m, [[1.0, 2.0, 4.0], [5.0, 6.0, 8.0]]);
        let s = UvTransform::from_mat4(&(Mat4::from_scale(Vec3::new(2.0, 3.0, 5.0)) * Mat4::from_translation(Vec3::Z)));
        assert_eq!(s.apply(Vec2::new(0.5, 0.25)), Vec2::new(1.0, 0.75));
        assert!(UvTransform::from_mat4(&Mat4::from_translation(Vec3::new(0.0, 0.0, 7.0))).is_identity());
    }
}
