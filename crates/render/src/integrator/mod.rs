//! Integrators: estimators of the radiance arriving along a camera ray.

pub mod direct;
mod packet;
pub mod path;
pub mod phong;
mod wide;

use crate::ray::Ray;
use crate::sampler::Sampler;
use crate::scene::Scene;
use radiometry::Rgb;

/// Which estimator to run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Integrator {
    /// Unidirectional path tracing (Mitsuba's `path`). `max_depth` counts path vertices
    /// (1: emitters seen directly, 2: direct lighting; `u32::MAX`: unbounded); Russian
    /// roulette starts once `rr_depth` vertices exist.
    Path {
        /// The longest path, in vertices.
        max_depth: u32,
        /// The depth from which Russian roulette may end paths.
        rr_depth: u32,
        /// The camera sees through area lights and does not see the environment.
        hide_emitters: bool,
    },
    /// Direct lighting only: emitters seen directly plus light and BRDF samples combined by
    /// MIS at the first surface (Mitsuba's `direct`).
    Direct {
        /// Light and BRDF samples per camera sample.
        samples: direct::DirectSamples,
        /// The camera sees through area lights and does not see the environment.
        hide_emitters: bool,
    },
    /// The lecture's Phong illumination model, L = k_a L_a + Σ_l L_l [k_d (I·N) + k_s (R·V)^k_e],
    /// with point lights only and L_a the constant environment's radiance (see [`phong`]).
    Phong {
        /// Trace a shadow ray to each light (the 1975 model has none).
        shadows: bool,
    },
}

impl Default for Integrator {
    /// Mitsuba's defaults for `path`: unbounded depth, roulette from depth 5.
    fn default() -> Self {
        Integrator::path(u32::MAX, 5)
    }
}

impl Integrator {
    /// Mitsuba's `path` with `max_depth` and `rr_depth`, emitters shown.
    pub const fn path(max_depth: u32, rr_depth: u32) -> Integrator {
        Integrator::Path { max_depth, rr_depth, hide_emitters: false }
    }

    /// Mitsuba's `direct` with its defaults: one light and one BRDF sample.
    pub const DIRECT: Integrator =
        Integrator::Direct { samples: direct::DirectSamples { emitter: 1, bsdf: 1 }, hide_emitters: false };

    /// The radiance estimate along `ray`.
    #[inline]
    pub fn li(&self, scene: &Scene, ray: Ray, sampler: &mut Sampler) -> Rgb {
        match *self {
            Integrator::Path { max_depth, rr_depth, hide_emitters } => {
                path::li(scene, ray, sampler, max_depth, rr_depth, hide_emitters)
            }
            Integrator::Direct { samples, hide_emitters } => direct::li(scene, ray, sampler, samples, hide_emitters),
            Integrator::Phong { shadows } => phong::li(scene, ray, shadows),
        }
    }
}

/// A non-finite estimate only comes from a model bug: dropped rather than poisoning a pixel.
#[inline]
pub(crate) fn finite(c: Rgb) -> Rgb {
    if c.is_finite() {
        c
    } else {
        Rgb::ZERO
    }
}

/// The power heuristic with β = 2 (Veach 1997, §9.2.4): weight of a strategy of density `a`
/// against one of density `b`, one sample each.
#[inline]
pub fn power_heuristic(a: f32, b: f32) -> f32 {
    // As a ratio, so that tiny or huge densities neither underflow nor overflow.
    let r = if b > 0.0 { b / a } else { 0.0 };
    let w = 1.0 / (1.0 + r * r);
    // Selections rather than early returns: a loop over many lanes of this becomes vector code.
    let at_infinity = if b.is_infinite() { 0.5 } else { 1.0 };
    let w = if a.is_infinite() { at_infinity } else { w };
    // Zero for a ≤ 0 and for NaN.
    if a > 0.0 {
        w
    } else {
        0.0
    }
}

/// What the tests of the batch integrators share.
#[cfg(test)]
pub(crate) mod batch_check {
    use super::Integrator;
    use crate::ray::Ray;
    use crate::sampler::{PixelKey, Sampler};
    use crate::scene::Scene;
    use glam::Vec2;
    use radiometry::Rgb;

    /// One jittered camera sample per pixel of `scene`'s image under `seed` (sample number
    /// pixel mod `spread`): the rays and the samplers after drawing the film position.
    pub(crate) fn camera_samples(scene: &Scene, seed: u64, spread: u64) -> (Vec<Ray>, Vec<Sampler>) {
        let (w, h) = (scene.camera.width as u64, scene.camera.height as u64);
        let (mut rays, mut samplers) = (Vec::new(), Vec::new());
        for pixel in 0..w * h {
            let mut sampler = PixelKey::new(seed, pixel).sampler(pixel % spread);
            let pos = Vec2::new((pixel % w) as f32, (pixel / w) as f32) + sampler.next_2d();
            rays.push(scene.camera.ray(pos, Vec2::splat(0.5)));
            samplers.push(sampler);
        }
        (rays, samplers)
    }

    /// A patchy 24 × 12 map (one channel up to 3), turned about two axes, of scale 2: a sky
    /// whose sampling and lookups cross cells and rows.
    pub(crate) fn patchy_map() -> crate::light::envmap::EnvMap {
        let mut img = crate::image::Image::new(24, 12);
        let mut s = Sampler::new(9, 0, 0);
        for p in img.pixels.iter_mut() {
            *p = Rgb::new(s.next_1d(), 3.0 * s.next_1d().powi(4), s.next_1d());
        }
        let turn = glam::Mat3::from_rotation_y(1.1) * glam::Mat3::from_rotation_z(0.2);
        crate::light::envmap::EnvMap::new(&img, 2.0).unwrap().with_rotation(turn).unwrap()
    }

    /// Asserts that [`Integrator::li_batch`], handed the samples in batches of each size of
    /// `batches`, gives every sample bit for bit what [`Integrator::li`] gives it; returns the
    /// one-ray estimates. `label` goes into the failure message.
    pub(crate) fn assert_batches_match(
        scene: &Scene,
        integrator: Integrator,
        rays: &[Ray],
        samplers: &[Sampler],
        batches: &[usize],
        label: &str,
    ) -> Vec<Rgb> {
        let one: Vec<Rgb> = rays.iter().zip(samplers).map(|(&r, s)| integrator.li(scene, r, &mut s.clone())).collect();
        for &batch in batches {
            let mut out = vec![Rgb::splat(-1.0); rays.len()];
            for ((r, s), o) in rays.chunks(batch).zip(samplers.chunks(batch)).zip(out.chunks_mut(batch)) {
                integrator.li_batch(scene, r, s, o);
            }
            for (k, (a, b)) in out.iter().zip(&one).enumerate() {
                let (a, b) = (a.0.map(f32::to_bits), b.0.map(f32::to_bits));
                let simd = scene.simd();
                assert_eq!(a, b, "{label} {simd:?} {integrator:?} batches of {batch}, sample {k}");
            }
        }
        one
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn power_heuristic_weights_sum_to_one() {
        for (a, b) in [(1.0, 1.0), (0.3, 7.0), (1e-30, 1e-30), (5.0, 0.0), (1e30, 1e-30)] {
            assert!((power_heuristic(a, b) + power_heuristic(b, a) - 1.0).abs() < 1e-6);
        }
        assert_eq!(power_heuristic(0.0, 0.0), 0.0);
        assert!((power_heuristic(1.0, 3.0) - 0.1).abs() < 1e-7);
        assert_eq!(power_heuristic(f32::INFINITY, 1.0), 1.0);
    }
}
