//! The scenes the batch path integrator ([`crate::integrator`]'s `wide`) renders: meshes and
//! other shapes, lit by one area light of constant radiance on a mesh and nothing else (Cornell
//! boxes, interiors), or by lights none of which is an area light (an environment map, point
//! lights, the sun), and seen mostly on shapes of Lambert's model with a constant or textured
//! albedo (on one side, or `twosided`), which it shades in lane arrays; it shades those of any
//! other model lane by lane, as the path integrator shades them.

use super::{Scene, Shape, SurfaceInteraction};
use crate::light::Light;
use crate::material::Material;
use crate::shape::Geometry;
use crate::texture::Texture;
use glam::Vec2;
use radiometry::Rgb;

/// A Lambertian side's albedo.
#[derive(Clone, Debug)]
pub(crate) enum Albedo {
    /// The same everywhere.
    Constant(Rgb),
    /// Lambert's model with a textured albedo, built at each hit.
    Textured(Material),
}

impl Albedo {
    /// The albedo of material `m`, where it is Lambert's model everywhere.
    fn of(m: &Material) -> Option<Albedo> {
        match m {
            Material::Fixed(b) => b.lambertian().map(Albedo::Constant),
            Material::Textured(t) if t.spec.name == brdf::lambert::SPEC.name => Some(Albedo::Textured(m.clone())),
            _ => None,
        }
    }

    /// The albedo at surface coordinates `uv`, as the model built there has it (a textured
    /// model reads nothing of the hit but its uv).
    #[inline]
    pub fn at(&self, uv: Vec2) -> Rgb {
        match self {
            Albedo::Constant(a) => *a,
            Albedo::Textured(m) => {
                m.with(&SurfaceInteraction { uv, ..SurfaceInteraction::PROBE }, |b| b.lambertian().unwrap_or(Rgb::ZERO))
            }
        }
    }

    /// Starts loading the texels that [`at`](Self::at) reads at `uv`: a hint.
    #[inline]
    pub fn prefetch(&self, uv: Vec2) {
        if let Albedo::Textured(m) = self {
            m.prefetch(uv);
        }
    }

    /// The constant albedo, or None where it varies.
    #[inline]
    pub fn constant(&self) -> Option<Rgb> {
        match self {
            Albedo::Constant(a) => Some(*a),
            Albedo::Textured(_) => None,
        }
    }
}

/// What the batch integrator reads of such a scene.
#[derive(Clone, Debug)]
pub(crate) struct DiffuseSurfaces {
    /// Per shape of Lambert's model, its albedo on the front and, for a `twosided` one, on the
    /// back; None for a shape of another model.
    pub albedo: Vec<Option<(Albedo, Option<Albedo>)>>,
    /// The emitting mesh and its radiance, where one area light is the only light; None where
    /// no light is an area light (they are sampled through the scene, lane by lane).
    pub area: Option<(usize, Rgb)>,
}

impl DiffuseSurfaces {
    /// The description of a scene of `shapes` and `lights` when it is of this kind. A scene
    /// without a mesh is not: the tracer's vector code is the meshes' hit points, and without
    /// them it is slower than the packet path (a diffuse sphere under a constant sky, 128 spp:
    /// 3.60 → 3.66 s). Nor is one without a Lambertian shape, whose lanes would all be shaded
    /// one by one.
    pub(super) fn of(shapes: &[Shape], lights: &[Light]) -> Option<Self> {
        if !shapes.iter().any(|s| matches!(s.geometry, Geometry::Mesh(_))) {
            return None;
        }
        let area = match lights {
            [Light::Area(light)] => match (&light.radiance, &shapes[light.shape].geometry) {
                (Texture::Constant(radiance), Geometry::Mesh(_)) => Some((light.shape, *radiance)),
                _ => return None,
            },
            [] => return None,
            _ if lights.iter().any(|l| matches!(l, Light::Area(_))) => return None,
            _ => None,
        };
        let albedo: Vec<_> = shapes
            .iter()
            .map(|s| match &s.material {
                Material::TwoSided(front, back) => Some((Albedo::of(front)?, Some(Albedo::of(back)?))),
                m => Some((Albedo::of(m)?, None)),
            })
            .collect();
        albedo.iter().any(Option::is_some).then_some(DiffuseSurfaces { albedo, area })
    }

    /// Whether four fifths or more of what the camera of `scene` sees (a grid of 16 × 16 rays
    /// through the image) is Lambertian: the lanes of other models are slower in the tracer
    /// than in the packet path, so a scene gains only where Lambertian surfaces make most of
    /// the paths. Against the packet path, with the Lambertian share of this grid's hits (64
    /// spp unless said): the Cornell box with glass boxes, 82 %: −29 %; with rough plastic
    /// ones −35 %, rough metal ones −32 %; the bench's spheres with a Lambertian cube added,
    /// 84 %: −10 % (16 spp); Mitsuba's material preview, a plastic object on a Lambertian
    /// plane, 75 %: −1 % (16 spp); the textures scene with a plain diffuse floor, 62 %: −1 % (32
    /// spp); a rough plastic torus under a sky, 0 % (a Lambertian cube out of view): +14 % (16
    /// spp); the textures scene likewise: +10 % (32 spp).
    pub(super) fn mostly_in_view(&self, scene: &Scene) -> bool {
        const GRID: u32 = 16;
        let camera = &scene.camera;
        let (mut seen, mut lambertian) = (0u32, 0u32);
        for j in 0..GRID {
            for i in 0..GRID {
                let at = |k: u32, size: u32| (k as f32 + 0.5) / GRID as f32 * size as f32;
                let ray = camera.ray(Vec2::new(at(i, camera.width), at(j, camera.height)), Vec2::splat(0.5));
                if let Some(si) = scene.intersect(&ray) {
                    seen += 1;
                    lambertian += self.albedo[si.shape].is_some() as u32;
                }
            }
        }
        lambertian > 0 && 5 * lambertian >= 4 * seen
    }
}
