//! A periodic Gaussian random height field, triangulated, and a ray caster over it.
//!
//! Heights live on an n × n grid of unit cells, vertex (i, j) at (x, y) = (i, j), wrapping with
//! period n in x and y. Each cell is split along its (0,0)–(1,1) diagonal into two triangles, so
//! the surface is a continuous piecewise-planar sheet whose facet normals are the triangle normals.
//!
//! Synthesis: white Gaussian noise convolved (periodically, separably) with a Gaussian kernel of
//! standard deviation σ_k cells. The result is a stationary Gaussian field with correlation
//! exp(−r²/(4σ_k²)); every triangle slope is a linear combination of heights, hence Gaussian too.
//! The heights are then scaled so the RMS slope over the triangles (all of equal projected area,
//! so this is the projected-area average microfacet theory uses) is exactly the requested m:
//!   m² = ⟨(∂h/∂x)² + (∂h/∂y)²⟩,
//! which is Beckmann's m (each slope component has variance m²/2).
//! Source: the spectral/convolution method for Gaussian random surfaces, e.g. J. J. Koenderink &
//! A. van Doorn, or the rough-surface literature (Beckmann & Spizzichino 1963, ch. 5).
//!
//! Ray casting: a 2D DDA (Amanatides & Woo, "A Fast Voxel Traversal Algorithm", Eurographics 1987)
//! walks the cells the ray's footprint crosses, skipping cells whose height range the ray misses.
//! Only front faces are hit (d · n < 0): a ray leaving a facet can then never re-hit that facet.

use radiometry::DVec3;
use rand::Rng;
use rand_pcg::Pcg32;

/// A periodic, triangulated height field on an n × n grid of unit cells.
#[derive(Clone, Debug)]
pub struct HeightField {
    n: usize,
    h: Vec<f64>,
    cell_min: Vec<f64>,
    cell_max: Vec<f64>,
    h_min: f64,
    h_max: f64,
}

/// A ray's first intersection with the surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// The point hit.
    pub p: DVec3,
    /// The unit facet normal there (z > 0).
    pub n: DVec3,
}

/// What a cast ray did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Cast {
    /// It hit a facet's front face.
    Hit(Hit),
    /// It rose above the highest point: it leaves the surface for good.
    Escaped,
    /// It fell below the lowest point (through a crack between triangles, numerically) or wandered
    /// too far without resolving; the caller counts it as lost.
    Lost,
}

