//! A scene: a camera, shapes each with a material (and optionally an emission), lights, and
//! the BVH over every primitive. Built once with [`SceneBuilder`], then only read.

mod diffuse;
mod few;
mod light_choice;
mod light_sample;
mod packet;
mod walk;

pub(crate) use diffuse::{Albedo, DiffuseSurfaces};
pub use light_sample::LightNumbers;
pub(crate) use packet::PACKET_MIN;
pub use packet::{lanes_of, PacketHits};

use crate::bvh::{Bvh, Tri16};
use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::light::{AreaLight, Light, LightSample};
use crate::material::Material;
use crate::ray::{spawn_ray, spawn_ray_to, surface_epsilon, Ray};
use crate::shape::mesh::intersect_triangle;
use crate::shape::{Geometry, SurfacePoint};
use crate::simd::{dispatch, Simd};
use crate::texture::Texture;
use glam::{Vec2, Vec3};
use radiometry::Frame;

/// A shape with its material and, when it glows, its emitted radiance.
#[derive(Clone, Debug)]
pub struct Shape {
    /// The geometry, in world space.
    pub geometry: Geometry,
    /// How it scatters.
    pub material: Material,
    /// Radiance emitted from the side its shading normal faces, W/(m²·sr), over its uv;
    /// makes it an area light.
    pub emission: Option<Texture>,
}

impl Shape {
    /// A non-emitting shape.
    pub fn new(geometry: Geometry, material: impl Into<Material>) -> Self {
        Shape { geometry, material: material.into(), emission: None }
    }
}

/// Where a ray meets a surface.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceInteraction {
    /// The hit distance along the ray.
    pub t: f32,
    /// The point.
    pub p: Vec3,
    /// Unit geometric normal.
    pub ng: Vec3,
    /// Shading frame (its `n` is the shading normal, its `s` follows ∂p/∂u).
    pub frame: Frame,
    /// Surface coordinates.
    pub uv: Vec2,
    /// ∂p/∂u.
    pub dp_du: Vec3,
    /// ∂p/∂v.
    pub dp_dv: Vec3,
    /// The shape's index.
    pub shape: usize,
}

impl SurfaceInteraction {
    /// A point at the origin facing +z with uv (½, ½), where a material may be built to learn
    /// what does not depend on the point.
    pub const PROBE: SurfaceInteraction = SurfaceInteraction {
        t: 1.0,
        p: Vec3::ZERO,
        ng: Vec3::Z,
        frame: Frame { s: Vec3::X, t: Vec3::Y, n: Vec3::Z },
        uv: Vec2::splat(0.5),
        dp_du: Vec3::X,
        dp_dv: Vec3::Y,
        shape: 0,
    };

    /// The interaction at surface point `s` of shape `shape`, `t` along the ray.
    pub fn new(t: f32, s: &SurfacePoint, shape: usize) -> Self {
        Self::with_frame(t, s, s.frame(), shape)
    }

    /// [`new`](Self::new) with `s`'s shading frame already made.
    #[inline]
    fn with_frame(t: f32, s: &SurfacePoint, frame: Frame, shape: usize) -> Self {
        SurfaceInteraction { t, p: s.p, ng: s.ng, frame, uv: s.uv, dp_du: s.dp_du, dp_dv: s.dp_dv, shape }
    }
}

/// A shadow ray and the shape whose primitives it does not count ([`Scene::shadow_ray`]); None
/// when nothing can block it.
pub type ShadowTest = Option<(Ray, Option<u32>)>;

/// Collects shapes and lights; `build` makes the BVH and the area lights.
pub struct SceneBuilder {
    camera: Camera,
    shapes: Vec<Shape>,
    lights: Vec<Light>,
}

impl SceneBuilder {
    /// An empty scene seen by `camera`.
    pub fn new(camera: Camera) -> Self {
        SceneBuilder { camera, shapes: Vec::new(), lights: Vec::new() }
    }

    /// Adds a shape with the registry model `name` and its parameters; returns its index.
    pub fn shape_with_model(&mut self, geometry: Geometry, name: &str, params: &[(&str, &str)]) -> Result<usize> {
        let brdf = brdf::build(name, params).map_err(|e| Error::Invalid(e.to_string()))?;
        Ok(self.shape(Shape::new(geometry, brdf)))
    }

