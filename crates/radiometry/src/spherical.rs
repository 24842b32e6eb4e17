//! Spherical coordinates (θ from +z, φ from +x towards +y) and solid angle.

use glam::Vec3;
use std::f64::consts::PI;

/// cos θ of a local direction.
#[inline]
pub fn cos_theta(w: Vec3) -> f32 {
    w.z
}

/// Polar angle θ in [0, π].
#[inline]
pub fn theta(w: Vec3) -> f32 {
    w.z.clamp(-1.0, 1.0).acos()
}

/// Azimuth φ in [0, 2π).
#[inline]
pub fn phi(w: Vec3) -> f32 {
    let p = w.y.atan2(w.x);
    if p < 0.0 {
        p + std::f32::consts::TAU
    } else {
        p
    }
}

/// The unit direction with polar angle `theta` and azimuth `phi`.
#[inline]
pub fn spherical_direction(theta: f32, phi: f32) -> Vec3 {
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    Vec3::new(st * cp, st * sp, ct)
}

/// Solid angle of the spherical cap of half-angle `alpha`: 2π(1 − cos α).
pub fn cap_solid_angle(alpha: f64) -> f64 {
    2.0 * PI * (1.0 - alpha.cos())
}

/// Solid angle of the patch θ ∈ [θ0, θ1], φ ∈ [φ0, φ1]: (cos θ0 − cos θ1)(φ1 − φ0).
pub fn patch_solid_angle(theta0: f64, theta1: f64, phi0: f64, phi1: f64) -> f64 {
    (theta0.cos() - theta1.cos()) * (phi1 - phi0)
}

/// Solid angle subtended by a small flat patch of `area` at `distance`, tilted by `cos_tilt`
/// against the line of sight: dω = A cos θ / r².
pub fn small_patch_solid_angle(area: f64, cos_tilt: f64, distance: f64) -> f64 {
    area * cos_tilt / (distance * distance)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angles_round_trip() {
        for &(t, p) in &[(0.3f32, 0.1f32), (1.2, 4.0), (2.9, 6.0), (0.7, 3.1)] {
            let w = spherical_direction(t, p);
            assert!((w.length() - 1.0).abs() < 1e-6);
            assert!((theta(w) - t).abs() < 1e-4);
            assert!((phi(w) - p).abs() < 1e-4);
        }
    }

    #[test]
    fn whole_sphere_is_four_pi() {
        assert!((patch_solid_angle(0.0, PI, 0.0, 2.0 * PI) - 4.0 * PI).abs() < 1e-12);
        assert!((cap_solid_angle(PI) - 4.0 * PI).abs() < 1e-12);
        assert!((cap_solid_angle(PI / 2.0) - 2.0 * PI).abs() < 1e-12);
    }
}
