//! The scenes the batch path integrator ([`crate::integrator`]'s `wide`) renders: triangle
//! meshes, each of Lambert's model with a constant albedo (on one side, or `twosided`), lit by
//! one area light of constant radiance and nothing else (Cornell boxes, diffuse interiors), or
//! by lights none of which is an area light (an environment map, point lights, the sun).

use super::Shape;
use crate::light::Light;
use crate::material::Material;
use crate::shape::Geometry;
use crate::texture::Texture;
use radiometry::Rgb;

/// What the batch integrator reads of such a scene.
#[derive(Clone, Debug)]
pub(crate) struct DiffuseMeshes {
    /// Per shape, its albedo on the front and, for a `twosided` one, on the back.
    pub albedo: Vec<(Rgb, Option<Rgb>)>,
    /// The emitting shape and its radiance, where one area light is the only light; None where
    /// no light is an area light (they are sampled through the scene, lane by lane).
    pub area: Option<(usize, Rgb)>,
}

impl DiffuseMeshes {
    /// The description of a scene of `shapes` and `lights` when it is of this kind.
    pub(super) fn of(shapes: &[Shape], lights: &[Light]) -> Option<Self> {
        let area = match lights {
            [Light::Area(light)] => match light.radiance {
                Texture::Constant(radiance) => Some((light.shape, radiance)),
                _ => return None,
            },
            [] => return None,
            _ if lights.iter().any(|l| matches!(l, Light::Area(_))) => return None,
            _ => None,
        };
        let lambert = |m: &Material| match m {
            Material::Fixed(b) => b.lambertian(),
            _ => None,
        };
        let albedo = shapes
            .iter()
            .map(|s| match (&s.geometry, &s.material) {
                (Geometry::Mesh(_), Material::TwoSided(front, back)) => Some((lambert(front)?, Some(lambert(back)?))),
                (Geometry::Mesh(_), m) => Some((lambert(m)?, None)),
                _ => None,
            })
            .collect::<Option<Vec<_>>>()?;
        Some(DiffuseMeshes { albedo, area })
    }
}
