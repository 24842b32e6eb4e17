//! Rendering an image: per-pixel deterministic sample streams, rows in parallel, passes
//! of growing sample counts so that a cancelled render still holds a whole (noisier) image.

use crate::film::{RowSplats, SplatFilm};
use crate::filter::Filter;
use crate::image::Image;
use crate::integrator::Integrator;
use crate::ray::Ray;
use crate::sampler::{PixelKey, Sampler};
use crate::scene::Scene;
use crate::simd::LANES;
use glam::Vec2;
use radiometry::Rgb;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;

/// How to render.
#[derive(Clone, Debug)]
pub struct RenderOptions {
    /// Samples per pixel.
    pub spp: u32,
    /// Index of the first sample of each pixel's stream: the render takes samples
    /// `first_sample .. first_sample + spp`, so renders of disjoint ranges are independent.
    pub first_sample: u32,
    /// Seed of every random stream.
    pub seed: u64,
    /// Worker threads; 0 uses every core.
    pub threads: usize,
    /// The estimator.
    pub integrator: Integrator,
    /// Set to true (from anywhere) to stop early; the image then holds the samples taken.
    pub cancel: Option<Arc<AtomicBool>>,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions { spp: 16, first_sample: 0, seed: 0, threads: 0, integrator: Integrator::default(), cancel: None }
    }
}

/// Progress: camera samples taken so far out of the total.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Progress {
    /// Samples taken.
    pub done: u64,
    /// Samples the render will take when not cancelled.
    pub total: u64,
}

/// The passes' sample ranges from `first`: 1, 1, 2, 4, … samples (doubling, at most 64),
/// `spp` in all. Depends on its arguments only, so the image does not depend on how the work
/// is scheduled.
fn passes(first: u32, spp: u32) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    let (mut start, mut size) = (first, 1u32);
    let end = first.saturating_add(spp);
    while start < end {
        let n = size.min(end - start);
        out.push((start, start + n));
        start += n;
        if out.len() > 1 {
            size = (size * 2).min(64);
        }
    }
    out
}

/// Renders `scene`, sample `s` of pixel `p` drawn from the stream (seed, p, s). With the box
/// filter each pixel is the mean of `spp` samples uniform over its area; with a wider filter
/// the samples (still uniform over their pixel) are splatted into every pixel the filter
/// reaches and each pixel is normalised by its summed weights (`film.rs`). `progress` is
/// called from worker threads after each row of each pass.
pub fn render(scene: &Scene, opts: &RenderOptions, progress: impl Fn(Progress) + Sync) -> Image {
    let (w, h) = (scene.camera.width as usize, scene.camera.height as usize);
    if w == 0 || h == 0 {
        return Image::new(w as u32, h as u32);
    }
    let run =
        Run { scene, opts, progress: &progress, done: AtomicU64::new(0), total: w as u64 * h as u64 * opts.spp as u64 };
    let work = || match scene.camera.filter {
        Filter::Box => run.boxed(w, h),
        _ => run.splatted(w, h),
    };
    match rayon::ThreadPoolBuilder::new().num_threads(opts.threads).build() {
        Ok(pool) => pool.install(work),
        // No pool could be made (e.g. no threads allowed): run on the global one.
        Err(_) => work(),
    }
}

/// The camera ray through image position `pos`, with a lens sample drawn when the camera has
/// a lens (Mitsuba's order: position, then lens, then the integrator's numbers).
#[inline]
pub fn camera_ray(scene: &Scene, pos: Vec2, sampler: &mut crate::sampler::Sampler) -> crate::ray::Ray {
    let aperture = if scene.camera.needs_aperture_sample() { sampler.next_2d() } else { Vec2::splat(0.5) };
    scene.camera.ray(pos, aperture)
}

/// Camera samples handed to the integrator at once: sixteen packets, so that the sixteen-lane
/// tracer refills a lane whose path ended with the next sample far more often than it drains.
const BATCH: usize = 16 * LANES;

/// What every row task of a render shares.
struct Run<'a, P> {
    scene: &'a Scene,
    opts: &'a RenderOptions,
    progress: &'a P,
    done: AtomicU64,
    total: u64,
}

