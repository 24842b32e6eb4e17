//! The splatting film, for reconstruction filters wider than the pixel (as Mitsuba's `hdrfilm`
//! with a non-box `rfilter`): camera samples are drawn uniformly over their pixel; each adds
//! f(Δx)·f(Δy)·L and f(Δx)·f(Δy) to every pixel whose centre lies within the filter's radius of
//! it (Δ = pixel centre − sample position), and a pixel's value is Σ f·L / Σ f. This ratio
//! estimates ∫ f(x − c) L(x) dx / ∫ f(x − c) dx, consistently (its bias falls as 1/N), with
//! less variance than filter importance sampling since no sample carries a weight f/pdf.
//! As in Mitsuba, samples are drawn inside the image only and splats that land outside it are
//! dropped, so an edge pixel averages the image under its truncated filter.
//!
//! Same seed, same image, whatever the thread count: a source row's samples splat into that
//! row's own buffer of 2B+1 image rows (B = the filter's reach in rows), and each destination
//! row then adds the buffers in source-row order. Rows go in bands so that the buffers take a
//! bounded amount of memory (`BAND_BYTES`).

use crate::filter::Filter;
use crate::floor::{ceil_i64, floor_i64};
use crate::image::Image;
use crate::simd::Simd;
use glam::Vec2;
use radiometry::Rgb;
use rayon::prelude::*;

/// Σ f·L (RGB) and Σ f of one pixel.
type Cell = [f64; 4];

/// Bytes of row buffers a band may hold: ~32 MiB, 54 rows of a 3840-wide image at B = 2.
const BAND_BYTES: usize = 32 << 20;

/// The accumulated splats of the whole image.
pub struct SplatFilm {
    filter: Filter,
    table: FilterTable,
    width: usize,
    height: usize,
    reach: usize,
    cells: Vec<Cell>,
}

/// Intervals of the tabulated filter over its radius.
const TABLE: usize = 2048;

/// The filter's 1D factor tabulated at `TABLE` + 1 points over [0, r] and read with linear
/// interpolation, so that a splat's ten or so factors cost a few loads each rather than an
/// `exp` or a `sin` (every splatted filter is even and smooth, and 0 at its radius). The
/// interpolation error is at most h²/8·max|f″| for the table's step h, below 1e-6 of the peak
/// for each filter at its defaults (tested). The rows of a band share one table.
#[derive(Clone, Debug)]
struct FilterTable {
    /// Table intervals per pixel.
    scale: f32,
    /// A fixed size, so that reads at i and i + 1 for i < `TABLE` need no bounds checks.
    values: std::sync::Arc<[f32; TABLE + 1]>,
}

impl FilterTable {
    fn new(filter: &Filter) -> Self {
        let r = filter.radius();
        let values = std::array::from_fn(|i| filter.eval_1d(r * i as f32 / TABLE as f32));
        FilterTable { scale: TABLE as f32 / r, values: std::sync::Arc::new(values) }
    }

    /// The factor at offset `x` pixels (that at the radius beyond it).
    #[inline(always)]
    fn eval(&self, x: f32) -> f32 {
        let t = x.abs() * self.scale;
        // Through i32: a float-to-usize cast saturates in more instructions (same result here).
        let i = (t as i32 as usize).min(TABLE - 1);
        let f = (t - i as f32).min(1.0);
        self.values[i] + f * (self.values[i + 1] - self.values[i])
    }
}

/// The splats of the samples of one source row `y`, over image rows y − B ..= y + B.
pub struct RowSplats {
    radius: f32,
    table: FilterTable,
    y: usize,
    width: usize,
    height: usize,
    reach: usize,
    cells: Vec<Cell>,
    /// Scratch: the filter's x factors of the sample being splatted.
    wx: Vec<f64>,
}

