//! An environment map's work for sixteen rays or light samples at once: the radiance along
//! escaping rays, the lookups of bounce rays' directions, and light samples drawn ahead from
//! their numbers. The lookups' angles (two atan2 per direction) and the samples' place in their
//! cell, angles and density cost more than the table reads; computed lane by lane in loops
//! they become vector code, making the same operations in the same order as [`EnvMap::eval`],
//! [`EnvMap::lookup`] and [`EnvMap::sample_direction`] do, so the same bits.

// Lane loops index several arrays in step: the form the vectoriser reads best.
#![allow(clippy::needless_range_loop)]

use super::{direction_to_uv, solid_angle_pdf, EnvDensity, EnvDirection, EnvLookup, EnvMap};
use crate::simd::{dispatch, Bits, Simd, LANES};
use glam::{Vec2, Vec3};
use radiometry::warp2d::{place_in_cell, Bilinear2D};
use radiometry::Rgb;

impl EnvMap {
    /// [`eval`](Self::eval) of the directions `d` of lanes `lanes` (zero elsewhere), computed
    /// on instruction set `simd`.
    pub fn eval_packet(&self, d: &[Vec3; LANES], lanes: u32, simd: Simd) -> [Rgb; LANES] {
        dispatch!(simd, self: EnvMap, eval_lanes(d: &[Vec3; LANES], lanes: u32) -> [Rgb; LANES])
    }

    /// [`lookup`](Self::lookup) of each of the directions `d`, computed on instruction set
    /// `simd`.
    pub fn lookup_packet(&self, d: &[Vec3; LANES], simd: Simd) -> [EnvLookup; LANES] {
        dispatch!(simd, self: EnvMap, lookup_lanes(d: &[Vec3; LANES]) -> [EnvLookup; LANES])
    }

    /// [`sample_direction`](Self::sample_direction) for the numbers `uc`, `u` of lanes
    /// `lanes` (unset elsewhere), computed on instruction set `simd`.
    pub fn sample_packet(
        &self,
        uc: &[f32; LANES],
        u: &[Vec2; LANES],
        lanes: u32,
        d: EnvDensity,
        simd: Simd,
    ) -> [Option<EnvDirection>; LANES] {
        let mut out = [None; LANES];
        let Some(warp) = self.warp(d) else {
            for k in Bits(lanes) {
                out[k] = Some(self.sample_direction(uc[k], u[k], d));
            }
            return out;
        };
        let s = dispatch!(simd, self: EnvMap, sample_lanes(warp: &Bilinear2D, uc: &[f32; LANES], u: &[Vec2; LANES], lanes: u32) -> [EnvDirection; LANES]);
        for k in Bits(lanes) {
            out[k] = Some(s[k]);
        }
        out
    }

    /// Samples by density `warp`: the table reads (the cell choice, its corners) lane by lane,
    /// then the arithmetic (the place in the cell, the angles, the density) in loops over all
    /// lanes.
    #[inline(always)]
    fn sample_lanes(
        &self,
        warp: &Bilinear2D,
        uc: &[f32; LANES],
        u: &[Vec2; LANES],
        lanes: u32,
    ) -> [EnvDirection; LANES] {
        let (mut i, mut j, mut ry) = ([0usize; LANES], [0usize; LANES], [0.0f32; LANES]);
        let (mut corners, mut scale) = ([[0.0f32; 4]; LANES], [0.0f32; LANES]);
        for k in Bits(lanes) {
            (i[k], j[k], ry[k]) = warp.choose_cell(uc[k], u[k].y);
            (corners[k], scale[k]) = (warp.corners(i[k], j[k]), warp.cell_scale(i[k], j[k]));
        }
        let (mut fx, mut fy, mut pdf) = ([0.0f32; LANES], [0.0f32; LANES], [0.0f32; LANES]);
        for k in 0..LANES {
            let (f, p) = place_in_cell(corners[k], scale[k], ry[k], u[k].x);
            (fx[k], fy[k], pdf[k]) = (f.x, f.y, p);
        }
        let (mut x, mut y, mut z, mut sin_t) = ([0.0f32; LANES], [0.0f32; LANES], [0.0f32; LANES], [0.0f32; LANES]);
        for k in 0..LANES {
            let (w, s) = self.cell_direction(i[k], j[k], Vec2::new(fx[k], fy[k]));
            (x[k], y[k], z[k], sin_t[k]) = (w.x, w.y, w.z, s);
            pdf[k] = solid_angle_pdf(pdf[k], s);
        }
        let mut out = [EnvDirection { wi: Vec3::ZERO, li: Rgb::ZERO, pdf: 0.0 }; LANES];
        for k in Bits(lanes) {
            let f = Vec2::new(fx[k], fy[k]);
            // At a pole the density is the limit that `density` takes.
            let pdf = if sin_t[k] > 1e-18 { pdf[k] } else { self.density(warp, i[k], j[k], f, sin_t[k]) };
            let wi = self.map_to_world(Vec3::new(x[k], y[k], z[k]));
            out[k] = EnvDirection { wi, li: self.radiance(i[k], j[k], f), pdf };
        }
        out
    }

