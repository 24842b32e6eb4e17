//! Rendering until the image is converged, with a progress bar.
//!
//! Samples are taken in rounds. Each round adds as many samples as the image already has,
//! split into two halves A and B that draw disjoint ranges of every pixel's sample stream.
//! The noise of the whole image is then estimated from the halves as the RMS of (d(A) − d(B))/2
//! in display values d = sRGB(2^E · L) clamped to [0, 1], what the PNG shows: with n samples
//! in each half, A − B has twice the variance of one half's mean, that is, four times that of
//! the full image's mean. The RMS runs over the pixels and channels where the halves differ,
//! so a background that has no noise (an environment seen directly, a clipped highlight) does
//! not dilute it. The render stops once the estimate is at most the threshold, or when the
//! sample budget is spent.

use radiometry::Rgb;
use render::io::png::srgb_encode;
use render::{Image, RenderOptions, Scene};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};

/// Samples each half takes in the first round.
const FIRST_HALF: u32 = 4;

/// When a render stops.
#[derive(Clone, Copy, Debug)]
pub struct Target {
    /// The sample budget per pixel.
    pub max_spp: u32,
    /// Stop once the estimated display noise is at most this; None takes `max_spp` samples.
    pub noise: Option<f32>,
    /// Exposure in stops of the display values the noise is measured in.
    pub exposure: f32,
}

/// A finished render.
pub struct Converged {
    /// The image: the mean of every sample taken.
    pub image: Image,
    /// Samples per pixel taken.
    pub spp: u32,
    /// The last noise estimate (None without a noise target).
    pub noise: Option<f32>,
    /// Whether Ctrl-C cut it short.
    pub cancelled: bool,
}

/// The process-wide cancel flag, set by Ctrl-C (the handler can be installed only once).
pub fn cancel_flag() -> Arc<AtomicBool> {
    static FLAG: OnceLock<Arc<AtomicBool>> = OnceLock::new();
    FLAG.get_or_init(|| {
        let flag = Arc::new(AtomicBool::new(false));
        let f = flag.clone();
        // Without a handler (e.g. none can be installed) Ctrl-C simply ends the process.
        let _ = ctrlc::set_handler(move || f.store(true, Ordering::Relaxed));
        flag
    })
    .clone()
}

