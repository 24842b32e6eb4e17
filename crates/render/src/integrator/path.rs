//! Unidirectional path tracing with next-event estimation and multiple importance sampling
//! (Veach 1997, ch. 9; the loop follows Mitsuba 3's `path` integrator so that depths and
//! Russian roulette mean the same). At each surface vertex: one light sample (shadow ray)
//! and one BRDF sample, each weighted by the power heuristic against the other; emission
//! found by the BRDF sample gets its weight at the next vertex. Delta lights and delta
//! lobes take weight 1, since no other strategy can produce them.
//!
//! Depth. `max_depth` counts path vertices, the camera's included: 1 shows only the emitters
//! the camera sees, 2 is direct lighting. Every surface event uses one, a pass through a mask
//! or a null surface included (as in Mitsuba). Russian roulette starts once `rr_depth`
//! vertices exist and judges β η², η the product of the index ratios crossed, so that radiance
//! brightened by entering glass does not make a path look more valuable than its power.
//!
//! Sides are the shading frame's, as in Mitsuba: a one-sided model (most BRDFs) ends the path
//! on its back face; a model with a back side (`twosided`) is handed the local directions as
//! they are (wo.z < 0 on the back) and mirrors them itself; one that transmits (`dielectric`,
//! `mask`) may send the path through the surface, and its light samples are drawn over the
//! whole sphere. Rays leave a surface offset along its geometric normal.
//!
//! `hide_emitters`: the camera ray passes through area lights to what is behind them, and the
//! environment is not seen by paths that have only passed straight through surfaces (Mitsuba
//! 3's rule; emitters seen in mirrors or through glass stay, and they light the scene).

use crate::integrator::{finite, power_heuristic};
use crate::light::envmap::EnvLookup;
use crate::light::RefPoint;
use crate::ray::{spawn_ray, Ray};
use crate::sampler::Sampler;
use crate::scene::{LightNumbers, Scene, ShadowTest, SurfaceInteraction};
use glam::Vec2;
use radiometry::Rgb;

/// What the previous vertex's BRDF sample needs for the MIS weight of emission found next.
pub(super) struct Previous {
    /// The reference point of its light samples.
    pub r: RefPoint,
    /// The BRDF sample's density.
    pub pdf: f32,
    /// Whether the sample took a delta lobe.
    pub delta: bool,
}

/// The uniform numbers a vertex uses: its light samples', then its BRDF sample's.
#[derive(Clone, Copy)]
pub(super) struct VertexNumbers {
    pub light: LightNumbers,
    pub bc: f32,
    pub bu: Vec2,
}

impl VertexNumbers {
    /// Zeros, for lanes without a path.
    pub(super) const ZERO: VertexNumbers = VertexNumbers { light: LightNumbers::ZERO, bc: 0.0, bu: Vec2::ZERO };

    /// Draws them, in the order every integrator of paths draws them, and starts loading the
    /// light sample's first table entry.
    #[inline]
    pub(super) fn draw(sampler: &mut Sampler, scene: &Scene) -> Self {
        let light = LightNumbers::draw(sampler, scene);
        let (bc, bu) = (sampler.next_1d(), sampler.next_2d());
        VertexNumbers { light, bc, bu }
    }
}

/// The reference point of a light sample at `si` seen from `wo` (local): a model that
/// transmits takes light from every side, any other from wo's.
#[inline(always)]
pub(super) fn reference(si: &SurfaceInteraction, wo: glam::Vec3, transmits: bool) -> RefPoint {
    RefPoint { p: si.p, n: if transmits { None } else { Some(si.frame.n * wo.z.signum()) } }
}

/// The first surface the camera ray meets; with `hide` it passes through area lights.
pub fn first_hit(scene: &Scene, ray: Ray, hide: bool) -> Option<SurfaceInteraction> {
    past_hidden(scene, ray, scene.intersect(&ray), hide)
}

/// `hit`, the closest hit of camera ray `ray`, or with `hide` the first surface behind it that
/// is not an area light.
pub fn past_hidden(
    scene: &Scene,
    mut ray: Ray,
    mut hit: Option<SurfaceInteraction>,
    hide: bool,
) -> Option<SurfaceInteraction> {
    loop {
        let si = hit?;
        if !hide || scene.area_light(si.shape).is_none() {
            return Some(si);
        }
        let t_max = ray.t_max - si.t;
        ray = spawn_ray(si.p, si.ng, ray.d);
        ray.t_max = t_max;
        hit = scene.intersect(&ray);
    }
}

/// The radiance estimate along `ray` with paths of at most `max_depth` vertices and
/// Russian roulette from `rr_depth` on.
pub fn li(scene: &Scene, ray: Ray, sampler: &mut Sampler, max_depth: u32, rr_depth: u32, hide_emitters: bool) -> Rgb {
    // The first vertex's numbers before its ray query, so that the light sample's table read
    // loads meanwhile.
    let numbers = VertexNumbers::draw(sampler, scene);
    let first = if max_depth == 0 { None } else { first_hit(scene, ray, hide_emitters) };
    let mut lit = Rgb::ZERO;
    let unlit = trace(scene, ray, first, numbers, sampler, max_depth, rr_depth, hide_emitters, &mut |test, c| {
        if scene.visible(test) {
            lit += c;
        }
    });
    finite(unlit + lit)
}

