//! The perspective pinhole camera, with Mitsuba 3's conventions: camera space looks along
//! +z with +x to the left and +y up; `look_at` builds the to-world matrix whose columns are
//! (left, up, forward, origin); `fov` is in degrees along `fov_axis`.

use crate::filter::Filter;
use crate::ray::Ray;
use glam::{Mat4, Vec2, Vec3, Vec4};

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

/// A pinhole camera producing rays through a `width` × `height` film.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// Camera space (x left, y up, z forward) to world.
    pub to_world: Mat4,
    /// Film width in pixels.
    pub width: u32,
    /// Film height in pixels.
    pub height: u32,
    /// tan of half the field of view along x and y.
    tan_half: Vec2,
    /// Rays start this far along camera-space z (Mitsuba's near_clip).
    pub near_clip: f32,
    /// Rays end this far along camera-space z (Mitsuba's far_clip).
    pub far_clip: f32,
    /// The film's reconstruction filter (box unless set).
    pub filter: Filter,
}

impl Camera {
    /// A camera with `fov_deg` degrees along `axis`; `to_world` as from [`look_at`].
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
            tan_half: Vec2::new(tan_x, tan_x * h / w),
            near_clip: 0.0,
            far_clip: f32::INFINITY,
            filter: Filter::Box,
        }
    }

    /// A film position for a sample of pixel `pixel` (its top-left corner) drawn from the
    /// filter with uniform `u`, and the weight that multiplies the sample's radiance.
    #[inline]
    pub fn film_sample(&self, pixel: Vec2, u: Vec2) -> (Vec2, f32) {
        match &self.filter {
            Filter::Box => (pixel + u, 1.0),
            f => {
                let (offset, weight) = f.sample(u);
                (pixel + Vec2::splat(0.5) + offset, weight)
            }
        }
    }

    /// The ray through film position `film` in pixels (x right, y down; pixel (i, j) covers
    /// [i, i+1) × [j, j+1)), limited to [near_clip, far_clip] along the view axis.
    pub fn ray(&self, film: Vec2) -> Ray {
        let nx = 1.0 - 2.0 * film.x / self.width as f32;
        let ny = 1.0 - 2.0 * film.y / self.height as f32;
        // Camera +x is to the left, so the left image edge (nx = 1) maps to +x.
        let local = Vec3::new(nx * self.tan_half.x, ny * self.tan_half.y, 1.0);
        // The translation column: transform_point3(0) would multiply the other columns by 0.
        let o = self.to_world.w_axis.truncate();
        let d_world = self.to_world.transform_vector3(local);
        let len = d_world.length();
        let d = d_world / len;
        // local.z = 1, so one unit of camera depth is `len` world units along d.
        let t_min = self.near_clip * len;
        Ray { o: o + d * t_min, d, t_max: (self.far_clip - self.near_clip).max(0.0) * len }
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
    fn look_at_centre_and_edges() {
        let m = look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y).unwrap();
        let cam = Camera::new(m, 90.0, FovAxis::X, 64, 32);
        let c = cam.ray(Vec2::new(32.0, 16.0));
        assert!((c.d - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-6);
        assert!((c.o - Vec3::new(0.0, 0.0, 5.0)).length() < 1e-6);
        // 90° along x: the right edge is 45° to the right (+x in world when looking down -z).
        let r = cam.ray(Vec2::new(64.0, 16.0));
        assert!((r.d - Vec3::new(1.0, 0.0, -1.0).normalize()).length() < 1e-6, "{:?}", r.d);
        // The top edge: tan = 0.5 (height/width), upwards.
        let t = cam.ray(Vec2::new(32.0, 0.0));
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
