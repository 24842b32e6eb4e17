//! A piecewise-bilinear density on the unit square, sampled exactly.
//!
//! Non-negative values f(i, j) sit on an nx × ny grid of points (x = i/(nx − 1),
//! y = j/(ny − 1)); the density is their bilinear interpolant divided by its integral. It is
//! the density of Mitsuba 3's `Hierarchical2D` warp (which its `envmap` uses), reached by
//! inversion instead of a mip-map descent:
//! 1. a cell is picked ∝ its integral, the mean of its four corners, in constant time by an
//!    alias table over all cells (`AliasTable`: one lookup, where inverting a marginal and a
//!    conditional CDF costs several cache misses on a large map), whose coin is rescaled into
//!    the uniform number for fy of step 2;
//! 2. within the cell, of corners f00, f10, f01, f11 (f_xy), the marginal density of fy is
//!    linear between f00 + f10 and f01 + f11, and the density of fx given fy is linear between
//!    lerp(f00, f01, fy) and lerp(f10, f11, fy): each is inverted in closed form
//!    (`sample_linear`). Their product is bilinear(fx, fy) / mean of the corners, so the
//!    density is continuous across cells and positive wherever the interpolant is.

use crate::alias::AliasTable;
use glam::Vec2;

/// A point drawn from a [`Bilinear2D`]: its cell, its place in the cell, and its density.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CellSample {
    /// Cell column, 0..nx − 1.
    pub i: usize,
    /// Cell row, 0..ny − 1.
    pub j: usize,
    /// Position within the cell, each in [0, 1).
    pub frac: Vec2,
    /// Density on the unit square.
    pub pdf: f32,
}

/// A bilinearly interpolated grid of non-negative values as a sampling density on [0, 1]².
#[derive(Clone, Debug)]
pub struct Bilinear2D {
    nx: usize,
    ny: usize,
    /// Row-major grid values, nx per row.
    values: Vec<f32>,
    /// Picks a cell (row-major, nx − 1 per row) ∝ its corners' sum.
    cell: AliasTable,
    /// The density over the bilinear interpolant: 4·cx·cy / Σ corner sums.
    scale: f32,
}

impl Bilinear2D {
    /// From nx × ny row-major grid values (negative or non-finite ones count as zero).
    /// None without at least 2 × 2 points or when every cell is zero.
    pub fn new(values: &[f32], nx: usize, ny: usize) -> Option<Self> {
        if nx < 2 || ny < 2 || values.len() != nx * ny {
            return None;
        }
        let clean = |v: f32| if v.is_finite() && v > 0.0 { v } else { 0.0 };
        // Scaled to a maximum of 1 (the density does not change), so that `sample_linear`
        // can square them without overflow.
        let max = values.iter().fold(0.0f32, |m, &v| m.max(clean(v)));
        let values: Vec<f32> = values.iter().map(|&v| if max > 0.0 { clean(v) / max } else { 0.0 }).collect();
        let weights: Vec<f32> = (0..(nx - 1) * (ny - 1))
            .map(|k| corners_of(&values, nx, k % (nx - 1), k / (nx - 1)).iter().sum())
            .collect();
        let cell = AliasTable::new(&weights)?;
        let scale = (4.0 * ((nx - 1) * (ny - 1)) as f64 / cell.total()) as f32;
        scale.is_finite().then_some(Bilinear2D { nx, ny, values, cell, scale })
    }

    /// The number of cells along x and y.
    pub fn cells(&self) -> (usize, usize) {
        (self.nx - 1, self.ny - 1)
    }

    /// The corner values f00, f10, f01, f11 of cell (i, j).
    #[inline]
    pub fn corners(&self, i: usize, j: usize) -> [f32; 4] {
        corners_of(&self.values, self.nx, i, j)
    }

    /// The density at fraction `frac` of cell (i, j) is `cell_scale(i, j)` × the bilinear
    /// interpolant of its corners there: the same for every cell that can be drawn (0 for an
    /// empty one).
    #[inline]
    pub fn cell_scale(&self, i: usize, j: usize) -> f32 {
        if self.corners(i, j).iter().sum::<f32>() > 0.0 {
            self.scale
        } else {
            0.0
        }
    }

    /// The density at fraction `frac` of cell (i, j).
    #[inline]
    pub fn density(&self, i: usize, j: usize, frac: Vec2) -> f32 {
        self.cell_scale(i, j) * bilerp(self.corners(i, j), frac)
    }

    /// Starts loading the alias-table entry that `sample(uc, …)` will read.
    #[inline]
    pub fn prefetch_cell_choice(&self, uc: f32) {
        self.cell.prefetch(uc);
    }

    /// The cell `sample(uc, u)` lands in, with its corners asked for.
    #[inline]
    pub fn prefetch_cell(&self, uc: f32, u_y: f32) -> (usize, usize) {
        let (i, j, _) = self.choose_cell(uc, u_y);
        self.prefetch_corners(i, j);
        (i, j)
    }

