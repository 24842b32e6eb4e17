//! A nested model in a perturbed shading frame: Mitsuba 3's `normalmap` and `bumpmap`.
//!
//! The perturbed normal n' (a normal map's texel, 2c − 1, or the normal of a height field's
//! tangent plane) is first flipped to the viewer's side of the surface when it faces away from
//! it, n' ← (−n'_x, −n'_y, n'_z) if wo_z (wo·n') ≤ 0 (`flip_invalid_normals`); the frame is
//! s = the tangent hint made orthogonal to n', t = n' × s. With primes for directions in that
//! frame and G the shadowing term of Mitsuba's normal maps,
//!
//!   ρ(wi, wo) = ρ_n(wi', wo') |wi'_z| / |wi_z| · G(wi),   pdf = p_n(wi' | wo'),
//!   G(w) = 2 / (1 + √(1 + α² tan²θ_w)),   α² = min(tan²θ_n' / 8, 1)  (`use_shadowing_function`),
//!
//! zero where wi lies on different sides of the two frames. The cosine ratio keeps ρ cos θi equal
//! to the nested model's in its own frame; a rotation keeps solid angles, so the pdf is the
//! nested one's. So the albedo ∫ ρ cos θi dωi at a given wo stays below the nested model's, but
//! the light reflected from a grazing wi, ∫ ρ cos θo dωo, grows as 1/cos θi (8.5 at 89.99° for a
//! tilted GGX normal map): neither reciprocity nor energy conservation is claimed. Source: Mitsuba 3, `src/bsdfs/normalmap.cpp`, `bumpmap.cpp`
//! (behaviour only); Blinn, "Simulation of wrinkled surfaces", SIGGRAPH 1978, for bump mapping.

use crate::model::{Brdf, BrdfSample, Claims};
use crate::params::{ParamError, ParamSource, ParamSpec};
use crate::registry::{by_value, ModelSpec};
use radiometry::{Frame, Rgb, Vec2, Vec3};

/// A nested model seen in a perturbed frame.
#[derive(Clone, Copy, Debug)]
pub struct Perturbed<N> {
    /// The perturbed normal in the local frame (any length > 0).
    normal: Vec3,
    /// The vector whose part orthogonal to the normal is the new tangent.
    tangent: Vec3,
    /// Turn a normal that faces away from the viewer to its side.
    flip_invalid: bool,
    /// Apply the shadowing term G.
    shadowing: bool,
    /// The model in the perturbed frame.
    pub nested: N,
    /// The frame of the unflipped normal and its α², built once: a path asks for it at each
    /// light sample and the BRDF sample of a vertex (None where the normal or tangent is
    /// degenerate).
    plain: Option<(Frame, f32)>,
}

impl<N: Brdf> Perturbed<N> {
    /// `nested` in the frame of `normal` (any length > 0) with tangent `tangent`'s part
    /// orthogonal to it; `flip_invalid` and `shadowing` are Mitsuba's flags.
    #[inline]
    pub fn new(normal: Vec3, tangent: Vec3, flip_invalid: bool, shadowing: bool, nested: N) -> Self {
        let plain = frame_of(normal, tangent);
        Perturbed { normal, tangent, flip_invalid, shadowing, nested, plain }
    }

    /// The perturbed frame for viewer direction `wo`, with its α².
    #[inline]
    fn frame(&self, wo: Vec3) -> Option<(Frame, f32)> {
        let n = self.normal;
        if self.flip_invalid && wo.z * wo.dot(n) <= 0.0 {
            return frame_of(Vec3::new(-n.x, -n.y, n.z), self.tangent);
        }
        self.plain
    }

    /// The shadowing term G for direction `w` under a normal of α² `a2`.
    #[inline]
    fn g(&self, a2: f32, w: Vec3) -> f32 {
        if !self.shadowing {
            return 1.0;
        }
        2.0 / (1.0 + (1.0 + a2 * tan2(w.z)).sqrt())
    }
}

/// tan²θ for cos θ = `c`.
#[inline]
fn tan2(c: f32) -> f32 {
    ((1.0 - c * c) / (c * c)).max(0.0)
}

/// The frame of normal `n` and tangent hint `tangent`, with the normal's α² = min(tan²θ_n / 8, 1).
#[inline]
fn frame_of(n: Vec3, tangent: Vec3) -> Option<(Frame, f32)> {
    let n = n.try_normalize()?;
    let s = (tangent - n * n.dot(tangent)).try_normalize()?;
    Some((Frame { s, t: n.cross(s), n }, (0.125 * tan2(n.z)).min(1.0)))
}

