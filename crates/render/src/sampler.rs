//! Deterministic random streams: one independent PCG32 stream per (seed, pixel, sample),
//! so an image depends on the seed and the sample count only, never on the thread count.
//! PCG32: M. E. O'Neill, "PCG: A family of simple fast space-efficient statistically good
//! algorithms for random number generation", 2014 (XSH-RR output, 64-bit LCG state).

use crate::simd::LANES;
use glam::Vec2;

const PCG_MULT: u64 = 6364136223846793005;

/// SplitMix64's finaliser (Steele et al. 2014): a bijective 64-bit mix.
#[inline]
fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58476d1ce4e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d049bb133111eb);
    z ^ (z >> 31)
}

/// A stream of uniform numbers in [0, 1) for one camera sample.
#[derive(Clone, Debug)]
pub struct Sampler {
    state: u64,
    inc: u64,
}

/// The hash of (seed, pixel) that every sample stream of one pixel starts from: computing it once
/// per pixel spares two of the four hashes per sample.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PixelKey(u64);

impl PixelKey {
    /// The key of pixel `pixel` under `seed`.
    #[inline]
    pub fn new(seed: u64, pixel: u64) -> Self {
        PixelKey(mix64(mix64(seed ^ 0x9e3779b97f4a7c15) ^ pixel))
    }

    /// The stream for sample `sample` of this pixel: `Sampler::new(seed, pixel, sample)`.
    #[inline]
    pub fn sampler(self, sample: u64) -> Sampler {
        Sampler::from_hash(mix64(self.0 ^ sample.wrapping_mul(0xd1b54a32d192ed03)))
    }
}

impl Sampler {
    /// The stream for sample `sample` of pixel `pixel` under `seed`.
    pub fn new(seed: u64, pixel: u64, sample: u64) -> Self {
        // The three indices are hashed in sequence so that neighbouring indices give unrelated
        // states; the stream selector (odd increment) comes from a second hash.
        PixelKey::new(seed, pixel).sampler(sample)
    }

    /// The stream whose indices hash to `h`.
    #[inline]
    fn from_hash(h: u64) -> Self {
        let inc = (mix64(h ^ 0x5851f42d4c957f2d) << 1) | 1;
        let mut s = Sampler { state: 0, inc };
        s.next_u32();
        s.state = s.state.wrapping_add(h);
        s.next_u32();
        s
    }

    /// The next 32 random bits.
    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old.wrapping_mul(PCG_MULT).wrapping_add(self.inc);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        let rot = (old >> 59) as u32;
        xorshifted.rotate_right(rot)
    }

    /// A uniform number in [0, 1) (24 bits, so it never rounds up to 1).
    #[inline]
    pub fn next_1d(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }

    /// A uniform point in [0, 1)².
    #[inline]
    pub fn next_2d(&mut self) -> Vec2 {
        let x = self.next_1d();
        Vec2::new(x, self.next_1d())
    }
}

/// Sixteen streams side by side, lane i drawing exactly what the [`Sampler`] put there with
/// [`set`](Self::set) draws, written as loops over the lanes that the compiler turns into vector
/// code: the sixteen-lane tracer draws a vertex's numbers for all its paths at once.
#[derive(Clone, Debug)]
pub struct Samplers16 {
    state: [u64; LANES],
    inc: [u64; LANES],
}

impl Samplers16 {
    /// Sixteen copies of one stream.
    pub fn new(s: &Sampler) -> Self {
        Samplers16 { state: [s.state; LANES], inc: [s.inc; LANES] }
    }

    /// Lane `i` continues the stream `s`.
    #[inline(always)]
    pub fn set(&mut self, i: usize, s: &Sampler) {
        (self.state[i], self.inc[i]) = (s.state, s.inc);
    }

    /// Lane `i`'s stream as it stands.
    #[inline(always)]
    pub fn get(&self, i: usize) -> Sampler {
        Sampler { state: self.state[i], inc: self.inc[i] }
    }

    /// The next number of every lane, as [`Sampler::next_1d`].
    #[inline(always)]
    pub fn next_1d(&mut self) -> [f32; LANES] {
        let mut u = [0.0; LANES];
        for (i, u) in u.iter_mut().enumerate() {
            *u = self.next_1d_lane(i);
        }
        u
    }

    /// The next number of lane `i` alone.
    #[inline(always)]
    pub fn next_1d_lane(&mut self, i: usize) -> f32 {
        let mut s = Sampler { state: self.state[i], inc: self.inc[i] };
        let u = s.next_1d();
        self.state[i] = s.state;
        u
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sixteen_lanes_draw_what_their_streams_draw() {
        let mut one: Vec<Sampler> = (0..LANES as u64).map(|i| Sampler::new(3, i, 7 * i)).collect();
        let mut lanes = Samplers16::new(&one[0]);
        for (i, s) in one.iter().enumerate() {
            lanes.set(i, s);
        }
        for step in 0..200 {
            if step % 3 == 2 {
                // One lane draws alone, as a path playing Russian roulette does.
                let i = step % LANES;
                assert_eq!(lanes.next_1d_lane(i).to_bits(), one[i].next_1d().to_bits(), "step {step}");
            } else {
                let u = lanes.next_1d();
                for (i, s) in one.iter_mut().enumerate() {
                    assert_eq!(u[i].to_bits(), s.next_1d().to_bits(), "step {step}, lane {i}");
                }
            }
        }
    }

    #[test]
    fn same_indices_same_stream_and_different_indices_differ() {
        let a: Vec<u32> = (0..8)
            .map({
                let mut s = Sampler::new(1, 2, 3);
                move |_| s.next_u32()
            })
            .collect();
        let mut s = Sampler::new(1, 2, 3);
        assert!(a.iter().all(|&x| x == s.next_u32()));
        for (seed, px, sm) in [(2, 2, 3), (1, 3, 3), (1, 2, 4)] {
            let mut o = Sampler::new(seed, px, sm);
            assert_ne!(a[0], o.next_u32());
        }
    }

    #[test]
    fn pixel_keys_give_the_same_streams() {
        for (seed, px, sm) in [(0u64, 0u64, 0u64), (1, 2, 3), (u64::MAX, 12345, 63), (7, u64::MAX, u64::MAX)] {
            let (mut a, mut b) = (Sampler::new(seed, px, sm), PixelKey::new(seed, px).sampler(sm));
            assert!((0..16).all(|_| a.next_u32() == b.next_u32()));
        }
    }

    #[test]
    fn uniform_mean_and_variance() {
        // Mean 1/2 and variance 1/12 of U[0,1); over n draws the mean has σ = sqrt(1/(12 n)).
        let n = 200_000u64;
        let (mut sum, mut sum2) = (0.0f64, 0.0f64);
        for i in 0..n {
            // One draw per stream: checks that stream starts are themselves uniform.
            let x = Sampler::new(7, i, i % 5).next_1d() as f64;
            assert!((0.0..1.0).contains(&x));
            sum += x;
            sum2 += x * x;
        }
        let mean = sum / n as f64;
        let sigma = (1.0 / (12.0 * n as f64)).sqrt();
        assert!((mean - 0.5).abs() < 4.0 * sigma, "{mean}");
        // Var of x² has σ = sqrt(4/45 / n) around E[x²] = 1/3.
        let m2 = sum2 / n as f64;
        assert!((m2 - 1.0 / 3.0).abs() < 4.0 * (4.0 / 45.0 / n as f64).sqrt(), "{m2}");
    }
}
