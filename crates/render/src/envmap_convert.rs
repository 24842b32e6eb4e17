//! Light-probe conversions between the three ways of storing the radiance arriving from every
//! direction: a mirror ball (a photograph of a chrome sphere, the lecture's "capture an HDR
//! image of a light probe"), an equirectangular (latitude-longitude) map and a cube map.
//!
//! World frame: +Y up, as for [`EnvMap`] (u = atan2(d.x, −d.z)/2π, v = acos(d.y)/π).
//! - Mirror ball, seen orthographically from +Z: the ball pixel at (x, y) ∈ [−1, 1]² (y up) has
//!   normal n = (x, y, √(1 − x² − y²)) and reflects the viewer direction v = +Z into
//!   d = 2(n·v)n − v, so the centre shows +Z and the rim −Z; conversely n = (d + v)/|d + v|.
//! - Cube map: OpenGL's faces +X, −X, +Y, −Y, +Z, −Z (face coordinates s right, t down in
//!   [−1, 1]); the horizontal cross is 4N × 3N with +Y above and −Y below +Z, and the middle row
//!   −X, +Z, +X, −Z.
//!
//! Every conversion resamples through a radiance lookup `Fn(Vec3) -> Rgb` (bilinear), so any
//! source can be written to any target.

use crate::error::{Error, Result};
use crate::image::Image;
use crate::light::envmap::{uv_to_direction, EnvMap};
use glam::{DVec3, Vec2, Vec3};
use radiometry::Rgb;

/// A light probe in one of the three layouts.
#[derive(Clone, Debug)]
pub enum Probe {
    /// An equirectangular map (Mitsuba's lookup).
    Equirect(Box<EnvMap>),
    /// A mirror-ball image (square; the ball fills it).
    MirrorBall(Image),
    /// Six square faces in the order +X, −X, +Y, −Y, +Z, −Z.
    Cube(Vec<Image>),
}

/// The cube faces' names, in storage order.
pub const FACE_NAMES: [&str; 6] = ["px", "nx", "py", "ny", "pz", "nz"];

/// Bilinear lookup at continuous pixel coordinates (pixel centres at integer + ½), clamped.
fn bilinear(img: &Image, x: f32, y: f32) -> Rgb {
    let (w, h) = (img.width as i64, img.height as i64);
    let (x, y) = (x - 0.5, y - 0.5);
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let at = |i: i64, j: i64| img.get(i.clamp(0, w - 1) as u32, j.clamp(0, h - 1) as u32);
    let (i, j) = (x0 as i64, y0 as i64);
    let top = at(i, j) * (1.0 - fx) + at(i + 1, j) * fx;
    let bottom = at(i, j + 1) * (1.0 - fx) + at(i + 1, j + 1) * fx;
    top * (1.0 - fy) + bottom * fy
}

/// The direction through cube face `face` at face coordinates (s, t) ∈ [−1, 1]², unnormalised.
#[inline]
fn cube_direction(face: usize, s: f32, t: f32) -> Vec3 {
    match face {
        0 => Vec3::new(1.0, -t, -s),
        1 => Vec3::new(-1.0, -t, s),
        2 => Vec3::new(s, 1.0, t),
        3 => Vec3::new(s, -1.0, -t),
        4 => Vec3::new(s, -t, 1.0),
        _ => Vec3::new(-s, -t, -1.0),
    }
}

/// The face and (s, t) ∈ [−1, 1]² a direction passes through (the inverse of `cube_direction`).
#[inline]
fn cube_face(d: Vec3) -> (usize, f32, f32) {
    let a = d.abs();
    if a.x >= a.y && a.x >= a.z {
        if d.x > 0.0 {
            (0, -d.z / a.x, -d.y / a.x)
        } else {
            (1, d.z / a.x, -d.y / a.x)
        }
    } else if a.y >= a.z {
        if d.y > 0.0 {
            (2, d.x / a.y, d.z / a.y)
        } else {
            (3, d.x / a.y, -d.z / a.y)
        }
    } else if d.z > 0.0 {
        (4, d.x / a.z, -d.y / a.z)
    } else {
        (5, -d.x / a.z, -d.y / a.z)
    }
}

