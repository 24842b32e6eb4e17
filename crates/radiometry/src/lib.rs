//! Radiometry: local frames, RGB spectra, spherical coordinates, solid angle,
//! sample warps with their densities, and hemisphere integrals.
//!
//! Directions are unit `Vec3` in a z-up local frame: `cos_theta(w) = w.z`.

pub mod alias;
pub mod cie;
pub mod distribution;
pub mod frame;
pub mod integrate;
pub mod prefetch;
pub mod spectrum;
pub mod spherical;
pub mod trig;
pub mod warp;
pub mod warp2d;

pub use frame::Frame;
pub use glam::{DVec3, Vec2, Vec3};
pub use spectrum::Rgb;
pub use spherical::{cos_theta, phi, spherical_direction, theta};
