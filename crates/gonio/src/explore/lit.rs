//! The lit sphere and lit object: gonio's path tracer renders one pass (one sample per pixel)
//! after another, and each accumulated image is streamed to the page as a frame until the
//! sample budget is spent or the page goes away (a failed write stops the render).
//!
//! Stream format, repeated: `GNF1`, then width, height and samples per pixel as little-endian
//! u32, then width × height RGBA bytes (8-bit sRGB, alpha 255).

use super::cache::Cache;
use super::files::{Files, Source};
use super::http::{ApiError, Query};
use super::model::Resolved;
use crate::demo_scene::{object_scene, probe_light, Lighting};
use render::light::EnvMap;
use render::shape::TriangleMesh;
use render::{Image, Integrator, RenderOptions, Scene};
use std::collections::HashMap;
use std::io::Write;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// Loaded meshes and probes by name, so dragging the light does not reload them.
#[derive(Debug, Default)]
pub struct Assets {
    meshes: Cache<Arc<TriangleMesh>, 4>,
    probes: Cache<Arc<EnvMap>, 4>,
}

/// Renders at once, all tabs together; more are refused (503) rather than queued.
pub const MAX_RENDERS: usize = 8;

/// What one stream renders.
pub struct Job {
    scene: Scene,
    spp: u32,
    exposure: f32,
}

impl Assets {
    fn mesh(&self, files: &Files, name: &str) -> Result<Option<Arc<TriangleMesh>>, ApiError> {
        match name {
            "sphere" => Ok(None),
            "suzanne" => self
                .meshes
                .get_or(name, || {
                    crate::demo_scene::suzanne().map(Arc::new).map_err(|e| ApiError::new(500, e.to_string()))
                })
                .map(Some),
            file => {
                let src = files.resolve("object", file)?;
                self.meshes
                    .get_or(file, || {
                        let bytes = src.read("object")?;
                        render::io::parse_mesh(&bytes, file)
                            .map(Arc::new)
                            .map_err(|e| ApiError::new(400, e).named("object"))
                    })
                    .map(Some)
            }
        }
    }

    /// The probe `name` (`studio`: the embedded one) as a light at `scale`; its sampling tables,
    /// which cost more than a first frame, are built once per probe.
    fn probe(&self, files: &Files, name: &str, scale: f32) -> Result<EnvMap, ApiError> {
        let path = match name {
            "studio" => None,
            _ => match files.resolve("probe", name)? {
                Source::Disk(path) => Some(path),
                Source::Upload(_) => {
                    return Err(
                        ApiError::new(400, "probes are opened from the data folders, not uploaded").named("probe")
                    )
                }
            },
        };
        let bad = |e: render::Error| ApiError::new(400, e.to_string()).named("probe");
        let unit = self.probes.get_or(name, || {
            let image = path.map(Image::load).transpose().map_err(bad)?;
            probe_light(image.as_ref(), 1.0).map(Arc::new).map_err(bad)
        })?;
        Ok(unit.scaled(scale))
    }

    /// The scene, sample budget and exposure a `/api/render` query asks for.
    pub fn job(&self, files: &Files, r: &Resolved, q: &Query) -> Result<Job, ApiError> {
        let size = q.number("size", 16.0, 1024.0, 256.0)? as u32;
        let spp = q.number("spp", 1.0, 65536.0, 256.0)? as u32;
        let exposure = q.number("exposure", -20.0, 20.0, 0.0)? as f32;
        let env_scale = q.number("env", 0.0, 100.0, 1.0)? as f32;
        let irradiance = q.number("irradiance", 0.0, 1000.0, 3.0)? as f32;
        let mesh = self.mesh(files, q.get("object").unwrap_or("sphere"))?;
        let env = match env_scale > 0.0 {
            true => Some(self.probe(files, q.get("probe").unwrap_or("studio"), env_scale)?),
            false => None,
        };
        let point = match q.get("light") {
            Some(_) => Some((super::http::direction(q, "light")?, irradiance)),
            None => None,
        };
        let lighting = Lighting { env, point };
        let scene = object_scene(r.brdf.clone(), mesh.as_deref(), &lighting, size, size)
            .map_err(|e| ApiError::new(400, e.to_string()))?;
        Ok(Job { scene, spp, exposure })
    }
}