impl SplatFilm {
    /// An empty film of `width` × `height` pixels for `filter`.
    pub fn new(filter: &Filter, width: usize, height: usize) -> Self {
        // A sample in row y reaches pixel centres j + ½ with |j + ½ − (y + v)| ≤ r, v ∈ [0, 1).
        let reach = (filter.radius() as f64 + 0.5).floor() as usize;
        let table = FilterTable::new(filter);
        SplatFilm { filter: filter.clone(), table, width, height, reach, cells: vec![[0.0; 4]; width * height] }
    }

    /// Source rows per band, so that their buffers stay within `BAND_BYTES`.
    pub fn band_rows(&self) -> usize {
        let row = (2 * self.reach + 1) * self.width.max(1) * std::mem::size_of::<Cell>();
        (BAND_BYTES / row).clamp(1, self.height.max(1))
    }

    /// An empty buffer for one source row.
    pub fn row_splats(&self) -> RowSplats {
        RowSplats {
            radius: self.filter.radius(),
            table: self.table.clone(),
            y: 0,
            width: self.width,
            height: self.height,
            reach: self.reach,
            cells: vec![[0.0; 4]; (2 * self.reach + 1) * self.width],
            wx: vec![0.0; 2 * self.reach + 2],
        }
    }

    /// Adds the buffers of source rows `first`, `first + 1`, … (in that order for every
    /// destination row, so the sums do not depend on scheduling), in parallel over rows.
    pub fn gather(&mut self, first: usize, rows: &[RowSplats]) {
        let (w, reach) = (self.width, self.reach);
        let lo = first.saturating_sub(reach);
        let hi = (first + rows.len() + reach).min(self.height);
        if w == 0 || lo >= hi {
            return;
        }
        self.cells[lo * w..hi * w].par_chunks_mut(w).enumerate().for_each(|(k, dst)| {
            let d = lo + k;
            for src in rows.iter().filter(|s| s.y <= d + reach && d <= s.y + reach) {
                let off = d + reach - src.y;
                for (a, b) in dst.iter_mut().zip(&src.cells[off * w..(off + 1) * w]) {
                    for (x, y) in a.iter_mut().zip(b) {
                        *x += y;
                    }
                }
            }
        });
    }

    /// The image: Σ f·L / Σ f per pixel, black where no weight arrived.
    pub fn develop(&self) -> Image {
        let mut img = Image::new(self.width as u32, self.height as u32);
        for (p, c) in img.pixels.iter_mut().zip(&self.cells) {
            if c[3] > 0.0 {
                *p = Rgb::new((c[0] / c[3]) as f32, (c[1] / c[3]) as f32, (c[2] / c[3]) as f32);
            }
        }
        img
    }
}

impl RowSplats {
    /// Empties the buffer for source row `y`.
    pub fn reset(&mut self, y: usize) {
        self.y = y;
        self.cells.fill([0.0; 4]);
    }

    /// Splats the samples of radiance `l[k]` at film positions `at[k].1`, in order, in code
    /// compiled for AVX2 where `simd` asks for AVX2 or AVX-512 (a cell's four sums in one
    /// register; every lane rounds as the scalar sum does, so the sums are the same).
    pub fn splat_batch(&mut self, at: &[(usize, Vec2)], l: &[Rgb], simd: Simd) {
        #[cfg(target_arch = "x86_64")]
        if matches!(simd, Simd::Avx2 | Simd::Avx512) && Simd::Avx2.available() {
            #[target_feature(enable = "avx2")]
            unsafe fn avx2(film: &mut RowSplats, at: &[(usize, Vec2)], l: &[Rgb]) {
                film.splat_each(at, l)
            }
            // SAFETY: the CPU has AVX2 (checked just above).
            return unsafe { avx2(self, at, l) };
        }
        self.splat_each(at, l)
    }

    #[inline(always)]
    fn splat_each(&mut self, at: &[(usize, Vec2)], l: &[Rgb]) {
        for (&(_, pos), &l) in at.iter().zip(l) {
            self.splat(pos, l);
        }
    }