/// Renders `scene` (samples from `opts.first_sample` on) until `target` says stop, with a
/// progress bar labelled `label` on stderr (hidden when stderr is not a terminal). Without a
/// noise target the image is exactly `render::render`'s with `max_spp` samples.
pub fn render(scene: &Scene, opts: &RenderOptions, target: Target, label: &str) -> Converged {
    let cancel = cancel_flag();
    let pixels = scene.camera.width as u64 * scene.camera.height as u64;
    let bar = if std::io::stderr().is_terminal() {
        indicatif::ProgressBar::new(pixels * target.max_spp as u64)
    } else {
        indicatif::ProgressBar::hidden()
    };
    bar.set_style(
        indicatif::ProgressStyle::with_template("{msg} [{bar:40}] {percent:>3}% {elapsed_precise} ETA {eta}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    bar.set_message(label.to_string());
    let run = |first: u32, spp: u32| {
        let o = RenderOptions {
            spp,
            first_sample: opts.first_sample + first,
            cancel: Some(cancel.clone()),
            ..opts.clone()
        };
        let offset = pixels * first as u64;
        render::render(scene, &o, |p| bar.set_position(offset + p.done))
    };
    let stopped = || cancel.load(Ordering::Relaxed);
    let Some(threshold) = target.noise.filter(|_| target.max_spp >= 2 * FIRST_HALF) else {
        let image = run(0, target.max_spp);
        bar.finish_and_clear();
        return Converged { image, spp: target.max_spp, noise: None, cancelled: stopped() };
    };
    let (mut a, mut b) = (Halves::new(scene), Halves::new(scene));
    let mut noise = f32::INFINITY;
    let mut first_cut = None;
    while a.spp + b.spp < target.max_spp && noise > threshold && !stopped() {
        let total = a.spp + b.spp;
        let half = if total == 0 { FIRST_HALF } else { total / 2 };
        let left = target.max_spp - total;
        let (na, nb) = if 2 * half <= left { (half, half) } else { (left.div_ceil(2), left / 2) };
        let img = run(total, na);
        if stopped() {
            // Cut short in the first round: its whole passes are all there is.
            first_cut = (total == 0).then_some(img);
            break;
        }
        a.add(&img, na);
        if nb > 0 {
            let img = run(total + na, nb);
            if stopped() {
                // A is whole, B is partial: keep A's samples only.
                break;
            }
            b.add(&img, nb);
        }
        noise = display_noise(&a.mean(), &b.mean(), target.exposure);
    }
    bar.finish_and_clear();
    let spp = a.spp + b.spp;
    let image = match first_cut {
        Some(img) => img,
        None if b.spp == 0 => a.mean(),
        None => a.merged(&b),
    };
    Converged { image, spp, noise: noise.is_finite().then_some(noise), cancelled: stopped() }
}

/// Per-pixel sums of one half's samples.
struct Halves {
    width: u32,
    height: u32,
    sums: Vec<[f64; 3]>,
    spp: u32,
}

impl Halves {
    fn new(scene: &Scene) -> Self {
        let (width, height) = (scene.camera.width, scene.camera.height);
        Halves { width, height, sums: vec![[0.0; 3]; width as usize * height as usize], spp: 0 }
    }

    /// Adds an image that is the mean of `n` samples.
    fn add(&mut self, img: &Image, n: u32) {
        for (s, p) in self.sums.iter_mut().zip(&img.pixels) {
            for (a, c) in s.iter_mut().zip(p.0) {
                *a += c as f64 * n as f64;
            }
        }
        self.spp += n;
    }

    fn image(&self, sums: impl Iterator<Item = [f64; 3]>, n: u32) -> Image {
        let mut img = Image::new(self.width, self.height);
        let n = n.max(1) as f64;
        for (p, s) in img.pixels.iter_mut().zip(sums) {
            *p = Rgb::new((s[0] / n) as f32, (s[1] / n) as f32, (s[2] / n) as f32);
        }
        img
    }

    fn mean(&self) -> Image {
        self.image(self.sums.iter().copied(), self.spp)
    }

    /// The mean of both halves' samples.
    fn merged(&self, other: &Halves) -> Image {
        let sums = self.sums.iter().zip(&other.sums).map(|(a, b)| [a[0] + b[0], a[1] + b[1], a[2] + b[2]]);
        self.image(sums, self.spp + other.spp)
    }
}

/// The display value of a linear value at `exposure` stops.
fn display(c: f32, scale: f32) -> f32 {
    srgb_encode(c * scale).clamp(0.0, 1.0)
}

/// The estimated RMS display error of the mean of two equally sampled halves `a` and `b`:
/// RMS((d(a) − d(b))/2) over the pixel channels where they differ (0 where none do).
pub fn display_noise(a: &Image, b: &Image, exposure: f32) -> f32 {
    let scale = exposure.exp2();
    let (mut sum, mut n) = (0.0f64, 0u64);
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        for (x, y) in p.0.iter().zip(q.0) {
            let d = (display(*x, scale) - display(y, scale)) as f64 / 2.0;
            if d != 0.0 {
                sum += d * d;
                n += 1;
            }
        }
    }
    if n == 0 {
        0.0
    } else {
        (sum / n as f64).sqrt() as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::demo_scene::{object_scene, probe_light, Lighting};

    /// The squared display differences of `img` from `reference`, over the pixel channels
    /// where the reference's halves `ra` and `rb` differ.
    fn squared_errors(img: &Image, reference: &Image, ra: &Image, rb: &Image) -> Vec<f64> {
        let mut out = Vec::new();
        for (((p, r), a), b) in img.pixels.iter().zip(&reference.pixels).zip(&ra.pixels).zip(&rb.pixels) {
            for c in 0..3 {
                if display(a.0[c], 1.0) != display(b.0[c], 1.0) {
                    out.push(((display(p.0[c], 1.0) - display(r.0[c], 1.0)) as f64).powi(2));
                }
            }
        }
        out
    }

    #[test]
    fn the_adaptive_stop_reaches_its_noise_threshold() {
        // A glossy sphere under the studio probe, the probe seen behind it (noise-free pixels).
        let brdf = brdf::build("phong", &[("ke", "30"), ("diffuse", "0.5,0.1,0.1")]).unwrap();
        let lighting = Lighting { env: Some(probe_light(None, 1.0).unwrap()), point: None };
        let scene = object_scene(brdf.into(), None, &lighting, 32, 32).unwrap();
        let opts = RenderOptions { seed: 5, ..Default::default() };
        let threshold = 0.02;
        let done = render(&scene, &opts, Target { max_spp: 1 << 14, noise: Some(threshold), exposure: 0.0 }, "");
        let estimate = done.noise.unwrap();
        assert!(estimate <= threshold && done.spp < 1 << 14, "stopped by its noise: {estimate} at {} spp", done.spp);
        // A reference of 16 times the samples, from another range of the same streams, in halves.
        let half = 8 * done.spp;
        let far = RenderOptions { first_sample: 1 << 24, spp: half, ..opts.clone() };
        let ra = render::render(&scene, &far, |_| {});
        let rb = render::render(&scene, &RenderOptions { first_sample: (1 << 24) + half, ..far }, |_| {});
        let mut reference = ra.clone();
        for (p, q) in reference.pixels.iter_mut().zip(&rb.pixels) {
            *p = (*p + *q) * 0.5;
        }
        // E[(d(img) − d(ref))²] = noise² + the reference's own noise², estimated from its halves.
        let e = squared_errors(&done.image, &reference, &ra, &rb);
        let n = e.len() as f64;
        let (mean, ref_noise) = (e.iter().sum::<f64>() / n, display_noise(&ra, &rb, 0.0) as f64 / 2f64.sqrt());
        let measured = (mean - ref_noise * ref_noise).max(0.0).sqrt();
        // The RMS over n channels fluctuates by ½·sd(e²)/(mean·√n) relatively: allow 4 of those.
        let sd = (e.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
        let slack = 4.0 * 0.5 * sd / (mean * n.sqrt());
        assert!(
            measured <= threshold as f64 * (1.0 + slack),
            "measured noise {measured:.4} (estimate {estimate:.4}, {} spp, {n} channels, slack {slack:.3})",
            done.spp
        );
        // The estimate is of the right size, not merely small: within a factor 2 of the truth.
        assert!(measured > 0.5 * estimate as f64, "measured {measured:.4} against estimate {estimate:.4}");
        // Without a target: exactly render::render's image.
        let plain = render(&scene, &opts, Target { max_spp: 8, noise: None, exposure: 0.0 }, "");
        assert_eq!(plain.image, render::render(&scene, &RenderOptions { spp: 8, ..opts }, |_| {}));
    }
}