impl<N: Brdf> Brdf for Perturbed<N> {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        let Some((f, a2)) = self.frame(wo) else { return Rgb::ZERO };
        let (pi, po) = (f.to_local(wi), f.to_local(wo));
        if wi.z * pi.z <= 0.0 {
            return Rgb::ZERO;
        }
        let v = self.nested.eval(pi, po) * (pi.z.abs() / wi.z.abs() * self.g(a2, wi));
        if v.is_finite() {
            v
        } else {
            Rgb::ZERO
        }
    }

    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        let Some((f, _)) = self.frame(wo) else { return 0.0 };
        let pi = f.to_local(wi);
        if wi.z * pi.z <= 0.0 {
            return 0.0;
        }
        self.nested.pdf(pi, f.to_local(wo))
    }

    /// One frame for both: a light sample's eval and pdf made it twice.
    fn eval_pdf(&self, wi: Vec3, wo: Vec3) -> (Rgb, f32) {
        let Some((f, a2)) = self.frame(wo) else { return (Rgb::ZERO, 0.0) };
        let (pi, po) = (f.to_local(wi), f.to_local(wo));
        if wi.z * pi.z <= 0.0 {
            return (Rgb::ZERO, 0.0);
        }
        let (v, pdf) = self.nested.eval_pdf(pi, po);
        let v = v * (pi.z.abs() / wi.z.abs() * self.g(a2, wi));
        (if v.is_finite() { v } else { Rgb::ZERO }, pdf)
    }

    fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BrdfSample> {
        let (f, a2) = self.frame(wo)?;
        let s = self.nested.sample(f.to_local(wo), uc, u)?;
        let wi = f.to_world(s.wi);
        if s.wi.z * wi.z <= 0.0 {
            return None;
        }
        Some(BrdfSample { wi, weight: s.weight * self.g(a2, wi), ..s })
    }

    fn claims(&self) -> Claims {
        Claims { reciprocal: false, energy_conserving: false, isotropic: false }
    }

    fn has_delta(&self) -> bool {
        self.nested.has_delta()
    }

    fn transmits(&self) -> bool {
        self.nested.transmits()
    }

    fn back_side(&self) -> bool {
        self.nested.back_side()
    }

    fn eta(&self) -> f32 {
        self.nested.eta()
    }
}

/// A normal map's texel (Mitsuba's encoding, c = (n + 1)/2) as a normal.
pub fn normal_from_texel(c: Rgb) -> Vec3 {
    Vec3::new(2.0 * c.0[0] - 1.0, 2.0 * c.0[1] - 1.0, 2.0 * c.0[2] - 1.0)
}

fn flags() -> Vec<ParamSpec> {
    vec![
        ParamSpec::boolean("flip_invalid_normals", true, "turn a perturbed normal that faces away from the viewer"),
        ParamSpec::boolean("use_shadowing_function", true, "Mitsuba's shadowing term G for the perturbed normal"),
        ParamSpec::model("bsdf", "lambert", "the model in the perturbed frame"),
    ]
}

fn normalmap_params() -> Vec<ParamSpec> {
    let mut v = vec![ParamSpec::rgb(
        "normal",
        0.0,
        1.0,
        0.5,
        "the normal map's value c, normal 2c − 1 in the shading frame (0.5,0.5,1 is flat)",
    )
    .with_default(crate::Value::Rgb([0.5, 0.5, 1.0]))];
    v.extend(flags());
    v
}

fn bumpmap_params() -> Vec<ParamSpec> {
    let mut v = vec![
        ParamSpec::float(
            "slope_u",
            -100.0,
            100.0,
            0.0,
            "∂h/∂u of the height field (unit tangents ∂p/∂u = x, ∂p/∂v = y)",
        ),
        ParamSpec::float("slope_v", -100.0, 100.0, 0.0, "∂h/∂v of the height field"),
    ];
    v.extend(flags());
    v
}

fn perturbed(p: &dyn ParamSource, normal: Vec3) -> Result<Perturbed<crate::model::BoxedBrdf>, ParamError> {
    Ok(Perturbed::new(
        normal,
        Vec3::X,
        p.flag("flip_invalid_normals"),
        p.flag("use_shadowing_function"),
        crate::registry::build_item(p.model("bsdf"))?,
    ))
}

fn make_normalmap(p: &dyn ParamSource) -> Result<Perturbed<crate::model::BoxedBrdf>, ParamError> {
    let n = normal_from_texel(p.rgb("normal"));
    if n.length_squared() < 1e-12 {
        return Err(ParamError::Inconsistent("parameter 'normal': 0.5,0.5,0.5 is no direction".into()));
    }
    perturbed(p, n)
}