/// The path from camera ray `ray` whose first surface is `first`: returns the radiance found
/// without shadow rays, and hands each light sample's shadow test (see [`Scene::shadow_ray`])
/// with the radiance it adds when the light is visible to `shadow`, which may answer it at once
/// or later: the path does not depend on it. `numbers` are the first vertex's, drawn from
/// `sampler` (with [`VertexNumbers::draw`]) before anything else of the path.
#[allow(clippy::too_many_arguments)]
pub(super) fn trace(
    scene: &Scene,
    ray: Ray,
    first: Option<SurfaceInteraction>,
    numbers: VertexNumbers,
    sampler: &mut Sampler,
    max_depth: u32,
    rr_depth: u32,
    hide_emitters: bool,
    shadow: &mut impl FnMut(ShadowTest, Rgb),
) -> Rgb {
    if max_depth == 0 {
        return Rgb::ZERO;
    }
    let mut path = PathState::new(ray, numbers);
    let mut hit = first;
    while path.step(scene, hit.as_ref(), sampler, max_depth, rr_depth, hide_emitters, shadow) {
        path.looked = scene.prefetch_environment(path.ray.d);
        hit = scene.intersect(&path.ray);
        path.reached(hit.is_some(), sampler, scene, max_depth);
    }
    path.result
}

/// A path between two vertices: what it has found, its throughput, and the ray to its next
/// vertex with that vertex's numbers.
pub(super) struct PathState {
    /// The radiance found so far without shadow rays.
    pub result: Rgb,
    /// The throughput.
    pub beta: Rgb,
    /// Product of the index ratios crossed: β η² is the path's weight in power.
    pub eta: f32,
    /// The vertices the path has scattered at.
    pub depth: u32,
    /// None for the camera ray: emission seen directly has weight 1.
    pub prev: Option<Previous>,
    /// Whether the path has scattered off something (not only passed straight through).
    pub scattered: bool,
    /// The ray to the next vertex.
    pub ray: Ray,
    /// The next vertex's numbers, drawn once its ray has found it ([`reached`](Self::reached)),
    /// so that the light sample's first table read loads while the hit points are computed.
    /// The draws keep their order (a vertex's, then its Russian roulette). None are drawn for a
    /// ray that escapes or a vertex where the path ends before sampling: the stream is the
    /// sample's own, and nothing would be drawn from it after them, so the image is the same as
    /// where they are drawn (the sixteen-lane tracer draws them ahead for every lane).
    pub numbers: VertexNumbers,
    /// Where the ray's direction falls on an environment map, once asked (bounce rays).
    pub looked: Option<EnvLookup>,
}

impl PathState {
    /// A path along a ray from the origin up +z, with zero numbers: a lane's value until it
    /// has a path.
    pub(super) const IDLE: PathState = PathState {
        result: Rgb::ZERO,
        beta: Rgb::ONE,
        eta: 1.0,
        depth: 0,
        prev: None,
        scattered: false,
        ray: Ray { o: glam::Vec3::ZERO, d: glam::Vec3::Z, t_max: f32::INFINITY },
        numbers: VertexNumbers::ZERO,
        looked: None,
    };

    /// A path starting along camera ray `ray`, its first vertex's numbers `numbers`.
    #[inline]
    pub(super) fn new(ray: Ray, numbers: VertexNumbers) -> Self {
        PathState { ray, numbers, ..Self::IDLE }
    }

    /// Whether the next vertex is the last (`max_depth` reached there): it draws no samples.
    #[inline(always)]
    pub(super) fn at_last_vertex(&self, max_depth: u32) -> bool {
        self.depth.saturating_add(1) >= max_depth
    }

    /// The next vertex's light numbers.
    #[inline(always)]
    pub(super) fn light_numbers(&mut self) -> &mut LightNumbers {
        &mut self.numbers.light
    }

