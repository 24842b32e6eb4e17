//! The GGX (Trowbridge-Reitz) distribution of microfacet normals, anisotropic.
//!
//! D(h) = 1 / (π α_x α_y (h_x²/α_x² + h_y²/α_y² + h_z²)²) for h_z > 0, which is
//! 1 / (π α_x α_y cos⁴θ (1 + tan²θ (cos²φ/α_x² + sin²φ/α_y²))²) written without dividing by cos θ.
//! Smith: Λ(w) = (√(1 + α(w)² tan²θ) − 1) / 2 with α(w)² tan²θ = (w_x²α_x² + w_y²α_y²) / w_z².
//! Slopes: P22(x̃, ỹ) = 1 / (π (1 + x̃² + ỹ²)²) for α = 1, whose radial CDF 1 − 1/(1 + r²) inverts
//! to r² = u/(1 − u); other α by stretching the slopes.
//! Visible normals: sampled as in E. Heitz, "Sampling the GGX Distribution of Visible
//! Normals", JCGT 7(4), 2018: stretch wo to the α = 1 configuration, where the visible
//! normals are the projection of a uniform disk, half of it squashed by cos θo, onto the
//! hemisphere, then unstretch.
//! Sources: T. S. Trowbridge & K. P. Reitz, JOSA 65(5), 1975; B. Walter et al., "Microfacet
//! Models for Refraction through Rough Surfaces", EGSR 2007.

use super::{stretched_tan2, Ndf, MIN_ALPHA};
use radiometry::trig::sin_cos_pi;
use radiometry::{Vec2, Vec3};
use std::f32::consts::PI;

/// The anisotropic GGX distribution with roughnesses `alpha_x`, `alpha_y` along the tangents.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ggx {
    /// Roughness along the local x (tangent) axis.
    pub alpha_x: f32,
    /// Roughness along the local y (bitangent) axis.
    pub alpha_y: f32,
}

impl Ggx {
    /// A GGX distribution; roughnesses below `MIN_ALPHA` are raised to it (a mirror is a delta).
    pub fn new(alpha_x: f32, alpha_y: f32) -> Self {
        Ggx { alpha_x: alpha_x.max(MIN_ALPHA), alpha_y: alpha_y.max(MIN_ALPHA) }
    }
}

impl Ndf for Ggx {
    #[inline]
    fn d(&self, h: Vec3) -> f32 {
        if h.z <= 0.0 {
            return 0.0;
        }
        let (ax, ay) = (self.alpha_x, self.alpha_y);
        let s = (h.x / ax) * (h.x / ax) + (h.y / ay) * (h.y / ay) + h.z * h.z;
        1.0 / (PI * ax * ay * s * s)
    }

    #[inline]
    fn lambda(&self, w: Vec3) -> f32 {
        let t = stretched_tan2(w, self.alpha_x, self.alpha_y);
        if t.is_infinite() {
            return f32::INFINITY;
        }
        // t / (2(1 + √(1+t))) equals (√(1+t) − 1)/2 without its cancellation at small t.
        t / (2.0 * (1.0 + (1.0 + t).sqrt()))
    }

    #[inline]
    fn alphas(&self) -> (f32, f32) {
        (self.alpha_x, self.alpha_y)
    }

    fn sample_normal(&self, u: Vec2) -> Vec3 {
        let r2 = u.x / (1.0 - u.x).max(f32::MIN_POSITIVE);
        let r = r2.sqrt();
        let (s, c) = sin_cos_pi(2.0 * u.y);
        super::normal_from_slopes(r * c * self.alpha_x, r * s * self.alpha_y)
    }

    fn sample_visible(&self, wo: Vec3, u: Vec2) -> Vec3 {
        let (ax, ay) = (self.alpha_x, self.alpha_y);
        // In the stretched configuration the distribution is the α = 1 GGX, whose visible
        // normals are the unit hemisphere seen from v.
        let v = Vec3::new(ax * wo.x, ay * wo.y, wo.z).normalize();
        let len2 = v.x * v.x + v.y * v.y;
        let t1 = if len2 > 0.0 { Vec3::new(-v.y, v.x, 0.0) / len2.sqrt() } else { Vec3::X };
        let t2 = v.cross(t1);
        // A uniform point on the disk perpendicular to v ...
        let r = u.x.sqrt();
        let (sp, cp) = sin_cos_pi(2.0 * u.y);
        let p1 = r * cp;
        let mut p2 = r * sp;
        // ... whose far half is squashed by the hemisphere's projected outline, cos of v's angle.
        let s = 0.5 * (1.0 + v.z);
        p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * p2;
        // Lifted onto the hemisphere and unstretched.
        let nh = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * v;
        Vec3::new(ax * nh.x, ay * nh.y, nh.z.max(0.0)).normalize_or_zero()
    }
}
