//! Reflection models in a z-up local shading frame, Fresnel terms, microfacet
//! distributions, and the property checks every model is held to.
//!
//! Conventions: `wi` (towards the light) and `wo` (towards the viewer) both point away
//! from the surface; `eval` returns ρ in 1/sr without the cosine; `pdf` is in solid angle.

pub mod check;
pub mod combine;
pub mod lambert;
pub mod model;
pub mod params;
pub mod registry;

pub use model::{Brdf, BrdfSample, Claims};
pub use params::{ParamError, ParamKind, ParamSpec, Params, Value};
pub use registry::{build, find, models, ModelSpec};
