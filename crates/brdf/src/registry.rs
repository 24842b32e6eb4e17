//! Every model by name, with its parameters as data: the one list the CLI, the scene
//! loader and the web page are generated from.

use crate::params::{ParamError, ParamSource, ParamSpec, Params};
use crate::Brdf;

/// Builds a model on the heap.
pub type OwnedBuild = fn(&dyn ParamSource) -> Result<Box<dyn Brdf>, ParamError>;
/// Builds a model on the stack and hands it to a continuation.
pub type ScopedBuild = fn(&dyn ParamSource, &mut dyn FnMut(&dyn Brdf)) -> Result<(), ParamError>;
/// A model named in text: its entry and its (parameter, value) pairs.
pub type Item = (&'static ModelSpec, Vec<(String, String)>);

/// How a model is built from its parameters.
#[derive(Clone, Copy)]
pub struct Build {
    /// On the heap: a constant material, a model named on the command line.
    pub owned: OwnedBuild,
    /// On the stack, handed to `f`: a textured material at one surface point, which must not
    /// allocate.
    pub scoped: ScopedBuild,
}

/// The [`Build`] of a model whose function `$make(&dyn ParamSource) -> Result<M, ParamError>`
/// returns it by value.
macro_rules! by_value {
    ($make:path) => {
        $crate::registry::Build {
            owned: |p| Ok(Box::new($make(p)?)),
            scoped: |p, f| {
                f(&$make(p)?);
                Ok(())
            },
        }
    };
}
pub(crate) use by_value;

/// The [`Build`] of a model read from a file by `$make(&dyn ParamSource) -> Result<Box<dyn Brdf>,
/// ParamError>`: nothing of it varies over a surface, so the scoped build (which boxes) is used
/// once per material, never per hit.
macro_rules! boxed {
    ($make:path) => {
        $crate::registry::Build {
            owned: $make,
            scoped: |p, f| {
                f(&*$make(p)?);
                Ok(())
            },
        }
    };
}
pub(crate) use boxed;

/// A named model: its parameter descriptions and how to build it.
#[derive(Clone, Copy)]
pub struct ModelSpec {
    /// The model's name everywhere (`gonio models` lists it).
    pub name: &'static str,
    /// One line saying what it is.
    pub summary: &'static str,
    /// The paper or text it comes from.
    pub reference: &'static str,
    /// Its parameters.
    pub params: fn() -> Vec<ParamSpec>,
    /// Builds it from resolved parameters.
    pub build: Build,
    /// Parameter sets worth checking besides the defaults (e.g. where the lecture shows a model
    /// failing a property); `gonio check --all` runs them too.
    pub showcase: &'static [&'static [(&'static str, &'static str)]],
}

impl std::fmt::Debug for ModelSpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ModelSpec").field("name", &self.name).finish()
    }
}

impl ModelSpec {
    /// Resolves `(name, value)` pairs (defaults filled in, ranges checked) and builds the model.
    pub fn build_with(&self, given: &[(&str, &str)]) -> Result<Box<dyn Brdf>, ParamError> {
        let params = Params::resolve(self.name, &(self.params)(), given)?;
        (self.build.owned)(&params)
    }

    /// Builds it from resolved (or varied) parameters.
    pub fn build_from(&self, p: &dyn ParamSource) -> Result<Box<dyn Brdf>, ParamError> {
        (self.build.owned)(p)
    }

    /// Builds it on the stack from `p` and returns what `f` makes of it.
    pub fn with<R>(&self, p: &dyn ParamSource, f: impl FnOnce(&dyn Brdf) -> R) -> Result<R, ParamError> {
        let mut f = Some(f);
        let mut out = None;
        (self.build.scoped)(p, &mut |b| out = f.take().map(|f| f(b)))?;
        Ok(out.expect("a model's scoped build calls its continuation once"))
    }

    /// True when the model is data read from a file (a path parameter with no default, e.g.
    /// `merl --filename`): it cannot be built from its defaults, so loops that build every
    /// model at its defaults (`check --all`, benches) skip it.
    pub fn requires_file(&self) -> bool {
        (self.params)()
            .iter()
            .any(|p| p.kind == crate::params::ParamKind::Path && p.default == crate::params::Value::Path(String::new()))
    }
}