    /// Adds a shape; returns its index.
    pub fn shape(&mut self, shape: Shape) -> usize {
        self.shapes.push(shape);
        self.shapes.len() - 1
    }

    /// Adds a light that is not a shape (point, constant, environment map).
    pub fn light(&mut self, light: Light) -> &mut Self {
        self.lights.push(light);
        self
    }

    /// Builds the scene.
    pub fn build(self) -> Result<Scene> {
        let SceneBuilder { camera, shapes, mut lights } = self;
        let mut light_of_shape = vec![None; shapes.len()];
        for (i, s) in shapes.iter().enumerate() {
            if let Some(radiance) = &s.emission {
                let (lo, hi) = radiance.range();
                if !(lo >= 0.0 && hi.is_finite()) {
                    return Err(Error::Invalid(format!(
                        "shape {i}: emitted radiance from {lo} to {hi} is not finite and ≥ 0"
                    )));
                }
                light_of_shape[i] = Some(lights.len());
                lights.push(Light::Area(AreaLight { shape: i, radiance: radiance.clone() }));
            }
        }
        if lights.iter().filter(|l| matches!(l, Light::Constant(_) | Light::EnvMap(_))).count() > 1 {
            return Err(Error::Invalid("a scene can hold at most one environment (constant or envmap)".into()));
        }
        let mut refs = Vec::new();
        let mut bounds = Vec::new();
        let mut alone = Vec::new();
        for (si, s) in shapes.iter().enumerate() {
            for k in 0..s.geometry.primitive_count() {
                refs.push((si as u32, k as u32));
                bounds.push(s.geometry.primitive_bounds(k));
                // Triangles are tested a pack at a time, the other primitives one by one.
                alone.push(!matches!(s.geometry, Geometry::Mesh(_)));
            }
        }
        let bvh = Bvh::build_with(&bounds, &alone);
        let refs: Vec<(u32, u32)> = bvh.order.iter().map(|&i| refs[i as usize]).collect();
        let mut tri16 = vec![Tri16::default(); bvh.pack_count()];
        let mut others = vec![0u32; bvh.pack_count()];
        for (p, (pack, other)) in tri16.iter_mut().zip(&mut others).enumerate() {
            for (lane, k) in bvh.pack(p).enumerate() {
                let (s, i) = refs[k];
                match &shapes[s as usize].geometry {
                    Geometry::Mesh(m) => {
                        let (p0, e1, e2) = corner_edges(m, i);
                        pack.set(lane, p0, e1, e2);
                        *other |= HAS_TRIANGLES;
                    }
                    _ => *other |= 1 << lane,
                }
            }
        }
        // Meshes alone: the traversal then skips the lookup.
        if others.iter().all(|&m| m == HAS_TRIANGLES) {
            others.clear();
        }
        let geometry = |k: usize| &shapes[refs[k].0 as usize].geometry;
        let triangles = (0..refs.len()).filter(|&k| matches!(geometry(k), Geometry::Mesh(_))).count();
        let few = (triangles <= FEW_TRIANGLES && refs.len() - triangles <= LINEAR_MAX).then(|| {
            few::Few::new(refs.len(), |k| match geometry(k) {
                Geometry::Mesh(m) => {
                    let (p0, e1, e2) = corner_edges(m, refs[k].1);
                    few::Prim::Triangle(refs[k].0, p0, e1, e2)
                }
                Geometry::Sphere(s) => few::Prim::Sphere(*s),
                Geometry::Rectangle(r) => few::Prim::Flat(few::Flat::Rectangle(*r)),
                Geometry::Disk(d) => few::Prim::Flat(few::Flat::Disk(*d)),
            })
        });
        let environment = lights.iter().position(Light::is_environment);
        let light_bounds = light_choice::bounds(&lights, &shapes);
        let diffuse = diffuse::DiffuseSurfaces::of(&shapes, &lights);
        let transmits = shapes.iter().map(|s| s.material.with(&SurfaceInteraction::PROBE, |b| b.transmits())).collect();
        let delta_only = shapes.iter().map(|s| s.material.delta_only()).collect();
        let flat_frames = shapes
            .iter()
            .map(|s| match &s.geometry {
                Geometry::Rectangle(r) => Some(r.surface(r.center).frame()),
                _ => None,
            })
            .collect();
        let mut scene = Scene {
            camera,
            shapes,
            lights,
            light_bounds,
            light_of_shape,
            environment,
            bvh,
            tri16,
            others,
            few,
            refs,
            diffuse,
            transmits,
            delta_only,
            flat_frames,
            simd: Simd::detect(),
        };
        scene.diffuse = scene.diffuse.take().filter(|d| d.mostly_in_view(&scene));
        Ok(scene)
    }
}

