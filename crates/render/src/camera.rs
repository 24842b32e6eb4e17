//! Cameras with Mitsuba 3's conventions: camera space looks along +z with +x to the left and
//! +y up; `look_at` builds the to-world matrix whose columns are (left, up, forward, origin).
//!
//! - `perspective`: a pinhole with `fov` degrees along `fov_axis`. A film position f (in
//!   [0, 1]² of the full film, plus the principal point offset) looks along
//!   (t_x (1 − 2 f_x), t_y (1 − 2 f_y), 1), t = tan(fov/2) per axis.
//! - `thinlens`: the same frustum through a lens of `aperture_radius` focused on the plane
//!   z = `focus_distance`: the ray leaves a point of the lens (concentric disk sample) for the
//!   point of the focal plane the pinhole ray through f reaches.
//! - `orthographic`: parallel rays along +z from (1 − 2 f_x, (1 − 2 f_y) H/W) on the near
//!   plane, through `to_world` (whose scale sets the view's extent).
//!
//! Rays start on the near plane and end at the far plane, as Mitsuba's do. A crop window
//! renders a sub-rectangle of the film: the frustum stays the full film's.

use crate::filter::Filter;
use crate::ray::Ray;
use crate::simd::{dispatch, Simd, F16, LANES};
use glam::{Mat4, Vec2, Vec3, Vec4};
use radiometry::warp::concentric_disk;

/// How a camera projects.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// A pinhole.
    Perspective,
    /// A thin lens.
    ThinLens {
        /// Lens radius, scene units.
        aperture_radius: f32,
        /// Distance of the plane in focus along the view axis.
        focus_distance: f32,
    },
    /// Parallel rays.
    Orthographic,
}

/// Which image extent `fov` spans.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FovAxis {
    /// The image width.
    X,
    /// The image height.
    Y,
    /// The image diagonal.
    Diagonal,
    /// The shorter of width and height.
    Smaller,
    /// The longer of width and height.
    Larger,
}

impl std::str::FromStr for FovAxis {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "x" => Ok(FovAxis::X),
            "y" => Ok(FovAxis::Y),
            "diagonal" => Ok(FovAxis::Diagonal),
            "smaller" => Ok(FovAxis::Smaller),
            "larger" => Ok(FovAxis::Larger),
            _ => Err(format!("fov_axis '{s}' is not one of x|y|diagonal|smaller|larger")),
        }
    }
}

/// Mitsuba's look-at transform: columns (left, up, forward, origin), left = up × forward.
/// Returns None when `target` = `origin` or `up` is parallel to the view direction.
pub fn look_at(origin: Vec3, target: Vec3, up: Vec3) -> Option<Mat4> {
    let dir = (target - origin).try_normalize()?;
    let left = up.cross(dir).try_normalize()?;
    let new_up = dir.cross(left);
    Some(Mat4::from_cols(left.extend(0.0), new_up.extend(0.0), dir.extend(0.0), origin.extend(1.0)))
}

/// A camera producing rays through a film.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// Camera space (x left, y up, z forward) to world.
    pub to_world: Mat4,
    /// Image width in pixels (the crop window's).
    pub width: u32,
    /// Image height in pixels (the crop window's).
    pub height: u32,
    /// The full film's size in pixels, which the frustum spans.
    pub film: (u32, u32),
    /// The crop window's top-left pixel on the film.
    pub crop_offset: (u32, u32),
    /// The principal point's shift, as fractions of the film's width and height.
    pub principal_point: Vec2,
    /// tan of half the field of view along x and y.
    tan_half: Vec2,
    /// Rays start this far along camera-space z (Mitsuba's near_clip).
    pub near_clip: f32,
    /// Rays end this far along camera-space z (Mitsuba's far_clip).
    pub far_clip: f32,
    /// The film's reconstruction filter (box unless set).
    pub filter: Filter,
    /// The projection.
    pub projection: Projection,
}

impl Camera {
    /// A pinhole camera with `fov_deg` degrees along `axis`; `to_world` as from [`look_at`].
    pub fn new(to_world: Mat4, fov_deg: f32, axis: FovAxis, width: u32, height: u32) -> Self {
        let (w, h) = (width.max(1) as f32, height.max(1) as f32);
        let t = (0.5 * fov_deg.to_radians()).tan();
        let axis = match axis {
            FovAxis::Smaller if w <= h => FovAxis::X,
            FovAxis::Smaller => FovAxis::Y,
            FovAxis::Larger if w >= h => FovAxis::X,
            FovAxis::Larger => FovAxis::Y,
            a => a,
        };
        let tan_x = match axis {
            FovAxis::Y => t * w / h,
            FovAxis::Diagonal => t * w / (w * w + h * h).sqrt(),
            _ => t,
        };
        Camera {
            to_world,
            width,
            height,
            film: (width, height),
            crop_offset: (0, 0),
            principal_point: Vec2::ZERO,
            tan_half: Vec2::new(tan_x, tan_x * h / w),
            near_clip: 0.0,
            far_clip: f32::INFINITY,
            filter: Filter::Box,
            projection: Projection::Perspective,
        }
    }

