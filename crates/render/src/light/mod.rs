//! Lights: point, spot, directional, diffuse area, constant environment and environment map. Each can be
//! sampled from a reference point and report the density of a direction it might produce.

pub mod area;
pub mod constant;
pub mod directional;
pub mod envmap;
pub mod point;
pub mod spot;

pub use area::AreaLight;
pub use constant::ConstantEnv;
pub use directional::DirectionalLight;
pub use envmap::EnvMap;
pub use point::PointLight;
pub use spot::SpotLight;

use glam::Vec3;
use radiometry::Rgb;

/// Where light is sampled from: a point, and the shading normal when it is on a surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RefPoint {
    /// The point.
    pub p: Vec3,
    /// The shading normal (None in free space).
    pub n: Option<Vec3>,
}

/// A sampled direction towards a light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    /// Unit direction from the reference point towards the light.
    pub wi: Vec3,
    /// Distance to the light point (∞ for environments).
    pub dist: f32,
    /// The point on the light (for environments, a point one unit along `wi`).
    pub p: Vec3,
    /// Incident radiance; for a point light, I/r² (irradiance on a surface facing it).
    pub li: Rgb,
    /// Solid-angle density; 1 for a delta light.
    pub pdf: f32,
    /// True for a delta light (a point light): no other strategy can find it.
    pub delta: bool,
    /// The emitting shape, for an area light.
    pub shape: Option<usize>,
}

/// Any light.
#[derive(Clone, Debug)]
pub enum Light {
    /// A point light.
    Point(PointLight),
    /// A diffuse emitter on a shape.
    Area(AreaLight),
    /// A constant environment.
    Constant(ConstantEnv),
    /// An environment map.
    EnvMap(Box<EnvMap>),
    /// A spot light.
    Spot(SpotLight),
    /// A directional light (parallel light from infinitely far).
    Directional(DirectionalLight),
}

impl Light {
    /// True for lights at infinity (seen by rays that leave the scene).
    pub fn is_environment(&self) -> bool {
        matches!(self, Light::Constant(_) | Light::EnvMap(_))
    }

    /// Radiance from an environment light along an escaping ray direction `d`; zero otherwise.
    pub fn environment_radiance(&self, d: Vec3) -> Rgb {
        match self {
            Light::Constant(c) => c.radiance,
            Light::EnvMap(e) => e.eval(d),
            _ => Rgb::ZERO,
        }
    }
}
