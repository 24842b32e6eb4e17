//! Which light a vertex samples. An environment that shares the scene with other lights is
//! not chosen but sampled beside the choice ([`light_sample`](super::light_sample)); the choice
//! is among the other lights. With one there is no choice, and with more than
//! [`ADAPTIVE_MAX`] the choice is uniform, as in Mitsuba 3. Otherwise, as pbrt-v4's light
//! sampler does (Pharr, Jakob & Humphreys 2023, §12.6), they are chosen in proportion to an
//! estimate of the irradiance each gives the reference point unoccluded:
//!
//! - a point, spot or directional light: exactly its irradiance, E = I·cos θ / r² (the light
//!   sample itself), zero behind the surface;
//! - an area light: L_max·A·cos θ′ / max(d², r²) from the bounding sphere (centre c, radius r,
//!   d = |c − p|) of the emitting shape, where θ′ is the smallest angle between the normal and
//!   a direction into the sphere; zero only when the whole sphere lies behind the surface.
//!
//! Each estimate is positive wherever its light can add anything (for a reflecting surface,
//! light from behind it adds nothing), so the choice changes the noise, never the mean. A
//! surface that only reflects passes its normal; one that transmits passes none. An
//! environment's light is found by BSDF samples as much as by light samples, and no position
//! bounds it, so no estimate could weigh it against the others: given a fixed share of the
//! choices, it left a floor under a point light and the sky noisy where each vertex either
//! sampled the one or the other.

use super::{Scene, Shape};
use crate::light::{Light, RefPoint};
use crate::shape::Geometry;
use glam::Vec3;

/// Up to this many lights, choices follow the irradiance estimates (each vertex computes one
/// per light); more lights are chosen uniformly.
pub const ADAPTIVE_MAX: usize = 8;

/// What a light's estimate is computed from, fixed when the scene is built.
#[derive(Clone, Copy, Debug)]
pub(super) enum Bound {
    /// A delta light: its light sample gives the irradiance exactly.
    Delta,
    /// An area light within the sphere (centre, radius²) emitting at most `power` = L_max·A.
    Sphere { centre: Vec3, r2: f32, power: f32 },
    /// An environment: it is sampled beside the choice, or is the only light.
    Infinite,
}

/// The bound of each light of `lights`, whose area lights lie on `shapes`.
pub(super) fn bounds(lights: &[Light], shapes: &[Shape]) -> Vec<Bound> {
    lights
        .iter()
        .map(|l| match l {
            Light::Point(_) | Light::Spot(_) | Light::Directional(_) => Bound::Delta,
            Light::Area(a) => {
                let g = &shapes[a.shape].geometry;
                let (centre, r2) = bounding_sphere(g);
                Bound::Sphere { centre, r2, power: a.radiance.range().1.max(0.0) * g.area() }
            }
            Light::Constant(_) | Light::EnvMap(_) => Bound::Infinite,
        })
        .collect()
}

/// A sphere (centre, radius²) around the shape.
fn bounding_sphere(g: &Geometry) -> (Vec3, f32) {
    let b = (0..g.primitive_count()).fold(crate::shape::Aabb::EMPTY, |b, i| b.union(g.primitive_bounds(i)));
    let c = b.center();
    (c, (b.max - c).length_squared())
}

impl Scene {
    /// The irradiance estimate of light `i` at `r` (see the module's list).
    #[inline]
    fn light_weight(&self, i: usize, r: &RefPoint) -> f32 {
        let facing = |wi: Vec3| r.n.map_or(1.0, |n| wi.dot(n).max(0.0));
        let w = match self.light_bounds[i] {
            Bound::Delta => {
                let s = match &self.lights[i] {
                    Light::Point(l) => l.sample(r),
                    Light::Spot(l) => l.sample(r),
                    Light::Directional(l) => l.sample(r),
                    _ => None,
                };
                s.map_or(0.0, |s| s.li.max_channel() * facing(s.wi))
            }
            Bound::Sphere { centre, r2, power } => {
                let v = centre - r.p;
                let d2 = v.length_squared();
                let cos = match r.n {
                    Some(n) if d2 > r2 => {
                        // cos(max(0, θ − β)): θ from the normal to the centre, β the sphere's
                        // half angle, sin β = r/d.
                        let cos_t = (v.dot(n) / d2.sqrt()).clamp(-1.0, 1.0);
                        let sin_b2 = r2 / d2;
                        let cos_b = (1.0 - sin_b2).max(0.0).sqrt();
                        if cos_t >= cos_b {
                            1.0
                        } else {
                            let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
                            // A margin, so that rounding cannot turn away a light just in front.
                            let c = cos_t * cos_b + sin_t * sin_b2.sqrt();
                            if c < -1e-4 {
                                0.0
                            } else {
                                c.max(1e-4)
                            }
                        }
                    }
                    _ => 1.0,
                };
                power * cos / d2.max(r2).max(f32::MIN_POSITIVE)
            }
            // Not among the choices (see the module's doc).
            Bound::Infinite => 0.0,
        };
        // Finite, and small enough that the sum of all stays finite.
        if w.is_finite() {
            w.min(1e30)
        } else {
            1e30
        }
    }

