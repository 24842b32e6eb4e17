//! Sixteen camera samples at once. Their camera rays, which start at one pixel or its
//! neighbours and so are coherent, find their first surfaces as one packet; each path is then
//! traced on its own, and its shadow tests wait in a queue that answers them sixteen at a time
//! as a packet. A path never depends on its shadow tests, only its sum does, and each lane adds
//! its visible contributions in the order it made them: every lane gets exactly the estimate
//! the one-ray-at-a-time integrator gives it. [`Integrator::li_batch`] hands the camera samples
//! of a batch to this sixteen at a time, or, for scenes of Lambertian meshes under one area
//! light, to the sixteen-lane path tracer of [`super::wide`].

use super::{direct, finite, path, phong, Integrator};
use crate::ray::Ray;
use crate::sampler::Sampler;
use crate::scene::{Scene, ShadowTest};
use crate::simd::{for_bits, LANES};
use radiometry::Rgb;

/// Shadow tests waiting to be answered as a packet, with what each adds to its lane if visible.
struct ShadowQueue<'a> {
    scene: &'a Scene,
    rays: [Ray; LANES],
    skip: [Option<u32>; LANES],
    /// Bit i: entry i has a ray to test (else it is visible without one).
    tested: u32,
    add: [(usize, Rgb); LANES],
    len: usize,
    /// Per lane, the sum of its visible contributions so far.
    lit: [Rgb; LANES],
}

impl<'a> ShadowQueue<'a> {
    fn new(scene: &'a Scene) -> Self {
        let ray = Ray::new(glam::Vec3::ZERO, glam::Vec3::Z);
        ShadowQueue {
            scene,
            rays: [ray; LANES],
            skip: [None; LANES],
            tested: 0,
            add: [(0, Rgb::ZERO); LANES],
            len: 0,
            lit: [Rgb::ZERO; LANES],
        }
    }

    fn push(&mut self, lane: usize, test: ShadowTest, c: Rgb) {
        if let Some((ray, skip)) = test {
            self.rays[self.len] = ray;
            self.skip[self.len] = skip;
            self.tested |= 1 << self.len;
        }
        self.add[self.len] = (lane, c);
        self.len += 1;
        if self.len == LANES {
            self.flush();
        }
    }

    fn flush(&mut self) {
        let blocked = self.scene.occluded_packet(&self.rays, &self.skip, self.tested, self.scene.simd());
        for (k, &(lane, c)) in self.add[..self.len].iter().enumerate() {
            if blocked >> k & 1 == 0 {
                self.lit[lane] += c;
            }
        }
        (self.len, self.tested) = (0, 0);
    }
}

impl Integrator {
    /// The estimates along camera rays `rays`, each drawing from its sampler in `samplers`,
    /// written to `out`: for each what [`li`](Self::li) gives. Sixteen at a time through
    /// [`li_packet`](Self::li_packet), or all in the sixteen-lane tracer where the scene is one
    /// of its own.
    pub fn li_batch(&self, scene: &Scene, rays: &[Ray], samplers: &[Sampler], out: &mut [Rgb]) {
        if let (Integrator::Path { max_depth, rr_depth, hide_emitters: false }, Some(diffuse)) =
            (*self, scene.diffuse_meshes())
        {
            diffuse.li(scene, rays, samplers, out, max_depth, rr_depth);
            for l in out.iter_mut() {
                *l = finite(*l);
            }
            return;
        }
        for ((rays, samplers), out) in rays.chunks(LANES).zip(samplers.chunks(LANES)).zip(out.chunks_mut(LANES)) {
            let n = rays.len();
            let packet: [Ray; LANES] = std::array::from_fn(|i| rays[i.min(n - 1)]);
            let mut lanes: [Sampler; LANES] = std::array::from_fn(|i| samplers[i.min(n - 1)].clone());
            let l = self.li_packet(scene, &packet, &mut lanes, u32::MAX >> (32 - n));
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
        let mut out = [Rgb::ZERO; LANES];
        if let Integrator::Phong { shadows } = *self {
            for_bits(active, |i| out[i] = phong::li(scene, rays[i], shadows));
            return out;
        }
        // A path's first numbers are drawn before the camera rays' query, as `path::li` draws
        // them, so that the light sample's first table read loads meanwhile.
        let mut first = [path::VertexNumbers::ZERO; LANES];
        if let Integrator::Path { .. } = *self {
            for_bits(active, |i| first[i] = path::VertexNumbers::draw(&mut samplers[i], scene));
        }
        let hits = scene.intersect_t_packet(rays, active, scene.simd());
        let mut queue = ShadowQueue::new(scene);
        let mut unlit = [Rgb::ZERO; LANES];
        for_bits(active, |i| {
            let (ray, sampler) = (rays[i], &mut samplers[i]);
            let mut shadow = |test: ShadowTest, c: Rgb| queue.push(i, test, c);
            unlit[i] = match *self {
                Integrator::Path { max_depth, rr_depth, hide_emitters } => {
                    let hit = hits[i].filter(|_| max_depth > 0).map(|(k, t)| scene.interaction(&ray, k, t));
                    let hit = path::past_hidden(scene, ray, hit, hide_emitters);
                    path::trace(scene, ray, hit, first[i], sampler, max_depth, rr_depth, hide_emitters, &mut shadow)
                }
                Integrator::Direct { samples, hide_emitters } => {
                    let hit = hits[i].map(|(k, t)| scene.interaction(&ray, k, t));
                    let first = path::past_hidden(scene, ray, hit, hide_emitters);
                    direct::estimate(scene, ray, first, sampler, samples, hide_emitters, &mut shadow)
                }
                Integrator::Phong { .. } => unreachable!("answered above"),
            };
        });
        queue.flush();
        for_bits(active, |i| out[i] = finite(unlit[i] + queue.lit[i]));
        out
    }
}