    /// Splats radiance `l` of a sample at film position `pos` (pixels; pixel (i, j) covers
    /// [i, i+1) × [j, j+1)) of this buffer's source row.
    #[inline(always)]
    pub fn splat(&mut self, pos: Vec2, l: Rgb) {
        let (w, r) = (self.width as i64, self.radius as f64);
        // Positions relative to pixel centres: pixel i is reached when |i − px| ≤ r.
        let (px, py) = (pos.x as f64 - 0.5, pos.y as f64 - 0.5);
        let x0 = ceil_i64(px - r).max(0);
        let x1 = floor_i64(px + r).min(w - 1);
        let (y, reach) = (self.y as i64, self.reach as i64);
        let y0 = ceil_i64(py - r).max(y - reach).max(0);
        let y1 = floor_i64(py + r).min(y + reach).min(self.height as i64 - 1);
        if x0 > x1 || y0 > y1 {
            return;
        }
        // At most ⌊2r⌋ + 1 ≤ 2·reach + 1 columns (reach = ⌊r + ½⌋): the scratch holds them.
        let wxs = &mut self.wx[..(x1 - x0 + 1) as usize];
        for (i, w) in (x0..).zip(wxs.iter_mut()) {
            *w = self.table.eval((i as f64 - px) as f32) as f64;
        }
        // Σ f·L and Σ f of a cell as one four-lane sum (f·1 = f exactly).
        let l = [l.0[0] as f64, l.0[1] as f64, l.0[2] as f64, 1.0];
        for j in y0..=y1 {
            let wy = self.table.eval((j as f64 - py) as f32) as f64;
            if wy == 0.0 {
                continue;
            }
            let row = (j - y + reach) as usize * self.width;
            let cells = &mut self.cells[row + x0 as usize..=row + x1 as usize];
            for (c, &wx) in cells.iter_mut().zip(&*wxs) {
                let f = wx * wy;
                for (c, l) in c.iter_mut().zip(l) {
                    *c += f * l;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Splats n×n stratified samples per pixel of L(x, y) = x into a film and develops it.
    fn ramp_film(filter: &Filter, w: usize, h: usize, n: usize) -> Image {
        let mut film = SplatFilm::new(filter, w, h);
        let mut rows: Vec<RowSplats> = (0..h).map(|_| film.row_splats()).collect();
        for (y, buf) in rows.iter_mut().enumerate() {
            buf.reset(y);
            for x in 0..w {
                for k in 0..n * n {
                    let u = Vec2::new(((k % n) as f32 + 0.5) / n as f32, ((k / n) as f32 + 0.5) / n as f32);
                    let pos = Vec2::new(x as f32, y as f32) + u;
                    buf.splat(pos, Rgb::new(pos.x, 1.0, 0.0));
                }
            }
        }
        // Two bands, to check that a split gathers the same sums.
        let half = h / 2;
        film.gather(0, &rows[..half]);
        film.gather(half, &rows[half..]);
        film.develop()
    }

    /// ∫ f(x − c) x dx / ∫ f(x − c) dx over [0, w): the filtered ramp, by the midpoint rule.
    fn filtered_ramp(filter: &Filter, c: f64, w: usize) -> f64 {
        let m = 200_000;
        let (mut num, mut den) = (0.0, 0.0);
        for k in 0..m {
            let x = w as f64 * (k as f64 + 0.5) / m as f64;
            let f = filter.eval_1d((x - c) as f32) as f64;
            num += f * x;
            den += f;
        }
        num / den
    }

    #[test]
    fn a_ramp_is_filtered_and_edges_see_only_the_image() {
        let g = Filter::gaussian(0.5).unwrap();
        let (w, h) = (8, 6);
        let img = ramp_film(&g, w, h, 64);
        for y in 0..h {
            for x in 0..w {
                let p = img.get(x as u32, y as u32).0;
                let expect = filtered_ramp(&g, x as f64 + 0.5, w);
                // The 64² stratified samples integrate the smooth filter to ~1e-4 px.
                assert!((p[0] as f64 - expect).abs() < 1e-3, "({x}, {y}): {} vs {expect}", p[0]);
                assert!((p[1] - 1.0).abs() < 1e-6 && p[2] == 0.0);
            }
        }
        // The edge pixel's truncated filter pulls it inwards: 0.5 were the filter to reach out.
        let edge = filtered_ramp(&g, 0.5, w);
        assert!(edge > 0.6, "{edge}");
    }

    #[test]
    fn batches_splat_the_same_sums_on_every_instruction_set() {
        // Samples anywhere in a row's pixels, with radiances of many magnitudes, for a filter
        // of each reach (Lanczos is the widest).
        let (w, h) = (9, 5);
        let mut seed = 1u32;
        let mut next = || {
            seed = seed.wrapping_mul(1664525).wrapping_add(1013904223);
            (seed >> 8) as f32 / (1u32 << 24) as f32
        };
        let at: Vec<(usize, Vec2)> = (0..200).map(|_| (0, Vec2::new(next() * w as f32, 2.0 + next()))).collect();
        let l: Vec<Rgb> = (0..200).map(|_| Rgb::new(next() * 1e3, next(), next() * 1e-3)).collect();
        for filter in [Filter::gaussian(0.5).unwrap(), Filter::Lanczos { lobes: 3 }] {
            let mut one = SplatFilm::new(&filter, w, h).row_splats();
            one.reset(2);
            for (&(_, pos), &l) in at.iter().zip(&l) {
                one.splat(pos, l);
            }
            for simd in Simd::ALL.map(|(_, s)| s).into_iter().filter(|s| s.available()) {
                let mut batch = SplatFilm::new(&filter, w, h).row_splats();
                batch.reset(2);
                batch.splat_batch(&at, &l, simd);
                assert!(one.cells == batch.cells, "{simd:?}");
            }
        }
    }

    #[test]
    fn the_table_follows_every_filter() {
        let filters = [
            Filter::gaussian(0.5).unwrap(),
            Filter::gaussian(2.0).unwrap(),
            Filter::Tent { radius: 1.0 },
            Filter::Mitchell { b: 1.0 / 3.0, c: 1.0 / 3.0 },
            Filter::Mitchell { b: 0.0, c: 0.5 },
            Filter::Lanczos { lobes: 3 },
        ];
        // h²/8·max|f″| is below 1e-6 of the peak for each (Lanczos, the most curved: h = 3/2048,
        // |f″| ≤ 3.7), plus the f32 rounding of the values and of the interpolation.
        let tol = 1e-6 + 4.0 * f32::EPSILON;
        for filter in filters {
            let (table, r) = (FilterTable::new(&filter), filter.radius());
            let peak = filter.eval_1d(0.0);
            for k in 0..=20_000 {
                let x = -1.1 * r + 2.2 * r * k as f32 / 20_000.0;
                let exact = if x.abs() <= r { filter.eval_1d(x) } else { 0.0 };
                let err = (table.eval(x) - exact).abs() / peak;
                assert!(err <= tol, "{filter:?} at {x}: {} vs {exact}", table.eval(x));
            }
        }
    }

    #[test]
    fn empty_films_and_lone_pixels_stay_finite() {
        let g = Filter::gaussian(2.0).unwrap();
        assert_eq!(SplatFilm::new(&g, 0, 0).develop().pixels.len(), 0);
        let img = ramp_film(&g, 1, 1, 4);
        assert!((img.get(0, 0).0[0] - 0.5).abs() < 1e-6);
        // No sample: black, not NaN.
        let film = SplatFilm::new(&g, 3, 2);
        assert!(film.develop().pixels.iter().all(|p| p.0 == [0.0; 3]));
        assert_eq!(film.band_rows(), 2);
    }
}