impl Probe {
    /// An equirectangular probe from an image.
    pub fn equirect(image: &Image) -> Result<Probe> {
        Ok(Probe::Equirect(Box::new(EnvMap::new(image, 1.0)?)))
    }

    /// A mirror-ball probe; the image must be square.
    pub fn mirror_ball(image: Image) -> Result<Probe> {
        if image.width != image.height || image.width == 0 {
            return Err(Error::Invalid(format!(
                "a mirror-ball image must be square, not {}x{}",
                image.width, image.height
            )));
        }
        Ok(Probe::MirrorBall(image))
    }

    /// A cube-map probe from six square faces of one size (+X, −X, +Y, −Y, +Z, −Z).
    pub fn cube(faces: Vec<Image>) -> Result<Probe> {
        let n = faces.first().map_or(0, |f| f.width);
        if faces.len() != 6 || n == 0 || faces.iter().any(|f| f.width != n || f.height != n) {
            return Err(Error::Invalid("a cube map needs six square faces of the same size".into()));
        }
        Ok(Probe::Cube(faces))
    }

    /// A cube-map probe from a horizontal cross (4N × 3N).
    pub fn cross(image: &Image) -> Result<Probe> {
        Probe::cube(cross_to_faces(image)?)
    }

    /// Radiance arriving from unit direction `d`.
    pub fn eval(&self, d: Vec3) -> Rgb {
        match self {
            Probe::Equirect(e) => e.eval(d),
            Probe::MirrorBall(img) => {
                let Some(n) = (d + Vec3::Z).try_normalize() else {
                    // Straight behind the ball: the rim, any point of it.
                    return bilinear(img, img.width as f32 * 0.5, 0.0);
                };
                let size = img.width as f32;
                bilinear(img, (n.x + 1.0) * 0.5 * size, (1.0 - n.y) * 0.5 * size)
            }
            Probe::Cube(faces) => {
                let (f, s, t) = cube_face(d);
                let n = faces[f].width as f32;
                bilinear(&faces[f], (s + 1.0) * 0.5 * n, (t + 1.0) * 0.5 * n)
            }
        }
    }

    /// A `width` × `height` equirectangular image, texel (i, j) at u = (i + ½)/W, v = j/(H − 1).
    pub fn to_equirect(&self, width: u32, height: u32) -> Image {
        let mut img = Image::new(width, height);
        let dv = 1.0 / (height.max(2) - 1) as f32;
        for j in 0..height {
            for i in 0..width {
                let d = uv_to_direction(Vec2::new((i as f32 + 0.5) / width as f32, j as f32 * dv));
                img.set(i, j, self.eval(d));
            }
        }
        img
    }

    /// A `size` × `size` mirror-ball image; pixels outside the ball are black.
    pub fn to_mirror_ball(&self, size: u32) -> Image {
        let mut img = Image::new(size, size);
        for y in 0..size {
            for x in 0..size {
                let nx = 2.0 * (x as f32 + 0.5) / size as f32 - 1.0;
                let ny = 1.0 - 2.0 * (y as f32 + 0.5) / size as f32;
                let r2 = nx * nx + ny * ny;
                if r2 > 1.0 {
                    continue;
                }
                let nz = (1.0 - r2).sqrt();
                let d = Vec3::new(2.0 * nz * nx, 2.0 * nz * ny, 2.0 * nz * nz - 1.0);
                img.set(x, y, self.eval(d.normalize()));
            }
        }
        img
    }

    /// Six `size` × `size` cube faces (+X, −X, +Y, −Y, +Z, −Z).
    pub fn to_cube_faces(&self, size: u32) -> Vec<Image> {
        (0..6)
            .map(|f| {
                let mut img = Image::new(size, size);
                for y in 0..size {
                    for x in 0..size {
                        let s = 2.0 * (x as f32 + 0.5) / size as f32 - 1.0;
                        let t = 2.0 * (y as f32 + 0.5) / size as f32 - 1.0;
                        img.set(x, y, self.eval(cube_direction(f, s, t).normalize()));
                    }
                }
                img
            })
            .collect()
    }

