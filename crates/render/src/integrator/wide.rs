//! Sixteen paths at once, their state in structure-of-arrays form, for the scenes of
//! [`DiffuseSurfaces`]: mostly Lambertian surfaces lit by one area light on a mesh, or by
//! lights none of which is an area light. A lane on a surface of another model takes the step
//! of [`PathState::step`] on its own, from its path's state in the lanes' arrays and back (the
//! Cornell box with glass boxes, 64 spp: 29 % less time than the packet path); the other lanes
//! go on together. Each step of the path loop runs over all lanes together: the
//! triangles' corners are gathered in one pass, then the arithmetic of the hit point, its
//! frame, the area light's sample, the BRDF and the throughput runs in loops over the lanes,
//! which the compiler turns into vector code; the shadow rays of a step go out as packets.
//! Spheres, rectangles and disks find their hits lane by lane through the scene, and textured
//! albedos are looked up lane by lane. An environment (a map, whose directions are drawn as
//! one packet, or a constant sky) and a point or directional light, one of each at most, are
//! sampled with the lanes' data in lane arrays, each kind's shadow rays one query of sixteen:
//! 7 to 16 % less time than sampling them through the scene one lane at a time (diffuse
//! scenes under a map and a point light, a map and the sun, the point light alone, the map
//! alone, a constant sky alone and beside a point light; 64 spp). Other lights are sampled
//! lane by lane through the scene. The directions of the rays about to be traced fall on the
//! map as one packet too, for the paths that escape (the Cornell box lit by a map through its
//! open front instead of its lamp, 64 spp: 2.23 → 1.64 s against the packet path of other
//! scenes, 1.83 → 1.68 s more with the escapes' packet; a 60 000-triangle scene under a map
//! gains 1 %: there the ray queries' memory traffic, not the shading, sets the pace). A lane
//! whose path ends takes the next camera sample of the batch (path regeneration), so that
//! lanes do not idle until the longest path of sixteen is done: on the Cornell box a lane was
//! idle in 29 % of the steps without it.
//!
//! Every lane makes the operations, in the same order, that [`path::trace`](super::path::trace)
//! makes for its path (branches written as selections where a loop is to become vector code),
//! so the estimates are the same bit for bit (a test compares them); only their schedule differs.

use super::packet::ShadowQueue;
use super::path::{PathState, Previous, VertexNumbers};
use super::power_heuristic;
use crate::light::envmap::{EnvDirection, EnvLookup};
use crate::light::Light;
use crate::light::RefPoint;
use crate::ray::{offset_origin, spawn_ray, spawn_ray_to, surface_epsilon, Ray};
use crate::sampler::{Sampler, Samplers16};
use crate::scene::{Albedo, DiffuseSurfaces, LightNumbers, PacketHits, Scene, SurfaceInteraction, PACKET_MIN};
use crate::shape::sphere::solid_angle_pdf;
use crate::shape::{Geometry, TriangleMesh};
use crate::simd::{dispatch, Bits, LANES};
use glam::{Vec2, Vec3};
use radiometry::warp::{cosine_hemisphere, cosine_hemisphere_pdf, uniform_triangle};
use radiometry::{Frame, Rgb};
use std::f32::consts::FRAC_1_PI;

const N: usize = LANES;

/// Three numbers per lane: a point, a direction or an RGB value.
#[derive(Clone, Copy)]
struct V3 {
    x: [f32; N],
    y: [f32; N],
    z: [f32; N],
}

impl V3 {
    const ZERO: V3 = V3::splat(0.0);

    const fn splat(v: f32) -> V3 {
        V3 { x: [v; N], y: [v; N], z: [v; N] }
    }

    #[inline(always)]
    fn get(&self, i: usize) -> Vec3 {
        Vec3::new(self.x[i], self.y[i], self.z[i])
    }

    #[inline(always)]
    fn set(&mut self, i: usize, v: Vec3) {
        (self.x[i], self.y[i], self.z[i]) = (v.x, v.y, v.z);
    }

    #[inline(always)]
    fn rgb(&self, i: usize) -> Rgb {
        Rgb::new(self.x[i], self.y[i], self.z[i])
    }

    #[inline(always)]
    fn set_rgb(&mut self, i: usize, c: Rgb) {
        (self.x[i], self.y[i], self.z[i]) = (c.0[0], c.0[1], c.0[2]);
    }
}

/// A frame per lane, its axes in lane arrays (an array of frames took a scatter and gathers
/// where the lane loops became vector code).
struct Frames {
    s: V3,
    t: V3,
    n: V3,
}

impl Frames {
    #[inline(always)]
    fn get(&self, i: usize) -> Frame {
        Frame { s: self.s.get(i), t: self.t.get(i), n: self.n.get(i) }
    }

    #[inline(always)]
    fn set(&mut self, i: usize, f: &Frame) {
        self.s.set(i, f.s);
        self.t.set(i, f.t);
        self.n.set(i, f.n);
    }
}

/// The uniform numbers of one vertex per lane, drawn as `path`'s vertices draw them.
struct Numbers {
    /// The light choice.
    uc: [f32; N],
    /// The light's triangle.
    uc2: [f32; N],
    /// The point on it.
    ux: [f32; N],
    uy: [f32; N],
    /// The environment's own sample, where it is sampled beside the choice.
    ue: [f32; N],
    uex: [f32; N],
    uey: [f32; N],
    /// The BRDF lobe.
    bc: [f32; N],
    /// The BRDF sample.
    bx: [f32; N],
    by: [f32; N],
}

impl Numbers {
    const ZERO: Numbers = Numbers {
        uc: [0.0; N],
        uc2: [0.0; N],
        ux: [0.0; N],
        uy: [0.0; N],
        ue: [0.0; N],
        uex: [0.0; N],
        uey: [0.0; N],
        bc: [0.0; N],
        bx: [0.0; N],
        by: [0.0; N],
    };

    /// Lane `i`'s numbers from `v`.
    #[inline(always)]
    fn set(&mut self, i: usize, v: &VertexNumbers) {
        (self.uc[i], self.uc2[i], self.ux[i], self.uy[i]) = (v.light.uc, v.light.uc2, v.light.u.x, v.light.u.y);
        (self.ue[i], self.uex[i], self.uey[i]) = (v.light.ue, v.light.ue2.x, v.light.ue2.y);
        (self.bc[i], self.bx[i], self.by[i]) = (v.bc, v.bu.x, v.bu.y);
    }

    /// Lane `i`'s numbers as `path` holds them, with an environment map's direction `env`
    /// drawn ahead.
    #[inline(always)]
    fn vertex(&self, i: usize, env: Option<EnvDirection>) -> VertexNumbers {
        VertexNumbers { light: self.light(i, env), bc: self.bc[i], bu: Vec2::new(self.bx[i], self.by[i]) }
    }

    /// Lane `i`'s light numbers, as [`LightNumbers::draw`] drew them, with an environment
    /// map's direction `env` drawn ahead.
    #[inline(always)]
    fn light(&self, i: usize, env: Option<EnvDirection>) -> LightNumbers {
        let (u, ue2) = (Vec2::new(self.ux[i], self.uy[i]), Vec2::new(self.uex[i], self.uey[i]));
        LightNumbers { uc: self.uc[i], uc2: self.uc2[i], u, ue: self.ue[i], ue2, env }
    }
}

/// Draws a vertex's numbers for every lane at once, in the order [`VertexNumbers::draw`] draws
/// them: the light choice, the light's 1D and 2D numbers, the environment's where it is sampled
/// beside the choice (`split`), the BRDF lobe, the BRDF sample.
#[inline(always)]
fn draw(s: &mut Samplers16, split: bool) -> Numbers {
    let uc = s.next_1d();
    let uc2 = s.next_1d();
    let (ux, uy) = (s.next_1d(), s.next_1d());
    let (ue, uex, uey) = if split { (s.next_1d(), s.next_1d(), s.next_1d()) } else { ([0.0; N], [0.0; N], [0.0; N]) };
    let bc = s.next_1d();
    let (bx, by) = (s.next_1d(), s.next_1d());
    Numbers { uc, uc2, ux, uy, ue, uex, uey, bc, bx, by }
}