    /// The environment's index where it is sampled at every vertex beside the choice, not
    /// chosen: where it shares the scene with other lights.
    #[inline]
    pub(super) fn split_environment(&self) -> Option<usize> {
        self.environment.filter(|_| self.lights.len() > 1)
    }

    /// Whether the vertices draw numbers of their own for the environment
    /// ([`split_environment`](Self::split_environment)).
    #[inline]
    pub(crate) fn splits_environment(&self) -> bool {
        self.split_environment().is_some()
    }

    /// How many lights the choice is among: all but a split environment.
    #[inline]
    fn choice_count(&self) -> usize {
        self.lights.len() - usize::from(self.split_environment().is_some())
    }

    /// Whether the choice depends on the reference point (2 to [`ADAPTIVE_MAX`] lights to
    /// choose from); else it is uniform.
    #[inline]
    pub(super) fn choice_adapts(&self) -> bool {
        (2..=ADAPTIVE_MAX).contains(&self.choice_count())
    }

    /// The probability of choosing each light at `r`, by light index (a split environment's
    /// entry is 0, as are those past the last light).
    #[inline]
    fn choice_pmf(&self, r: &RefPoint) -> [f32; ADAPTIVE_MAX + 1] {
        let n = self.lights.len();
        let mut p = [0.0f32; ADAPTIVE_MAX + 1];
        let mut sum = 0.0f32;
        for (i, p) in p[..n].iter_mut().enumerate() {
            *p = self.light_weight(i, r);
            sum += *p;
        }
        let scale = if sum > 0.0 { 1.0 / sum } else { 0.0 };
        for p in &mut p[..n] {
            *p *= scale;
        }
        p
    }

    /// The light chosen from `r` with number `uc`, and the probability of that choice; None
    /// when no light can light `r` (or there is none to choose).
    #[inline]
    pub(super) fn choose_light(&self, r: &RefPoint, uc: f32) -> Option<(usize, f32)> {
        let m = self.choice_count();
        if m == 0 {
            return None;
        }
        if !self.choice_adapts() {
            // The k-th light of the choice, skipping a split environment.
            let k = ((uc * m as f32) as usize).min(m - 1);
            let light = match self.split_environment() {
                Some(e) if k >= e => k + 1,
                _ => k,
            };
            return Some((light, self.uniform_choice_pdf()));
        }
        pick(&self.choice_pmf(r)[..self.lights.len()], uc)
    }

    /// The probability that light `i` is sampled from `r`: chosen by
    /// [`choose_light`](Self::choose_light), or 1 for a split environment.
    #[inline]
    pub fn light_choice_pdf(&self, i: usize, r: &RefPoint) -> f32 {
        if self.split_environment() == Some(i) {
            return 1.0;
        }
        if !self.choice_adapts() {
            return self.uniform_choice_pdf();
        }
        self.choice_pmf(r)[i]
    }

    /// The probability of each light of a choice that does not adapt.
    #[inline]
    fn uniform_choice_pdf(&self) -> f32 {
        1.0 / self.choice_count().max(1) as f32
    }
}