    /// The irradiance on an upward-facing surface, H = ∫ L(ω) cos θ dω over the upper (+Y)
    /// hemisphere, per channel (W/m² when L is in W/(m²·sr)).
    pub fn irradiance_up(&self) -> [f64; 3] {
        // The quadrature is in a z-up frame; world +Y is its z.
        let world = |d: DVec3| Vec3::new(d.x as f32, d.z as f32, -d.y as f32);
        [0, 1, 2].map(|c| radiometry::integrate::irradiance_quadrature(|d| self.eval(world(d)).0[c] as f64, 256, 512))
    }
}

/// The six faces (+X, −X, +Y, −Y, +Z, −Z) laid out as a horizontal cross, black elsewhere.
pub fn faces_to_cross(faces: &[Image]) -> Image {
    let n = faces[0].width;
    let mut img = Image::new(4 * n, 3 * n);
    for (f, &(cx, cy)) in CROSS_CELLS.iter().enumerate() {
        for y in 0..n {
            for x in 0..n {
                img.set(cx * n + x, cy * n + y, faces[f].get(x, y));
            }
        }
    }
    img
}

/// The six faces cut from a horizontal cross (4N × 3N).
pub fn cross_to_faces(image: &Image) -> Result<Vec<Image>> {
    let n = image.width / 4;
    if n == 0 || image.width != 4 * n || image.height != 3 * n {
        return Err(Error::Invalid(format!(
            "a cube-map cross must be 4N x 3N pixels, not {}x{}",
            image.width, image.height
        )));
    }
    Ok(CROSS_CELLS
        .iter()
        .map(|&(cx, cy)| {
            let mut f = Image::new(n, n);
            for y in 0..n {
                for x in 0..n {
                    f.set(x, y, image.get(cx * n + x, cy * n + y));
                }
            }
            f
        })
        .collect())
}

/// Cell (column, row) of each face in the cross.
const CROSS_CELLS: [(u32, u32); 6] = [(2, 1), (0, 1), (1, 0), (1, 2), (1, 1), (3, 1)];

/// Flat (uncompressed) Radiance RGBE bytes of `image`, readable by `io::hdr::parse_hdr`.
pub fn encode_rgbe(image: &Image) -> Vec<u8> {
    let mut out =
        format!("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {} +X {}\n", image.height, image.width).into_bytes();
    for p in &image.pixels {
        let m = p.max_channel();
        if m.is_nan() || m <= 1e-32 || !m.is_finite() {
            out.extend_from_slice(&[0, 0, 0, 0]);
            continue;
        }
        // m = f·2^e with f ∈ [0.5, 1): the mantissas are c/2^e·256, rounded to the nearest,
        // since a reader multiplies them back without an offset.
        let e = m.log2().floor() as i32 + 1;
        let scale = 256.0 / (e as f32).exp2();
        let q = |c: f32| (c.max(0.0) * scale + 0.5).min(255.0) as u8;
        out.extend_from_slice(&[q(p.0[0]), q(p.0[1]), q(p.0[2]), (e + 128).clamp(0, 255) as u8]);
    }
    out
}

