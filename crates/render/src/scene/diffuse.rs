//! The scenes the batch path integrator ([`crate::integrator`]'s `wide`) renders: meshes and
//! other shapes, each of Lambert's model with a constant or textured albedo (on one side, or
//! `twosided`), lit by one area light of constant radiance on a mesh and nothing else (Cornell
//! boxes, diffuse interiors), or by lights none of which is an area light (an environment map,
//! point lights, the sun).

use super::{Shape, SurfaceInteraction};
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
    /// Per shape, its albedo on the front and, for a `twosided` one, on the back.
    pub albedo: Vec<(Albedo, Option<Albedo>)>,
    /// The emitting mesh and its radiance, where one area light is the only light; None where
    /// no light is an area light (they are sampled through the scene, lane by lane).
    pub area: Option<(usize, Rgb)>,
}

impl DiffuseSurfaces {
    /// The description of a scene of `shapes` and `lights` when it is of this kind. A scene
    /// without a mesh is not: the tracer's vector code is the meshes' hit points, and without
    /// them it is slower than the packet path (a diffuse sphere under a constant sky, 128 spp:
    /// 3.60 → 3.66 s).
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
        let albedo = shapes
            .iter()
            .map(|s| match &s.material {
                Material::TwoSided(front, back) => Some((Albedo::of(front)?, Some(Albedo::of(back)?))),
                m => Some((Albedo::of(m)?, None)),
            })
            .collect::<Option<Vec<_>>>()?;
        Some(DiffuseSurfaces { albedo, area })
    }
}
