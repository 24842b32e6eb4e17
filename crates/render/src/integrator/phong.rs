//! The lecture's Phong illumination model (Phong 1975), evaluated at the first surface a
//! camera ray meets:
//!
//!   L = k_a L_a + Σ_l L_l [k_d (I·N) + k_s (R·V)^k_e]
//!
//! with I the unit direction to point light l, N the shading normal, R = 2(I·N)N − I the
//! mirror direction of I, V the unit direction to the viewer, L_l = I_l/r² the light's
//! intensity over the squared distance, and L_a the radiance of a constant environment
//! (zero when the scene has none). Blinn's variant replaces (R·V) by (N·H), H = (I+V)/|I+V|.
//! Only point lights contribute to the sum; area lights and environment maps are ignored, as
//! the model knows of neither. Dot products are clamped at zero.
//!
//! Coefficients come from the shape's model (`Brdf::phong_terms`): `lambert` a: k_d = a/π, k_a = a;
//! `phong`/`blinn-phong` k_s, k_e and their `diffuse` a as Lambert. k_a = a is the choice that
//! makes the ambient term exact for an unshadowed Lambert surface under a constant environment
//! (L = a L_a). For a shape with any other model, the term in brackets is the model's own
//! ρ(I, V) (I·N) and k_a = π ρ(N, V), exact for Lambert again.
//!
//! Source: B. T. Phong, "Illumination for Computer Generated Pictures", CACM 18(6), 1975;
//! J. F. Blinn, "Models of light reflection for computer synthesized pictures", SIGGRAPH 1977.

use crate::light::{Light, RefPoint};
use crate::ray::Ray;
use crate::scene::Scene;
use brdf::PhongTerms;
use glam::Vec3;
use radiometry::Rgb;
use std::f32::consts::PI;

/// The bracketed term k_d (I·N) + k_s (R·V)^k_e of coefficients `k`, for unit `n`,
/// `to_light`, `to_viewer`.
#[inline]
pub fn reflect(k: &PhongTerms, n: Vec3, to_light: Vec3, to_viewer: Vec3) -> Rgb {
    let cos_i = n.dot(to_light);
    if cos_i <= 0.0 || n.dot(to_viewer) <= 0.0 {
        return Rgb::ZERO;
    }
    let c = if k.half_vector {
        (to_light + to_viewer).try_normalize().map_or(0.0, |h| n.dot(h))
    } else {
        (2.0 * cos_i * n - to_light).dot(to_viewer)
    };
    // 0^0 is 1 in powf; a lobe with k_e = 0 is then constant over the hemisphere, as it should be.
    let spec = if c > 0.0 { c.min(1.0).powf(k.ke) } else { 0.0 };
    k.kd * cos_i + k.ks * spec
}

