//! Linear RGB (Rec.709 primaries) radiometric quantities.

use std::ops::{Add, AddAssign, Div, Mul, MulAssign, Sub};

/// A linear RGB triple: radiance, reflectance or a BRDF value per channel.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Rgb(pub [f32; 3]);

impl Rgb {
    /// All channels zero.
    pub const ZERO: Rgb = Rgb([0.0; 3]);
    /// All channels one.
    pub const ONE: Rgb = Rgb([1.0; 3]);

    /// A triple from its three channels.
    #[inline]
    pub const fn new(r: f32, g: f32, b: f32) -> Self {
        Rgb([r, g, b])
    }

    /// The same value in every channel.
    #[inline]
    pub const fn splat(v: f32) -> Self {
        Rgb([v; 3])
    }

    /// Luminance (Rec.709 / sRGB weights).
    #[inline]
    pub fn luminance(self) -> f32 {
        0.2126 * self.0[0] + 0.7152 * self.0[1] + 0.0722 * self.0[2]
    }

    /// The largest channel.
    #[inline]
    pub fn max_channel(self) -> f32 {
        self.0[0].max(self.0[1]).max(self.0[2])
    }

    /// The smallest channel.
    #[inline]
    pub fn min_channel(self) -> f32 {
        self.0[0].min(self.0[1]).min(self.0[2])
    }

    /// Mean of the three channels.
    #[inline]
    pub fn mean(self) -> f32 {
        (self.0[0] + self.0[1] + self.0[2]) / 3.0
    }

    /// True when every channel is zero.
    #[inline]
    pub fn is_black(self) -> bool {
        // Without short-circuits, so that loops over many values of it become vector code.
        (self.0[0] == 0.0) & (self.0[1] == 0.0) & (self.0[2] == 0.0)
    }

    /// True when every channel is finite (no NaN, no infinity).
    #[inline]
    pub fn is_finite(self) -> bool {
        self.0.iter().all(|c| c.is_finite())
    }

    /// Applies `f` to each channel.
    #[inline]
    pub fn map(self, f: impl Fn(f32) -> f32) -> Self {
        Rgb(self.0.map(f))
    }

    /// Combines two triples channel by channel.
    #[inline]
    pub fn zip(self, o: Rgb, f: impl Fn(f32, f32) -> f32) -> Self {
        Rgb([f(self.0[0], o.0[0]), f(self.0[1], o.0[1]), f(self.0[2], o.0[2])])
    }
}

impl From<[f32; 3]> for Rgb {
    fn from(c: [f32; 3]) -> Self {
        Rgb(c)
    }
}

impl Add for Rgb {
    type Output = Rgb;
    #[inline]
    fn add(self, o: Rgb) -> Rgb {
        self.zip(o, |a, b| a + b)
    }
}

impl AddAssign for Rgb {
    #[inline]
    fn add_assign(&mut self, o: Rgb) {
        *self = *self + o;
    }
}

impl Sub for Rgb {
    type Output = Rgb;
    #[inline]
    fn sub(self, o: Rgb) -> Rgb {
        self.zip(o, |a, b| a - b)
    }
}

impl Mul for Rgb {
    type Output = Rgb;
    #[inline]
    fn mul(self, o: Rgb) -> Rgb {
        self.zip(o, |a, b| a * b)
    }
}

impl Mul<f32> for Rgb {
    type Output = Rgb;
    #[inline]
    fn mul(self, s: f32) -> Rgb {
        self.map(|a| a * s)
    }
}

impl Mul<Rgb> for f32 {
    type Output = Rgb;
    #[inline]
    fn mul(self, c: Rgb) -> Rgb {
        c * self
    }
}

impl MulAssign<f32> for Rgb {
    #[inline]
    fn mul_assign(&mut self, s: f32) {
        *self = *self * s;
    }
}

impl Div<f32> for Rgb {
    type Output = Rgb;
    #[inline]
    fn div(self, s: f32) -> Rgb {
        self.map(|a| a / s)
    }
}

impl Div for Rgb {
    type Output = Rgb;
    #[inline]
    fn div(self, o: Rgb) -> Rgb {
        self.zip(o, |a, b| a / b)
    }
}