    #[inline(always)]
    fn eval_lanes(&self, d: &[Vec3; LANES], lanes: u32) -> [Rgb; LANES] {
        let l = self.lookup_lanes(d);
        let mut out = [Rgb::ZERO; LANES];
        for k in Bits(lanes) {
            out[k] = self.eval_at(&l[k]);
        }
        out
    }

    #[inline(always)]
    fn lookup_lanes(&self, d: &[Vec3; LANES]) -> [EnvLookup; LANES] {
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
        // A loop over a filled array, not `array::from_fn`, which was left a call per packet.
        let mut out = [EnvLookup { m: Vec3::ZERO, i: 0, j: 0, f: Vec2::ZERO }; LANES];
        for (k, o) in out.iter_mut().enumerate() {
            *o = EnvLookup { m: Vec3::new(x[k], y[k], z[k]), i: i[k], j: j[k], f: Vec2::new(fx[k], fy[k]) };
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

    #[test]
    fn sixteen_samples_are_what_each_draws_alone() {
        // A map with a black row and a bright spot, so that cells of every kind are drawn:
        // poles, empty neighbours, steep corners.
        let mut img = Image::new(16, 9);
        let mut s = Sampler::new(8, 0, 0);
        for (k, p) in img.pixels.iter_mut().enumerate() {
            *p = if k / 16 == 4 { Rgb::ZERO } else { Rgb::new(s.next_1d(), 2.0 * s.next_1d(), 0.1) };
        }
        img.pixels[16 * 2 + 5] = Rgb::splat(500.0);
        let map = EnvMap::new(&img, 1.0).unwrap();
        let turn = glam::Mat3::from_rotation_x(0.4);
        for map in [map.clone(), map.with_rotation(turn).unwrap()] {
            for density in [EnvDensity::Radiance, EnvDensity::Compensated] {
                for (_, simd) in Simd::ALL.into_iter().filter(|(_, s)| s.available()) {
                    for round in 0..300 {
                        let uc: [f32; LANES] = std::array::from_fn(|_| s.next_1d());
                        let mut u: [Vec2; LANES] = std::array::from_fn(|_| s.next_2d());
                        u[0] = Vec2::ZERO;
                        u[1] = Vec2::new(0.999_999_9, 0.999_999_9);
                        let lanes = if round % 2 == 0 { u32::MAX >> 16 } else { 0b0110_1011_1001_0110 };
                        let got = map.sample_packet(&uc, &u, lanes, density, simd);
                        for k in 0..LANES {
                            let want = (lanes >> k & 1 != 0).then(|| map.sample_direction(uc[k], u[k], density));
                            let bits = |e: Option<EnvDirection>| {
                                e.map(|e| {
                                    (e.wi.to_array().map(f32::to_bits), e.li.0.map(f32::to_bits), e.pdf.to_bits())
                                })
                            };
                            assert_eq!(bits(got[k]), bits(want), "{simd:?} {density:?} lane {k}");
                        }
                    }
                }
            }
        }
    }
}