    /// Starts loading the corners of cell (i, j) (its two rows), which `corners(i, j)` reads.
    #[inline]
    pub fn prefetch_corners(&self, i: usize, j: usize) {
        let at = j * self.nx + i;
        crate::prefetch::prefetch(&self.values[at]);
        crate::prefetch::prefetch(&self.values[at + self.nx]);
    }

    /// The cell holding point `p` of the unit square, and the fraction within it.
    #[inline]
    pub fn locate(&self, p: Vec2) -> (usize, usize, Vec2) {
        let (cx, cy) = self.cells();
        let (x, y) = ((p.x * cx as f32).max(0.0), (p.y * cy as f32).max(0.0));
        let (i, j) = ((x as usize).min(cx - 1), (y as usize).min(cy - 1));
        (i, j, Vec2::new((x - i as f32).min(1.0), (y - j as f32).min(1.0)))
    }

    /// The density at point `p` of the unit square.
    pub fn pdf(&self, p: Vec2) -> f32 {
        let (i, j, frac) = self.locate(p);
        self.density(i, j, frac)
    }

    /// A point for the uniform numbers `uc` (the cell) and `u` (the place in it, u.y also
    /// deciding the cell's alias coin); its density is `density(i, j, frac)`.
    #[inline]
    pub fn sample(&self, uc: f32, u: Vec2) -> CellSample {
        let (i, j, ry) = self.choose_cell(uc, u.y);
        let (frac, pdf) = place_in_cell(self.corners(i, j), self.cell_scale(i, j), ry, u.x);
        CellSample { i, j, frac, pdf }
    }

    /// [`sample`](Self::sample)'s first half: the cell (i, j) for `uc` and `u_y`, with `u_y`
    /// rescaled to a fresh uniform number for [`place_in_cell`].
    #[inline]
    pub fn choose_cell(&self, uc: f32, u_y: f32) -> (usize, usize, f32) {
        let (k, ry) = self.cell.sample(uc, u_y);
        let cx = self.nx - 1;
        (k % cx, k / cx, ry)
    }
}

/// [`Bilinear2D::sample`]'s second half, arithmetic only (so that a loop over many samples
/// becomes vector code): the place (fx, fy) in a cell of corners f00, f10, f01, f11 and cell
/// scale `scale`, for the rescaled `ry` and `u_x`, and its density.
#[inline(always)]
pub fn place_in_cell([f00, f10, f01, f11]: [f32; 4], scale: f32, ry: f32, u_x: f32) -> (Vec2, f32) {
    let fy = sample_linear(f00 + f10, f01 + f11, ry);
    let (c0, c1) = (lerp(f00, f01, fy), lerp(f10, f11, fy));
    let fx = sample_linear(c0, c1, u_x);
    (Vec2::new(fx, fy), scale * lerp(c0, c1, fx))
}

/// The corners f00, f10, f01, f11 of cell (i, j) in a row-major grid `nx` wide.
#[inline]
fn corners_of(values: &[f32], nx: usize, i: usize, j: usize) -> [f32; 4] {
    let k = j * nx + i;
    [values[k], values[k + 1], values[k + nx], values[k + nx + 1]]
}

/// (1 − t)·a + t·b: for a, b ≥ 0 both terms are, so there is no cancellation near a zero.
#[inline(always)]
fn lerp(a: f32, b: f32, t: f32) -> f32 {
    a * (1.0 - t) + b * t
}

/// The bilinear interpolant of corners f00, f10, f01, f11 at (fx, fy).
#[inline]
pub fn bilerp([f00, f10, f01, f11]: [f32; 4], f: Vec2) -> f32 {
    lerp(lerp(f00, f10, f.x), lerp(f01, f11, f.x), f.y)
}