/// A triangle's corners, vertex normals and uvs (zero where the mesh has none) and flip
/// sign, per lane.
struct Corners {
    p: [V3; 3],
    n: [V3; 3],
    uv: [[Vec2; N]; 3],
    /// With vertex normals.
    smooth: [bool; N],
    /// With uvs.
    textured: [bool; N],
    /// −1 for a mesh with flipped normals, else 1.
    sign: [f32; N],
}

impl Corners {
    fn new() -> Self {
        let (z, no) = (V3::ZERO, [false; N]);
        Corners { p: [z; 3], n: [z; 3], uv: [[Vec2::ZERO; N]; 3], smooth: no, textured: no, sign: [1.0; N] }
    }

    /// Loads triangle `t` of mesh `m` into lane `i`.
    #[inline(always)]
    fn load(&mut self, i: usize, m: &TriangleMesh, t: usize) {
        let [a, b, c] = m.indices[t].map(|k| k as usize);
        self.p[0].set(i, m.positions[a]);
        self.p[1].set(i, m.positions[b]);
        self.p[2].set(i, m.positions[c]);
        self.smooth[i] = m.normals.is_some();
        if let Some(n) = &m.normals {
            self.n[0].set(i, n[a]);
            self.n[1].set(i, n[b]);
            self.n[2].set(i, n[c]);
        }
        self.textured[i] = m.uvs.is_some();
        if let Some(t) = &m.uvs {
            (self.uv[0][i], self.uv[1][i], self.uv[2][i]) = (t[a], t[b], t[c]);
        }
        self.sign[i] = if m.flip { -1.0 } else { 1.0 };
    }

    /// Lane `i`'s ∂p/∂u, as [`TriangleMesh::surface`] computes it; `ng` is the unit geometric
    /// normal before any flip.
    #[inline(always)]
    fn dp_du(&self, i: usize, ng: Vec3) -> Vec3 {
        let (p0, p1, p2) = (self.corner(i, 0), self.corner(i, 1), self.corner(i, 2));
        let (dp0, dp1) = (p1 - p0, p2 - p0);
        let [t0, t1, t2] = [self.uv[0][i], self.uv[1][i], self.uv[2][i]];
        let (duv0, duv1) = (t1 - t0, t2 - t0);
        let det = duv0.x * duv1.y - duv0.y * duv1.x;
        let inv = 1.0 / det;
        let du = (dp0 * duv1.y - dp1 * duv0.y) * inv;
        let uv_du = if det != 0.0 { du } else { Frame::from_normal(ng).s };
        if self.textured[i] {
            uv_du
        } else {
            dp0
        }
    }

    /// Lane `i`'s surface coordinates at barycentrics (b1, b2), as [`TriangleMesh::surface`]
    /// computes them.
    #[inline(always)]
    fn uv(&self, i: usize, b1: f32, b2: f32) -> Vec2 {
        if !self.textured[i] {
            return Vec2::new(b1, b2);
        }
        let b0 = 1.0 - b1 - b2;
        self.uv[0][i] * b0 + self.uv[1][i] * b1 + self.uv[2][i] * b2
    }

    /// Lane `i`'s corner `c`.
    #[inline(always)]
    fn corner(&self, i: usize, c: usize) -> Vec3 {
        self.p[c].get(i)
    }

    /// Lane `i`'s point at barycentrics (b1, b2) with its geometric and shading normals, as
    /// [`TriangleMesh::surface`] computes them.
    #[inline(always)]
    fn surface(&self, i: usize, b1: f32, b2: f32) -> (Vec3, Vec3, Vec3) {
        let (p0, p1, p2) = (self.corner(i, 0), self.corner(i, 1), self.corner(i, 2));
        let b0 = 1.0 - b1 - b2;
        let p = p0 * b0 + p1 * b1 + p2 * b2;
        let ng = normalize_or((p1 - p0).cross(p2 - p0), Vec3::Z);
        let (n0, n1, n2) = (self.n[0].get(i), self.n[1].get(i), self.n[2].get(i));
        let smooth = normalize_or(n0 * b0 + n1 * b1 + n2 * b2, ng);
        let ns = if self.smooth[i] { smooth } else { ng };
        (p, ng * self.sign[i], ns * self.sign[i])
    }
}

/// `v.try_normalize().unwrap_or(fallback)`, as a selection.
#[inline(always)]
fn normalize_or(v: Vec3, fallback: Vec3) -> Vec3 {
    let rcp = v.length().recip();
    if rcp.is_finite() & (rcp > 0.0) {
        v * rcp
    } else {
        fallback
    }
}

/// The barycentrics (u, v) that `intersect_triangle(o, d, ∞, p0, e1, e2)` finds, or (0, 0)
/// where it finds no hit, as selections.
#[inline(always)]
fn barycentrics(o: Vec3, d: Vec3, p0: Vec3, e1: Vec3, e2: Vec3) -> (f32, f32) {
    let pvec = d.cross(e2);
    let det = e1.dot(pvec);
    let inv = 1.0 / det;
    let tvec = o - p0;
    let u = tvec.dot(pvec) * inv;
    let qvec = tvec.cross(e1);
    let v = d.dot(qvec) * inv;
    let t = e2.dot(qvec) * inv;
    let hit = (det != 0.0) & (0.0..=1.0).contains(&u) & (v >= 0.0) & (u + v <= 1.0) & (t > 0.0) & (t < f32::INFINITY);
    if hit {
        (u, v)
    } else {
        (0.0, 0.0)
    }
}

/// [`SurfacePoint::frame`](crate::shape::SurfacePoint::frame) as selections.
#[inline(always)]
fn frame_of(n: Vec3, dp_du: Vec3) -> Frame {
    let any = Frame::from_normal(n);
    let s = (dp_du - n * n.dot(dp_du)).normalize();
    let tangent =
        ((dp_du.x != 0.0) | (dp_du.y != 0.0) | (dp_du.z != 0.0)) & s.x.is_finite() & s.y.is_finite() & s.z.is_finite();
    let t = n.cross(s);
    Frame { s: if tangent { s } else { any.s }, t: if tangent { t } else { any.t }, n }
}

/// `w` mirrored in the surface plane when `mirror` (the back model's view, as `twosided` has it).
#[inline(always)]
fn mirror_if(mirror: bool, w: Vec3) -> Vec3 {
    Vec3::new(w.x, w.y, if mirror { -w.z } else { w.z })
}

/// The lights that [`DiffuseSurfaces::lights_in_lanes`] samples in lane arrays: an
/// environment (a map or a constant sky; sampled beside the choice, or the only light), one
/// point or directional light (the only one to choose), or both; nothing else.
struct LaneLights<'a> {
    /// The environment, if any: [`Light::EnvMap`] or [`Light::Constant`].
    env: Option<&'a Light>,
    /// The point or directional light, if any.
    delta: Option<&'a Light>,
}