/// The bit of `Scene::others` saying a pack holds triangles (lanes take bits 0 to 15).
const HAS_TRIANGLES: u32 = 1 << crate::bvh::PACK;

/// Up to this many analytic primitives, testing each beats walking the BVH (measured with
/// callgrind on the bench scenes: one to five spheres and rectangles).
const LINEAR_MAX: usize = 8;

/// Up to this many triangles (four packs), a single ray tests all packs faster than it walks
/// the BVH: in the Cornell box (38 triangles, three packs; the BVH's leaves hold six part-full
/// packs) random rays find their closest hit 1.45× as fast.
const FEW_TRIANGLES: usize = 4 * crate::bvh::PACK;

/// A built scene.
pub struct Scene {
    /// The camera.
    pub camera: Camera,
    shapes: Vec<Shape>,
    lights: Vec<Light>,
    /// Per light, what its choice probability is estimated from.
    light_bounds: Vec<light_choice::Bound>,
    light_of_shape: Vec<Option<usize>>,
    environment: Option<usize>,
    bvh: Bvh,
    /// The triangles of each BVH pack, in its lanes.
    tri16: Vec<Tri16>,
    /// Per BVH pack, the lanes holding other primitives than triangles, and [`HAS_TRIANGLES`]
    /// when some lane holds a triangle; empty when all packs hold triangles only.
    others: Vec<u32>,
    /// A few primitives: rays test them all, without the BVH.
    few: Option<few::Few>,
    /// (shape, primitive within the shape) per BVH-ordered primitive.
    refs: Vec<(u32, u32)>,
    /// Set when the batch path integrator can render the scene.
    diffuse: Option<diffuse::DiffuseSurfaces>,
    /// Per shape, whether its model transmits, as built at [`SurfaceInteraction::PROBE`]
    /// (textured models may differ elsewhere).
    transmits: Vec<bool>,
    /// Per shape, whether its model has delta lobes only at every hit
    /// ([`Material::delta_only`]).
    delta_only: Vec<bool>,
    /// Per shape, its shading frame where that is the same at every point (a rectangle's),
    /// made once rather than at every hit.
    flat_frames: Vec<Option<Frame>>,
    /// The instruction set single-ray queries are compiled for.
    simd: Simd,
}

impl Scene {
    /// The instruction set its ray queries run on (the image does not depend on it): the
    /// widest the CPU has unless set otherwise ([`Simd::detect`]).
    pub fn simd(&self) -> Simd {
        self.simd
    }

    /// Makes its ray queries run on `simd`; on a set this CPU lacks they run the baseline code.
    pub fn set_simd(&mut self, simd: Simd) {
        self.simd = simd;
    }

    /// The shapes.
    pub fn shapes(&self) -> &[Shape] {
        &self.shapes
    }

    /// The lights (area lights included, one per emitting shape).
    pub fn lights(&self) -> &[Light] {
        &self.lights
    }

    /// The number of BVH primitives.
    pub fn primitive_count(&self) -> usize {
        self.refs.len()
    }

    /// Whether single rays test every primitive instead of walking the BVH (a scene of few
    /// primitives; packets of triangles still walk it).
    pub fn without_bvh(&self) -> bool {
        self.few.is_some()
    }

