//! Reflection and transmission models in a z-up local shading frame, Fresnel terms,
//! microfacet distributions, and the property checks every model is held to.
//!
//! Conventions: `wi` (towards the light) and `wo` (towards the viewer) both point away
//! from the surface; `eval` returns ρ in 1/sr without the cosine; `pdf` is in solid angle.

pub mod blend;
pub mod blinn_phong;
pub mod check;
pub mod combine;
pub mod cook_torrance;
pub mod dielectric;
pub mod fit;
pub mod fresnel;
pub mod ior;
pub mod lambert;
pub mod mask;
pub mod measured;
pub mod microfacet;
pub mod microfacet_brdf;
pub mod mirror;
pub mod model;
pub mod null;
pub mod params;
pub mod perturbed;
pub mod phong;
pub mod plastic;
pub mod principled;
mod principled_common;
pub mod principled_thin;
pub mod registry;
pub mod rough_dielectric;
pub mod roughness;
pub mod thin_dielectric;
pub mod two_sided;
pub mod ward;

pub use model::{Brdf, BrdfSample, Claims, PhongTerms};
pub use params::{AskOrder, ParamError, ParamKind, ParamSource, ParamSpec, Params, Recorder, Value, Varied};
pub use registry::{build, build_item, find, models, parse_item, Build, ModelSpec};