/// Standard normal variates by Box–Muller.
fn normal(rng: &mut Pcg32) -> f64 {
    let u1: f64 = 1.0 - rng.gen::<f64>();
    let u2: f64 = rng.gen();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

impl HeightField {
    /// A Gaussian random field on an n × n grid with correlation kernel σ_k = `corr_cells`,
    /// scaled to RMS slope `rms_slope` (Beckmann's m), from `seed`.
    pub fn gaussian(n: usize, corr_cells: f64, rms_slope: f64, seed: u64) -> Self {
        let n = n.max(2);
        let mut rng = Pcg32::new(seed ^ 0x853C_49E6_748F_EA9B, 0xDA3E_39CB_94B9_5BDB);
        let noise: Vec<f64> = (0..n * n).map(|_| normal(&mut rng)).collect();
        let sigma = corr_cells.max(0.25);
        let radius = (4.0 * sigma).ceil() as i64;
        let kernel: Vec<f64> = (-radius..=radius).map(|k| (-(k * k) as f64 / (2.0 * sigma * sigma)).exp()).collect();
        let wrap = |i: i64| i.rem_euclid(n as i64) as usize;
        // Rows, then columns; the wrap makes the field periodic whatever the kernel's width.
        let mut tmp = vec![0.0; n * n];
        for j in 0..n {
            for i in 0..n {
                tmp[j * n + i] =
                    kernel.iter().enumerate().map(|(k, w)| w * noise[j * n + wrap(i as i64 + k as i64 - radius)]).sum();
            }
        }
        let mut h = vec![0.0; n * n];
        for j in 0..n {
            for i in 0..n {
                h[j * n + i] =
                    kernel.iter().enumerate().map(|(k, w)| w * tmp[wrap(j as i64 + k as i64 - radius) * n + i]).sum();
            }
        }
        let mut f = HeightField::from_heights(n, h);
        let m = f.rms_slope();
        if m > 0.0 {
            let scale = rms_slope.max(0.0) / m;
            f = HeightField::from_heights(n, f.h.iter().map(|v| v * scale).collect());
        }
        f
    }

    /// A field from n × n heights, row-major (index j · n + i for vertex (i, j)).
    pub fn from_heights(n: usize, h: Vec<f64>) -> Self {
        assert_eq!(h.len(), n * n, "n × n heights");
        let mut cell_min = vec![0.0; n * n];
        let mut cell_max = vec![0.0; n * n];
        for j in 0..n {
            for i in 0..n {
                let v = [
                    h[j * n + i],
                    h[j * n + (i + 1) % n],
                    h[((j + 1) % n) * n + i],
                    h[((j + 1) % n) * n + (i + 1) % n],
                ];
                cell_min[j * n + i] = v.iter().copied().fold(f64::INFINITY, f64::min);
                cell_max[j * n + i] = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            }
        }
        let h_min = cell_min.iter().copied().fold(f64::INFINITY, f64::min);
        let h_max = cell_max.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        HeightField { n, h, cell_min, cell_max, h_min, h_max }
    }

    /// The period n (cells per side).
    pub fn size(&self) -> usize {
        self.n
    }

    /// The highest vertex.
    pub fn max_height(&self) -> f64 {
        self.h_max
    }

    /// The lowest vertex.
    pub fn min_height(&self) -> f64 {
        self.h_min
    }

    /// Height of vertex (i, j), periodic.
    #[inline]
    pub fn height(&self, i: i64, j: i64) -> f64 {
        let n = self.n as i64;
        self.h[(j.rem_euclid(n) * n + i.rem_euclid(n)) as usize]
    }

    /// Slopes (∂h/∂x, ∂h/∂y) of the two triangles of cell (i, j): the lower one (u ≥ v) first.
    #[inline]
    fn cell_slopes(&self, i: i64, j: i64) -> ([f64; 2], [f64; 2], f64) {
        let h00 = self.height(i, j);
        let h10 = self.height(i + 1, j);
        let h01 = self.height(i, j + 1);
        let h11 = self.height(i + 1, j + 1);
        ([h10 - h00, h11 - h10], [h11 - h01, h01 - h00], h00)
    }

    /// Every triangle's slope (∂h/∂x, ∂h/∂y); all triangles have projected area 1/2.
    pub fn slopes(&self) -> Vec<[f64; 2]> {
        let n = self.n as i64;
        let mut out = Vec::with_capacity(2 * self.n * self.n);
        for j in 0..n {
            for i in 0..n {
                let (a, b, _) = self.cell_slopes(i, j);
                out.push(a);
                out.push(b);
            }
        }
        out
    }

    /// The RMS slope √⟨s_x² + s_y²⟩ over the triangles (projected-area weighted).
    pub fn rms_slope(&self) -> f64 {
        let s = self.slopes();
        (s.iter().map(|v| v[0] * v[0] + v[1] * v[1]).sum::<f64>() / s.len() as f64).sqrt()
    }

    /// The first front-face hit of the ray o + t d, t > 0 (d need not be unit).
    pub fn cast(&self, o: DVec3, d: DVec3) -> Cast {
        if d.z > 0.0 && o.z >= self.h_max {
            return Cast::Escaped;
        }
        if d.z <= 0.0 && o.z < self.h_min {
            return Cast::Lost;
        }
        let (mut ci, mut cj) = (o.x.floor() as i64, o.y.floor() as i64);
        let step = |dc: f64| if dc > 0.0 { 1 } else { -1 };
        let (sx, sy) = (step(d.x), step(d.y));
        let next = |c: i64, oc: f64, dc: f64| {
            if dc == 0.0 {
                f64::INFINITY
            } else {
                ((c + i64::from(dc > 0.0)) as f64 - oc) / dc
            }
        };
        let (mut tx, mut ty) = (next(ci, o.x, d.x), next(cj, o.y, d.y));
        let (dtx, dty) = (
            if d.x == 0.0 { f64::INFINITY } else { 1.0 / d.x.abs() },
            if d.y == 0.0 { f64::INFINITY } else { 1.0 / d.y.abs() },
        );
        let mut t_enter = 0.0f64;
        // Cells a ray may cross before it must have risen out or fallen through: far more than any
        // non-horizontal ray needs; a ray grazing the mean plane forever is dropped as lost.
        let max_steps = 64 * self.n + 1024;
        let n = self.n as i64;
        for _ in 0..max_steps {
            let t_exit = tx.min(ty);
            let (z0, z1) = (o.z + t_enter * d.z, o.z + t_exit.min(1e300) * d.z);
            let (zlo, zhi) = (z0.min(z1), z0.max(z1));
            let cell = (cj.rem_euclid(n) * n + ci.rem_euclid(n)) as usize;
            if zhi >= self.cell_min[cell] && zlo <= self.cell_max[cell] {
                if let Some(hit) = self.hit_cell(ci, cj, o, d, t_enter, t_exit) {
                    return Cast::Hit(hit);
                }
            }
            if d.z > 0.0 && z1 > self.h_max {
                return Cast::Escaped;
            }
            if d.z < 0.0 && z1 < self.h_min {
                return Cast::Lost;
            }
            if !t_exit.is_finite() {
                return Cast::Lost;
            }
            t_enter = t_exit;
            if tx < ty {
                ci += sx;
                tx += dtx;
            } else {
                cj += sy;
                ty += dty;
            }
        }
        Cast::Lost
    }

    /// The nearest front-face hit with the two triangles of cell (ci, cj) within [t0, t1].
    fn hit_cell(&self, ci: i64, cj: i64, o: DVec3, d: DVec3, t0: f64, t1: f64) -> Option<Hit> {
        let (a, b, h00) = self.cell_slopes(ci, cj);
        // Cell-local coordinates u = x − ci, v = y − cj.
        let (ou, ov) = (o.x - ci as f64, o.y - cj as f64);
        const EPS: f64 = 1e-9;
        let mut best: Option<(f64, [f64; 2])> = None;
        for (k, s) in [a, b].into_iter().enumerate() {
            // Plane z = h00 + s_x u + s_y v (both triangles contain vertex (0,0)); normal ∝ (−s_x, −s_y, 1).
            let denom = d.z - s[0] * d.x - s[1] * d.y;
            if denom >= 0.0 {
                continue; // back face or parallel
            }
            let t = (h00 + s[0] * ou + s[1] * ov - o.z) / denom;
            if !(t > 0.0 && t >= t0 - EPS && t <= t1 + EPS) {
                continue;
            }
            let (u, v) = (ou + t * d.x, ov + t * d.y);
            let inside = (-EPS..=1.0 + EPS).contains(&u) && (-EPS..=1.0 + EPS).contains(&v);
            let side = if k == 0 { u >= v - EPS } else { v >= u - EPS };
            if inside && side && best.is_none_or(|(bt, _)| t < bt) {
                best = Some((t, s));
            }
        }
        best.map(|(t, s)| Hit { p: o + t * d, n: DVec3::new(-s[0], -s[1], 1.0).normalize() })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flat_field_is_hit_at_its_height_with_normal_up() {
        let f = HeightField::from_heights(4, vec![0.5; 16]);
        let o = DVec3::new(1.3, 2.7, 2.0);
        let d = DVec3::new(0.6, -0.3, -1.0);
        match f.cast(o, d) {
            Cast::Hit(h) => {
                assert!((h.p.z - 0.5).abs() < 1e-12 && (h.n - DVec3::Z).length() < 1e-12);
                assert!((h.p.x - (1.3 + 1.5 * 0.6)).abs() < 1e-12);
            }
            c => panic!("{c:?}"),
        }
        assert_eq!(f.cast(DVec3::new(0.2, 0.2, 0.5), DVec3::new(0.1, 0.0, 1.0)), Cast::Escaped);
    }

    #[test]
    fn a_tilted_plane_has_its_slope_everywhere() {
        // h = 0.3 x is not periodic; a single ramp cell is enough to check the plane equation.
        let n = 8;
        let h: Vec<f64> = (0..n * n).map(|k| 0.3 * (k % n) as f64).collect();
        let f = HeightField::from_heights(n, h);
        let (a, b, _) = f.cell_slopes(2, 3);
        assert!((a[0] - 0.3).abs() < 1e-12 && a[1].abs() < 1e-12 && (b[0] - 0.3).abs() < 1e-12 && b[1].abs() < 1e-12);
        match f.cast(DVec3::new(2.5, 3.5, 10.0), DVec3::new(0.0, 0.0, -1.0)) {
            Cast::Hit(h) => {
                assert!((h.p.z - 0.75).abs() < 1e-12);
                assert!((h.n - DVec3::new(-0.3, 0.0, 1.0).normalize()).length() < 1e-12);
            }
            c => panic!("{c:?}"),
        }
    }
}