    /// The BVH.
    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }

    #[inline(always)]
    fn intersect_prim(&self, k: usize, o: Vec3, d: Vec3, t_max: f32) -> Option<f32> {
        let (s, i) = self.refs[k];
        match &self.shapes[s as usize].geometry {
            Geometry::Mesh(m) => {
                let (p0, e1, e2) = corner_edges(m, i);
                intersect_triangle(o, d, t_max, p0, e1, e2).map(|h| h.0)
            }
            Geometry::Sphere(sp) => sp.intersect(o, d, t_max),
            Geometry::Rectangle(r) => r.intersect(o, d, t_max),
            Geometry::Disk(dk) => dk.intersect(o, d, t_max),
        }
    }

    /// The closest hit as (BVH-ordered primitive, distance), without shading data.
    #[inline]
    pub fn intersect_t(&self, ray: &Ray) -> Option<(usize, f32)> {
        dispatch!(self.simd, self: Scene, intersect_t_in::<AVX>(ray: &Ray) -> Option<(usize, f32)>)
    }

    /// [`intersect_t`](Self::intersect_t) inlined into a caller compiled for an instruction set
    /// (`AVX`: AVX2 or AVX-512, see `dispatch!`), which saves a dispatch per ray.
    #[inline(always)]
    pub(crate) fn intersect_t_in<const AVX: bool>(&self, ray: &Ray) -> Option<(usize, f32)> {
        match &self.few {
            Some(few) => self.intersect_t_few::<AVX>(few, ray),
            None => self.closest_walk::<AVX>(ray),
        }
    }

    /// The closest hit by testing every primitive (no BVH): the reference the BVH is tested
    /// and benchmarked against.
    pub fn intersect_t_linear(&self, ray: &Ray) -> Option<(usize, f32)> {
        let mut best = None;
        let mut t_max = ray.t_max;
        for k in 0..self.refs.len() {
            if let Some(t) = self.intersect_prim(k, ray.o, ray.d, t_max) {
                t_max = t;
                best = Some((k, t));
            }
        }
        best
    }

    /// True when anything lies along the ray within (0, t_max).
    #[inline]
    pub fn occluded(&self, ray: &Ray) -> bool {
        self.occluded_but(ray, None)
    }

    /// [`occluded`](Self::occluded), not counting the analytic (non-mesh) primitives of shape
    /// `skip`: a shadow ray towards a point on a convex emitter cannot be blocked by it.
    #[inline]
    pub(crate) fn occluded_but(&self, ray: &Ray, skip: Option<u32>) -> bool {
        if let Some(few) = &self.few {
            return dispatch!(self.simd, self: Scene, occluded_few::<AVX>(few: &few::Few, ray: &Ray, skip: Option<u32>) -> bool);
        }
        dispatch!(self.simd, self: Scene, any_walk::<AVX>(ray: &Ray, skip: Option<u32>) -> bool)
    }

    /// True when the light sample `ls` is unobstructed from surface point `p` (geometric
    /// normal `ng`). A point on an area light is seen when nothing lies along the ray up to a
    /// tolerance short of it, an any-hit query that may stop at the first blocker. Spheres,
    /// rectangles and disks are convex, so nothing of theirs can hide the point and their own
    /// primitives are not counted: a shadow ray grazing a curved emitter would otherwise meet
    /// it early, since the origin's offset moves a grazing hit far along the ray. A mesh
    /// emitter counts like any other mesh (it may shade itself).
    pub fn unoccluded(&self, p: Vec3, ng: Vec3, ls: &LightSample) -> bool {
        self.visible(self.shadow_ray(p, ng, ls))
    }

    /// The answer to a shadow test: true when nothing blocks it.
    #[inline]
    pub fn visible(&self, test: ShadowTest) -> bool {
        test.is_none_or(|(ray, skip)| !self.occluded_but(&ray, skip))
    }

    /// The shadow ray of [`unoccluded`](Self::unoccluded) and the shape whose primitives it does
    /// not count; None when the light point is too close to be blocked.
    pub fn shadow_ray(&self, p: Vec3, ng: Vec3, ls: &LightSample) -> ShadowTest {
        if !ls.dist.is_finite() {
            return Some((spawn_ray(p, ng, ls.wi), None));
        }
        let (mut ray, _, dist) = spawn_ray_to(p, ng, ls.p);
        let Some(shape) = ls.shape else { return Some((ray, None)) };
        let tolerance = 1e-3 * dist + surface_epsilon(ls.p);
        ray.t_max = (ls.p - ray.o).length() - tolerance;
        (ray.t_max > 0.0).then_some((ray, Some(shape as u32)))
    }

    /// The closest hit with its surface data.
    pub fn intersect(&self, ray: &Ray) -> Option<SurfaceInteraction> {
        let (k, t) = self.intersect_t(ray)?;
        Some(self.interaction(ray, k, t))
    }

    /// The surface data where `ray` meets BVH-ordered primitive `k` at distance `t`.
    pub fn interaction(&self, ray: &Ray, k: usize, t: f32) -> SurfaceInteraction {
        let (shape, index) = self.refs[k];
        let surface = match &self.shapes[shape as usize].geometry {
            Geometry::Mesh(m) => {
                // Recompute the barycentrics of the winning triangle (cheaper than carrying them).
                let (p0, e1, e2) = corner_edges(m, index);
                let (_, u, v) = intersect_triangle(ray.o, ray.d, f32::INFINITY, p0, e1, e2).unwrap_or((t, 0.0, 0.0));
                m.surface(index as usize, u, v)
            }
            Geometry::Sphere(s) => s.surface(ray.at(t)),
            Geometry::Rectangle(r) => r.surface(ray.at(t)),
            Geometry::Disk(dk) => dk.surface(ray.at(t)),
        };
        let shape = shape as usize;
        match self.flat_frames[shape] {
            Some(frame) => SurfaceInteraction::with_frame(t, &surface, frame, shape),
            None => SurfaceInteraction::new(t, &surface, shape),
        }
    }

    /// Starts loading what [`interaction`](Self::interaction) reads first for BVH-ordered
    /// primitive `k`: its reference. Then [`prefetch_indices`](Self::prefetch_indices) and
    /// [`prefetch_vertices`](Self::prefetch_vertices), each once the loads before it have had
    /// time: the three reads of a hit depend on one another. Hints; they change no result.
    #[inline]
    pub(crate) fn prefetch_primitive(&self, k: usize) {
        radiometry::prefetch::prefetch(&self.refs[k]);
    }

    /// Starts loading the vertex indices of primitive `k` where it is a mesh triangle (see
    /// `prefetch_primitive`).
    #[inline]
    pub(crate) fn prefetch_indices(&self, k: usize) {
        if let Some((m, i)) = self.mesh_triangle(k) {
            m.prefetch_indices(i);
        }
    }

    /// Starts loading the vertex data of primitive `k` where it is a mesh triangle (see
    /// `prefetch_primitive`).
    #[inline]
    pub(crate) fn prefetch_vertices(&self, k: usize) {
        if let Some((m, i)) = self.mesh_triangle(k) {
            m.prefetch_vertices(i);
        }
    }

    /// The mesh and triangle of BVH-ordered primitive `k`, if it is a mesh triangle.
    #[inline]
    fn mesh_triangle(&self, k: usize) -> Option<(&crate::shape::TriangleMesh, usize)> {
        let (shape, index) = self.refs[k];
        match &self.shapes[shape as usize].geometry {
            Geometry::Mesh(m) => Some((m, index as usize)),
            _ => None,
        }
    }

    /// The (shape, primitive within the shape) of BVH-ordered primitive `k`.
    #[inline]
    pub(crate) fn primitive(&self, k: usize) -> (u32, u32) {
        self.refs[k]
    }

    /// The geometry of shape `shape`.
    #[inline]
    pub(crate) fn geometry(&self, shape: usize) -> &Geometry {
        &self.shapes[shape].geometry
    }

    /// What the batch path integrator needs, when it can render the scene.
    #[inline]
    pub(crate) fn diffuse_surfaces(&self) -> Option<&diffuse::DiffuseSurfaces> {
        self.diffuse.as_ref()
    }

    /// The material of shape `shape`.
    #[inline]
    pub fn material(&self, shape: usize) -> &Material {
        &self.shapes[shape].material
    }

    /// Whether the model of shape `shape` likely transmits ([`brdf::Brdf::transmits`]), known
    /// without building it: exact unless it is textured (Mitsuba's principled BSDF with a
    /// textured transmission can switch), so a caller that acts on it checks the model after.
    #[inline]
    pub fn transmits_guess(&self, shape: usize) -> bool {
        self.transmits[shape]
    }

    /// Whether the model of shape `shape` has delta lobes only at every hit: light samples
    /// can add nothing there.
    #[inline]
    pub fn delta_only(&self, shape: usize) -> bool {
        self.delta_only[shape]
    }

    /// The area light on shape `shape`, with its light index.
    #[inline]
    pub fn area_light(&self, shape: usize) -> Option<(usize, &AreaLight)> {
        let i = self.light_of_shape[shape]?;
        match &self.lights[i] {
            Light::Area(a) => Some((i, a)),
            _ => None,
        }
    }

    /// The environment light, if any, with its index.
    #[inline]
    pub fn environment(&self) -> Option<(usize, &Light)> {
        self.environment.map(|i| (i, &self.lights[i]))
    }
}

