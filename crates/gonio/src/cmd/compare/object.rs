//! What every panel shows: Mitsuba's material-preview scene (built in), a Mitsuba scene file
//! with one of its BSDFs replaced, or one object alone (a mesh, or a sphere) under the probe.

use super::panel::Panel;
use crate::demo_scene::{object_scene, Lighting};
use anyhow::{bail, Context, Result};
use glam::{Mat4, Vec3};
use render::shape::TriangleMesh;
use render::{Integrator, Scene};
use std::path::{Path, PathBuf};

/// The material-preview scene: its XML (the object's BSDF has id `bsdf-matpreview`) and meshes.
const MATPREVIEW_XML: &str = include_str!("../../../assets/matpreview.xml");
const MATPREVIEW_MESHES: &[u8] = include_bytes!("../../../assets/matpreview.serialized");
/// The id of the material-preview object's BSDF.
const MATPREVIEW_BSDF: &str = "bsdf-matpreview";

/// Where the material-preview camera stands (its `lookat` origin).
const CAMERA: Vec3 = Vec3::new(3.69558, -3.46243, 3.25463);
/// Half the width, and the height, of the space the material-preview object fills.
const OBJECT_HALF_WIDTH: f32 = 0.85;
/// Distance of a point light from the object's centre.
const POINT_DISTANCE: f32 = 6.0;

/// What stands on the checkerboard.
pub enum Subject {
    /// Mitsuba's material-preview object.
    Matpreview,
    /// A sphere.
    Sphere,
    /// A mesh in its file's frame (+Y up, facing +Z).
    Mesh(TriangleMesh),
}

/// The rotation from an object's frame (+Y up, facing +Z, as `--light` is given) to the
/// material-preview scene's (+Z up, facing its camera).
fn object_to_scene() -> Mat4 {
    let facing = CAMERA.truncate().normalize();
    // +Y → +Z turns the front (+Z) to −Y; then −Y turns to the camera's side.
    let turn = facing.y.atan2(facing.x) + std::f32::consts::FRAC_PI_2;
    Mat4::from_rotation_z(turn) * Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2)
}

/// Files a scene text reads, written to a folder of this process's own for as long as it lives.
pub struct Assets {
    dir: PathBuf,
}

impl Assets {
    fn new(files: &[(&str, &[u8])]) -> Result<Self> {
        static NEXT: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);
        let n = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("gonio-assets-{}-{n}", std::process::id()));
        std::fs::create_dir_all(&dir).with_context(|| format!("creating the folder '{}'", dir.display()))?;
        let assets = Assets { dir };
        for (name, bytes) in files {
            let path = assets.dir.join(name);
            std::fs::write(&path, bytes).with_context(|| format!("writing '{}'", path.display()))?;
        }
        Ok(assets)
    }
}

