//! Materials: what a shape's surface is at each point. A material holds, for each parameter
//! of a model, a constant or a texture; at a hit it evaluates its textures at the hit's uv and
//! builds the model on the stack (pbrt-v4's Material → BSDF split), so a hit allocates
//! nothing. Mitsuba's wrappers (`twosided`, `mask`, `blendbsdf`, `normalmap`, `bumpmap`) are
//! materials around materials, assembled per hit from `brdf`'s generic wrapper models.
//!
//! A bump map perturbs the normal by the height's gradient: with N the shading normal and g the
//! height's uv gradient times `scale`, ∂p/∂u' = ∂p/∂u + N (g_u − N·∂p/∂u) (likewise v), the new
//! normal ∂p/∂u' × ∂p/∂v' turned to the geometric normal's side; its tangent is built from the
//! world-space ∂p/∂u against that local normal, which is what Mitsuba 3.9.1 does (it only shows
//! on anisotropic nested models, and gonio renders what Mitsuba renders).

use crate::scene::SurfaceInteraction;
use crate::texture::Texture;
use brdf::blend::Blend;
use brdf::lambert::Lambert;
use brdf::mask::Mask;
use brdf::perturbed::{normal_from_texel, Perturbed};
use brdf::two_sided::TwoSided;
use brdf::{AskOrder, Brdf, ModelSpec, ParamSpec, Params, Recorder, Value, Varied};
use glam::Vec3;
use radiometry::Rgb;
use std::sync::Arc;

/// Most textured parameters one model may have (a model has fewer parameters than this).
const MAX_TEXTURED: usize = 24;

/// A surface's scattering, constant or varying over it.
#[derive(Clone, Debug)]
pub enum Material {
    /// A model whose parameters are the same everywhere, built once.
    Fixed(Arc<dyn Brdf>),
    /// A model with textured parameters, built at each hit.
    Textured(Arc<Textured>),
    /// `front` on the front side, `back` on the back side.
    TwoSided(Box<Material>, Box<Material>),
    /// An opacity over a nested material; the rest passes through.
    Mask {
        /// Opacity in [0, 1] (one-number lookup).
        opacity: Texture,
        /// What the opaque part is.
        nested: Box<Material>,
    },
    /// Two materials mixed.
    Blend {
        /// The weight of `second` in [0, 1] (one-number lookup).
        weight: Texture,
        /// At weight 0.
        first: Box<Material>,
        /// At weight 1.
        second: Box<Material>,
    },
    /// A nested material in the frame of a normal map (texel c: normal 2c − 1).
    NormalMap {
        /// The map (RGB lookup).
        map: Texture,
        /// Mitsuba's `flip_invalid_normals`.
        flip_invalid: bool,
        /// Mitsuba's `use_shadowing_function`.
        shadowing: bool,
        /// The material in the perturbed frame.
        nested: Box<Material>,
    },
    /// A nested material in the frame of a height field.
    BumpMap {
        /// The height (one-number lookup, with its gradient).
        height: Texture,
        /// Height scale.
        scale: f32,
        /// Mitsuba's `flip_invalid_normals`.
        flip_invalid: bool,
        /// Mitsuba's `use_shadowing_function`.
        shadowing: bool,
        /// The material in the perturbed frame.
        nested: Box<Material>,
    },
}

/// A registry model with some parameters given by textures.
#[derive(Debug)]
pub struct Textured {
    /// The model.
    pub spec: &'static ModelSpec,
    /// Every parameter's value; a textured one holds a placeholder.
    pub base: Params,
    /// The textured parameters: description and texture.
    pub textures: Vec<(ParamSpec, Texture)>,
    /// The questions the model's build asks of its parameters, recorded at the first build.
    order: AskOrder,
}

impl Textured {
    /// Checks what can be checked before rendering: every textured parameter may vary and
    /// takes a value of its kind, and the model builds with the textures' mean values.
    pub fn new(spec: &'static ModelSpec, base: Params, textures: Vec<(ParamSpec, Texture)>) -> Result<Self, String> {
        if textures.len() > MAX_TEXTURED {
            return Err(format!("{} textured parameters; at most {MAX_TEXTURED}", textures.len()));
        }
        for (p, _) in &textures {
            if !p.varies {
                return Err(format!("parameter '{}' of model '{}' cannot be given a texture", p.name, spec.name));
            }
        }
        let mut t = Textured { spec, base, textures, order: AskOrder::default() };
        let mean: Vec<(&'static str, Value)> =
            t.textures.iter().map(|(p, tex)| (p.name, p.clamp(value_of(p, tex.mean())))).collect();
        let recorder = Recorder::new(&t.base, &mean);
        t.spec.build_from(&recorder).map_err(|e| e.to_string())?;
        t.order = recorder.order();
        Ok(t)
    }

    /// The model at `uv` handed to `f`, its textured values held in an array of `N` ≥ the
    /// number of textured parameters.
    #[inline]
    fn visit<const N: usize>(&self, uv: glam::Vec2, f: &mut dyn FnMut(&dyn Brdf)) {
        let values: [(&'static str, Value); N] = std::array::from_fn(|k| match self.textures.get(k) {
            Some((p, tex)) => {
                let v = match p.kind {
                    brdf::ParamKind::Float { .. } => [tex.eval_1(uv); 3],
                    _ => tex.eval(uv).0,
                };
                (p.name, p.clamp(v))
            }
            None => ("", Value::Float(0.0)),
        });
        let here = Varied::new(&self.base, &values[..self.textures.len()]).with_order(&self.order);
        let mut called = false;
        let r = (self.spec.build.scoped)(&here, &mut |b| {
            called = true;
            f(b)
        });
        if r.is_err() && !called {
            f(&ABSORBER);
        }
    }
}

/// A texture's RGB value as what parameter `p` takes: one number (the channel mean, as a
/// constant texture's one-number lookup) or RGB.
fn value_of(p: &ParamSpec, c: Rgb) -> [f32; 3] {
    match p.kind {
        brdf::ParamKind::Float { .. } => [c.mean(); 3],
        _ => c.0,
    }
}

/// The model where nothing valid could be built: it absorbs everything.
const ABSORBER: Lambert = Lambert { albedo: Rgb::ZERO };

impl From<Arc<dyn Brdf>> for Material {
    fn from(b: Arc<dyn Brdf>) -> Self {
        Material::Fixed(b)
    }
}

impl From<Box<dyn Brdf>> for Material {
    fn from(b: Box<dyn Brdf>) -> Self {
        Material::Fixed(Arc::from(b))
    }
}

impl Material {
    /// The model, when it is the same everywhere.
    pub fn fixed(&self) -> Option<&dyn Brdf> {
        match self {
            Material::Fixed(b) => Some(&**b),
            _ => None,
        }
    }

