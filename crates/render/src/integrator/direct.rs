//! Direct lighting: the path integrator stopped at two vertices (camera → surface →
//! emitter), without Russian roulette. At a transmitting surface the BRDF sample may cross
//! it, and counts only if it reaches an emitter (or the environment) straight away: a glass
//! sphere shows its reflections and, through one refraction, its inside wall's emission,
//! as Mitsuba's `direct` does.

use crate::ray::Ray;
use crate::sampler::Sampler;
use crate::scene::Scene;
use radiometry::Rgb;

/// The direct-lighting radiance estimate along `ray`.
pub fn li(scene: &Scene, ray: Ray, sampler: &mut Sampler) -> Rgb {
    super::path::li(scene, ray, sampler, 2, u32::MAX)
}
