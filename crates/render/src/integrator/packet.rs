//! Sixteen camera samples at once. Their camera rays, which start at one pixel or its
//! neighbours and so are coherent, find their first surfaces as one packet. The rays that
//! escape at once end there, their environment lookups made as one packet (the angles in
//! vector code: under an open sky, the envmap bench scene without its sphere, these rays took
//! 40 % of the render one by one). With the path integrator the paths of the others go on
//! vertex by vertex together (see [`trace_together`]), each shading on its own; the direct
//! integrator estimates each on its own. Shadow tests wait in a queue that answers them
//! sixteen at a time as a packet. A path never depends on its shadow tests, only its sum does,
//! and each lane adds its visible contributions in the order it made them: every lane gets
//! exactly the estimate the one-ray-at-a-time integrator gives it. [`Integrator::li_batch`]
//! hands the camera samples of a batch to this sixteen at a time, or, for scenes seen mostly on
//! Lambertian surfaces (see [`DiffuseSurfaces`](crate::scene::DiffuseSurfaces)), to the
//! sixteen-lane path tracer of [`super::wide`].

use super::path::PathState;
use super::{direct, finite, path, phong, Integrator};
use crate::ray::Ray;
use crate::sampler::Sampler;
use crate::scene::{PacketHits, Scene, ShadowTest, SurfaceInteraction};
use crate::simd::{for_bits, LANES};
use radiometry::Rgb;

/// Shadow tests waiting to be answered as a packet, with what each adds to its lane if visible.
pub(super) struct ShadowQueue<'a> {
    scene: &'a Scene,
    rays: [Ray; LANES],
    skip: [Option<u32>; LANES],
    /// Bit i: entry i has a ray to test (else it is visible without one).
    tested: u32,
    add: [(usize, Rgb); LANES],
    len: usize,
    /// Per lane, the sum of its visible contributions so far.
    pub(super) lit: [Rgb; LANES],
    /// Bit i: lane i has contributions waiting, not yet in `lit`.
    pub(super) pending: u32,
}

impl<'a> ShadowQueue<'a> {
    /// An empty queue, every lane's sum zero.
    pub(super) fn new(scene: &'a Scene) -> Self {
        let ray = Ray::new(glam::Vec3::ZERO, glam::Vec3::Z);
        ShadowQueue {
            scene,
            rays: [ray; LANES],
            skip: [None; LANES],
            tested: 0,
            add: [(0, Rgb::ZERO); LANES],
            len: 0,
            lit: [Rgb::ZERO; LANES],
            pending: 0,
        }
    }

    /// Empties it, every lane's sum zero again.
    pub(super) fn clear(&mut self) {
        (self.len, self.tested, self.pending) = (0, 0, 0);
        self.lit = [Rgb::ZERO; LANES];
    }

    /// Queues shadow test `test` of lane `lane`, which adds `c` to its sum if visible (at once
    /// when there is nothing to test).
    pub(super) fn push(&mut self, lane: usize, test: ShadowTest, c: Rgb) {
        if let Some((ray, skip)) = test {
            self.rays[self.len] = ray;
            self.skip[self.len] = skip;
            self.tested |= 1 << self.len;
        }
        self.add[self.len] = (lane, c);
        self.len += 1;
        self.pending |= 1 << lane;
        if self.len == LANES {
            self.flush();
        }
    }

    /// Answers the queued tests and adds what is visible, in the order queued.
    pub(super) fn flush(&mut self) {
        let blocked = self.scene.occluded_packet(&self.rays, &self.skip, self.tested, self.scene.simd());
        for (k, &(lane, c)) in self.add[..self.len].iter().enumerate() {
            if blocked >> k & 1 == 0 {
                self.lit[lane] += c;
            }
        }
        (self.len, self.tested, self.pending) = (0, 0, 0);
    }

    /// Answers the queued tests where one of lanes `lanes` has contributions waiting, so that
    /// their sums in `lit` are whole.
    #[inline]
    pub(super) fn settle(&mut self, lanes: u32) {
        if self.pending & lanes != 0 {
            self.flush();
        }
    }
}

/// The arrays a packet of paths works in, kept from packet to packet of a batch (made afresh
/// for each packet, they were 6.6 kB written per packet, most of it copies of an idle path).
struct PacketWork<'a> {
    queue: ShadowQueue<'a>,
    paths: [PathState; LANES],
    at: [Option<SurfaceInteraction>; LANES],
}