impl Drop for Assets {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// The scene every panel renders, its model aside.
pub enum Object {
    /// A Mitsuba scene whose BSDF `bsdf` each panel replaces.
    Xml {
        /// The file's text.
        text: String,
        /// The folder its relative paths resolve against.
        base_dir: PathBuf,
        /// Where the text came from, for errors.
        file: PathBuf,
        /// The id of the replaced BSDF (None: the only one a shape references).
        bsdf: Option<String>,
        /// `$name` values.
        defines: Vec<(String, String)>,
        /// The built-in scene's files, kept while it renders.
        _assets: Option<Assets>,
    },
    /// One object, alone under `lighting`, seen square.
    Alone {
        /// A mesh (scaled to fit), or None for a unit sphere.
        mesh: Option<TriangleMesh>,
        /// How it is lit.
        lighting: Box<Lighting>,
        /// Side of the image, in pixels.
        size: u32,
    },
}

impl Object {
    /// The material-preview scene at `size` × `size` with `subject` on its checkerboard, lit
    /// by `probe` (an equirect image, its upward irradiance brought to π, times `scale`) and
    /// `point` (a direction in the object's frame and the irradiance at its centre).
    pub fn matpreview(
        probe: &render::Image,
        scale: f32,
        size: u32,
        subject: Subject,
        point: Option<(Vec3, f32)>,
    ) -> Result<Self> {
        let assets = Assets::new(&[("matpreview.serialized", MATPREVIEW_MESHES)])?;
        let exr = assets.dir.join("probe.exr");
        render::io::exr::write_exr(probe, &exr).with_context(|| format!("writing '{}'", exr.display()))?;
        let (start, end) = (MATPREVIEW_XML.find("<!-- object -->"), MATPREVIEW_XML.find("<!-- end of object -->"));
        let (Some(start), Some(end)) = (start, end) else { bail!("internal error: the built-in scene has no object") };
        let bsdf = format!(r#"<ref name="bsdf" id="{MATPREVIEW_BSDF}"/>"#);
        let centre = Vec3::new(0.0, 0.0, OBJECT_HALF_WIDTH);
        let mut object = match subject {
            Subject::Matpreview => MATPREVIEW_XML[start..end].to_string(),
            Subject::Sphere => format!(
                r#"<shape type="sphere"><point name="center" x="0" y="0" z="{r}"/><float name="radius" value="{r}"/>{bsdf}</shape>"#,
                r = OBJECT_HALF_WIDTH
            ),
            Subject::Mesh(mut m) => {
                m.transform(&object_to_scene());
                let (lo, hi) = crate::demo_scene::mesh_bounds(&m)?;
                let half = 0.5 * (hi - lo).max_element();
                let lift = Vec3::new(-0.5 * (lo.x + hi.x), -0.5 * (lo.y + hi.y), -lo.z);
                m.transform(&(Mat4::from_scale(Vec3::splat(OBJECT_HALF_WIDTH / half)) * Mat4::from_translation(lift)));
                let bytes = render::io::serialized::write(&[(
                    &m.positions,
                    m.normals.as_deref(),
                    m.uvs.as_deref(),
                    &m.indices,
                )]);
                std::fs::write(assets.dir.join("object.serialized"), bytes).context("writing the mesh")?;
                format!(r#"<shape type="serialized"><string name="filename" value="object.serialized"/>{bsdf}</shape>"#)
            }
        };
        if let Some((dir, irradiance)) = point {
            let Some(dir) = object_to_scene().transform_vector3(dir).try_normalize() else {
                bail!("the point light's direction is zero");
            };
            let (p, i) = (centre + POINT_DISTANCE * dir, irradiance * POINT_DISTANCE * POINT_DISTANCE);
            object += &format!(
                r#"<emitter type="point"><point name="position" x="{}" y="{}" z="{}"/><rgb name="intensity" value="{i}"/></emitter>"#,
                p.x, p.y, p.z
            );
        }
        let mut text = format!("{}{object}\n{}", &MATPREVIEW_XML[..start], &MATPREVIEW_XML[end..]);
        if scale == 0.0 {
            // No probe: the envmap emitter goes.
            let (Some(a), Some(b)) = (text.find("<emitter type=\"envmap\""), text.find("</emitter>")) else {
                bail!("internal error: the built-in scene has no probe");
            };
            text.replace_range(a..b + "</emitter>".len(), "");
        }
        let scale = crate::demo_scene::probe_scale(probe)? * scale;
        let defines = [("width", size.to_string()), ("height", size.to_string()), ("envmap", "probe.exr".into())];
        let mut defines: Vec<(String, String)> = defines.into_iter().map(|(k, v)| (k.to_string(), v)).collect();
        defines.push(("env_scale".into(), scale.to_string()));
        Ok(Object::Xml {
            text,
            base_dir: assets.dir.clone(),
            file: PathBuf::from("<built-in matpreview.xml>"),
            bsdf: Some(MATPREVIEW_BSDF.into()),
            defines,
            _assets: Some(assets),
        })
    }

    /// A scene file; the panels replace its BSDF `bsdf`.
    pub fn scene_file(path: &Path, bsdf: Option<String>, defines: Vec<(String, String)>) -> Result<Self> {
        let text = std::fs::read_to_string(path).with_context(|| format!("reading the scene '{}'", path.display()))?;
        Ok(Object::Xml {
            text,
            base_dir: path.parent().map(Path::to_path_buf).unwrap_or_default(),
            file: path.to_path_buf(),
            bsdf,
            defines,
            _assets: None,
        })
    }

    /// The scene with `panel`'s model, and the estimator to render it with.
    pub fn scene(&self, panel: &Panel) -> Result<(Scene, Integrator)> {
        match self {
            Object::Xml { text, base_dir, file, bsdf, defines, .. } => {
                let element = render::xml::export::gonio_bsdf_xml(panel.spec.name, &panel.params()?)
                    .map_err(|e| anyhow::anyhow!("model '{}' cannot go in a scene file: {e}", panel.title()))?;
                let text = render::xml::export::replace_bsdf(text, bsdf.as_deref(), &element)
                    .map_err(|e| anyhow::anyhow!("{}: {e}", file.display()))?;
                let loaded = render::xml::load_scene_str(&text, base_dir, defines)
                    .with_context(|| format!("loading '{}' with model '{}'", file.display(), panel.title()))?;
                Ok((loaded.scene, loaded.integrator))
            }
            Object::Alone { mesh, lighting, size } => {
                let scene = object_scene(panel.build()?, mesh.as_ref(), lighting, *size, *size)?;
                Ok((scene, Integrator::default()))
            }
        }
    }
}