/// The entry of `p` that number `uc` picks, with its probability: the first positive entry
/// whose running sum exceeds `uc`, or the last positive one; None when none is positive.
#[inline]
fn pick(p: &[f32], uc: f32) -> Option<(usize, f32)> {
    let mut acc = 0.0;
    let mut chosen = None;
    for (i, &pi) in p.iter().enumerate() {
        if pi > 0.0 {
            chosen = Some(i);
            acc += pi;
            if uc < acc {
                break;
            }
        }
    }
    chosen.map(|i| (i, p[i]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{look_at, Camera, FovAxis};
    use crate::light::{ConstantEnv, DirectionalLight, PointLight, SpotLight};
    use crate::sampler::Sampler;
    use crate::scene::{LightNumbers, SceneBuilder};
    use crate::shape::{Rectangle, Sphere};
    use crate::texture::Texture;
    use glam::Mat4;
    use radiometry::Rgb;

    /// An empty scene seen by a small camera.
    fn builder() -> SceneBuilder {
        SceneBuilder::new(Camera::new(look_at(Vec3::Z * 10.0, Vec3::ZERO, Vec3::Y).unwrap(), 40.0, FovAxis::X, 8, 8))
    }

    /// Six lights of every kind: an emitting rectangle and sphere, a point, a spot, a
    /// directional light and a constant environment.
    fn six_lights() -> Scene {
        let mut b = builder();
        let emitter = |g: Geometry, l: f32| {
            let mut s = Shape::new(g, brdf::build("lambert", &[]).unwrap());
            s.emission = Some(Texture::Constant(Rgb::new(l, 0.5 * l, 0.25 * l)));
            s
        };
        let m = Mat4::from_translation(Vec3::new(0.0, 2.0, 0.0))
            * Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2)
            * Mat4::from_scale(Vec3::splat(0.5));
        b.shape(emitter(Geometry::Rectangle(Rectangle::new(&m).unwrap()), 20.0));
        b.shape(emitter(Geometry::Sphere(Sphere::new(Vec3::new(-2.0, 0.5, 1.0), 0.3)), 5.0));
        b.light(Light::Point(PointLight { position: Vec3::new(1.5, 1.0, -1.0), intensity: Rgb::splat(3.0) }));
        b.light(Light::Spot(SpotLight {
            position: Vec3::new(0.0, 3.0, 2.0),
            axis: Vec3::new(0.0, -1.0, -0.5).normalize(),
            intensity: Rgb::splat(8.0),
            cutoff: 0.5,
            beam_width: 0.4,
            texture: None,
        }));
        b.light(Light::Directional(DirectionalLight {
            direction: Vec3::new(0.3, -1.0, 0.2).normalize(),
            irradiance: Rgb::splat(0.7),
        }));
        b.light(Light::Constant(ConstantEnv { radiance: Rgb::splat(0.1) }));
        b.build().unwrap()
    }

    /// Reference points around the lights (some inside the emitters' bounding spheres), half
    /// with a normal.
    fn points(n: usize) -> Vec<RefPoint> {
        let mut s = Sampler::new(7, 0, 0);
        (0..n)
            .map(|k| {
                let p = Vec3::new(s.next_1d() - 0.5, s.next_1d() - 0.5, s.next_1d() - 0.5) * 6.0;
                let d = radiometry::warp::uniform_sphere(s.next_2d());
                RefPoint { p, n: (k % 2 == 0).then_some(d) }
            })
            .collect()
    }

    #[test]
    fn the_environment_beside_other_lights_is_sampled_at_every_vertex_and_never_chosen() {
        let point = |x: f32| Light::Point(PointLight { position: Vec3::new(x, 1.0, -1.0), intensity: Rgb::splat(3.0) });
        let env = || Light::Constant(ConstantEnv { radiance: Rgb::splat(0.1) });
        // Alone, the environment is the choice.
        let mut b = builder();
        b.light(env());
        let alone = b.build().unwrap();
        // Beside one light, the environment first; beside two, the environment between them.
        let mut b = builder();
        b.light(env()).light(point(1.5));
        let one = b.build().unwrap();
        let mut b = builder();
        b.light(point(1.5)).light(env()).light(point(-1.5));
        let two = b.build().unwrap();
        let mut s = Sampler::new(5, 0, 0);
        for r in points(200) {
            let n = LightNumbers::draw(&mut s, &alone);
            assert_eq!((n.ue, n.ue2), (0.0, glam::Vec2::ZERO), "no numbers of its own when alone");
            assert_eq!(alone.choose_light(&r, n.uc), Some((0, 1.0)));
            assert_eq!(alone.light_choice_pdf(0, &r), 1.0);
            let [chosen, beside] = alone.sample_lights(&r, &n, true);
            assert!(chosen.is_some() && beside.is_none());

            // The one other light is always chosen, the environment always sampled.
            assert_eq!(one.light_choice_pdf(0, &r), 1.0);
            assert_eq!(one.light_choice_pdf(1, &r), 1.0);
            for uc in [0.0, 0.3, 0.7, 0.999] {
                assert_eq!(one.choose_light(&r, uc), Some((1, 1.0)));
            }
            let n = LightNumbers::draw(&mut s, &one);
            let [chosen, beside] = one.sample_lights(&r, &n, true);
            assert!(chosen.is_none_or(|c| c.delta), "the point light's sample, where it can light r");
            let beside = beside.expect("the environment lights every point");
            assert!(!beside.delta && beside.dist == f32::INFINITY);
            let pdf = one.environment_eval(beside.wi, Some(&r), true).unwrap().1;
            assert!((pdf - beside.pdf).abs() <= 1e-5 * beside.pdf, "{pdf} against {}", beside.pdf);

            // Two lights share the choice, skipping the environment, which keeps its 1.
            assert_eq!(two.light_choice_pdf(1, &r), 1.0);
            let (p0, p2) = (two.light_choice_pdf(0, &r), two.light_choice_pdf(2, &r));
            assert!(p0 + p2 == 0.0 || (p0 + p2 - 1.0).abs() < 1e-6, "{p0} + {p2}");
            for k in 0..64 {
                if let Some((i, p)) = two.choose_light(&r, (k as f32 + 0.5) / 64.0) {
                    assert!(i != 1 && p == two.light_choice_pdf(i, &r) && p > 0.0, "light {i} with {p}");
                }
            }
        }
    }

    #[test]
    fn choices_follow_their_probabilities() {
        let scene = six_lights();
        assert_eq!(scene.lights().len(), 6);
        const K: usize = 4096;
        for r in points(200) {
            let pmf: Vec<f32> = (0..6).map(|i| scene.light_choice_pdf(i, &r)).collect();
            // The environment is sampled beside the choice among the other five.
            let env = scene.environment().unwrap().0;
            assert_eq!(pmf[env], 1.0);
            let total = pmf.iter().sum::<f32>() - 1.0;
            if total == 0.0 {
                // No other light can light r: nothing is chosen.
                assert_eq!(scene.choose_light(&r, 0.5), None);
                continue;
            }
            assert!((total - 1.0).abs() < 1e-5, "{pmf:?} sums to {total}");
            // Numbers evenly spread over [0, 1): each light is chosen in the share its
            // probability gives, to within one number.
            let mut count = [0usize; 6];
            for k in 0..K {
                let (i, p) = scene.choose_light(&r, (k as f32 + 0.5) / K as f32).unwrap();
                assert!(i != env && p == pmf[i], "light {i} with {p}");
                count[i] += 1;
            }
            for i in (0..6).filter(|&i| i != env) {
                let share = count[i] as f32 / K as f32;
                assert!((share - pmf[i]).abs() <= 1.5 / K as f32, "light {i}: chosen {share}, pmf {}", pmf[i]);
            }
        }
    }

    #[test]
    fn a_light_that_can_add_light_is_never_turned_away() {
        let scene = six_lights();
        let mut s = Sampler::new(11, 0, 0);
        for r in points(2000) {
            for (i, light) in scene.lights().iter().enumerate() {
                // Some direction towards the light that the surface at `r` would use.
                let seen = (0..64).any(|_| {
                    let (uc, u) = (s.next_1d(), s.next_2d());
                    let ls = match light {
                        Light::Area(a) => a.sample(&scene.shapes[a.shape].geometry, &r, uc, u),
                        Light::Point(l) => l.sample(&r),
                        Light::Spot(l) => l.sample(&r),
                        Light::Directional(l) => l.sample(&r),
                        Light::Constant(c) => c.sample(&r, u),
                        Light::EnvMap(e) => e.sample(r.p, uc, u),
                    };
                    ls.is_some_and(|ls| !ls.li.is_black() && r.n.is_none_or(|n| ls.wi.dot(n) > 0.0))
                });
                if seen {
                    assert!(scene.light_choice_pdf(i, &r) > 0.0, "light {i} from {r:?}");
                }
            }
        }
    }

    #[test]
    fn a_light_sample_has_the_density_the_light_reports() {
        let scene = six_lights();
        let mut s = Sampler::new(3, 0, 0);
        let mut checked = 0;
        for r in points(500) {
            let n = LightNumbers::draw(&mut s, &scene);
            for ls in scene.sample_lights(&r, &n, false).iter().flatten() {
                if ls.delta {
                    continue;
                }
                let pdf = match ls.shape {
                    Some(shape) => {
                        let (i, _) = scene.area_light(shape).unwrap();
                        let n = match &scene.shapes[shape].geometry {
                            Geometry::Rectangle(q) => q.n,
                            Geometry::Sphere(sp) => (ls.p - sp.center).normalize(),
                            _ => unreachable!(),
                        };
                        scene.light_pdf(i, &r, ls.wi, Some((ls.p, n)), false)
                    }
                    None => scene.environment_eval(ls.wi, Some(&r), false).unwrap().1,
                };
                assert!((pdf - ls.pdf).abs() <= 1e-3 * ls.pdf, "{pdf} against {} from {r:?}", ls.pdf);
                checked += 1;
            }
        }
        assert!(checked > 100, "{checked}");
    }
}