impl<'a> PacketWork<'a> {
    fn new(scene: &'a Scene) -> Self {
        PacketWork { queue: ShadowQueue::new(scene), paths: [PathState::IDLE; LANES], at: [None; LANES] }
    }
}

impl Integrator {
    /// The estimates along camera rays `rays`, each drawing from its sampler in `samplers`,
    /// written to `out`: for each what [`li`](Self::li) gives. Sixteen at a time through
    /// [`li_packet`](Self::li_packet), or all in the sixteen-lane tracer where the scene is one
    /// of its own.
    pub fn li_batch(&self, scene: &Scene, rays: &[Ray], samplers: &[Sampler], out: &mut [Rgb]) {
        if let (Integrator::Path { max_depth, rr_depth, hide_emitters: false }, Some(diffuse)) =
            (*self, scene.diffuse_surfaces())
        {
            diffuse.li(scene, rays, samplers, out, max_depth, rr_depth);
            for l in out.iter_mut() {
                *l = finite(*l);
            }
            return;
        }
        let mut work = PacketWork::new(scene);
        for ((rays, samplers), out) in rays.chunks(LANES).zip(samplers.chunks(LANES)).zip(out.chunks_mut(LANES)) {
            let n = rays.len();
            let packet: [Ray; LANES] = std::array::from_fn(|i| rays[i.min(n - 1)]);
            let mut lanes: [Sampler; LANES] = std::array::from_fn(|i| samplers[i.min(n - 1)].clone());
            let l = self.li_packet_in(scene, &packet, &mut lanes, u32::MAX >> (32 - n), &mut work);
            out.copy_from_slice(&l[..n]);
        }
    }

    /// The estimates along the camera rays of lanes `active`, each drawing from its own sampler:
    /// for every lane what [`li`](Self::li) gives, ray queries made on the scene's instruction
    /// set (sixteen at a time unless it is [`Simd::Scalar`](crate::simd::Simd::Scalar)).
    pub fn li_packet(
        &self,
        scene: &Scene,
        rays: &[Ray; LANES],
        samplers: &mut [Sampler; LANES],
        active: u32,
    ) -> [Rgb; LANES] {
        self.li_packet_in(scene, rays, samplers, active, &mut PacketWork::new(scene))
    }

    /// [`li_packet`](Self::li_packet) in the arrays of `work`.
    fn li_packet_in<'a>(
        &self,
        scene: &'a Scene,
        rays: &[Ray; LANES],
        samplers: &mut [Sampler; LANES],
        active: u32,
        work: &mut PacketWork<'a>,
    ) -> [Rgb; LANES] {
        let mut out = [Rgb::ZERO; LANES];
        if let Integrator::Phong { shadows } = *self {
            for_bits(active, |i| out[i] = phong::li(scene, rays[i], shadows));
            return out;
        }
        let hits = scene.intersect_t_packet(rays, active, scene.simd());
        let mut unlit = [Rgb::ZERO; LANES];
        // Rays that escape at once see the environment (if shown) and end: their lookups go
        // as one packet.
        let (traced, shown) = match *self {
            Integrator::Path { max_depth: 0, .. } => (0, false),
            Integrator::Path { hide_emitters, .. } | Integrator::Direct { hide_emitters, .. } => {
                let hit = hits.iter().enumerate().fold(0, |m, (i, h)| m | (h.is_some() as u32) << i);
                (active & hit, !hide_emitters)
            }
            Integrator::Phong { .. } => unreachable!("answered above"),
        };
        if shown && active & !traced != 0 {
            unlit = scene.environment_packet(rays, active & !traced, scene.simd());
        }
        work.queue.clear();
        match *self {
            Integrator::Path { max_depth, rr_depth, hide_emitters } => {
                if traced != 0 {
                    let depths = (max_depth, rr_depth, hide_emitters);
                    trace_together(scene, rays, &hits, traced, samplers, depths, work);
                    for_bits(traced, |i| unlit[i] = work.paths[i].result);
                }
            }
            Integrator::Direct { samples, hide_emitters } => for_bits(traced, |i| {
                let mut shadow = |test: ShadowTest, c: Rgb| work.queue.push(i, test, c);
                let hit = hits[i].map(|(k, t)| scene.interaction(&rays[i], k, t));
                let first = path::past_hidden(scene, rays[i], hit, hide_emitters);
                unlit[i] =
                    direct::estimate(scene, rays[i], first, &mut samplers[i], samples, hide_emitters, &mut shadow);
            }),
            Integrator::Phong { .. } => unreachable!("answered above"),
        }
        work.queue.flush();
        for_bits(active, |i| out[i] = finite(unlit[i] + work.queue.lit[i]));
        out
    }
}

