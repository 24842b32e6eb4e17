//! Rendering: scenes of meshes, spheres and rectangles under point, area and environment
//! lights, a BVH, a perspective camera, path and direct-lighting integrators, image I/O.
//!
//! Conventions are Mitsuba 3's (see `shared/bench/README.md`): +Y up, right-handed,
//! `look_at` cameras with `fov` along an axis, box-filtered pixels, the equirectangular
//! environment lookup u = atan2(d.x, −d.z)/2π, v = acos(d.y)/π, path depths counted in
//! vertices. Reflection models are reached only through the `brdf::Brdf` trait.
//!
//! ```no_run
//! use render::{camera, light, scene, shape, RenderOptions};
//! # fn main() -> render::Result<()> {
//! let to_world = camera::look_at([0., 0., 4.].into(), [0.; 3].into(), [0., 1., 0.].into()).unwrap();
//! let cam = camera::Camera::new(to_world, 40.0, camera::FovAxis::X, 64, 64);
//! let mut b = scene::SceneBuilder::new(cam);
//! let white = brdf::build("lambert", &[("albedo", "1")]).unwrap();
//! let ball = shape::Geometry::Sphere(shape::Sphere::new([0.; 3].into(), 1.0));
//! b.shape(scene::Shape::new(ball, white));
//! b.light(light::Light::Constant(light::ConstantEnv { radiance: radiometry::Rgb::ONE }));
//! let img = render::render(&b.build()?, &RenderOptions { spp: 16, ..Default::default() }, |_| {});
//! img.save("furnace.exr")?;
//! # Ok(()) }
//! ```

pub mod atan;
pub mod bvh;
pub mod camera;
pub mod envmap_convert;
pub mod error;
pub mod film;
pub mod filter;
pub mod floor;
pub mod image;
pub mod integrator;
pub mod io;
pub mod light;
pub mod material;
pub mod ray;
pub mod renderer;
pub mod sampler;
pub mod scene;
pub mod shape;
pub mod simd;
pub mod texture;
pub mod xml;

pub use error::{Error, Result};
pub use image::Image;
pub use integrator::Integrator;
pub use renderer::{render, Progress, RenderOptions};
pub use scene::{Scene, SceneBuilder, Shape};