    /// The same camera rendering only the `width` × `height` window at `offset` of its film;
    /// None when the window does not fit.
    pub fn cropped(mut self, offset: (u32, u32), width: u32, height: u32) -> Option<Self> {
        let fits = |o: u32, s: u32, f: u32| s >= 1 && o.checked_add(s).is_some_and(|e| e <= f);
        if !(fits(offset.0, width, self.film.0) && fits(offset.1, height, self.film.1)) {
            return None;
        }
        self.crop_offset = offset;
        self.width = width;
        self.height = height;
        Some(self)
    }

    /// True when a ray needs a lens sample.
    #[inline]
    pub fn needs_aperture_sample(&self) -> bool {
        matches!(self.projection, Projection::ThinLens { .. })
    }

    /// The point of the film for image position `film` (pixels of the crop window), as
    /// fractions of the full film.
    #[inline]
    fn film_fraction(&self, film: Vec2) -> Vec2 {
        (film + self.crop_offset_px()) / self.film_size() + self.principal_point
    }

    /// The crop window's offset in the full film, in pixels, as floats.
    fn crop_offset_px(&self) -> Vec2 {
        Vec2::new(self.crop_offset.0 as f32, self.crop_offset.1 as f32)
    }

    /// The full film's size in pixels, as floats.
    fn film_size(&self) -> Vec2 {
        Vec2::new(self.film.0 as f32, self.film.1 as f32)
    }

    /// The ray through image position `film` in pixels (x right, y down; pixel (i, j) covers
    /// [i, i+1) × [j, j+1)), through lens point `aperture` (uniform in [0, 1)², used by the
    /// thin lens), limited to [near_clip, far_clip] along the view axis.
    pub fn ray(&self, film: Vec2, aperture: Vec2) -> Ray {
        let f = self.film_fraction(film);
        let (nx, ny) = (1.0 - 2.0 * f.x, 1.0 - 2.0 * f.y);
        // The translation column: transform_point3(0) would multiply the other columns by 0.
        let origin = self.to_world.w_axis.truncate();
        let depth = (self.far_clip - self.near_clip).max(0.0);
        match self.projection {
            Projection::Perspective => {
                // Camera +x is to the left, so the left image edge (nx = 1) maps to +x.
                let local = Vec3::new(nx * self.tan_half.x, ny * self.tan_half.y, 1.0);
                let d_world = self.to_world.transform_vector3(local);
                let len = d_world.length();
                let d = d_world / len;
                // local.z = 1, so one unit of camera depth is `len` world units along d.
                Ray { o: origin + d * (self.near_clip * len), d, t_max: depth * len }
            }
            Projection::ThinLens { aperture_radius, focus_distance } => {
                let focus = Vec3::new(nx * self.tan_half.x, ny * self.tan_half.y, 1.0) * focus_distance;
                let lens = (concentric_disk(aperture) * aperture_radius).extend(0.0);
                let local = (focus - lens).normalize();
                let d = self.to_world.transform_vector3(local).normalize();
                let o = self.to_world.transform_point3(lens);
                Ray { o: o + d * (self.near_clip / local.z), d, t_max: depth / local.z }
            }
            Projection::Orthographic => {
                let (w, h) = (self.film.0.max(1) as f32, self.film.1.max(1) as f32);
                let o = self.to_world.transform_point3(Vec3::new(nx, ny * h / w, self.near_clip));
                let d = self.to_world.transform_vector3(Vec3::Z).normalize();
                Ray { o, d, t_max: depth }
            }
        }
    }

    /// The rays through the sixteen image positions `film` (see [`ray`](Self::ray), whose
    /// results they are bit for bit), computed in SIMD lanes on `simd` for a perspective camera,
    /// one by one otherwise (the lens needs its own samples).
    pub fn rays(&self, film: &[Vec2; LANES], simd: Simd) -> [Ray; LANES] {
        match self.projection {
            Projection::Perspective if simd != Simd::Scalar => {
                dispatch!(simd, self: Camera, perspective_rays(film: &[Vec2; LANES]) -> [Ray; LANES])
            }
            _ => std::array::from_fn(|i| self.ray(film[i], Vec2::splat(0.5))),
        }
    }

