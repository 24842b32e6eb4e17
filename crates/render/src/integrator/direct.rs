//! Direct lighting (Mitsuba 3's `direct`): emitters seen directly, plus at the first surface
//! N_e light samples and N_b BRDF samples combined by the power heuristic with Veach's
//! sample-count weighting: a light sample of density p_l gets w = (f_e p_l)² / ((f_e p_l)² +
//! (f_b p_b)²) / N_e, f_e = N_e/(N_e + N_b), f_b = N_b/(N_e + N_b), and a BRDF sample the
//! converse over N_b. A BRDF sample counts only if it reaches an emitter (or the environment)
//! straight away, so a glass sphere shows its reflections and, through one refraction, what
//! glows behind it.
//!
//! Delta lights (point, spot, directional) are added once per light sample without the 1/N_e,
//! so `emitter_samples = 4` lights a surface four times as brightly as 1 does: that is what
//! Mitsuba 3.9.1 renders, and a scene means what it renders there.

use crate::integrator::path::{self, first_hit};
use crate::integrator::{finite, power_heuristic};
use crate::ray::{spawn_ray, Ray};
use crate::sampler::Sampler;
use crate::scene::{LightNumbers, Scene, ShadowTest, SurfaceInteraction};
use radiometry::Rgb;

/// The sample counts of the estimator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DirectSamples {
    /// Light samples per pixel sample.
    pub emitter: u32,
    /// BRDF samples per pixel sample.
    pub bsdf: u32,
}

/// The direct-lighting radiance estimate along `ray`.
pub fn li(scene: &Scene, ray: Ray, sampler: &mut Sampler, n: DirectSamples, hide_emitters: bool) -> Rgb {
    let first = first_hit(scene, ray, hide_emitters);
    let mut lit = Rgb::ZERO;
    let unlit = estimate(scene, ray, first, sampler, n, hide_emitters, &mut |test, c| {
        if scene.visible(test) {
            lit += c;
        }
    });
    finite(unlit + lit)
}

/// The estimate along camera ray `ray` whose first surface is `first`, its light samples'
/// shadow tests handed to `shadow` as [`path::trace`](super::path::trace) does.
pub fn estimate(
    scene: &Scene,
    ray: Ray,
    first: Option<SurfaceInteraction>,
    sampler: &mut Sampler,
    n: DirectSamples,
    hide_emitters: bool,
    shadow: &mut impl FnMut(ShadowTest, Rgb),
) -> Rgb {
    let mut result = Rgb::ZERO;
    let Some(si) = first else {
        if !hide_emitters {
            if let Some((le, _)) = scene.environment_eval(ray.d, None, false) {
                result += le;
            }
        }
        return result;
    };
    let wo_world = -ray.d;
    if !hide_emitters {
        if let Some((_, light)) = scene.area_light(si.shape) {
            result += light.emitted(si.frame.n, si.uv, wo_world);
        }
    }
    let wo = si.frame.to_local(wo_world);
    if !(wo.z != 0.0) {
        return result;
    }
    let total = (n.emitter + n.bsdf).max(1) as f32;
    let (frac_e, frac_b) = (n.emitter as f32 / total, n.bsdf as f32 / total);
    scene.material(si.shape).with(&si, |brdf| {
        if wo.z < 0.0 && !brdf.back_side() {
            return;
        }
        let transmits = brdf.transmits();
        let usable = |wi_z: f32| transmits || wi_z * wo.z > 0.0;
        let r = path::reference(&si, wo, transmits);
        for _ in 0..n.emitter {
            let numbers = LightNumbers::draw(sampler, scene);
            for ls in scene.sample_lights(&r, &numbers, n.bsdf > 0).iter().flatten() {
                let wi = si.frame.to_local(ls.wi);
                if !usable(wi.z) {
                    continue;
                }
                let (f, brdf_pdf) = brdf.eval_pdf(wi, wo);
                if f.is_black() {
                    continue;
                }
                let w =
                    if ls.delta { 1.0 } else { power_heuristic(ls.pdf * frac_e, brdf_pdf * frac_b) / n.emitter as f32 };
                shadow(scene.shadow_ray(si.p, si.ng, ls), f * ls.li * (wi.z.abs() * w / ls.pdf));
            }
        }
        for _ in 0..n.bsdf {
            let (uc, u) = (sampler.next_1d(), sampler.next_2d());
            let Some(bs) = brdf.sample(wo, uc, u) else { continue };
            if !usable(bs.wi.z) || !bs.weight.is_finite() {
                continue;
            }
            let d = si.frame.to_world(bs.wi);
            let next = spawn_ray(si.p, si.ng, d);
            let light_pdf = |pdf: f32| if bs.delta { 0.0 } else { pdf * frac_e };
            let w = |light: f32| power_heuristic(bs.pdf * frac_b, light_pdf(light)) / n.bsdf as f32;
            match scene.intersect(&next) {
                None => {
                    let from = (!bs.delta).then_some(&r);
                    if let Some((le, pdf)) = scene.environment_eval(d, from, true) {
                        result += bs.weight * le * w(pdf);
                    }
                }
                Some(hit) => {
                    let Some((index, light)) = scene.area_light(hit.shape) else { continue };
                    let le = light.emitted(hit.frame.n, hit.uv, -d);
                    if le.is_black() {
                        continue;
                    }
                    result += bs.weight * le * w(scene.light_pdf(index, &r, d, Some((hit.p, hit.ng)), true));
                }
            }
        }
    });
    result
}