impl<'a> LaneLights<'a> {
    /// The lights of `scene` when they are of this kind.
    fn of(scene: &'a Scene) -> Option<LaneLights<'a>> {
        let (mut env, mut delta) = (None, None);
        for light in scene.lights() {
            match light {
                Light::EnvMap(_) | Light::Constant(_) if env.is_none() => env = Some(light),
                Light::Point(_) | Light::Directional(_) if delta.is_none() => delta = Some(light),
                _ => return None,
            }
        }
        (env.is_some() || delta.is_some()).then_some(LaneLights { env, delta })
    }
}

/// What a light sample of direction `wi` (world), radiance `li` and density `pdf` (`delta`:
/// a delta light's) adds to lane `i` of the vertices `(wo, frame, albedo, beta, on_back)`
/// where the light is seen, and whether it can add anything there (the light is on wo's side
/// and the lane's Lambertian side reflects it), as `path` weighs it.
#[inline(always)]
fn light_contribution(
    i: usize,
    (wo, frame, albedo, beta, on_back): (&V3, &Frames, &V3, &V3, &[bool; N]),
    wi: Vec3,
    li: Rgb,
    pdf: f32,
    delta: bool,
) -> (Rgb, bool) {
    let (wil, wol) = (frame.get(i).to_local(wi), wo.get(i));
    let (wim, wom) = (mirror_if(on_back[i], wil), mirror_if(on_back[i], wol));
    let upper = (wim.z > 0.0) & (wom.z > 0.0);
    let f = if upper { albedo.rgb(i) * FRAC_1_PI } else { Rgb::ZERO };
    let w = if delta { 1.0 } else { power_heuristic(pdf, cosine_hemisphere_pdf(wim.z)) };
    (beta.rgb(i) * f * li * (wil.z.abs() * w / pdf), (wil.z * wol.z > 0.0) & !f.is_black())
}

/// The step of [`PathState::step`] at the hits `hit` of lanes `lanes` (shapes of models not
/// shaded in lane arrays), from the lanes' paths as they stand: their rays `(o, d)`, throughputs,
/// results, index ratios and depths, their previous vertices, their numbers (with the map's
/// directions `env` drawn ahead) and samplers. Their hits' surface data are read in passes
/// over the lanes, so that the lanes' cache misses overlap: the corners (their indices asked
/// for already), then the texels, before the steps (`at` holds the hits). The shadow tests
/// join `queue`; a lane whose path ends leaves `alive`. Each lane's path after its step is
/// left in `stepped`.
#[inline(always)]
#[allow(clippy::type_complexity)]
fn step_by_lane(
    scene: &Scene,
    (lanes, hit, alive): (u32, &PacketHits, &mut u32),
    (o, d, beta, result, eta, depth): (&V3, &V3, &V3, &V3, &[f32; N], &[u32; N]),
    (prev_p, prev_n, prev_n_some, prev_pdf, prev_delta, has_prev): (
        &V3,
        &V3,
        &[bool; N],
        &[f32; N],
        &[bool; N],
        &[bool; N],
    ),
    (numbers, env, samplers): (&Numbers, &[Option<EnvDirection>; N], &mut Samplers16),
    (max_depth, rr_depth): (u32, u32),
    (at, stepped, queue): (&mut [SurfaceInteraction; N], &mut [PathState; N], &mut ShadowQueue),
) {
    let hit = |i: usize| hit[i].expect("a lane on a shape has a hit");
    for i in Bits(lanes) {
        scene.prefetch_vertices(hit(i).0);
    }
    for i in Bits(lanes) {
        let (k, t) = hit(i);
        at[i] = scene.interaction(&Ray::new(o.get(i), d.get(i)), k, t);
        scene.material(at[i].shape).prefetch(at[i].uv);
    }
    for i in Bits(lanes) {
        let r = RefPoint { p: prev_p.get(i), n: prev_n_some[i].then(|| prev_n.get(i)) };
        let prev = has_prev[i].then_some(Previous { r, pdf: prev_pdf[i], delta: prev_delta[i] });
        let path = &mut stepped[i];
        *path = PathState {
            result: result.rgb(i),
            beta: beta.rgb(i),
            eta: eta[i],
            depth: depth[i],
            prev,
            ray: Ray::new(o.get(i), d.get(i)),
            numbers: numbers.vertex(i, env[i]),
            ..PathState::IDLE
        };
        let mut s = samplers.get(i);
        let on =
            path.step(scene, Some(&at[i]), &mut s, max_depth, rr_depth, false, &mut |test, c| queue.push(i, test, c));
        samplers.set(i, &s);
        if !on {
            *alive &= !(1 << i);
        }
    }
}

/// The mesh of the emitting shape `shape` (an area light of these scenes lies on one).
#[inline(always)]
fn light_mesh(scene: &Scene, shape: usize) -> &TriangleMesh {
    match scene.geometry(shape) {
        Geometry::Mesh(m) => m,
        _ => unreachable!("DiffuseSurfaces takes area lights on meshes only"),
    }
}

impl DiffuseSurfaces {
    /// Next-event estimation where the lights are sampled through the scene (no area light):
    /// lane by lane, as `path` samples them, an environment map's directions `env` drawn ahead
    /// as one packet; each visible contribution is added to its lane's sum in `queue`, whose
    /// shadow tests go out sixteen at a time.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn lights_by_lane(
        &self,
        scene: &Scene,
        (numbers, env): (&Numbers, &[Option<EnvDirection>; N]),
        alive: u32,
        (p, ng, wo, frame): (&V3, &V3, &V3, &Frames),
        (albedo, beta, on_back): (&V3, &V3, &[bool; N]),
        queue: &mut ShadowQueue,
    ) {
        let surface = (wo, frame, albedo, beta, on_back);
        for i in Bits(alive) {
            let pi = p.get(i);
            let r = RefPoint { p: pi, n: Some(frame.n.get(i) * wo.z[i].signum()) };
            for ls in scene.sample_lights(&r, &numbers.light(i, env[i]), true).iter().flatten() {
                let (c, seen) = light_contribution(i, surface, ls.wi, ls.li, ls.pdf, ls.delta);
                if seen {
                    queue.push(i, scene.shadow_ray(pi, ng.get(i), ls), c);
                }
            }
        }
    }

