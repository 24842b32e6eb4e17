//! Rays and the offsets that keep a spawned ray from re-hitting the surface it leaves.

use glam::Vec3;

/// A ray `o + t·d` for t in (0, `t_max`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Origin.
    pub o: Vec3,
    /// Direction (unit length for camera and scattered rays).
    pub d: Vec3,
    /// The farthest distance of interest.
    pub t_max: f32,
}

impl Ray {
    /// A ray with no far limit.
    #[inline]
    pub fn new(o: Vec3, d: Vec3) -> Self {
        Ray { o, d, t_max: f32::INFINITY }
    }

    /// The point at distance `t`.
    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.o + self.d * t
    }
}

/// How far a spawned ray's origin is pushed off a surface at `p`: a relative bound
/// large enough to cover the f32 rounding of an intersection point (a few hundred ulps).
#[inline]
pub fn surface_epsilon(p: Vec3) -> f32 {
    2e-5 * (1.0 + p.abs().max_element())
}

/// The origin for a ray leaving a surface at `p` (geometric normal `ng`) along `d`:
/// pushed to the side of the surface that `d` points to.
#[inline]
pub fn offset_origin(p: Vec3, ng: Vec3, d: Vec3) -> Vec3 {
    let eps = surface_epsilon(p);
    if d.dot(ng) >= 0.0 {
        p + ng * eps
    } else {
        p - ng * eps
    }
}

/// A ray leaving the surface point `p` (geometric normal `ng`) along unit `d`.
#[inline]
pub fn spawn_ray(p: Vec3, ng: Vec3, d: Vec3) -> Ray {
    Ray::new(offset_origin(p, ng, d), d)
}

/// A shadow ray from surface point `p` towards `target`, stopping short of it; also returns
/// the unit direction and the distance from `p` to `target`.
#[inline]
pub fn spawn_ray_to(p: Vec3, ng: Vec3, target: Vec3) -> (Ray, Vec3, f32) {
    let delta = target - p;
    let dist = delta.length();
    let d = delta / dist.max(f32::MIN_POSITIVE);
    let o = offset_origin(p, ng, d);
    // Stop short of the target by both ends' epsilons: the target may lie on a surface too.
    let t_max = (target - o).length() - surface_epsilon(target) - surface_epsilon(p);
    (Ray { o, d, t_max: t_max.max(0.0) }, d, dist)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_go_to_the_side_of_the_direction() {
        let p = Vec3::new(1.0, 2.0, 3.0);
        let r = spawn_ray(p, Vec3::Z, Vec3::new(0.0, 0.6, 0.8));
        assert!(r.o.z > p.z);
        let r = spawn_ray(p, Vec3::Z, Vec3::new(0.0, 0.6, -0.8));
        assert!(r.o.z < p.z);
        let (s, d, dist) = spawn_ray_to(p, Vec3::Z, p + Vec3::new(0.0, 0.0, 5.0));
        assert!((dist - 5.0).abs() < 1e-6 && (d - Vec3::Z).length() < 1e-6);
        assert!(s.t_max < 5.0 && s.t_max > 4.99);
    }
}