/// Counts a render while it runs.
struct Running<'a>(&'a AtomicUsize);

impl Drop for Running<'_> {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::SeqCst);
    }
}

/// Frames after the first are sent at most this often.
const FRAME_INTERVAL: Duration = Duration::from_millis(120);

fn frame(sum: &Image, passes: u32, exposure: f32) -> Vec<u8> {
    let mut mean = sum.clone();
    let inv = 1.0 / passes as f32;
    mean.pixels.iter_mut().for_each(|p| *p *= inv);
    let rgb = render::io::png::to_srgb8(&mean, exposure);
    let mut out = Vec::with_capacity(16 + rgb.len() / 3 * 4);
    out.extend_from_slice(b"GNF1");
    for v in [sum.width, sum.height, passes] {
        out.extend_from_slice(&v.to_le_bytes());
    }
    for px in rgb.chunks_exact(3) {
        out.extend_from_slice(&[px[0], px[1], px[2], 255]);
    }
    out
}

/// The renders running, by the name the page gives them (`stream=`), so that a new request
/// stops the renders it supersedes at once, mid-pass, rather than after their pass when the
/// write to the closed connection fails: a render named N stops the render of that name and
/// those named N/… (the page names its sphere `P/lit` and its object `P/lit/object`).
#[derive(Debug, Default)]
pub struct Streams(Mutex<HashMap<String, Arc<AtomicBool>>>);

impl Streams {
    /// A cancel flag for a new render named `id`, after stopping the renders it supersedes.
    pub fn start(&self, id: Option<&str>) -> Arc<AtomicBool> {
        let flag = Arc::new(AtomicBool::new(false));
        if let Some(id) = id {
            self.stop(id);
            self.0.lock().unwrap_or_else(|e| e.into_inner()).insert(id.to_string(), flag.clone());
        }
        flag
    }

    /// Stops the render named `id` and those below it (`id/…`).
    pub fn stop(&self, id: &str) {
        let mut m = self.0.lock().unwrap_or_else(|e| e.into_inner());
        m.retain(|name, f| {
            let stop = name == id || name.strip_prefix(id).is_some_and(|rest| rest.starts_with('/'));
            if stop {
                f.store(true, Ordering::SeqCst);
            }
            // Renders that have ended hold no other reference: forget them too.
            !stop && Arc::strong_count(f) > 1
        });
    }
}

/// Renders `job` pass by pass into `out` (the response body); returns when done, when `cancel`
/// is set, or when a write fails because the page closed the connection.
pub fn stream(job: Job, out: &mut dyn Write, running: &AtomicUsize, cancel: Arc<AtomicBool>) {
    running.fetch_add(1, Ordering::SeqCst);
    let _running = Running(running);
    let (w, h) = (job.scene.camera.width, job.scene.camera.height);
    let mut sum = Image::new(w, h);
    let mut last = Instant::now();
    for pass in 0..job.spp {
        if cancel.load(Ordering::SeqCst) {
            return;
        }
        let opts = RenderOptions {
            spp: 1,
            first_sample: 0,
            seed: u64::from(pass),
            threads: 0,
            integrator: Integrator::default(),
            cancel: Some(cancel.clone()),
        };
        let img = render::render(&job.scene, &opts, |_| {});
        if cancel.load(Ordering::SeqCst) {
            return;
        }
        for (s, p) in sum.pixels.iter_mut().zip(&img.pixels) {
            *s += *p;
        }
        let n = pass + 1;
        // The first pass at once, then at a steady rate (each frame costs the page a redraw), and the last.
        if n == 1 || n == job.spp || last.elapsed() >= FRAME_INTERVAL {
            last = Instant::now();
            if out.write_all(&frame(&sum, n, job.exposure)).and_then(|()| out.flush()).is_err() {
                return;
            }
            if n == 1 {
                // The first frame is what the page waits for; the refinement yields to the plots.
                // (The priority can only be lowered, so it starts at the plots' level.)
                super::background(5);
            }
        }
    }
}
