//! Smooth and rough dielectrics: Fresnel R + T = 1 in power, total internal reflection, and
//! the rough interface tending to the smooth one as α → 0.

use brdf::check::{albedo_integral, Integral};
use brdf::Brdf;
use radiometry::{spherical_direction, Vec2};

fn glass(name: &str, extra: &[(&str, &str)]) -> Box<dyn Brdf> {
    let mut p = vec![("int_ior", "1.5"), ("ext_ior", "1")];
    p.extend_from_slice(extra);
    brdf::build(name, &p).unwrap()
}

#[test]
fn fresnel_reflected_plus_transmitted_power_is_one() {
    let g = glass("dielectric", &[]);
    for deg in [0.0f32, 20.0, 41.0, 41.9, 42.0, 60.0, 89.0, 91.0, 120.0, 138.1, 139.0, 170.0, 180.0] {
        let wo = spherical_direction(deg.to_radians(), 0.7);
        let r = g.sample(wo, 0.0, Vec2::ZERO).unwrap();
        let t = g.sample(wo, 1.0 - f32::EPSILON, Vec2::ZERO).unwrap();
        // Probabilities F and 1 − F; power weights R_s = 1 and T_s η² / η² = 1.
        let power = |s: &brdf::BrdfSample| s.pdf * s.weight.0[1] * s.eta * s.eta;
        // Inside, beyond the critical angle asin(1/1.5) = 41.8°: total internal reflection.
        if wo.z < 0.0 && (180.0 - deg) > 41.82 {
            assert!(r.pdf == 1.0 && t.pdf == 1.0 && t.wi.z < 0.0 && t.eta == 1.0, "θ {deg}: {t:?}");
            continue;
        }
        assert!((r.pdf + t.pdf - 1.0).abs() < 1e-6, "θ {deg}: F + T = {}", r.pdf + t.pdf);
        assert!((power(&r) + power(&t) - 1.0).abs() < 1e-6, "θ {deg}");
    }
}

#[test]
fn rough_interface_tends_to_the_smooth_one() {
    // At α = 0.001 facets barely tilt: the power scattered (reflected + transmitted) is that of
    // the smooth interface, 1, less the light the facets shadow, which vanishes with α.
    let rough = glass("roughdielectric", &[("alpha", "0.001")]);
    for deg in [10.0f32, 50.0, 150.0, 170.0] {
        let wo = spherical_direction(deg.to_radians(), 0.3);
        let (m, se) = albedo_integral(rough.as_ref(), Integral::OverIncident, wo, 20_000, 7);
        assert!((m[1] - 1.0).abs() < 4.0 * se[1] + 1e-3, "θo {deg}: {} ± {}", m[1], se[1]);
        // Transmission is the smooth one: the mean refracted direction is Snell's.
        let s = rough.sample(wo, 0.999, Vec2::new(0.5, 0.5)).unwrap();
        let smooth = glass("dielectric", &[]).sample(wo, 0.999, Vec2::ZERO).unwrap();
        assert!(s.wi.dot(smooth.wi) > 0.999, "θo {deg}: {:?} vs {:?}", s.wi, smooth.wi);
        assert!(s.wi.z * wo.z < 0.0 && (s.eta - smooth.eta).abs() < 1e-6);
    }
}
