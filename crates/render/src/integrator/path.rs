//! Unidirectional path tracing with next-event estimation and multiple importance sampling
//! (Veach 1997, ch. 9; the loop follows Mitsuba 3's `path` integrator so that depths and
//! Russian roulette mean the same). At each surface vertex: one light sample (shadow ray)
//! and one BRDF sample, each weighted by the power heuristic against the other; emission
//! found by the BRDF sample gets its weight at the next vertex. Delta lights and delta
//! lobes take weight 1, since no other strategy can produce them.
//!
//! Sides. A one-sided model (most BRDFs) ends the path on its back face, as in Mitsuba. A model
//! with a back side (`twosided`) is handed the local directions as they are (wo.z < 0 on the
//! back) and mirrors them itself; one that transmits (`dielectric`, `roughdielectric`) may
//! send the path through the surface, where the continuation ray starts on the far side, and
//! its light samples are drawn over the whole sphere (no normal in the reference point).
//! Shading and geometric normals must agree on the side of every direction, else the
//! contribution is dropped (light would leak through the surface). Russian roulette judges
//! β η², η the product of the index ratios crossed, so that radiance brightened by entering
//! glass does not make a path look more valuable than its power (Mitsuba 3's `path`).

use crate::integrator::power_heuristic;
use crate::light::RefPoint;
use crate::ray::{spawn_ray, Ray};
use crate::sampler::Sampler;
use crate::scene::Scene;
use radiometry::Rgb;

/// What the previous vertex's BRDF sample needs for the MIS weight of emission found next.
struct Previous {
    r: RefPoint,
    pdf: f32,
    delta: bool,
}

/// The radiance estimate along `ray` with paths of at most `max_depth` vertices and
/// Russian roulette from `rr_depth` on.
pub fn li(scene: &Scene, mut ray: Ray, sampler: &mut Sampler, max_depth: u32, rr_depth: u32) -> Rgb {
    let mut result = Rgb::ZERO;
    let mut beta = Rgb::ONE;
    // Product of the index ratios crossed: β η² is the path's weight in power.
    let mut eta = 1.0f32;
    let mut depth = 0u32;
    // None for the camera ray: emission seen directly has weight 1.
    let mut prev: Option<Previous> = None;
    if max_depth == 0 {
        return result;
    }
    loop {
        let Some(si) = scene.intersect(&ray) else {
            // The light pdf only where a BRDF sample needs its MIS weight.
            let from = prev.as_ref().filter(|pv| !pv.delta);
            if let Some((le, pdf)) = scene.environment_eval(ray.d, from.map(|pv| &pv.r)) {
                let w = from.map_or(1.0, |pv| power_heuristic(pv.pdf, pdf));
                result += beta * le * w;
            }
            break;
        };
        let wo_world = -ray.d;
        if let Some((index, light)) = scene.area_light(si.shape) {
            let le = light.emitted(si.ng, wo_world);
            if !le.is_black() {
                let w = match &prev {
                    Some(pv) if !pv.delta => {
                        power_heuristic(pv.pdf, scene.light_pdf(index, &pv.r, ray.d, Some((si.p, si.ng))))
                    }
                    _ => 1.0,
                };
                result += beta * le * w;
            }
        }
        if depth.saturating_add(1) >= max_depth {
            break;
        }
        let brdf = scene.brdf(si.shape);
        let wo = si.frame.to_local(wo_world);
        // A direction is on a side only if both normals agree; a one-sided model scatters
        // nothing on its back.
        let side = wo_world.dot(si.ng);
        if wo.z * side <= 0.0 || wo.z.is_nan() || (wo.z < 0.0 && !brdf.back_side()) {
            break;
        }
        let transmits = brdf.transmits();
        // Where `wi` may lie: on wo's side, or anywhere for a model that transmits.
        let usable = |wi: f32, wi_ng: f32| wi * wi_ng > 0.0 && (transmits || wi * wo.z > 0.0);
        let n = if transmits { None } else { Some(si.frame.n * wo.z.signum()) };
        let r = RefPoint { p: si.p, n };

        // Next-event estimation.
        let (uc, uc2, u) = (sampler.next_1d(), sampler.next_1d(), sampler.next_2d());
        if let Some(ls) = scene.sample_light(&r, uc, uc2, u) {
            let wi = si.frame.to_local(ls.wi);
            if usable(wi.z, ls.wi.dot(si.ng)) {
                let (f, brdf_pdf) = brdf.eval_pdf(wi, wo);
                if !f.is_black() && scene.unoccluded(si.p, si.ng, &ls) {
                    let w = if ls.delta { 1.0 } else { power_heuristic(ls.pdf, brdf_pdf) };
                    result += beta * f * ls.li * (wi.z.abs() * w / ls.pdf);
                }
            }
        }

        // BRDF sampling: the direction the path continues in.
        let Some(bs) = brdf.sample(wo, sampler.next_1d(), sampler.next_2d()) else { break };
        let wi_world = si.frame.to_world(bs.wi);
        if !usable(bs.wi.z, wi_world.dot(si.ng)) || !bs.weight.is_finite() {
            break;
        }
        beta = beta * bs.weight;
        eta *= bs.eta;
        prev = Some(Previous { r, pdf: bs.pdf, delta: bs.delta });
        ray = spawn_ray(si.p, si.ng, wi_world);
        depth += 1;

        // Russian roulette: survive with q = min(max channel of β η², 0.95), reweight by 1/q.
        let q = (beta.max_channel() * eta * eta).min(0.95);
        if depth >= rr_depth {
            if sampler.next_1d() >= q {
                break;
            }
            beta = beta / q;
        }
        if beta.max_channel() <= 0.0 {
            break;
        }
    }
    // A path can only go non-finite through a model bug; drop it rather than poison a pixel.
    if result.is_finite() {
        result
    } else {
        Rgb::ZERO
    }
}