    /// The vertex where the ray meets `hit`, or escapes (None): adds what is found there, hands
    /// the light samples' shadow tests to `shadow`, and returns whether the path goes on; it
    /// then has its next ray, and [`reached`](Self::reached) draws that vertex's numbers once
    /// the ray has found it. `max_depth` is at least 1.
    // Values are borrowed rather than moved where they were just written field by field (the
    // hit, the light sample, the next step): moved, they were copied with wide loads that
    // waited on the narrow stores (perf).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(super) fn step(
        &mut self,
        scene: &Scene,
        hit: Option<&SurfaceInteraction>,
        sampler: &mut Sampler,
        max_depth: u32,
        rr_depth: u32,
        hide_emitters: bool,
        shadow: &mut impl FnMut(ShadowTest, Rgb),
    ) -> bool {
        let ray = self.ray;
        let Some(si) = hit else {
            if !hide_emitters || self.scattered {
                // The light pdf only where a BRDF sample needs its MIS weight.
                let from = self.prev.as_ref().filter(|pv| !pv.delta);
                let looked = self.looked.as_ref();
                if let Some((le, pdf)) = scene.environment_eval_at(ray.d, looked, from.map(|pv| &pv.r), true) {
                    let w = from.map_or(1.0, |pv| power_heuristic(pv.pdf, pdf));
                    self.result += self.beta * le * w;
                }
            }
            return false;
        };
        let wo_world = -ray.d;
        if let Some((index, light)) = scene.area_light(si.shape) {
            let le = light.emitted(si.frame.n, si.uv, wo_world);
            if !le.is_black() {
                let w = match &self.prev {
                    Some(pv) if !pv.delta => {
                        power_heuristic(pv.pdf, scene.light_pdf(index, &pv.r, ray.d, Some((si.p, si.ng)), true))
                    }
                    _ => 1.0,
                };
                self.result += self.beta * le * w;
            }
        }
        if self.at_last_vertex(max_depth) {
            return false;
        }
        let wo = si.frame.to_local(wo_world);
        if !(wo.z != 0.0) {
            return false;
        }
        let VertexNumbers { light: ln, bc, bu } = self.numbers;
        // A model of delta lobes only gives light samples nothing (ρ = 0 towards them): none
        // are drawn there (their numbers were, so the stream does not change).
        let lights = !scene.delta_only(si.shape);
        if lights && ln.env.is_none() {
            scene.prefetch_light_cell(&ln);
        }
        // The light is sampled before the model is built, from the reference point the model
        // likely gives (checked below), so that the light sample's table reads and the model's
        // texel reads can be under way together. (Packets of paths ask for the texels of all
        // their lanes before any steps; asked for here, just before the reads, they cost more
        // than they saved.)
        let material = scene.material(si.shape);
        let guess = scene.transmits_guess(si.shape);
        let guessed = if lights { scene.sample_lights(&reference(si, wo, guess), &ln, true) } else { [None, None] };
        // The model continues the path from here: it sets the next ray, the step's throughput
        // factor and index ratio, and what the next vertex's MIS needs; false ends the path.
        let (mut weight, mut step_eta, mut pass_through) = (Rgb::ZERO, 1.0f32, false);
        let beta = self.beta;
        let go_on = material.with(si, |brdf| {
            if wo.z < 0.0 && !brdf.back_side() {
                return false;
            }
            let transmits = brdf.transmits();
            // Where `wi` may lie: on wo's side, or anywhere for a model that transmits.
            let usable = |wi_z: f32| transmits || wi_z * wo.z > 0.0;
            let r = reference(si, wo, transmits);

            // Next-event estimation (the light samples drawn again, with the same numbers, where
            // the guess was wrong).
            let redrawn;
            let samples = if !lights || guess == transmits {
                &guessed
            } else {
                redrawn = scene.sample_lights(&r, &ln, true);
                &redrawn
            };
            for ls in samples.iter().flatten() {
                let wi = si.frame.to_local(ls.wi);
                if usable(wi.z) {
                    let (f, brdf_pdf) = brdf.eval_pdf(wi, wo);
                    if !f.is_black() {
                        let w = if ls.delta { 1.0 } else { power_heuristic(ls.pdf, brdf_pdf) };
                        shadow(scene.shadow_ray(si.p, si.ng, ls), beta * f * ls.li * (wi.z.abs() * w / ls.pdf));
                    }
                }
            }

            // BRDF sampling: the direction the path continues in.
            let Some(bs) = brdf.sample(wo, bc, bu) else { return false };
            if !usable(bs.wi.z) || !bs.weight.is_finite() {
                return false;
            }
            self.ray = spawn_ray(si.p, si.ng, si.frame.to_world(bs.wi));
            (weight, step_eta, pass_through) = (bs.weight, bs.eta, bs.delta && bs.wi == -wo);
            self.prev = Some(Previous { r, pdf: bs.pdf, delta: bs.delta });
            true
        });
        if !go_on {
            return false;
        }
        self.scattered |= !pass_through;
        self.beta = self.beta * weight;
        self.eta *= step_eta;
        self.depth += 1;

        // Russian roulette: survive with q = min(max channel of β η², 0.95), reweight by 1/q.
        let q = (self.beta.max_channel() * self.eta * self.eta).min(0.95);
        if self.depth >= rr_depth {
            if sampler.next_1d() >= q {
                return false;
            }
            self.beta = self.beta / q;
        }
        self.beta.max_channel() > 0.0
    }

    /// Draws the numbers of the vertex the ray has found, where the path samples there: `hit`
    /// when it found one (see [`numbers`](Self::numbers)).
    #[inline(always)]
    pub(super) fn reached(&mut self, hit: bool, sampler: &mut Sampler, scene: &Scene, max_depth: u32) {
        if hit && !self.at_last_vertex(max_depth) {
            self.numbers = VertexNumbers::draw(sampler, scene);
        }
    }
}
