//! An orthonormal frame: world <-> local shading coordinates (z = normal).

use glam::Vec3;

/// An orthonormal basis whose `n` is the local +z axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Local +x (the tangent).
    pub s: Vec3,
    /// Local +y (the bitangent).
    pub t: Vec3,
    /// Local +z (the normal).
    pub n: Vec3,
}

impl Frame {
    /// The identity frame: local = world.
    pub const IDENTITY: Frame = Frame { s: Vec3::X, t: Vec3::Y, n: Vec3::Z };

    /// A frame around unit normal `n`, tangent chosen without branches on
    /// the normal's sign (Duff et al. 2017, "Building an orthonormal basis, revisited").
    pub fn from_normal(n: Vec3) -> Self {
        let sign = 1.0f32.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        let s = Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
        let t = Vec3::new(b, sign + n.y * n.y * a, -n.y);
        Frame { s, t, n }
    }

    /// A frame from a normal and a tangent hint (made orthogonal by Gram-Schmidt);
    /// falls back to `from_normal` when the hint is parallel to the normal.
    pub fn from_normal_tangent(n: Vec3, tangent: Vec3) -> Self {
        let s = tangent - n * n.dot(tangent);
        if s.length_squared() < 1e-12 {
            return Self::from_normal(n);
        }
        let s = s.normalize();
        Frame { s, t: n.cross(s), n }
    }

    /// World direction -> local coordinates.
    #[inline]
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.s), v.dot(self.t), v.dot(self.n))
    }

    /// Local coordinates -> world direction.
    #[inline]
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.s * v.x + self.t * v.y + self.n * v.z
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_orthonormal() {
        for n in [Vec3::Z, -Vec3::Z, Vec3::X, Vec3::new(0.3, -0.5, 0.81).normalize(), Vec3::new(0.0, 0.0, -1.0)] {
            let f = Frame::from_normal(n);
            assert!((f.s.length() - 1.0).abs() < 1e-5);
            assert!((f.t.length() - 1.0).abs() < 1e-5);
            assert!(f.s.dot(f.t).abs() < 1e-5 && f.s.dot(f.n).abs() < 1e-5 && f.t.dot(f.n).abs() < 1e-5);
            assert!((f.s.cross(f.t) - f.n).length() < 1e-5, "right-handed");
            let v = Vec3::new(0.2, 0.7, -0.1);
            assert!((f.to_world(f.to_local(v)) - v).length() < 1e-5);
            assert!((f.to_local(n) - Vec3::Z).length() < 1e-5);
        }
    }

    #[test]
    fn tangent_hint_is_kept() {
        let f = Frame::from_normal_tangent(Vec3::Z, Vec3::new(1.0, 0.0, 0.3));
        assert!((f.s - Vec3::X).length() < 1e-6);
        assert!((f.t - Vec3::Y).length() < 1e-6);
    }
}