    /// [`rays`](Self::rays) for the perspective projection: `ray`'s operations, lane by lane.
    #[inline(always)]
    fn perspective_rays(&self, film: &[Vec2; LANES]) -> [Ray; LANES] {
        let lanes = |f: &dyn Fn(usize) -> f32| F16(std::array::from_fn(f));
        let s = F16::splat;
        let (off, size) = (self.crop_offset_px(), self.film_size());
        let fx = (lanes(&|i| film[i].x) + s(off.x)) / s(size.x) + s(self.principal_point.x);
        let fy = (lanes(&|i| film[i].y) + s(off.y)) / s(size.y) + s(self.principal_point.y);
        let (nx, ny) = (s(1.0) - s(2.0) * fx, s(1.0) - s(2.0) * fy);
        let (lx, ly) = (nx * s(self.tan_half.x), ny * s(self.tan_half.y));
        let m = &self.to_world;
        let axis = |a: usize| {
            // glam's transform_vector3: (x_axis·x + y_axis·y) + z_axis·z, z = 1.
            lx * s(m.x_axis[a]) + ly * s(m.y_axis[a]) + s(m.z_axis[a] * 1.0)
        };
        let d = [axis(0), axis(1), axis(2)];
        let len = F16(std::array::from_fn(|i| {
            let (x, y, z) = (d[0].0[i], d[1].0[i], d[2].0[i]);
            (x * x + y * y + z * z).sqrt()
        }));
        let d = d.map(|c| c / len);
        let depth = (self.far_clip - self.near_clip).max(0.0);
        let near = s(self.near_clip) * len;
        let o = [0, 1, 2].map(|a| s(m.w_axis[a]) + d[a] * near);
        let t_max = s(depth) * len;
        let mut rays = [Ray::new(Vec3::ZERO, Vec3::Z); LANES];
        for (i, r) in rays.iter_mut().enumerate() {
            *r = Ray {
                o: Vec3::new(o[0].0[i], o[1].0[i], o[2].0[i]),
                d: Vec3::new(d[0].0[i], d[1].0[i], d[2].0[i]),
                t_max: t_max.0[i],
            };
        }
        rays
    }

    /// The camera position in world space.
    pub fn origin(&self) -> Vec3 {
        (self.to_world * Vec4::W).truncate()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn batched_perspective_rays_are_the_single_rays_bit_for_bit() {
        let m = look_at(Vec3::new(0.3, -1.0, 5.0), Vec3::new(0.1, 0.2, 0.0), Vec3::Y).unwrap();
        let mut cam = Camera::new(m, 37.0, FovAxis::Y, 40, 30).cropped((3, 4), 20, 10).unwrap();
        cam.principal_point = Vec2::new(0.05, -0.1);
        cam.near_clip = 0.7;
        let film: [Vec2; LANES] = std::array::from_fn(|i| Vec2::new(i as f32 * 2.37 + 0.13, 29.9 - i as f32 * 1.7));
        for (_, simd) in Simd::ALL.into_iter().filter(|(_, s)| s.available()) {
            let rays = cam.rays(&film, simd);
            for (r, &f) in rays.iter().zip(&film) {
                let want = cam.ray(f, Vec2::splat(0.5));
                assert_eq!((r.o, r.d, r.t_max.to_bits()), (want.o, want.d, want.t_max.to_bits()), "{simd:?} at {f}");
            }
        }
    }

    #[test]
    fn look_at_centre_and_edges() {
        let m = look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y).unwrap();
        let cam = Camera::new(m, 90.0, FovAxis::X, 64, 32);
        let c = cam.ray(Vec2::new(32.0, 16.0), Vec2::splat(0.5));
        assert!((c.d - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-6);
        assert!((c.o - Vec3::new(0.0, 0.0, 5.0)).length() < 1e-6);
        // 90° along x: the right edge is 45° to the right (+x in world when looking down -z).
        let r = cam.ray(Vec2::new(64.0, 16.0), Vec2::splat(0.5));
        assert!((r.d - Vec3::new(1.0, 0.0, -1.0).normalize()).length() < 1e-6, "{:?}", r.d);
        // The top edge: tan = 0.5 (height/width), upwards.
        let t = cam.ray(Vec2::new(32.0, 0.0), Vec2::splat(0.5));
        assert!((t.d - Vec3::new(0.0, 0.5, -1.0).normalize()).length() < 1e-6, "{:?}", t.d);
    }

    #[test]
    fn fov_axes() {
        let m = Mat4::IDENTITY;
        let y = Camera::new(m, 60.0, FovAxis::Y, 200, 100);
        let t = (30.0f32).to_radians().tan();
        assert!((y.tan_half.y - t).abs() < 1e-6 && (y.tan_half.x - 2.0 * t).abs() < 1e-6);
        let d = Camera::new(m, 60.0, FovAxis::Diagonal, 300, 400);
        assert!((d.tan_half.length() - t).abs() < 1e-6);
        let s = Camera::new(m, 60.0, FovAxis::Smaller, 300, 400);
        assert!((s.tan_half.x - t).abs() < 1e-6);
        assert!(look_at(Vec3::ZERO, Vec3::Y, Vec3::Y).is_none());
    }
}