    /// True when the model at every hit has delta lobes only ([`Brdf::delta_only`]): known
    /// without textures (a textured model counts as not, whatever it is built as).
    pub fn delta_only(&self) -> bool {
        match self {
            Material::Fixed(b) => b.delta_only(),
            Material::Textured(_) => false,
            Material::TwoSided(front, back) => front.delta_only() && back.delta_only(),
            // What passes through, or is mixed in, is delta or nothing.
            Material::Mask { nested, .. } | Material::NormalMap { nested, .. } | Material::BumpMap { nested, .. } => {
                nested.delta_only()
            }
            Material::Blend { first, second, .. } => first.delta_only() && second.delta_only(),
        }
    }

    /// Starts loading the texels that the model at `uv` is built from: a hint, which changes
    /// no result; asked for early, their cache misses overlap other work.
    pub fn prefetch(&self, uv: glam::Vec2) {
        match self {
            Material::Fixed(_) => {}
            Material::Textured(t) => t.textures.iter().for_each(|(_, tex)| tex.prefetch(uv)),
            Material::TwoSided(front, back) => {
                front.prefetch(uv);
                back.prefetch(uv);
            }
            Material::Mask { opacity, nested } => {
                opacity.prefetch(uv);
                nested.prefetch(uv);
            }
            Material::Blend { weight, first, second } => {
                weight.prefetch(uv);
                first.prefetch(uv);
                second.prefetch(uv);
            }
            Material::NormalMap { map: t, nested, .. } | Material::BumpMap { height: t, nested, .. } => {
                t.prefetch(uv);
                nested.prefetch(uv);
            }
        }
    }

    /// The model at hit `si`, handed to `f` (once); what `f` returns.
    #[inline]
    pub fn with<R>(&self, si: &SurfaceInteraction, mut f: impl FnMut(&dyn Brdf) -> R) -> R {
        if let Material::Fixed(b) = self {
            return f(&**b);
        }
        // `f` borrowed, not moved into an Option: the move copied its captures with wide loads
        // that waited on the narrow stores just made (perf, at every textured hit).
        let mut out = None;
        self.visit(si, &mut |b| out = Some(f(b)));
        out.expect("every material hands its model to the continuation")
    }

    /// The model at `si`, handed to `f` exactly once.
    fn visit(&self, si: &SurfaceInteraction, f: &mut dyn FnMut(&dyn Brdf)) {
        let uv = si.uv;
        match self {
            Material::Fixed(b) => f(&**b),
            // Arrays sized to the textured parameters (usually one or two): each entry is
            // written and dropped at every hit.
            Material::Textured(t) => match t.textures.len() {
                0 | 1 => t.visit::<1>(uv, f),
                2 => t.visit::<2>(uv, f),
                3 | 4 => t.visit::<4>(uv, f),
                _ => t.visit::<MAX_TEXTURED>(uv, f),
            },
            Material::TwoSided(front, back) => front.visit(si, &mut |a| {
                back.visit(si, &mut |b| match TwoSided::new(a, b) {
                    Ok(t) => f(&t),
                    Err(_) => f(&ABSORBER),
                })
            }),
            Material::Mask { opacity, nested } => {
                let opacity = opacity.eval_1(uv).clamp(0.0, 1.0);
                nested.visit(si, &mut |n| f(&Mask { opacity, nested: n }))
            }
            Material::Blend { weight, first, second } => {
                let weight = weight.eval_1(uv).clamp(0.0, 1.0);
                first.visit(si, &mut |a| second.visit(si, &mut |b| f(&Blend { weight, first: a, second: b })))
            }
            Material::NormalMap { map, flip_invalid, shadowing, nested } => {
                let normal = normal_from_texel(map.eval(uv));
                let (flip_invalid, shadowing) = (*flip_invalid, *shadowing);
                nested.visit(si, &mut |n| f(&Perturbed::new(normal, Vec3::X, flip_invalid, shadowing, n)))
            }
            Material::BumpMap { height, scale, flip_invalid, shadowing, nested } => {
                let g = height.eval_1_grad(uv).unwrap_or_default() * *scale;
                let n = si.frame.n;
                let du = si.dp_du + n * (g.x - n.dot(si.dp_du));
                let dv = si.dp_dv + n * (g.y - n.dot(si.dp_dv));
                let mut c = du.cross(dv);
                if si.ng.dot(c) < 0.0 {
                    c = -c;
                }
                let normal = si.frame.to_local(c);
                let (flip_invalid, shadowing, tangent) = (*flip_invalid, *shadowing, si.dp_du);
                nested.visit(si, &mut |m| f(&Perturbed::new(normal, tangent, flip_invalid, shadowing, m)))
            }
        }
    }
}
