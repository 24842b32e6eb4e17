//! An environment map's radiance along sixteen escaping rays at once: the lookup's angles,
//! two atan2 per ray, cost more than its texel reads, and computed lane by lane in loops
//! they become vector code (the same operations in the same order as [`EnvMap::eval`], so the
//! same bits). Camera rays that miss every surface, most of the pixels of a scene under an
//! open sky, take this path.

// Lane loops index several arrays in step: the form the vectoriser reads best.
#![allow(clippy::needless_range_loop)]

use super::{direction_to_uv, EnvMap};
use crate::simd::{dispatch, Bits, Simd, LANES};
use glam::{Vec2, Vec3};
use radiometry::Rgb;

impl EnvMap {
    /// [`eval`](Self::eval) of the directions `d` of lanes `lanes` (zero elsewhere), computed
    /// on instruction set `simd`.
    pub fn eval_packet(&self, d: &[Vec3; LANES], lanes: u32, simd: Simd) -> [Rgb; LANES] {
        dispatch!(simd, self: EnvMap, eval_lanes(d: &[Vec3; LANES], lanes: u32) -> [Rgb; LANES])
    }

    #[inline(always)]
    fn eval_lanes(&self, d: &[Vec3; LANES], lanes: u32) -> [Rgb; LANES] {
        let (mut x, mut y, mut z) = ([0.0f32; LANES], [0.0f32; LANES], [0.0f32; LANES]);
        for k in 0..LANES {
            let m = self.to_map(d[k]);
            (x[k], y[k], z[k]) = (m.x, m.y, m.z);
        }
        let (mut i, mut j, mut fx, mut fy) = ([0usize; LANES], [0usize; LANES], [0.0f32; LANES], [0.0f32; LANES]);
        for k in 0..LANES {
            let (ci, cj, f) = self.cell(direction_to_uv(Vec3::new(x[k], y[k], z[k])));
            (i[k], j[k], fx[k], fy[k]) = (ci, cj, f.x, f.y);
        }
        let mut out = [Rgb::ZERO; LANES];
        for k in Bits(lanes) {
            out[k] = self.radiance(i[k], j[k], Vec2::new(fx[k], fy[k]));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::Image;
    use crate::sampler::Sampler;
    use radiometry::warp::uniform_sphere;

    #[test]
    fn sixteen_lanes_give_what_each_direction_gives_alone() {
        let mut img = Image::new(37, 19);
        let mut s = Sampler::new(5, 0, 0);
        for p in img.pixels.iter_mut() {
            *p = Rgb::new(s.next_1d(), 4.0 * s.next_1d(), s.next_1d() * s.next_1d());
        }
        let map = EnvMap::new(&img, 1.5).unwrap();
        let turn = glam::Mat3::from_rotation_y(0.7) * glam::Mat3::from_rotation_x(-0.3);
        for map in [map.clone(), map.with_rotation(turn).unwrap()] {
            for (_, simd) in Simd::ALL.into_iter().filter(|(_, s)| s.available()) {
                for round in 0..200 {
                    // Random directions, the poles, the seam and the axes among them.
                    let mut d: [Vec3; LANES] = std::array::from_fn(|_| uniform_sphere(s.next_2d()));
                    d[0] = Vec3::Y;
                    d[1] = -Vec3::Y;
                    d[2] = Vec3::new(0.0, 0.3, 1.0).normalize();
                    d[3] = Vec3::new(-1e-30, 0.1, 1.0).normalize();
                    d[4] = Vec3::X;
                    let lanes = if round % 2 == 0 { u32::MAX >> 16 } else { 0b1010_0110_1101_0011 };
                    let got = map.eval_packet(&d, lanes, simd);
                    for k in 0..LANES {
                        let want = if lanes >> k & 1 != 0 { map.eval(d[k]) } else { Rgb::ZERO };
                        assert_eq!(
                            got[k].0.map(f32::to_bits),
                            want.0.map(f32::to_bits),
                            "{simd:?} lane {k}: {:?}",
                            d[k]
                        );
                    }
                }
            }
        }
    }
}
