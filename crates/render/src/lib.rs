//! Rendering: scenes, ray tracing and image synthesis on top of the `brdf` crate.
//! The path tracer arrives with the renderer; the crate holds its place in the workspace.