/// t ∈ [0, 1) with density ∝ (1 − t)·a + t·b for a uniform `u`, for 0 ≤ a, b ≤ 1e18 (their
/// squares must not overflow): the root of the CDF (a·t + (b − a)·t²/2) / ((a + b)/2) = u
/// written as u(a + b)/(a + √((1 − u)a² + u·b²)), which has no cancellation. When a and b
/// are both 0 (or their squares underflow), t = u: uniform, the limit of a = b.
#[inline(always)]
pub fn sample_linear(a: f32, b: f32, u: f32) -> f32 {
    let den = a + ((1.0 - u) * a * a + u * b * b).sqrt();
    let t = if den > 0.0 { u * (a + b) / den } else { u };
    t.min(1.0 - f32::EPSILON / 2.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    #[test]
    fn linear_sampling_inverts_its_cdf() {
        let cdf = |a: f64, b: f64, t: f64| (a * t + (b - a) * t * t / 2.0) / ((a + b) / 2.0);
        for (a, b) in [(1.0, 1.0), (0.0, 1.0), (1.0, 0.0), (1e-15, 1e15), (3.0, 0.2), (0.0, 0.0)] {
            for k in 0..=100 {
                let u = (k as f32 / 100.0).min(1.0 - f32::EPSILON);
                let t = sample_linear(a, b, u);
                assert!((0.0..1.0).contains(&t), "{a} {b} {u}: {t}");
                let (a, b) = (a as f64, b as f64);
                let want = if a + b > 0.0 { cdf(a / a.max(b), b / a.max(b), t as f64) } else { t as f64 };
                assert!((want - u as f64).abs() < 1e-6, "a {a} b {b} u {u}: F(t) = {want}");
            }
        }
        // Squares that underflow still give a number in [0, 1).
        for (a, b) in [(1e-42, 0.0), (0.0, 1e-30), (1e-30, 1e-25)] {
            assert!((0..=100).all(|k| (0.0..1.0).contains(&sample_linear(a, b, k as f32 / 101.0))));
        }
    }

    /// A 5 × 4 grid with a zero corner, a zero cell and a 1000× point.
    fn grid() -> Bilinear2D {
        let mut v = vec![1.0f32; 20];
        v[0] = 0.0;
        for k in [13, 14, 18, 19] {
            v[k] = 0.0;
        }
        v[7] = 1000.0;
        Bilinear2D::new(&v, 5, 4).unwrap()
    }

    #[test]
    fn density_integrates_to_one_and_is_continuous() {
        let g = grid();
        // The midpoint rule is exact for a bilinear function over each cell.
        let (cx, cy) = g.cells();
        let mut integral = 0.0f64;
        for j in 0..cy {
            for i in 0..cx {
                integral += g.density(i, j, Vec2::splat(0.5)) as f64 / (cx * cy) as f64;
            }
        }
        assert!((integral - 1.0).abs() < 1e-6, "{integral}");
        // Both sides of every inner cell edge agree, to the rounding of the interpolation.
        let rel = |_: usize, _: usize| 1e-6;
        for j in 0..cy {
            for i in 0..cx {
                for t in [0.0, 0.3, 1.0] {
                    if i + 1 < cx {
                        let (l, r) = (g.density(i, j, Vec2::new(1.0, t)), g.density(i + 1, j, Vec2::new(0.0, t)));
                        let tol = l.max(r) * (rel(i, j) + rel(i + 1, j));
                        assert!(l == r || (l - r).abs() <= tol, "x edge {i} {j} {t}: {l} {r}");
                    }
                    if j + 1 < cy {
                        let (b, a) = (g.density(i, j, Vec2::new(t, 1.0)), g.density(i, j + 1, Vec2::new(t, 0.0)));
                        let tol = a.max(b) * (rel(i, j) + rel(i, j + 1));
                        assert!(a == b || (b - a).abs() <= tol, "y edge {i} {j} {t}: {b} {a}");
                    }
                }
            }
        }
        assert!(Bilinear2D::new(&[0.0; 4], 2, 2).is_none() && Bilinear2D::new(&[1.0; 2], 2, 1).is_none());
    }

    #[test]
    fn samples_follow_the_density() {
        // Sub-cell histogram (4 × 4 bins per cell) against the density's exact bin integrals
        // (bilinear: the mean of the bin's corner densities), by Pearson's χ² with 4σ of its
        // own spread as the bound; and the sample's pdf is density() at the sample.
        let g = grid();
        let (cx, cy) = g.cells();
        let sub = 4;
        let (bx, by) = (cx * sub, cy * sub);
        let mut counts = vec![0u32; bx * by];
        let mut rng = rand_pcg::Pcg64::seed_from_u64(7);
        let n = 400_000;
        for _ in 0..n {
            let s = g.sample(rng.gen(), Vec2::new(rng.gen(), rng.gen()));
            assert!(s.pdf > 0.0 && (s.pdf - g.density(s.i, s.j, s.frac)).abs() <= 1e-5 * s.pdf);
            let p = (Vec2::new(s.i as f32, s.j as f32) + s.frac) / Vec2::new(cx as f32, cy as f32);
            assert!((s.pdf - g.pdf(p)).abs() <= 1e-3 * s.pdf, "{p}: {} vs {}", s.pdf, g.pdf(p));
            let (ki, kj) = ((s.frac.x * sub as f32) as usize, (s.frac.y * sub as f32) as usize);
            counts[(s.j * sub + kj) * bx + s.i * sub + ki] += 1;
        }
        let (mut chi2, mut dof) = (0.0f64, 0i64);
        for j in 0..by {
            for i in 0..bx {
                let (ci, cj) = (i / sub, j / sub);
                let at = |a: usize, b: usize| {
                    g.density(ci, cj, Vec2::new((i % sub + a) as f32 / sub as f32, (j % sub + b) as f32 / sub as f32))
                };
                let p = (at(0, 0) + at(1, 0) + at(0, 1) + at(1, 1)) as f64 / 4.0 / (bx * by) as f64;
                let e = p * n as f64;
                if e > 0.0 {
                    chi2 += (counts[j * bx + i] as f64 - e).powi(2) / e;
                    dof += 1;
                } else {
                    assert_eq!(counts[j * bx + i], 0, "a sample where the density is zero");
                }
            }
        }
        let dof = (dof - 1) as f64;
        eprintln!("bilinear warp: χ² {chi2:.1} with {dof} degrees of freedom");
        assert!(chi2 < dof + 4.0 * (2.0 * dof).sqrt(), "χ² {chi2} with {dof} degrees of freedom");
    }
}