/// The Phong radiance along `ray`: the environment where it escapes, the model at the first
/// surface otherwise (plus that surface's emission); `shadows` tests each light's visibility.
pub fn li(scene: &Scene, ray: Ray, shadows: bool) -> Rgb {
    let Some(si) = scene.intersect(&ray) else {
        return scene.environment().map_or(Rgb::ZERO, |(_, env)| env.environment_radiance(ray.d));
    };
    let v = -ray.d;
    let mut result = Rgb::ZERO;
    if let Some((_, area)) = scene.area_light(si.shape) {
        result += area.emitted(si.frame.n, si.uv, v);
    }
    scene.material(si.shape).with(&si, |brdf| {
        let coefficients = brdf.phong_terms();
        // One-sided surfaces, as in the path tracer; a two-sided model is lit on the side seen,
        // with the normals turned to face the viewer. A transmitting model shows its reflection
        // only: the lecture's model knows no refraction.
        let (n, ng) =
            if si.frame.n.dot(v) < 0.0 && brdf.back_side() { (-si.frame.n, -si.ng) } else { (si.frame.n, si.ng) };
        if n.dot(v) <= 0.0 {
            return;
        }
        let wo = si.frame.to_local(v);
        let normal = Vec3::Z * wo.z.signum();
        if let Some((_, Light::Constant(c))) = scene.environment() {
            let ka = match &coefficients {
                Some(k) => k.ka,
                None => brdf.eval(normal, wo) * PI,
            };
            result += ka * c.radiance;
        }
        let r = RefPoint { p: si.p, n: Some(n) };
        for light in scene.lights() {
            let Light::Point(pl) = light else { continue };
            let Some(ls) = pl.sample(&r) else { continue };
            let term = match &coefficients {
                Some(k) => reflect(k, n, ls.wi, v),
                None => {
                    let wi = si.frame.to_local(ls.wi);
                    if wi.z * wo.z <= 0.0 {
                        continue;
                    }
                    brdf.eval(wi, wo) * wi.z.abs()
                }
            };
            if term.is_black() || (shadows && !scene.unoccluded(si.p, ng, &ls)) {
                continue;
            }
            result += ls.li * term;
        }
    });
    if result.is_finite() {
        result
    } else {
        Rgb::ZERO
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{look_at, Camera, FovAxis};
    use crate::light::{ConstantEnv, PointLight};
    use crate::scene::SceneBuilder;
    use crate::shape::{Geometry, Rectangle};
    use glam::Mat4;

    /// A 20×20 floor in the y = 0 plane, normal +y, with model `name`, a point light of
    /// intensity `intensity` at `light`, and optionally a constant environment.
    fn floor_scene(name: &str, params: &[(&str, &str)], light: Vec3, intensity: f32, ambient: Option<f32>) -> Scene {
        let cam = Camera::new(look_at(Vec3::new(0., 5., 5.), Vec3::ZERO, Vec3::Y).unwrap(), 40.0, FovAxis::X, 8, 8);
        let mut b = SceneBuilder::new(cam);
        // Local +z → world +y: rotate −90° about x, then scale the unit square by 10.
        let m = Mat4::from_rotation_x(-std::f32::consts::FRAC_PI_2) * Mat4::from_scale(Vec3::splat(10.0));
        let rect = Rectangle::new(&m).unwrap();
        assert!((rect.n - Vec3::Y).length() < 1e-6);
        b.shape_with_model(Geometry::Rectangle(rect), name, params).unwrap();
        b.light(Light::Point(PointLight { position: light, intensity: Rgb::splat(intensity) }));
        if let Some(la) = ambient {
            b.light(Light::Constant(ConstantEnv { radiance: Rgb::splat(la) }));
        }
        b.build().unwrap()
    }

    /// The radiance seen at floor point `p` from `eye`.
    fn seen(scene: &Scene, eye: Vec3, p: Vec3) -> Rgb {
        li(scene, Ray::new(eye, (p - eye).normalize()), true)
    }

    #[test]
    fn lambert_plane_under_a_point_light_is_the_closed_form() {
        let light = Vec3::new(0.0, 2.0, 0.0);
        let (intensity, albedo, la) = (5.0f32, 0.6f32, 0.25f32);
        let scene = floor_scene("lambert", &[("albedo", "0.6")], light, intensity, Some(la));
        let eye = Vec3::new(3.0, 4.0, 1.0);
        for x in [0.0f32, 0.5, 1.5, 3.0] {
            let p = Vec3::new(x, 0.0, -0.3 * x);
            let d2 = (light - p).length_squared();
            let cos = (light - p).normalize().y;
            // L = k_a L_a + I/r² · (a/π) cos θ.
            let expected = albedo * la + intensity / d2 * albedo / PI * cos;
            let got = seen(&scene, eye, p);
            for c in got.0 {
                assert!((c - expected).abs() <= 1e-5 * expected, "x = {x}: {c} vs {expected}");
            }
        }
    }

    #[test]
    fn phong_highlight_peaks_at_the_mirror_direction() {
        let light = Vec3::new(-1.0, 2.0, 0.0);
        let (ks, ke, a) = (0.7f32, 50.0f32, 0.2f32);
        let scene = floor_scene("phong", &[("ks", "0.7"), ("ke", "50"), ("diffuse", "0.2")], light, 4.0, None);
        let p = Vec3::new(0.5, 0.0, 0.0);
        let to_light = (light - p).normalize();
        let ll = 4.0 / (light - p).length_squared();
        let mirror = Vec3::new(-to_light.x, to_light.y, -to_light.z);
        let diffuse = ll * a / PI * to_light.y;
        // At the mirror direction R·V = 1: the full k_s is added.
        let at_mirror = seen(&scene, p + 3.0 * mirror, p).0[0];
        assert!((at_mirror - (diffuse + ll * ks)).abs() < 1e-4 * at_mirror, "{at_mirror}");
        // 10° off the mirror direction (rotated about the z axis): cos^k_e 10°.
        let off = glam::Quat::from_rotation_z(10f32.to_radians()) * mirror;
        let expected = diffuse + ll * ks * (off.dot(mirror)).powf(ke);
        let got = seen(&scene, p + 3.0 * off, p).0[0];
        assert!((got - expected).abs() < 1e-4 * expected, "{got} vs {expected}");
        assert!(got < at_mirror);
    }

    #[test]
    fn shadows_and_lights_below_the_surface_give_black() {
        let scene = floor_scene("lambert", &[], Vec3::new(0.0, -1.0, 0.0), 5.0, None);
        assert_eq!(seen(&scene, Vec3::new(0.0, 3.0, 1.0), Vec3::ZERO), Rgb::ZERO);
        // A light above, hidden by a sphere in between.
        let cam = Camera::new(look_at(Vec3::new(0., 5., 5.), Vec3::ZERO, Vec3::Y).unwrap(), 40.0, FovAxis::X, 8, 8);
        let mut b = SceneBuilder::new(cam);
        let m = Mat4::from_rotation_x(-std::f32::consts::FRAC_PI_2) * Mat4::from_scale(Vec3::splat(10.0));
        b.shape_with_model(Geometry::Rectangle(Rectangle::new(&m).unwrap()), "lambert", &[]).unwrap();
        let ball = crate::shape::Sphere::new(Vec3::new(0.0, 1.0, 0.0), 0.3);
        b.shape_with_model(Geometry::Sphere(ball), "lambert", &[]).unwrap();
        b.light(Light::Point(PointLight { position: Vec3::new(0.0, 2.0, 0.0), intensity: Rgb::ONE }));
        let scene = b.build().unwrap();
        let ray = Ray::new(Vec3::new(2.0, 3.0, 0.0), (Vec3::ZERO - Vec3::new(2.0, 3.0, 0.0)).normalize());
        assert_eq!(li(&scene, ray, true), Rgb::ZERO);
        assert!(li(&scene, ray, false).0[0] > 0.0);
    }

    #[test]
    fn coefficients_from_models() {
        let k = brdf::build("lambert", &[("albedo", "0.5")]).unwrap().phong_terms().unwrap();
        assert!((k.kd.0[0] - 0.5 / PI).abs() < 1e-7 && k.ka.0[0] == 0.5 && k.ks.is_black());
        let k = brdf::build("blinn-phong", &[("ks", "0.3"), ("ke", "8")]).unwrap().phong_terms().unwrap();
        assert!(k.half_vector && k.ke == 8.0 && k.ks.0[1] == 0.3 && k.kd.is_black());
        let k = brdf::build("phong", &[("ks", "0.3"), ("diffuse", "0.2")]).unwrap().phong_terms().unwrap();
        assert!(!k.half_vector && (k.kd.0[0] - 0.2 / PI).abs() < 1e-7 && k.ka.0[2] == 0.2);
        assert!(brdf::build("ggx", &[]).unwrap().phong_terms().is_none());
    }
}