/// Every model, in the order `gonio models` lists them.
pub fn models() -> &'static [ModelSpec] {
    &[
        crate::lambert::SPEC,
        crate::microfacet_brdf::SPEC,
        crate::microfacet_brdf::GGX_SPEC,
        crate::microfacet_brdf::BECKMANN_SPEC,
        crate::cook_torrance::SPEC,
        crate::mirror::SPEC,
        crate::phong::SPEC,
        crate::phong::MODIFIED_SPEC,
        crate::blinn_phong::SPEC,
        crate::blinn_phong::MODIFIED_SPEC,
        crate::ward::SPEC,
        crate::plastic::ROUGH_SPEC,
        crate::plastic::SMOOTH_SPEC,
        crate::dielectric::SPEC,
        crate::rough_dielectric::SPEC,
        crate::thin_dielectric::SPEC,
        crate::principled::SPEC,
        crate::principled_thin::SPEC,
        crate::two_sided::SPEC,
        crate::mask::SPEC,
        crate::blend::SPEC,
        crate::perturbed::NORMALMAP_SPEC,
        crate::perturbed::BUMPMAP_SPEC,
        crate::null::SPEC,
        crate::measured::SPEC,
        crate::measured::tabulated_model::SPEC,
    ]
}

/// The model called `name`, or an error listing every name.
pub fn find(name: &str) -> Result<&'static ModelSpec, ParamError> {
    models().iter().find(|m| m.name == name).ok_or_else(|| ParamError::UnknownModel {
        name: name.to_string(),
        valid: models().iter().map(|m| m.name).collect::<Vec<_>>().join(", "),
    })
}

/// Builds model `name` with `(parameter, value)` pairs given as text.
pub fn build(name: &str, given: &[(&str, &str)]) -> Result<Box<dyn Brdf>, ParamError> {
    find(name)?.build_with(given)
}

/// Splits a model written `NAME[:PARAM=VALUE]...` (`ward:alpha=0.1:ks=0.3`) into its entry and
/// its pairs; names are checked here, values when it is built.
pub fn parse_item(item: &str) -> Result<Item, ParamError> {
    let mut parts = item.split(':');
    let name = parts.next().unwrap_or_default().trim();
    let bad = |what: String| {
        ParamError::Inconsistent(format!("{what}; write MODEL[:PARAM=VALUE]..., e.g. ward:alpha=0.1:ks=0.3"))
    };
    if name.is_empty() {
        return Err(bad(format!("empty model name in '{item}'")));
    }
    let spec = find(name)?;
    let mut given = Vec::new();
    for p in parts {
        let Some((k, v)) = p.split_once('=') else {
            return Err(bad(format!("'{p}' in '{item}' is not PARAM=VALUE")));
        };
        given.push((k.trim().to_string(), v.trim().to_string()));
    }
    Ok((spec, given))
}

/// Builds a model written `NAME[:PARAM=VALUE]...` (a wrapper's nested model).
pub fn build_item(item: &str) -> Result<Box<dyn Brdf>, ParamError> {
    let (spec, given) = parse_item(item)?;
    let pairs: Vec<(&str, &str)> = given.iter().map(|(k, v)| (k.as_str(), v.as_str())).collect();
    spec.build_with(&pairs)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    #[test]
    fn every_model_builds_with_defaults_and_names_are_unique() {
        let mut names = std::collections::HashSet::new();
        for m in models() {
            assert!(names.insert(m.name), "duplicate model name {}", m.name);
            if m.requires_file() {
                // Explicitly: a model read from a file must refuse to build without one, saying so.
                let e = m.build_with(&[]).err().map(|e| e.to_string()).unwrap_or_default();
                assert!(e.contains("file"), "{} builds without its file or says nothing about it: {e}", m.name);
            } else {
                assert!(m.build_with(&[]).is_ok(), "{} fails to build with its defaults", m.name);
            }
            for p in (m.params)() {
                assert_eq!(p.parse(&p.default.to_string()).as_ref(), Ok(&p.default), "{}.{}", m.name, p.name);
            }
        }
    }

    #[test]
    fn a_model_of_delta_lobes_only_evaluates_to_zero_and_the_others_do_not() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(3);
        let mut dir = || {
            let v = glam::Vec3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0));
            v.normalize_or(glam::Vec3::Z)
        };
        let mut delta = Vec::new();
        for m in models().iter().filter(|m| !m.requires_file()) {
            let b = m.build_with(&[]).unwrap();
            // Every pair of directions, on the same side and across, above and below.
            let nonzero = (0..2000).filter(|_| !b.eval(dir(), dir()).is_black()).count();
            if b.delta_only() {
                assert!(b.has_delta(), "{} claims delta lobes only but has no delta lobe", m.name);
                assert_eq!(nonzero, 0, "{} claims delta lobes only", m.name);
                delta.push(m.name);
            } else {
                assert!(
                    nonzero > 0,
                    "{} evaluates to zero everywhere but does not say it has delta lobes only",
                    m.name
                );
            }
        }
        assert!(delta.contains(&"mirror") && delta.contains(&"dielectric"), "{delta:?}");
    }

    #[test]
    fn unknown_model_lists_the_valid_ones() {
        let e = build("phongg", &[]).unwrap_err().to_string();
        assert!(e.contains("lambert"), "{e}");
    }
}