impl<P: Fn(Progress) + Sync> Run<'_, P> {
    fn cancelled(&self) -> bool {
        self.opts.cancel.as_ref().is_some_and(|c| c.load(Ordering::Relaxed))
    }

    fn row_done(&self, w: usize, samples: u32) {
        let n = w as u64 * samples as u64;
        let d = self.done.fetch_add(n, Ordering::Relaxed) + n;
        (self.progress)(Progress { done: d, total: self.total });
    }

    /// Takes samples `s0..s1` of every pixel of row `y` (of `w`), a batch of [`BATCH`] camera
    /// samples at a time, and hands each batch to `out(&[(x, film position)], radiances)`,
    /// pixel by pixel and sample by sample in order.
    fn row_samples(&self, y: usize, w: usize, s0: u32, s1: u32, mut out: impl FnMut(&[(usize, Vec2)], &[Rgb])) {
        let (scene, opts) = (self.scene, self.opts);
        let (mut rays, mut samplers, mut at) = (Vec::with_capacity(BATCH), Vec::with_capacity(BATCH), Vec::new());
        let mut l = vec![Rgb::ZERO; BATCH];
        // Without a lens, the camera computes the rays of sixteen samples together.
        let lens = scene.camera.needs_aperture_sample();
        let mut film = [Vec2::ZERO; LANES];
        let mut run = |rays: &mut Vec<Ray>, samplers: &mut Vec<Sampler>, at: &mut Vec<(usize, Vec2)>| {
            if !lens {
                for group in at.chunks(LANES) {
                    for (f, &(_, pos)) in film.iter_mut().zip(group) {
                        *f = pos;
                    }
                    rays.extend_from_slice(&scene.camera.rays(&film, scene.simd())[..group.len()]);
                }
            }
            let l = &mut l[..at.len()];
            opts.integrator.li_batch(scene, rays, samplers, l);
            out(at, l);
            rays.clear();
            samplers.clear();
            at.clear();
        };
        for x in 0..w {
            let key = PixelKey::new(opts.seed, (y * w + x) as u64);
            for s in s0..s1 {
                let mut sampler = key.sampler(s as u64);
                let pos = Vec2::new(x as f32, y as f32) + sampler.next_2d();
                if lens {
                    rays.push(camera_ray(scene, pos, &mut sampler));
                }
                samplers.push(sampler);
                at.push((x, pos));
                if at.len() == BATCH {
                    run(&mut rays, &mut samplers, &mut at);
                }
            }
        }
        if !at.is_empty() {
            run(&mut rays, &mut samplers, &mut at);
        }
    }

    /// The box filter: each sample counts in its own pixel only.
    fn boxed(&self, w: usize, h: usize) -> Image {
        let opts = self.opts;
        let mut sums = vec![[0.0f64; 3]; w * h];
        let mut row_spp = vec![0u32; h];
        for (s0, s1) in passes(opts.first_sample, opts.spp) {
            // A task per row (`with_max_len(1)`): by default rayon hands a thread runs of rows
            // that an idle thread cannot take over, and each pass waits for the slowest run.
            let rows = sums.par_chunks_mut(w).zip(row_spp.par_iter_mut()).with_max_len(1);
            rows.enumerate().for_each(|(y, (row, count))| {
                if self.cancelled() {
                    return;
                }
                self.row_samples(y, w, s0, s1, |at, l| {
                    for (&(x, _), l) in at.iter().zip(l) {
                        for (a, c) in row[x].iter_mut().zip(l.0) {
                            *a += c as f64;
                        }
                    }
                });
                *count = s1 - opts.first_sample;
                self.row_done(w, s1 - s0);
            });
            if self.cancelled() {
                break;
            }
        }
        let mut img = Image::new(w as u32, h as u32);
        for (y, &n) in row_spp.iter().enumerate() {
            if n == 0 {
                continue;
            }
            for x in 0..w {
                let s = sums[y * w + x];
                img.pixels[y * w + x] =
                    Rgb::new((s[0] / n as f64) as f32, (s[1] / n as f64) as f32, (s[2] / n as f64) as f32);
            }
        }
        img
    }

    /// A filter wider than the pixel: samples splat into a `SplatFilm`, band by band of rows.
    /// A cancelled render keeps what was gathered: each pixel stays a normalised average.
    fn splatted(&self, w: usize, h: usize) -> Image {
        let (scene, opts) = (self.scene, self.opts);
        let mut film = SplatFilm::new(&scene.camera.filter, w, h);
        let band = film.band_rows();
        let mut bufs: Vec<RowSplats> = (0..band).map(|_| film.row_splats()).collect();
        'passes: for (s0, s1) in passes(opts.first_sample, opts.spp) {
            for b0 in (0..h).step_by(band) {
                let rows = &mut bufs[..band.min(h - b0)];
                // A task per row, as in `boxed` (matpreview without: two cores 10 % idle).
                rows.par_iter_mut().with_max_len(1).enumerate().for_each(|(k, buf)| {
                    let y = b0 + k;
                    buf.reset(y);
                    if self.cancelled() {
                        return;
                    }
                    self.row_samples(y, w, s0, s1, |at, l| buf.splat_batch(at, l, scene.simd()));
                    self.row_done(w, s1 - s0);
                });
                film.gather(b0, rows);
                if self.cancelled() {
                    break 'passes;
                }
            }
        }
        film.develop()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn passes_cover_every_sample_once() {
        for first in [0, 5, u32::MAX - 3] {
            for spp in [0, 1, 2, 3, 64, 100, 1000] {
                let mut next = first;
                for (a, b) in passes(first, spp) {
                    assert_eq!(a, next);
                    assert!(b > a && b - a <= 64);
                    next = b;
                }
                assert_eq!(next, first.saturating_add(spp));
            }
        }
    }
}