    /// Next-event estimation where the lights are an environment (a map or a constant sky), a
    /// point or directional light, or both (see [`LaneLights`]), from the lanes' data in lane
    /// arrays: each lane's light samples as `path` draws them (the delta light's, then the
    /// environment's, a map's direction `env` drawn ahead), their contributions and shadow
    /// rays, one query of sixteen for each kind (a packet where its rays are coherent, as a
    /// point light's from nearby points are). Each lane adds its visible contributions to its
    /// sum in `lit` in the order `path` adds them, so its estimate is the same.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn lights_in_lanes(
        &self,
        scene: &Scene,
        lights: &LaneLights,
        (numbers, env): (&Numbers, &[Option<EnvDirection>; N]),
        alive: u32,
        (p, ng, wo, frame): (&V3, &V3, &V3, &Frames),
        (albedo, beta, on_back): (&V3, &V3, &[bool; N]),
        lit: &mut [Rgb; N],
    ) {
        let split = scene.splits_environment();
        let surface = (wo, frame, albedo, beta, on_back);
        let (mut delta_add, mut delta_ok, mut delta_rays) = (V3::ZERO, 0u32, [Ray::new(Vec3::ZERO, Vec3::Z); N]);
        // The delta light's sample, as `PointLight::sample` or `DirectionalLight::sample`
        // draws it, chosen with probability 1; its shadow test as `Scene::shadow_ray` makes it.
        for i in Bits(if lights.delta.is_some() { alive } else { 0 }) {
            let (pi, ngi) = (p.get(i), ng.get(i));
            let (wi, li, ray) = match lights.delta {
                Some(Light::Point(light)) => {
                    let delta = light.position - pi;
                    let dist2 = delta.length_squared();
                    if !dist2.is_finite() || dist2 <= 0.0 {
                        continue;
                    }
                    let li = light.intensity / dist2;
                    if !li.is_finite() {
                        continue;
                    }
                    (delta / dist2.sqrt(), li, spawn_ray_to(pi, ngi, light.position).0)
                }
                Some(Light::Directional(light)) => {
                    (-light.direction, light.irradiance, spawn_ray(pi, ngi, -light.direction))
                }
                _ => unreachable!("LaneLights holds a point or directional light"),
            };
            let (c, ok) = light_contribution(i, surface, wi, li, 1.0, true);
            if ok {
                delta_add.set_rgb(i, c);
                delta_ok |= 1 << i;
                delta_rays[i] = ray;
            }
        }
        let (mut env_add, mut env_ok, mut env_rays) = (V3::ZERO, 0u32, [Ray::new(Vec3::ZERO, Vec3::Z); N]);
        for i in Bits(if lights.env.is_some() { alive } else { 0 }) {
            // The environment's sample (chosen with probability 1 where it is the only
            // light): a map's as `EnvMap::light_sample` makes it of the direction drawn
            // ahead; a constant sky's as `ConstantEnv::sample` draws it, cosine-weighted about
            // the normal on wo's side, from the environment's own numbers where it is sampled
            // beside the choice, else from the choice's.
            let (pi, fr, wol) = (p.get(i), frame.get(i), wo.get(i));
            let (wi, li, pdf) = match lights.env {
                Some(Light::EnvMap(_)) => {
                    let Some(s) = &env[i] else { continue };
                    if !(s.pdf > 0.0 && s.pdf.is_finite()) {
                        continue;
                    }
                    (s.wi, s.li, s.pdf)
                }
                Some(Light::Constant(c)) => {
                    let u = if split {
                        Vec2::new(numbers.uex[i], numbers.uey[i])
                    } else {
                        Vec2::new(numbers.ux[i], numbers.uy[i])
                    };
                    let w = cosine_hemisphere(u);
                    let pdf = cosine_hemisphere_pdf(w.z);
                    let sampled = pdf > 0.0;
                    if !sampled {
                        continue;
                    }
                    (Frame::from_normal(fr.n * wol.z.signum()).to_world(w), c.radiance, pdf)
                }
                _ => unreachable!("LaneLights holds a map or a constant sky"),
            };
            let (c, ok) = light_contribution(i, surface, wi, li, pdf, false);
            if ok {
                env_add.set_rgb(i, c);
                env_ok |= 1 << i;
                env_rays[i] = spawn_ray(pi, ng.get(i), wi);
            }
        }
        let skip = [None; N];
        let blocked = |rays: &[Ray; N], lanes: u32| {
            if lanes != 0 {
                scene.occluded_packet(rays, &skip, lanes, scene.simd())
            } else {
                0
            }
        };
        let (delta_seen, env_seen) = (delta_ok & !blocked(&delta_rays, delta_ok), env_ok & !blocked(&env_rays, env_ok));
        for i in Bits(alive) {
            if delta_seen >> i & 1 != 0 {
                lit[i] += delta_add.rgb(i);
            }
            if env_seen >> i & 1 != 0 {
                lit[i] += env_add.rgb(i);
            }
        }
    }

    /// The estimates of [`path::li`](super::path::li) along camera rays `rays`, each drawing
    /// from its sampler in `samplers`, written to `out`, without the finite-value filter.
    pub(super) fn li(
        &self,
        scene: &Scene,
        rays: &[Ray],
        samplers: &[Sampler],
        out: &mut [Rgb],
        max_depth: u32,
        rr_depth: u32,
    ) {
        dispatch!(scene.simd(), self: DiffuseSurfaces, trace::<AVX>(scene: &Scene, rays: &[Ray], samplers: &[Sampler],
            out: &mut [Rgb], max_depth: u32, rr_depth: u32) -> ())
    }

    #[inline(always)]
    #[allow(clippy::needless_range_loop)]
    fn trace<const AVX: bool>(
        &self,
        scene: &Scene,
        rays: &[Ray],
        samplers: &[Sampler],
        out: &mut [Rgb],
        max_depth: u32,
        rr_depth: u32,
    ) {
        if max_depth == 0 {
            out.fill(Rgb::ZERO);
            return;
        }
        // The area light, or None where the lights are sampled through the scene lane by lane.
        let light = self.area.map(|(shape, _)| light_mesh(scene, shape));
        let (light_shape, le) = self.area.unwrap_or((usize::MAX, Rgb::ZERO));
        // The area densities of `Geometry::pdf` and of `TriangleMesh::sample_area`.
        let light_area = light.map_or(1.0, |l| l.area());
        let inv_light_area = 1.0 / light_area;
        let light_pdf_area = 1.0 / light_area.max(f32::MIN_POSITIVE);
        let emits = !le.is_black();
        let lane_lights = if light.is_none() { LaneLights::of(scene) } else { None };
        let split = scene.splits_environment();
        let mut queue = ShadowQueue::new(scene);
        let (mut o, mut d) = (V3::ZERO, V3::ZERO);
        let mut hit: PacketHits = [None; N];
        // Each lane's throughput and the emission its path found; the visible contributions of
        // its light samples (the area light's or those tested through the queue) sum in `queue.lit`.
        // Each lane's product of the index ratios its path crossed (at lanes shaded one by one).
        let (mut beta, mut result, mut eta) = (V3::ZERO, V3::ZERO, [1.0f32; N]);
        let mut depth = [0u32; N];
        // The previous vertex (its point, BRDF sample density and whether that took a delta
        // lobe), for the MIS weight of the emission found next; none for the camera.
        let (mut prev_p, mut prev_pdf, mut prev_delta, mut has_prev) = (V3::ZERO, [0.0f32; N], [false; N], [false; N]);
        // Its reference normal, for the MIS weight of an environment found next (none where its
        // model transmits: `prev_n_some` false).
        let (mut prev_n, mut prev_n_some) = (V3::ZERO, [true; N]);
        // Lanes on a path, and lanes holding a sample (index `sample`) whose estimate is not
        // yet written.
        let (mut alive, mut held, mut sample, mut next) = (0u32, 0u32, [0usize; N], 0usize);
        let mut lane_samplers = Samplers16::new(&Sampler::new(0, 0, 0));
        let mut numbers = Numbers::ZERO;
        let (mut corners, mut light_corners) = (Corners::new(), Corners::new());
        let (mut shape, mut albedo) = ([0usize; N], V3::ZERO);
        // Each lane's barycentrics on its triangle.
        let mut bary = [Vec2::ZERO; N];
        // Per lane: the front and back albedos, whether the back scatters, and whether the
        // path arrived on the back (where the back model sees mirrored directions).
        let (mut front, mut back, mut two_sided, mut on_back) = (V3::ZERO, V3::ZERO, [false; N], [false; N]);
        let (mut p, mut ng, mut wo) = (V3::ZERO, V3::ZERO, V3::ZERO);
        let mut frame = Frames { s: V3::ZERO, t: V3::ZERO, n: V3::ZERO };
        let mut camera = [Ray::new(Vec3::ZERO, Vec3::Z); N];
        // Where each lane's ray falls on the environment map, looked up as a packet ahead of
        // the query, for the paths that escape.
        let map = scene.environment_map().is_some();
        let mut looked: [Option<EnvLookup>; N] = [None; N];
        // The hits and paths of the lanes of other models at their steps, kept from step to
        // step (made afresh at every step, these arrays cost the Cornell box with glass boxes
        // 6 % more time).
        let (mut at, mut stepped) = ([SurfaceInteraction::PROBE; N], [PathState::IDLE; N]);
        loop {
            // Path regeneration: a lane whose path ended writes its estimate and takes the next
            // camera sample, which draws its first numbers before its ray's query as `path`
            // does; the new lanes' camera rays go out as one packet.
            let mut fresh = 0u32;
            queue.settle(held & !alive);
            for i in Bits(!alive & (u32::MAX >> (32 - N))) {
                if held >> i & 1 == 1 {
                    out[sample[i]] = result.rgb(i) + queue.lit[i];
                    held &= !(1 << i);
                }
                if next == rays.len() {
                    continue;
                }
                (sample[i], next) = (next, next + 1);
                let mut s = samplers[sample[i]].clone();
                numbers.set(i, &VertexNumbers::draw(&mut s, scene));
                lane_samplers.set(i, &s);
                camera[i] = rays[sample[i]];
                o.set(i, camera[i].o);
                d.set(i, camera[i].d);
                beta.set(i, Vec3::ONE);
                result.set(i, Vec3::ZERO);
                queue.lit[i] = Rgb::ZERO;
                (depth[i], has_prev[i], eta[i]) = (0, false, 1.0);
                fresh |= 1 << i;
            }
            // Fewer go one by one, each walk inlined here (the packet query would take them
            // one by one too, through a dispatch each).
            if fresh.count_ones() >= PACKET_MIN {
                let hits = scene.intersect_t_packet(&camera, fresh, scene.simd());
                for i in Bits(fresh) {
                    hit[i] = hits[i];
                }
            } else {
                for i in Bits(fresh) {
                    hit[i] = scene.intersect_t_in::<AVX>(&camera[i]);
                }
            }
            (alive, held) = (alive | fresh, held | fresh);
            if alive == 0 {
                break;
            }
            if map {
                let missed = Bits(fresh).filter(|&i| hit[i].is_none()).fold(0u32, |m, i| m | 1 << i);
                if missed != 0 {
                    let found =
                        scene.prefetch_environment_packet(&std::array::from_fn(|i| d.get(i)), missed, scene.simd());
                    for i in Bits(missed) {
                        looked[i] = found[i];
                    }
                }
            }
            // Lanes on a Lambertian shape that is not a mesh (its hit found through the scene,
            // lane by lane), lanes with a side whose albedo varies (found once the uv is known),
            // and lanes on a shape of another model (shaded lane by lane, as `path` shades).
            let (mut analytic, mut varying, mut generic) = (0u32, 0u32, 0u32);
            // Escaped paths end, lit by the environment where there is one.
            for i in Bits(alive) {
                match hit[i] {
                    Some((k, _)) => {
                        let (s, tri) = scene.primitive(k);
                        shape[i] = s as usize;
                        let Some((a, b)) = &self.albedo[s as usize] else {
                            scene.prefetch_indices(k);
                            generic |= 1 << i;
                            continue;
                        };
                        let fixed = |side: &Albedo| side.constant().unwrap_or(Rgb::ZERO);
                        if a.constant().is_none() || b.as_ref().is_some_and(|b| b.constant().is_none()) {
                            varying |= 1 << i;
                        }
                        front.set_rgb(i, fixed(a));
                        back.set_rgb(i, fixed(b.as_ref().unwrap_or(a)));
                        two_sided[i] = b.is_some();
                        match scene.geometry(s as usize) {
                            Geometry::Mesh(m) => corners.load(i, m, tri as usize),
                            _ => analytic |= 1 << i,
                        }
                    }
                    None => {
                        let from = (has_prev[i] && !prev_delta[i])
                            .then(|| RefPoint { p: prev_p.get(i), n: prev_n_some[i].then(|| prev_n.get(i)) });
                        if let Some((le, pdf)) =
                            scene.environment_eval_at(d.get(i), looked[i].as_ref(), from.as_ref(), true)
                        {
                            let w = if from.is_some() { power_heuristic(prev_pdf[i], pdf) } else { 1.0 };
                            result.set_rgb(i, result.rgb(i) + beta.rgb(i) * le * w);
                        }
                        alive &= !(1 << i);
                    }
                }
            }
            // The hit points and their frames on meshes, as `Scene::interaction` finds them
            // (skipped where no lane is on one).
            if alive & !analytic & !generic != 0 {
                for i in 0..N {
                    let (p0, p1, p2) = (corners.corner(i, 0), corners.corner(i, 1), corners.corner(i, 2));
                    let (e1, e2) = (p1 - p0, p2 - p0);
                    let (b1, b2) = barycentrics(o.get(i), d.get(i), p0, e1, e2);
                    bary[i] = Vec2::new(b1, b2);
                    let (pi, ngi, ns) = corners.surface(i, b1, b2);
                    // Multiplying by the sign again undoes the flip exactly.
                    let f = frame_of(ns, corners.dp_du(i, ngi * corners.sign[i]));
                    let w = f.to_local(-d.get(i));
                    p.set(i, pi);
                    ng.set(i, ngi);
                    wo.set(i, w);
                    frame.set(i, &f);
                    on_back[i] = w.z < 0.0;
                    albedo.set_rgb(i, if on_back[i] { back.rgb(i) } else { front.rgb(i) });
                }
            }
            // Spheres, rectangles and disks: their hits as the scene finds them (with the uvs
            // that varying albedos are looked up at).
            let mut uv = [Vec2::ZERO; N];
            for i in Bits(analytic) {
                let Some((k, t)) = hit[i] else { continue };
                let si = scene.interaction(&Ray::new(o.get(i), d.get(i)), k, t);
                let w = si.frame.to_local(-d.get(i));
                p.set(i, si.p);
                ng.set(i, si.ng);
                wo.set(i, w);
                frame.set(i, &si.frame);
                on_back[i] = w.z < 0.0;
                albedo.set_rgb(i, if on_back[i] { back.rgb(i) } else { front.rgb(i) });
                uv[i] = si.uv;
            }
            // The sides' texels are asked for in one pass and read in the next, so that the
            // lanes' cache misses overlap.
            let side = |i: usize| {
                let (a, b) = self.albedo[shape[i]].as_ref().expect("a Lambertian lane's shape");
                if on_back[i] {
                    b.as_ref().unwrap_or(a)
                } else {
                    a
                }
            };
            for i in Bits(varying) {
                if analytic >> i & 1 == 0 {
                    uv[i] = corners.uv(i, bary[i].x, bary[i].y);
                }
                side(i).prefetch(uv[i]);
            }
            for i in Bits(varying) {
                albedo.set_rgb(i, side(i).at(uv[i]));
            }
            // Emission found by the previous vertex's BRDF sample (or seen by the camera).
            for i in Bits(alive & !generic) {
                if !(emits && shape[i] == light_shape && frame.n.get(i).dot(-d.get(i)) > 0.0) {
                    continue;
                }
                let w = if has_prev[i] && !prev_delta[i] {
                    let (pdf, ok) = solid_angle_pdf(inv_light_area, prev_p.get(i), p.get(i), ng.get(i));
                    power_heuristic(prev_pdf[i], if ok { pdf } else { 0.0 })
                } else {
                    1.0
                };
                result.set_rgb(i, result.rgb(i) + beta.rgb(i) * le * w);
            }
            // Paths that reached their last vertex, or a one-sided model's back, end.
            for i in Bits(alive & !generic) {
                if depth[i].saturating_add(1) >= max_depth || wo.z[i] == 0.0 || (on_back[i] && !two_sided[i]) {
                    alive &= !(1 << i);
                }
            }
            if alive == 0 {
                // All ended: their estimates are written and the lanes refilled at the top.
                continue;
            }
            // The map's directions for the light numbers of the lanes that sample lights.
            let lighting = Bits(generic).fold(alive, |m, i| m & !((scene.delta_only(shape[i]) as u32) << i));
            let env = scene.presample_environment_packet(lighting, |i| numbers.light(i, None));
            // The lanes of other models take `path`'s step, one by one; their shadow tests
            // join the queue.
            step_by_lane(
                scene,
                (generic, &hit, &mut alive),
                (&o, &d, &beta, &result, &eta, &depth),
                (&prev_p, &prev_n, &prev_n_some, &prev_pdf, &prev_delta, &has_prev),
                (&numbers, &env, &mut lane_samplers),
                (max_depth, rr_depth),
                (&mut at, &mut stepped, &mut queue),
            );
            for i in Bits(generic) {
                result.set_rgb(i, stepped[i].result);
            }
            // The queue's tests are answered as it fills, over several steps; a lane's sum is
            // made whole before anything is added to it directly, so that it adds in `path`'s
            // order.
            let shaded = alive & !generic;
            if light.is_some() || lane_lights.is_some() {
                queue.settle(shaded);
            }
            // Next-event estimation: a point on the light, its contribution and shadow ray.
            if let Some(light) = light {
                for i in Bits(shaded) {
                    light_corners.load(i, light, light.sampled_triangle(numbers.uc2[i]));
                }
                let (mut add, mut add_ok) = (V3::ZERO, [false; N]);
                let (mut so, mut sd, mut s_tmax, mut s_test, mut s_skip) =
                    (V3::ZERO, V3::ZERO, [0.0f32; N], [false; N], [false; N]);
                for i in 0..N {
                    let b = uniform_triangle(Vec2::new(numbers.ux[i], numbers.uy[i]));
                    let (lp, lng, lns) = light_corners.surface(i, b.x, b.y);
                    let (pi, ngi) = (p.get(i), ng.get(i));
                    let (pdf, pdf_ok) = solid_angle_pdf(light_pdf_area, pi, lp, lng);
                    let delta = lp - pi;
                    let dist = delta.length();
                    let wi = delta / dist;
                    let sampled = pdf_ok & (lns.dot(-wi) > 0.0) & emits & (dist > 0.0);
                    let (c, seen) = light_contribution(i, (&wo, &frame, &albedo, &beta, &on_back), wi, le, pdf, false);
                    add.set_rgb(i, c);
                    add_ok[i] = sampled & seen;
                    // The shadow test of `Scene::shadow_ray`: to the point, short of it; along
                    // the direction when the point is too far for a distance.
                    let (to, _, dist2) = spawn_ray_to(pi, ngi, lp);
                    let tolerance = 1e-3 * dist2 + surface_epsilon(lp);
                    let t_max = (lp - to.o).length() - tolerance;
                    let far = !dist.is_finite();
                    so.set(i, if far { offset_origin(pi, ngi, wi) } else { to.o });
                    sd.set(i, if far { wi } else { to.d });
                    s_tmax[i] = if far { f32::INFINITY } else { t_max };
                    s_test[i] = far | (t_max > 0.0);
                    s_skip[i] = !far;
                }
                let (mut adds, mut tested) = (0u32, 0u32);
                let mut shadow_rays = [Ray::new(Vec3::ZERO, Vec3::Z); N];
                let mut skip = [None; N];
                for i in Bits(shaded) {
                    if add_ok[i] {
                        adds |= 1 << i;
                        if s_test[i] {
                            tested |= 1 << i;
                            shadow_rays[i] = Ray { o: so.get(i), d: sd.get(i), t_max: s_tmax[i] };
                            skip[i] = s_skip[i].then_some(light_shape as u32);
                        }
                    }
                }
                let blocked =
                    if tested != 0 { scene.occluded_packet(&shadow_rays, &skip, tested, scene.simd()) } else { 0 };
                for i in Bits(adds & !blocked) {
                    queue.lit[i] += add.rgb(i);
                }
            } else if let Some(lights) = &lane_lights {
                self.lights_in_lanes(
                    scene,
                    lights,
                    (&numbers, &env),
                    shaded,
                    (&p, &ng, &wo, &frame),
                    (&albedo, &beta, &on_back),
                    &mut queue.lit,
                );
            } else {
                self.lights_by_lane(
                    scene,
                    (&numbers, &env),
                    shaded,
                    (&p, &ng, &wo, &frame),
                    (&albedo, &beta, &on_back),
                    &mut queue,
                );
            }
            // BRDF sampling: the direction each path continues in.
            let mut wi_z = [0.0f32; N];
            for i in 0..N {
                let wi = cosine_hemisphere(Vec2::new(numbers.bx[i], numbers.by[i]));
                wi_z[i] = wi.z;
                let (pi, dir) = (p.get(i), frame.get(i).to_world(mirror_if(on_back[i], wi)));
                o.set(i, offset_origin(pi, ng.get(i), dir));
                d.set(i, dir);
                prev_pdf[i] = cosine_hemisphere_pdf(wi.z);
                beta.set_rgb(i, beta.rgb(i) * albedo.rgb(i));
            }
            prev_p = p;
            for i in 0..N {
                prev_n.set(i, frame.n.get(i) * wo.z[i].signum());
            }
            (has_prev, prev_delta, prev_n_some) = ([true; N], [false; N], [true; N]);
            // The lanes of other models continue as their steps left them.
            for i in Bits(alive & generic) {
                let ps = &stepped[i];
                let pv = ps.prev.as_ref().expect("a path that goes on has a previous vertex");
                o.set(i, ps.ray.o);
                d.set(i, ps.ray.d);
                beta.set_rgb(i, ps.beta);
                (eta[i], depth[i], prev_pdf[i], prev_delta[i]) = (ps.eta, ps.depth, pv.pdf, pv.delta);
                prev_p.set(i, pv.r.p);
                prev_n.set(i, pv.r.n.unwrap_or(Vec3::ZERO));
                prev_n_some[i] = pv.r.n.is_some();
            }
            for i in Bits(shaded) {
                // The sample must lie above the model's own side, and on wo's side.
                let usable = wi_z[i] > 0.0 && (if on_back[i] { -wi_z[i] } else { wi_z[i] }) * wo.z[i] > 0.0;
                if !usable {
                    alive &= !(1 << i);
                    continue;
                }
                depth[i] += 1;
                // Russian roulette, as `path` plays it (η from the lanes' other models).
                let b = beta.rgb(i);
                let q = (b.max_channel() * eta[i] * eta[i]).min(0.95);
                if depth[i] >= rr_depth {
                    if lane_samplers.next_1d_lane(i) >= q {
                        alive &= !(1 << i);
                        continue;
                    }
                    beta.set_rgb(i, b / q);
                }
                if beta.rgb(i).max_channel() <= 0.0 {
                    alive &= !(1 << i);
                }
            }
            numbers = draw(&mut lane_samplers, split);
            if map {
                looked = scene.prefetch_environment_packet(&std::array::from_fn(|i| d.get(i)), alive, scene.simd());
            }
            for i in Bits(alive) {
                hit[i] = scene.intersect_t_in::<AVX>(&Ray::new(o.get(i), d.get(i)));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::camera::{look_at, Camera, FovAxis};
    use crate::integrator::batch_check::{assert_batches_match, camera_samples, patchy_map};
    use crate::integrator::Integrator;
    use crate::light::point::PointLight;
    use crate::light::{ConstantEnv, DirectionalLight, Light};
    use crate::material::Material;
    use crate::ray::Ray;
    use crate::sampler::Sampler;
    use crate::scene::{Scene, SceneBuilder, Shape};
    use crate::shape::{sphere::Sphere, Geometry, TriangleMesh};
    use crate::simd::{Simd, LANES};
    use crate::texture::Texture;
    use glam::{Vec2, Vec3};
    use radiometry::Rgb;
    use std::sync::Arc;

    /// The cube [−1, 1]³, its faces towards the inside, transformed by `f`, with vertex
    /// normals (towards the inside) and uvs when `smooth`.
    fn cube(f: impl Fn(Vec3) -> Vec3, smooth: bool) -> TriangleMesh {
        let (mut pos, mut idx) = (Vec::new(), Vec::new());
        for axis in 0..3 {
            for s in [-1.0f32, 1.0] {
                let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
                let base = pos.len() as u32;
                for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                    let mut p = Vec3::ZERO;
                    (p[axis], p[u], p[v]) = (s, a, b);
                    pos.push(p);
                }
                let inward = (pos[base as usize + 1] - pos[base as usize])
                    .cross(pos[base as usize + 2] - pos[base as usize])[axis]
                    * s
                    < 0.0;
                idx.extend(if inward {
                    [[base, base + 1, base + 2], [base, base + 2, base + 3]]
                } else {
                    [[base, base + 2, base + 1], [base, base + 3, base + 2]]
                });
            }
        }
        let normals = smooth.then(|| pos.iter().map(|p: &Vec3| -p.normalize()).collect());
        // The smooth box has uvs too, degenerate (u = v) on the two faces across z.
        let uv = |(k, p): (usize, &Vec3)| Vec2::new(p.x + p.y, if k / 8 == 2 { p.x + p.y } else { p.y + p.z });
        let uvs = smooth.then(|| pos.iter().enumerate().map(uv).collect());
        TriangleMesh::with_uvs(pos.into_iter().map(f).collect(), normals, uvs, idx).unwrap()
    }

    fn lambert(albedo: [f32; 3]) -> Arc<dyn brdf::Brdf> {
        Arc::new(brdf::lambert::Lambert { albedo: Rgb(albedo) })
    }

    /// Adds the room's contents: a smooth-shaded, uv-mapped box (its normals flipped to face
    /// out) and a sheet standing in the room, different on its two sides; with `others`, shapes
    /// of models that are not Lambert's too: a glass ball (delta lobes only, η ≠ 1), a rough
    /// metal box, a ball that lets part of the light through (a mask over two-sided Lambert)
    /// and a sheet of rough metal on both sides.
    fn furnish(b: &mut SceneBuilder, others: bool) {
        let mut block = cube(|p| p * 0.3 + Vec3::new(0.3, -0.7, -0.4), true);
        block.flip = true;
        b.shape(Shape::new(Geometry::Mesh(block), lambert([0.2, 0.8, 0.4])));
        let sheet = vec![Vec3::new(-0.4, -1.0, -0.9), Vec3::new(-0.4, 0.2, -0.9), Vec3::new(-0.4, 0.2, -0.1)];
        let sides = |a| Box::new(Material::Fixed(lambert(a)));
        let two_sided = Material::TwoSided(sides([0.9, 0.1, 0.1]), sides([0.1, 0.2, 0.9]));
        b.shape(Shape::new(Geometry::Mesh(TriangleMesh::new(sheet, None, vec![[0, 1, 2]]).unwrap()), two_sided));
        if !others {
            return;
        }
        b.shape_with_model(Geometry::Sphere(Sphere::new(Vec3::new(-0.1, -0.75, -0.3), 0.25)), "dielectric", &[])
            .unwrap();
        let metal = cube(|p| p * 0.15 + Vec3::new(0.05, 0.1, -0.7), false);
        b.shape_with_model(Geometry::Mesh(metal), "ggx", &[("alpha", "0.3")]).unwrap();
        let nested = Box::new(Material::TwoSided(sides([0.8, 0.8, 0.2]), sides([0.3, 0.3, 0.9])));
        let mask = Material::Mask { opacity: Texture::Constant(Rgb::splat(0.6)), nested };
        b.shape(Shape::new(Geometry::Sphere(Sphere::new(Vec3::new(0.55, -0.1, -0.5), 0.2)), mask));
        let metal = || Box::new(Material::Fixed(brdf::build("ggx", &[("alpha", "0.2")]).unwrap().into()));
        let sheet = vec![Vec3::new(-0.9, -1.0, -0.2), Vec3::new(-0.6, -0.1, -0.6), Vec3::new(-0.6, -1.0, -0.9)];
        let mesh = TriangleMesh::new(sheet, None, vec![[0, 1, 2]]).unwrap();
        b.shape(Shape::new(Geometry::Mesh(mesh), Material::TwoSided(metal(), metal())));
    }

    /// A room with a smooth-shaded, uv-mapped box in it (its normals flipped to face out) and a
    /// two-sided sheet (and the `others` of [`furnish`]), lit by a square mesh light under the
    /// ceiling.
    fn room(others: bool) -> Scene {
        let cam = Camera::new(
            look_at(Vec3::new(0.0, 0.0, 0.9), Vec3::new(0.0, -0.2, -1.0), Vec3::Y).unwrap(),
            70.0,
            FovAxis::X,
            16,
            12,
        );
        let mut b = SceneBuilder::new(cam);
        b.shape(Shape::new(Geometry::Mesh(cube(|p| p, false)), lambert([0.7, 0.5, 0.3])));
        furnish(&mut b, others);
        let (s, y) = (0.3, 0.98);
        let square = vec![Vec3::new(-s, y, -s), Vec3::new(s, y, -s), Vec3::new(s, y, s), Vec3::new(-s, y, s)];
        let square = TriangleMesh::new(square, None, vec![[0, 1, 2], [0, 2, 3]]).unwrap();
        let mut light = Shape::new(Geometry::Mesh(square), lambert([0.5; 3]));
        light.emission = Some(Texture::Constant(Rgb::new(6.0, 5.0, 4.0)));
        b.shape(light);
        b.build().unwrap()
    }

    /// The room's contents (with the `others` of [`furnish`]) on a floor, open to the sky, lit
    /// by `lights`, seen so that some camera rays escape.
    fn open_sky(lights: Vec<Light>, others: bool) -> Scene {
        let cam = Camera::new(
            look_at(Vec3::new(0.2, 0.6, 1.6), Vec3::new(0.0, -0.6, -0.5), Vec3::Y).unwrap(),
            70.0,
            FovAxis::X,
            16,
            12,
        );
        let mut b = SceneBuilder::new(cam);
        furnish(&mut b, others);
        let (s, y) = (1.5, -1.0);
        let floor = vec![Vec3::new(-s, y, s), Vec3::new(s, y, s), Vec3::new(s, y, -s), Vec3::new(-s, y, -s)];
        let floor = TriangleMesh::new(floor, None, vec![[0, 1, 2], [0, 2, 3]]).unwrap();
        b.shape(Shape::new(Geometry::Mesh(floor), lambert([0.6, 0.6, 0.5])));
        for light in lights {
            b.light(light);
        }
        b.build().unwrap()
    }

    /// Asserts that `scene` is one of the batch integrator's and, on every instruction set, for
    /// three depth settings, that lanes refilled from batches of every size (the whole image, a
    /// few packets and a remainder, one packet, fewer samples than lanes) give each sample its
    /// one-ray estimate, more than 100 of them lit.
    fn lit_in_batches(scene: &mut Scene, rays: &[Ray], samplers: &[Sampler], label: &str) {
        assert!(scene.diffuse_surfaces().is_some(), "{label} is a scene of the batch integrator");
        let mut lit = 0;
        for simd in Simd::ALL.map(|(_, s)| s).into_iter().filter(|s| s.available()) {
            scene.set_simd(simd);
            for integrator in [Integrator::path(8, 3), Integrator::path(2, 5), Integrator::default()] {
                let batches = [rays.len(), 37, LANES, 5];
                let one = assert_batches_match(scene, integrator, rays, samplers, &batches, label);
                lit += one.iter().filter(|l| l.max_channel() > 0.0).count();
            }
        }
        assert!(lit > 100, "{label}: {lit} lit estimates");
    }

    #[test]
    fn lanes_lit_through_the_scene_give_each_path_its_one_ray_estimate_bit_for_bit() {
        let point = Light::Point(PointLight { position: Vec3::new(0.5, 1.0, 0.5), intensity: Rgb::splat(2.0) });
        let sun = Light::Directional(DirectionalLight {
            direction: Vec3::new(-0.3, -1.0, -0.2).normalize(),
            irradiance: Rgb::new(2.0, 1.8, 1.5),
        });
        let map = || Light::EnvMap(Box::new(patchy_map()));
        let sky = Light::Constant(ConstantEnv { radiance: Rgb::new(0.8, 1.0, 1.2) });
        // Each kind of light sampled in lane arrays, alone and beside each environment, and two
        // point lights beside the map (sampled lane by lane).
        let lights = [
            vec![map()],
            vec![map(), point.clone()],
            vec![map(), sun.clone()],
            vec![sky.clone()],
            vec![sky, point.clone()],
            vec![point.clone()],
            vec![sun],
            vec![map(), point.clone(), point],
        ];
        for lights in lights {
            let mut scene = open_sky(lights, false);
            let (rays, samplers) = camera_samples(&scene, 7, 3);
            let escaping = rays.iter().filter(|r| scene.intersect(r).is_none()).count();
            assert!(escaping > rays.len() / 10 && escaping < rays.len() / 2, "{escaping} of {} escape", rays.len());
            lit_in_batches(&mut scene, &rays, &samplers, "open sky");
        }
    }

    /// Spheres, rectangles, a disk and a cube, of constant and checkered albedos (a two-sided
    /// sheet checkered in front only, its back in view), lit by a lamp (an emitting cube) or
    /// by a sky and a point.
    fn shapes_scene(lamp: bool) -> Scene {
        let lights = if lamp {
            r#"<shape type="cube"><transform name="to_world"><scale value="0.2"/><translate y="2.5"/></transform>
                <bsdf type="diffuse"/><emitter type="area"><rgb name="radiance" value="9, 8, 6"/></emitter></shape>"#
        } else {
            r#"<emitter type="constant"><rgb name="radiance" value="0.6, 0.7, 0.9"/></emitter>
               <emitter type="point"><point name="position" x="1" y="2" z="1"/>
                   <rgb name="intensity" value="3"/></emitter>"#
        };
        let xml = format!(
            r#"<scene version="3.0.0">
            <sensor type="perspective"><float name="fov" value="60"/>
                <transform name="to_world"><lookat origin="0, 1.6, 3.2" target="0, 0.3, 0" up="0, 1, 0"/></transform>
                <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="12"/></film>
            </sensor>
            <texture type="checkerboard" id="checks">
                <rgb name="color0" value="0.8, 0.3, 0.2"/><rgb name="color1" value="0.1, 0.5, 0.7"/>
                <transform name="to_uv"><scale x="5" y="5"/></transform>
            </texture>
            <shape type="rectangle"><transform name="to_world"><rotate x="1" angle="-90"/><scale value="2"/></transform>
                <bsdf type="diffuse"><ref name="reflectance" id="checks"/></bsdf></shape>
            <shape type="sphere"><point name="center" x="-0.8" y="0.5" z="0"/><float name="radius" value="0.5"/>
                <bsdf type="diffuse"><rgb name="reflectance" value="0.6, 0.6, 0.3"/></bsdf></shape>
            <shape type="cube">
                <transform name="to_world"><scale value="0.3"/><translate x="0.7" y="0.3" z="0.3"/></transform>
                <bsdf type="diffuse"><ref name="reflectance" id="checks"/></bsdf></shape>
            <shape type="rectangle"><boolean name="flip_normals" value="true"/><transform name="to_world">
                <scale value="0.5"/><rotate y="1" angle="150"/><translate x="0.1" y="0.5" z="-0.6"/></transform>
                <bsdf type="twosided"><bsdf type="diffuse"><ref name="reflectance" id="checks"/></bsdf>
                    <bsdf type="diffuse"><rgb name="reflectance" value="0.2, 0.7, 0.3"/></bsdf></bsdf></shape>
            <shape type="disk"><transform name="to_world">
                <scale value="0.3"/><rotate x="1" angle="-60"/><translate x="-0.2" y="0.2" z="0.9"/></transform>
                <bsdf type="diffuse"><rgb name="reflectance" value="0.9, 0.9, 0.9"/></bsdf></shape>
            {lights}
            </scene>"#
        );
        from_xml(&xml)
    }

    /// The scene of XML text `xml`.
    fn from_xml(xml: &str) -> Scene {
        crate::xml::load_scene_str(xml, std::path::Path::new("."), &[]).unwrap().scene
    }

    #[test]
    fn lanes_on_shapes_and_textured_albedos_give_each_path_its_one_ray_estimate_bit_for_bit() {
        for lamp in [false, true] {
            let mut scene = shapes_scene(lamp);
            let (rays, samplers) = camera_samples(&scene, 5, 3);
            // Every shape but the lamp is in view.
            let seen: std::collections::HashSet<_> =
                rays.iter().filter_map(|r| scene.intersect(r)).map(|si| si.shape).collect();
            assert!((0..5).all(|s| seen.contains(&s)), "shapes seen: {seen:?}");
            let label = if lamp { "shapes under a lamp" } else { "shapes under a sky" };
            lit_in_batches(&mut scene, &rays, &samplers, label);
        }
    }

    #[test]
    fn scenes_without_a_mesh_or_seen_mostly_on_other_models_stay_with_the_packet_path() {
        let xml = r#"<scene version="3.0.0"><sensor type="perspective"/>
            <shape type="sphere"><bsdf type="diffuse"/></shape><emitter type="constant"/></scene>"#;
        assert!(from_xml(xml).diffuse_surfaces().is_none());
        assert!(shapes_scene(false).diffuse_surfaces().is_some());
        // A cube in front and a ball beside it: the batch tracer where the cube is Lambertian.
        let pair = |cube: &str, ball: &str| {
            from_xml(&format!(
                r#"<scene version="3.0.0"><sensor type="perspective"><transform name="to_world">
                    <lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform></sensor>
                <shape type="cube"><bsdf type="{cube}"/></shape>
                <shape type="sphere"><point name="center" x="1.4" y="1.4" z="0"/><float name="radius" value="0.3"/>
                    <bsdf type="{ball}"/></shape><emitter type="constant"/></scene>"#
            ))
        };
        assert!(pair("diffuse", "roughconductor").diffuse_surfaces().is_some());
        assert!(pair("roughconductor", "diffuse").diffuse_surfaces().is_none());
    }

    #[test]
    fn lanes_on_other_models_give_each_path_its_one_ray_estimate_bit_for_bit() {
        let point = || Light::Point(PointLight { position: Vec3::new(0.5, 1.0, 0.5), intensity: Rgb::splat(2.0) });
        let map = || Light::EnvMap(Box::new(patchy_map()));
        let sky = Light::Constant(ConstantEnv { radiance: Rgb::new(0.8, 1.0, 1.2) });
        // The lights sampled in lane arrays, those sampled lane by lane, and the area light.
        let scenes = [
            open_sky(vec![map(), point()], true),
            open_sky(vec![sky], true),
            open_sky(vec![map(), point(), point()], true),
            room(true),
        ];
        for mut scene in scenes {
            let (rays, samplers) = camera_samples(&scene, 7, 3);
            // The four shapes of other models are in view.
            let seen: std::collections::HashSet<_> =
                rays.iter().filter_map(|r| scene.intersect(r)).map(|si| si.shape).collect();
            let albedo = &scene.diffuse_surfaces().expect("a scene of the batch integrator").albedo;
            let others = seen.iter().filter(|&&s| albedo[s].is_none()).count();
            assert_eq!(others, 4, "shapes seen: {seen:?}");
            lit_in_batches(&mut scene, &rays, &samplers, "other models");
        }
    }

    #[test]
    fn sixteen_lanes_give_each_path_its_one_ray_estimate_bit_for_bit() {
        let mut scene = room(false);
        let (rays, samplers) = camera_samples(&scene, 11, 3);
        lit_in_batches(&mut scene, &rays, &samplers, "room");
    }
}
