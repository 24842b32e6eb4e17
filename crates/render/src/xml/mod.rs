//! Mitsuba 3 XML scenes (`<scene version="3.0.0">`, and 2.x; older files are upgraded), read
//! as Mitsuba reads them and refused, with the file, line, element and what is accepted,
//! where gonio cannot render what they mean.
//!
//! - The language (`tree.rs`, `parse.rs`): `<include>` (nested, spliced), `<path>`, `<alias>`,
//!   `<ref id>` to any object with an id at any depth, `<default>` and `$name` in every
//!   attribute, every property tag (`<spectrum>` as one value, `λ:value` pairs or an `.spd` file,
//!   reduced to RGB for what it describes), every `<transform>` operation, `to_uv`.
//! - Objects: `<integrator>` and `<sensor>` (`sensor.rs`), `<shape>`s including `serialized`
//!   and `shapegroup`/`instance` (`shape.rs`), `<bsdf>`s and Mitsuba's wrappers (`bsdf.rs`),
//!   `<texture>`s and the spectrum plugins (`texture.rs`), `<emitter>`s (`emitter.rs`).
//!
//! Objects declared at the top level are built (so their errors show) but only rendered where
//! Mitsuba renders them: shapes and non-area emitters as they are, BSDFs, textures and area
//! emitters where something references them.

pub mod bsdf;
pub mod emitter;
pub mod error;
pub mod export;
pub mod parse;
pub mod sensor;
pub mod shape;
pub mod texture;
pub mod transform;
pub mod tree;

pub use error::{Pos, XmlError};

use crate::filter::Filter;
use crate::integrator::Integrator;
use crate::material::Material;
use crate::scene::{Scene, SceneBuilder};
use glam::Mat4;
use parse::{Ids, OBJECT_TAGS};
use radiometry::cie::SpectrumUse;
use std::cell::RefCell;
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use tree::Elem;

/// The elements accepted directly inside `<scene>` (besides `default`, `include`, `path`, which
/// the reader has applied).
pub const SCENE_ELEMENTS: &[&str] =
    &["integrator", "sensor", "shape", "bsdf", "texture", "emitter", "spectrum", "ref", "alias"];

/// A loaded scene with the render settings the file gave.
pub struct LoadedScene {
    /// The scene, ready to render.
    pub scene: Scene,
    /// `<sampler>` `sample_count` (Mitsuba's default 4).
    pub spp: u32,
    /// `<sampler>` `seed` (default 0).
    pub seed: u64,
    /// The `<integrator>` (default `path`, unbounded depth).
    pub integrator: Integrator,
    /// Image width in pixels (the crop window's).
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// The film's reconstruction filter (Mitsuba's default: gaussian, σ = 0.5 px).
    pub filter: Filter,
}

impl std::fmt::Debug for LoadedScene {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LoadedScene")
            .field("shapes", &self.scene.shapes().len())
            .field("lights", &self.scene.lights().len())
            .field("spp", &self.spp)
            .field("seed", &self.seed)
            .field("integrator", &self.integrator)
            .field("width", &self.width)
            .field("height", &self.height)
            .field("filter", &self.filter)
            .finish()
    }
}

/// What the builders share while one scene loads: the objects by id, and each object built
/// once however often it is referenced.
pub struct Loader<'t> {
    /// Every object with an id.
    pub ids: Ids<'t>,
    /// Built materials, by element.
    pub materials: RefCell<HashMap<*const Elem, Material>>,
    /// Built textures, by element and use.
    pub textures: RefCell<HashMap<(*const Elem, SpectrumUse), crate::texture::Texture>>,
    /// Bitmap files decoded ahead, by path; each is taken out by its first use.
    pub decoded: RefCell<HashMap<PathBuf, crate::texture::Decoded>>,
    /// Area emitters declared with an id and attached to a shape.
    pub area_used: RefCell<HashSet<*const Elem>>,
}

/// Loads the scene file `path`; `defines` give `$name` values (`-D name=value`), overriding
/// the file's `<default>`s.
pub fn load_scene(path: &Path, defines: &[(String, String)]) -> Result<LoadedScene, XmlError> {
    let text = std::fs::read_to_string(path).map_err(|e| XmlError::file(path, format!("cannot read: {e}")))?;
    let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
    load(&text, path, &base, defines)
}

/// Loads a scene from `text`; relative paths resolve against `base_dir`, and errors name
/// the file as `<string>`.
pub fn load_scene_str(text: &str, base_dir: &Path, defines: &[(String, String)]) -> Result<LoadedScene, XmlError> {
    load(text, &PathBuf::from("<string>"), base_dir, defines)
}

fn load(text: &str, file: &Path, base: &Path, defines: &[(String, String)]) -> Result<LoadedScene, XmlError> {
    let tree = tree::read(text, file, base, defines)?;
    let root = &tree.root;
    if root.tag != "scene" {
        return Err(root.err("the root element must be <scene>"));
    }
    root.check_attrs(&["version", "type", "id"])?;
    let ld = Loader {
        ids: Ids::new(root)?,
        materials: RefCell::new(HashMap::new()),
        textures: RefCell::new(HashMap::new()),
        decoded: RefCell::new(texture::prefetch(root)),
        area_used: RefCell::new(HashSet::new()),
    };
    let mut integrator = None;
    let mut sensor = None;
    for e in &root.children {
        let tag = e.tag.as_str();
        if !SCENE_ELEMENTS.contains(&tag) {
            let why = if OBJECT_TAGS.contains(&tag) { " (not supported yet)" } else { "" };
            return Err(e.err(format!(
                "unsupported element <{tag}> in <scene>{why}; accepted elements: {}, default, include, path",
                SCENE_ELEMENTS.join(", ")
            )));
        }
        match tag {
            "integrator" if integrator.is_some() => return Err(e.err("a second <integrator>")),
            "integrator" => integrator = Some(sensor::integrator(&ld, e)?),
            "sensor" if sensor.is_some() => return Err(e.err("a second <sensor>; one camera per scene")),
            "sensor" => sensor = Some(sensor::load(&ld, e)?),
            _ => {}
        }
    }
    let sensor = sensor.ok_or_else(|| root.err("the scene has no <sensor> (perspective, thinlens or orthographic)"))?;
    let (width, height) = (sensor.camera.width, sensor.camera.height);
    let mut builder = SceneBuilder::new(sensor.camera);
    for e in &root.children {
        let target = ld.ids.deref(e)?;
        match target.tag.as_str() {
            "shape" if target.attr("type") == Some("shapegroup") && e.tag == "ref" => {
                return Err(e.err("a shapegroup is placed by an <instance>, not referenced from the scene"));
            }
            "shape" if target.attr("type") == Some("shapegroup") => {}
            "shape" => {
                for s in shape::load(&ld, target, &Mat4::IDENTITY, false)? {
                    builder.shape(s);
                }
            }
            "emitter" => {
                if let Some(light) = emitter::load(&ld, target)? {
                    builder.light(light);
                }
            }
            "bsdf" => {
                bsdf::material(&ld, target)?;
            }
            "texture" | "spectrum" => {
                texture::object(&ld, target, SpectrumUse::Reflectance)
                    .or_else(|_| texture::object(&ld, target, SpectrumUse::Emission))?;
            }
            _ => {}
        }
    }
    let scene = builder.build().map_err(|e| root.err(e.to_string()))?;
    Ok(LoadedScene {
        scene,
        spp: sensor.spp,
        seed: sensor.seed,
        integrator: integrator.unwrap_or_default(),
        width,
        height,
        filter: sensor.filter,
    })
}
