//! Direct lighting: the path integrator stopped at two vertices (camera → surface →
//! emitter), without Russian roulette.

use crate::ray::Ray;
use crate::sampler::Sampler;
use crate::scene::Scene;
use radiometry::Rgb;

/// The direct-lighting radiance estimate along `ray`.
pub fn li(scene: &Scene, ray: Ray, sampler: &mut Sampler) -> Rgb {
    super::path::li(scene, ray, sampler, 2, u32::MAX)
}