fn make_bumpmap(p: &dyn ParamSource) -> Result<Perturbed<crate::model::BoxedBrdf>, ParamError> {
    // ∂p/∂u' = x + h_u z and ∂p/∂v' = y + h_v z: the normal of their plane.
    perturbed(p, Vec3::new(-p.float("slope_u"), -p.float("slope_v"), 1.0))
}

/// Registry entry: `normalmap`.
pub const NORMALMAP_SPEC: ModelSpec = ModelSpec {
    name: "normalmap",
    summary: "Mitsuba's normalmap: a nested model in the frame of a tilted normal (2c − 1)",
    reference: "Mitsuba 3 normalmap",
    params: normalmap_params,
    build: by_value!(make_normalmap),
    showcase: &[&[("normal", "0.65,0.5,0.98"), ("bsdf", "ggx:alpha_u=0.05:alpha_v=0.4")]],
};

/// Registry entry: `bumpmap`.
pub const BUMPMAP_SPEC: ModelSpec = ModelSpec {
    name: "bumpmap",
    summary: "Mitsuba's bumpmap: a nested model in the frame of a height field's slope",
    reference: "Mitsuba 3 bumpmap; Blinn 1978, Simulation of Wrinkled Surfaces",
    params: bumpmap_params,
    build: by_value!(make_bumpmap),
    showcase: &[&[("slope_u", "0.5"), ("slope_v", "-1")]],
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lambert::Lambert;

    fn diffuse_in(normal: Vec3) -> Perturbed<Lambert> {
        Perturbed::new(normal, Vec3::X, true, true, Lambert { albedo: Rgb::splat(0.5) })
    }

    #[test]
    fn normal_maps_match_mitsuba() {
        // Mitsuba 3.9.1, diffuse 0.5 nested, aligned frame, si.wi = normalize(0.8, 0, 0.6) (our
        // wo); its eval includes cos θ of the light direction (our wi): eval·cos and pdf.
        let wo = Vec3::new(0.8, 0.0, 0.6).normalize();
        let cases = [
            (Vec3::new(-0.9, 0.0, 0.3), Vec3::new(0.5, 0.1, 0.8), 0.111644, 0.2440376),
            (Vec3::new(-0.9, 0.0, 0.3), Vec3::new(0.95, 0.0, 0.1), 0.02945784, 0.3108535),
            (Vec3::new(0.3, 0.1, 1.0), Vec3::new(0.5, 0.1, 0.8), 0.153364, 0.3071169),
            (Vec3::new(0.3, 0.1, 1.0), Vec3::new(-0.3, 0.2, 0.9), 0.1298435, 0.2598172),
            (Vec3::new(0.3, 0.1, 1.0), Vec3::new(0.95, 0.0, 0.1), 0.04974772, 0.1223202),
        ];
        for (n, wi, e, p) in cases {
            let m = diffuse_in(n.normalize());
            let wi = wi.normalize();
            let got = m.eval(wi, wo).0[0] * wi.z;
            assert!((got - e).abs() < 2e-6 * e.max(1.0), "n {n} wi {wi}: {got} vs {e}");
            assert!((m.pdf(wi, wo) - p).abs() < 2e-6, "n {n} wi {wi}: pdf {} vs {p}", m.pdf(wi, wo));
        }
        // Without the flip, the first normal leaves the viewer below the perturbed horizon.
        let m = Perturbed::new(
            Vec3::new(-0.9, 0.0, 0.3).normalize(),
            Vec3::X,
            false,
            true,
            Lambert { albedo: Rgb::splat(0.5) },
        );
        assert_eq!(m.eval(Vec3::new(0.5, 0.1, 0.8).normalize(), wo), Rgb::ZERO);
        // A flat texel is the nested model itself.
        let flat = diffuse_in(normal_from_texel(Rgb::new(0.5, 0.5, 1.0)));
        let wi = Vec3::new(-0.3, 0.2, 0.9).normalize();
        assert!((flat.eval(wi, wo).0[0] - 0.5 / std::f32::consts::PI).abs() < 1e-7);
        // Sampling: Mitsuba's wo (−0.2690737, 0.3895774, 0.8808115), weight 0.499549, for
        // n = normalize(0.3, 0.1, 1), si.wi = +z, sample (0.3, (0.2, 0.7)).
        let m = diffuse_in(Vec3::new(0.3, 0.1, 1.0).normalize());
        let s = m.sample(Vec3::Z, 0.3, Vec2::new(0.2, 0.7)).unwrap();
        assert!((s.wi - Vec3::new(-0.2690737, 0.3895774, 0.8808115)).length() < 1e-5, "{s:?}");
        assert!((s.weight.0[0] - 0.499549).abs() < 1e-5);
    }
}