/// Writes `image` as a Radiance .hdr file, atomically.
pub fn write_hdr(image: &Image, path: &std::path::Path) -> Result<()> {
    crate::io::atomic::write_atomically(path, |tmp| {
        std::fs::write(tmp, encode_rgbe(image)).map_err(|e| Error::io(tmp, e))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// A smooth, direction-dependent radiance.
    fn smooth(d: Vec3) -> Rgb {
        Rgb::new(1.0 + 0.5 * d.x, 1.0 + 0.3 * d.y * d.y, 1.2 - 0.4 * d.z)
    }

    fn equirect_of(f: impl Fn(Vec3) -> Rgb, w: u32, h: u32) -> Image {
        let mut img = Image::new(w, h);
        for j in 0..h {
            for i in 0..w {
                let d = uv_to_direction(Vec2::new((i as f32 + 0.5) / w as f32, j as f32 / (h - 1) as f32));
                img.set(i, j, f(d));
            }
        }
        img
    }

    fn directions() -> impl Iterator<Item = Vec3> {
        (0..400).map(|k| {
            // A Fibonacci spiral: even coverage, no randomness.
            let z = 1.0 - (k as f32 + 0.5) / 200.0;
            let phi = k as f32 * 2.399_963;
            let r = (1.0 - z * z).sqrt();
            Vec3::new(r * phi.cos(), r * phi.sin(), z)
        })
    }

    fn close(a: Rgb, b: Rgb, tol: f32) -> bool {
        a.0.iter().zip(b.0).all(|(x, y)| (x - y).abs() <= tol)
    }

    #[test]
    fn cube_face_inverts_cube_direction() {
        for f in 0..6 {
            for (s, t) in [(0.0, 0.0), (0.5, -0.25), (-0.9, 0.8)] {
                let (g, s2, t2) = cube_face(cube_direction(f, s, t));
                assert_eq!(g, f);
                assert!((s - s2).abs() < 1e-6 && (t - t2).abs() < 1e-6, "face {f}");
            }
        }
    }

    #[test]
    fn round_trips_agree_with_the_source() {
        let src = Probe::equirect(&equirect_of(smooth, 256, 128)).unwrap();
        // The bilinear error of a smooth map at these resolutions is below 1e-2.
        let cube = Probe::cube(src.to_cube_faces(64)).unwrap();
        let cross = Probe::cross(&faces_to_cross(&cube.to_cube_faces(64))).unwrap();
        let ball = Probe::mirror_ball(src.to_mirror_ball(256)).unwrap();
        let back = Probe::equirect(&ball.to_equirect(256, 128)).unwrap();
        for d in directions() {
            let want = smooth(d);
            assert!(close(cube.eval(d), want, 1e-2), "cube {d}");
            assert!(close(cross.eval(d), want, 1e-2), "cross {d}");
            // The ball squeezes the hemisphere behind it into the rim: compare away from −Z.
            if d.z > -0.8 {
                assert!(close(ball.eval(d), want, 2e-2), "ball {d}: {:?} {want:?}", ball.eval(d));
                assert!(close(back.eval(d), want, 3e-2), "ball → equirect {d}");
            }
        }
    }

    #[test]
    fn constant_map_irradiance_is_pi_l() {
        let l = 0.75f32;
        for probe in [
            Probe::equirect(&equirect_of(|_| Rgb::splat(l), 64, 32)).unwrap(),
            Probe::cube(vec![Image { width: 4, height: 4, pixels: vec![Rgb::splat(l); 16] }; 6]).unwrap(),
        ] {
            for h in probe.irradiance_up() {
                assert!((h - PI * l as f64).abs() < 1e-4, "{h}");
            }
        }
        // Light only from below: nothing reaches an upward surface.
        let below = Probe::equirect(&equirect_of(|d| Rgb::splat(if d.y < -0.05 { 1.0 } else { 0.0 }), 64, 33)).unwrap();
        assert!(below.irradiance_up().iter().all(|&h| h.abs() < 1e-9));
    }

    #[test]
    fn rgbe_round_trip_is_within_quantisation() {
        let img = equirect_of(smooth, 16, 8);
        let back = crate::io::hdr::parse_hdr(&encode_rgbe(&img)).unwrap();
        for (a, b) in img.pixels.iter().zip(&back.pixels) {
            // 8-bit mantissas: relative error ≤ 2^-7 of the largest channel.
            assert!(close(*a, *b, a.max_channel() / 128.0), "{a:?} {b:?}");
        }
        assert!(Probe::mirror_ball(Image::new(4, 3)).is_err());
        assert!(cross_to_faces(&Image::new(8, 7)).is_err());
    }
}