/// The paths from the camera rays `rays` of lanes `lanes`, whose first hits are `hits`, each
/// drawing from its sampler; `depths` is (max_depth ≥ 1, rr_depth, hide_emitters). Each lane's
/// path and vertex are `work.paths[i]` and `work.at[i]` (no other lane's are read or written);
/// it ends with what it found without shadow rays in `work.paths[i].result`, its shadow tests
/// waiting in `work.queue`.
///
/// The paths go vertex by vertex together: each takes its step on its own, then the
/// directions of the next rays fall on the environment map as one packet, and the map's light
/// samples of the next vertices, which depend on their numbers alone, are drawn as one packet
/// after the ray queries, which give the cell-choice entries that drawing the numbers asked for
/// ([`LightNumbers::draw`](crate::scene::LightNumbers::draw)) time to load. (Asking for each
/// cell's corners and texels too, before the queries, cost more than it saved: that work is
/// wasted on the paths that escape, and the packet's sampling reads them soon enough.)
/// The surface data of the hits are read in passes over the lanes, each starting the loads
/// the next depends on (the hit's reference, its corners' indices, the corners, then the
/// texels its model is built from): the lanes' cache misses overlap rather than each stalling
/// its own lane.
/// A path's first numbers are drawn only for rays that hit something.
fn trace_together(
    scene: &Scene,
    rays: &[Ray; LANES],
    hits: &PacketHits,
    lanes: u32,
    samplers: &mut [Sampler; LANES],
    (max_depth, rr_depth, hide_emitters): (u32, u32, bool),
    work: &mut PacketWork,
) {
    let PacketWork { queue, paths, at } = work;
    for_bits(lanes, |i| {
        paths[i] = PathState::new(rays[i], path::VertexNumbers::draw(&mut samplers[i], scene));
        at[i] = hits[i].map(|(k, t)| scene.interaction(&rays[i], k, t));
        // Written in place, not moved through `past_hidden`, where nothing is hidden.
        if hide_emitters {
            at[i] = path::past_hidden(scene, rays[i], at[i], true);
        }
    });
    let map = scene.environment_map().is_some();
    ready_vertices(scene, paths, at, lanes, max_depth, map);
    let mut alive = lanes;
    while alive != 0 {
        let mut next = 0;
        for_bits(alive, |i| {
            let mut shadow = |test: ShadowTest, c: Rgb| queue.push(i, test, c);
            let on =
                paths[i].step(scene, at[i].as_ref(), &mut samplers[i], max_depth, rr_depth, hide_emitters, &mut shadow);
            next |= (on as u32) << i;
        });
        alive = next;
        let mut hits = [None; LANES];
        let mut escaped = 0;
        for_bits(alive, |i| {
            hits[i] = scene.intersect_t(&paths[i].ray);
            match hits[i] {
                Some((k, _)) => scene.prefetch_primitive(k),
                None => escaped |= 1 << i,
            }
        });
        // Where the rays that escaped fall on the map, for their lookups in the next step.
        if map && escaped != 0 {
            let looked = scene.prefetch_environment_packet(&paths.each_ref().map(|p| p.ray.d), escaped, scene.simd());
            for_bits(escaped, |i| paths[i].looked = looked[i]);
        }
        for_bits(alive, |i| hits[i].map_or((), |(k, _)| scene.prefetch_indices(k)));
        for_bits(alive, |i| hits[i].map_or((), |(k, _)| scene.prefetch_vertices(k)));
        for_bits(alive, |i| paths[i].reached(hits[i].is_some(), &mut samplers[i], scene, max_depth));
        for_bits(alive, |i| at[i] = hits[i].map(|(k, t)| scene.interaction(&paths[i].ray, k, t)));
        ready_vertices(scene, paths, at, alive, max_depth, map);
    }
}