/// Triangle `i` of mesh `m` as a corner and two edges, as the triangle tests take it (the same
/// values wherever computed, so the packs and the one-by-one tests agree bit for bit).
#[inline]
fn corner_edges(m: &crate::shape::TriangleMesh, i: u32) -> (Vec3, Vec3, Vec3) {
    let [a, b, c] = m.triangle(i as usize);
    (a, b - a, c - a)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{look_at, FovAxis};
    use crate::shape::rectangle::Rectangle;
    use glam::{Mat4, Quat};

    #[test]
    fn a_rectangles_hits_take_the_frame_each_would_compute_bit_for_bit() {
        // Rotated, stretched, mirrored (negative determinant) and flipped rectangles.
        let places = [
            Mat4::from_rotation_x(-1.3),
            Mat4::from_scale_rotation_translation(Vec3::new(2.0, 0.5, 1.0), Quat::from_rotation_y(0.7), Vec3::Y),
            Mat4::from_scale_rotation_translation(Vec3::new(-1.0, 1.5, 1.0), Quat::from_rotation_z(0.4), Vec3::X),
            Mat4::from_rotation_translation(Quat::from_euler(glam::EulerRot::XYZ, 0.3, -0.8, 1.9), -Vec3::Z),
        ];
        let cam = Camera::new(look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y).unwrap(), 40.0, FovAxis::X, 4, 4);
        let mut b = SceneBuilder::new(cam);
        for (k, m) in places.iter().enumerate() {
            let mut r = Rectangle::new(m).unwrap();
            r.flip = k % 2 == 1;
            b.shape_with_model(Geometry::Rectangle(r), "lambert", &[]).unwrap();
        }
        let scene = b.build().unwrap();
        let mut s = crate::sampler::Sampler::new(5, 0, 0);
        let mut hits = [0; 4];
        for _ in 0..4000 {
            let o = (Vec3::new(s.next_1d(), s.next_1d(), s.next_1d()) - 0.5) * 8.0;
            let ray = Ray::new(o, (Vec3::new(s.next_1d(), s.next_1d(), s.next_1d()) - 0.5).normalize() * -o.signum());
            let Some((k, t)) = scene.intersect_t(&ray) else { continue };
            let got = scene.interaction(&ray, k, t);
            let Geometry::Rectangle(r) = scene.geometry(got.shape) else { unreachable!("only rectangles") };
            let want = SurfaceInteraction::new(t, &r.surface(ray.at(t)), got.shape);
            let bits = |si: &SurfaceInteraction| {
                [si.p, si.ng, si.frame.s, si.frame.t, si.frame.n, si.dp_du, si.dp_dv, si.uv.extend(si.t)]
                    .map(|v| v.to_array().map(f32::to_bits))
            };
            assert_eq!(bits(&got), bits(&want), "shape {}", got.shape);
            hits[got.shape] += 1;
        }
        assert!(hits.iter().all(|&n| n > 20), "hits per rectangle: {hits:?}");
    }
}