/// Readies the next vertices `at` of `paths` in lanes `lanes` where a model is built there
/// (not where the path escapes or ends at `max_depth`), all lanes before any steps: first
/// starts loading the texels the models are built from, so that each lane's cache misses
/// overlap the steps before it; then, with an environment map (`map`), draws the map's light
/// samples as one packet ([`Scene::presample_environment_packet`]) where light samples may be
/// drawn (not on delta lobes only).
fn ready_vertices(
    scene: &Scene,
    paths: &mut [PathState; LANES],
    at: &[Option<SurfaceInteraction>; LANES],
    lanes: u32,
    max_depth: u32,
    map: bool,
) {
    let mut modelled = 0;
    for_bits(lanes, |i| {
        if let Some(si) = &at[i] {
            if !paths[i].at_last_vertex(max_depth) {
                scene.material(si.shape).prefetch(si.uv);
                modelled |= 1 << i;
            }
        }
    });
    if !map {
        return;
    }
    let mut lit = 0;
    for_bits(modelled, |i| {
        let si = at[i].as_ref().expect("a modelled lane has a hit");
        lit |= (!scene.delta_only(si.shape) as u32) << i;
    });
    let env = scene.presample_environment_packet(lit, |i| paths[i].numbers.light);
    for_bits(lit, |i| {
        if env[i].is_some() {
            paths[i].light_numbers().env = env[i];
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{look_at, Camera, FovAxis};
    use crate::integrator::batch_check::{assert_batches_match, camera_samples, patchy_map};
    use crate::light::constant::ConstantEnv;
    use crate::light::point::PointLight;
    use crate::light::Light;
    use crate::scene::SceneBuilder;
    use crate::shape::{sphere::Sphere, Geometry};
    use crate::simd::Simd;
    use glam::Vec3;

    /// The environments of [`open_sky`].
    #[derive(Clone, Copy, Debug)]
    enum Sky {
        /// A turned, patchy map, sampled by its radiance.
        Map,
        /// The same map sampled uniformly.
        UniformMap,
        /// A constant radiance.
        Constant,
    }

    /// A rough metal sphere and a glass one under `sky` (and a point light with `point`), seen
    /// so that about half the camera rays escape.
    fn open_sky(sky: Sky, point: bool) -> Scene {
        let cam =
            Camera::new(look_at(Vec3::new(0.0, 0.3, 3.0), Vec3::ZERO, Vec3::Y).unwrap(), 40.0, FovAxis::X, 20, 14);
        let mut b = SceneBuilder::new(cam);
        b.shape_with_model(Geometry::Sphere(Sphere::new(Vec3::new(-0.6, 0.0, 0.0), 0.6)), "ggx", &[("alpha", "0.3")])
            .unwrap();
        b.shape_with_model(Geometry::Sphere(Sphere::new(Vec3::new(0.7, -0.1, 0.2), 0.5)), "dielectric", &[]).unwrap();
        let mut map = patchy_map();
        map.importance = !matches!(sky, Sky::UniformMap);
        b.light(match sky {
            Sky::Constant => Light::Constant(ConstantEnv { radiance: Rgb::new(0.7, 1.0, 1.3) }),
            _ => Light::EnvMap(Box::new(map)),
        });
        if point {
            b.light(Light::Point(PointLight { position: Vec3::new(1.0, 2.0, 1.0), intensity: Rgb::splat(3.0) }));
        }
        b.build().unwrap()
    }

    #[test]
    fn packets_give_each_camera_ray_its_one_ray_estimate_bit_for_bit() {
        // The environment sampled beside the point light's choice, and as the only light.
        let skies = [(Sky::Map, true), (Sky::Map, false), (Sky::UniformMap, false), (Sky::Constant, true)];
        for (sky, point) in skies {
            let mut scene = open_sky(sky, point);
            let (rays, samplers) = camera_samples(&scene, 4, 5);
            let escaping = rays.iter().filter(|r| scene.intersect(r).is_none()).count();
            assert!(escaping > rays.len() / 4 && escaping < rays.len() * 3 / 4, "{escaping} of {} escape", rays.len());
            let integrators = [
                Integrator::path(8, 3),
                Integrator::path(1, 5),
                Integrator::path(0, 5),
                Integrator::Path { max_depth: 8, rr_depth: 3, hide_emitters: true },
                Integrator::DIRECT,
                Integrator::Direct { samples: direct::DirectSamples { emitter: 2, bsdf: 1 }, hide_emitters: true },
            ];
            for simd in Simd::ALL.map(|(_, s)| s).into_iter().filter(|s| s.available()) {
                scene.set_simd(simd);
                for integrator in integrators {
                    // Batches of 37: full packets and a remainder.
                    assert_batches_match(&scene, integrator, &rays, &samplers, &[37], &format!("{sky:?}"));
                }
            }
        }
    }
}
