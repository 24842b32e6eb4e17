//! Scene files read into one tree of elements, as Mitsuba 3's parser sees them before it builds
//! anything: every attribute `$name`-substituted, `<include>`d files spliced in, `<default>`
//! and `<path>` applied, files older than version 2.0.0 upgraded.
//!
//! - `$name` is replaced in every attribute, the longest matching name first; `\$` is a dollar
//!   sign. A `<default>` applies from where it stands on; the first value of a name wins, and
//!   the caller's defines (`-D`) come before every default. A define that no attribute uses is
//!   an error, as in Mitsuba.
//! - `<include filename>` reads a file found next to the including file, then in the `<path>`
//!   folders (the latest first), then next to the top-level scene. A `<scene>` root is spliced
//!   in place of the include; any other root (a `<bsdf>`, …) becomes one child, named by the
//!   include's `name`. Includes nest up to 15 deep; a cycle is reported with the chain of files.
//! - Files a scene names (meshes, images, spectra) are found next to the file that names them,
//!   then in the `<path>` folders, then next to the top-level scene: Mitsuba 3.9.1 looks in the
//!   last two only, so every scene it opens opens the same here.
//! - Version < 2.0.0: property names go from camelCase to snake_case, `diffuse`'s
//!   `diffuse_reflectance` becomes `reflectance`, and `uoffset`/`voffset`/`uscale`/`vscale`
//!   become a `to_uv` transform (Mitsuba's upgrade).

use super::error::{Pos, XmlError};
use super::parse::pos_at;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Deepest include nesting (Mitsuba's limit).
const MAX_INCLUDE_DEPTH: usize = 15;

/// Where an element was written.
#[derive(Clone, Debug)]
pub struct Src {
    /// The file.
    pub file: Arc<PathBuf>,
    /// Line and column of the element's start.
    pub pos: Pos,
    /// The folders a file named by this element is looked for in, in order.
    pub search: Arc<Vec<PathBuf>>,
}

/// One element, its attributes substituted.
#[derive(Clone, Debug)]
pub struct Elem {
    /// The tag.
    pub tag: String,
    /// The attributes, in file order.
    pub attrs: Vec<(String, String)>,
    /// Child elements (comments and text dropped).
    pub children: Vec<Elem>,
    /// Where it was written.
    pub src: Src,
}

impl Elem {
    /// Attribute `name`.
    pub fn attr(&self, name: &str) -> Option<&str> {
        self.attrs.iter().find(|(k, _)| k == name).map(|(_, v)| v.as_str())
    }

    /// The element as a reader finds it in the file: `<shape type="ply" id="torus">`.
    pub fn describe(&self) -> String {
        let mut s = format!("<{}", self.tag);
        for a in ["type", "name", "id"] {
            if let Some(v) = self.attr(a) {
                s.push_str(&format!(" {a}=\"{v}\""));
            }
        }
        s.push('>');
        s
    }

    /// An error located at this element.
    pub fn err(&self, message: impl Into<String>) -> XmlError {
        XmlError::at(self.src.file.as_path(), self.src.pos, self.describe(), message)
    }

    /// A required attribute.
    pub fn req(&self, name: &str) -> Result<&str, XmlError> {
        self.attr(name).ok_or_else(|| self.err(format!("missing attribute '{name}'")))
    }

    /// Fails on any attribute not in `allowed`, listing the allowed ones.
    pub fn check_attrs(&self, allowed: &[&str]) -> Result<(), XmlError> {
        for (a, _) in &self.attrs {
            if !allowed.contains(&a.as_str()) {
                let list = if allowed.is_empty() { "(none)".to_string() } else { allowed.join(", ") };
                return Err(self.err(format!("unknown attribute '{a}'; accepted attributes: {list}")));
            }
        }
        Ok(())
    }

    /// A file this element names, looked for in its search folders; the first folder's path
    /// when it is found nowhere (the error then names that path).
    pub fn path(&self, written: &str) -> PathBuf {
        let p = Path::new(written);
        if p.is_absolute() {
            return p.to_path_buf();
        }
        self.src
            .search
            .iter()
            .map(|d| d.join(p))
            .find(|c| c.exists())
            .unwrap_or_else(|| self.src.search.first().map_or_else(|| p.to_path_buf(), |d| d.join(p)))
    }
}

/// The scene as read: the root element and the defines it was read with.
pub struct Tree {
    /// The root element (`<scene>`).
    pub root: Elem,
}

/// The state shared by every file of one load.
struct Reader {
    /// `$name` values, first definition wins: the caller's defines first.
    vars: Vec<(String, String)>,
    /// Of the caller's defines, the ones an attribute used.
    used: Vec<bool>,
    /// How many of `vars` came from the caller.
    defines: usize,
    /// `<path>` folders, the latest first.
    paths: Vec<PathBuf>,
    /// The top-level scene's folder.
    top: PathBuf,
    /// The chain of files being read, outermost first.
    chain: Vec<PathBuf>,
}

/// Reads scene text `text` (from `file`, relative names resolved from `dir`) and every file
/// it includes.
pub fn read(text: &str, file: &Path, dir: &Path, defines: &[(String, String)]) -> Result<Tree, XmlError> {
    let mut r = Reader {
        vars: defines.to_vec(),
        used: vec![false; defines.len()],
        defines: defines.len(),
        paths: Vec::new(),
        top: dir.to_path_buf(),
        chain: vec![file.to_path_buf()],
    };
    let root = r.document(text, file, dir)?;
    if let Some(i) = r.used.iter().position(|u| !u) {
        return Err(XmlError::file(
            file,
            format!("the parameter ${} (-D {}=...) is used nowhere in the scene", r.vars[i].0, r.vars[i].0),
        ));
    }
    Ok(Tree { root })
}

/// Mitsuba's version number "X.Y.Z" as (X, Y, Z).
fn version(text: &str) -> Option<(u32, u32, u32)> {
    let mut it = text.trim().split('.').map(|p| p.parse::<u32>().ok());
    let v = (it.next()??, it.next()??, it.next()??);
    it.next().is_none().then_some(v)
}

impl Reader {
    /// One file's root element, read and converted.
    fn document(&mut self, text: &str, file: &Path, dir: &Path) -> Result<Elem, XmlError> {
        let doc = roxmltree::Document::parse(text).map_err(|e| {
            let p = e.pos();
            XmlError {
                file: file.to_path_buf(),
                pos: Some(Pos { line: p.row, col: p.col }),
                element: None,
                message: format!("malformed XML: {e}"),
            }
        })?;
        let root = doc.root_element();
        let file_arc = Arc::new(file.to_path_buf());
        let old = match root.attribute("version") {
            None => false,
            Some(v) => match version(v) {
                Some(v) => v < (2, 0, 0),
                None => {
                    return Err(XmlError::at(
                        file,
                        pos_at(text, root.range().start),
                        format!("<{}>", root.tag_name().name()),
                        format!("version \"{v}\" is not a version number X.Y.Z, e.g. 3.0.0"),
                    ))
                }
            },
        };
        let mut e = self.element(root, text, &file_arc, dir, true)?;
        if old {
            upgrade(&mut e);
        }
        Ok(e)
    }

    /// The search folders of an element of a file in `dir`.
    fn search(&self, dir: &Path) -> Arc<Vec<PathBuf>> {
        let mut v = vec![dir.to_path_buf()];
        v.extend(self.paths.iter().cloned());
        if !v.contains(&self.top) {
            v.push(self.top.clone());
        }
        Arc::new(v)
    }

    /// Converts `node` and its children (in document order: defaults apply from where they stand).
    fn element(
        &mut self,
        node: roxmltree::Node,
        text: &str,
        file: &Arc<PathBuf>,
        dir: &Path,
        is_root: bool,
    ) -> Result<Elem, XmlError> {
        let pos = pos_at(text, node.range().start);
        let tag = node.tag_name().name().to_string();
        let mut e = Elem {
            tag,
            attrs: Vec::new(),
            children: Vec::new(),
            src: Src { file: file.clone(), pos, search: self.search(dir) },
        };
        for a in node.attributes() {
            let v = self.substitute(&e, a.value())?;
            e.attrs.push((a.name().to_string(), v));
        }
        for child in node.children().filter(roxmltree::Node::is_element) {
            match child.tag_name().name() {
                "default" => {
                    let d = self.element(child, text, file, dir, false)?;
                    d.check_attrs(&["name", "value"])?;
                    let (name, value) = (d.req("name")?.to_string(), d.req("value")?.to_string());
                    if !self.vars.iter().any(|(k, _)| *k == name) {
                        self.vars.push((name, value));
                    }
                }
                "path" => {
                    let p = self.element(child, text, file, dir, false)?;
                    if !is_root {
                        return Err(p.err("<path> can only be a child of the root element"));
                    }
                    p.check_attrs(&["value"])?;
                    let v = Path::new(p.req("value")?);
                    let folder = if v.is_absolute() { v.to_path_buf() } else { dir.join(v) };
                    if !folder.is_dir() {
                        return Err(p.err(format!("<path>: folder \"{}\" not found", folder.display())));
                    }
                    self.paths.insert(0, folder);
                }
                "include" => {
                    let inc = self.element(child, text, file, dir, false)?;
                    self.include(&inc, dir, &mut e)?;
                }
                _ => {
                    let c = self.element(child, text, file, dir, false)?;
                    e.children.push(c);
                }
            }
        }
        Ok(e)
    }

    /// Reads the file an `<include>` names and adds what it holds to `parent`.
    fn include(&mut self, inc: &Elem, dir: &Path, parent: &mut Elem) -> Result<(), XmlError> {
        inc.check_attrs(&["filename", "name"])?;
        let written = inc.req("filename")?;
        let p = Path::new(written);
        let mut candidates = vec![if p.is_absolute() { p.to_path_buf() } else { dir.join(p) }];
        if !p.is_absolute() {
            candidates.extend(self.paths.iter().map(|d| d.join(p)));
            candidates.push(self.top.join(p));
            candidates.dedup();
        }
        let Some(path) = candidates.iter().find(|c| c.is_file()).cloned() else {
            return Err(inc.err(format!(
                "included file \"{written}\" not found (looked in: {})",
                candidates.iter().map(|c| c.display().to_string()).collect::<Vec<_>>().join(", ")
            )));
        };
        let canonical = std::fs::canonicalize(&path).unwrap_or_else(|_| path.clone());
        if let Some(k) = self.chain.iter().position(|f| std::fs::canonicalize(f).is_ok_and(|c| c == canonical)) {
            let cycle: Vec<String> = self.chain[k..].iter().chain([&path]).map(|f| f.display().to_string()).collect();
            return Err(inc.err(format!("include cycle: {}", cycle.join(" → "))));
        }
        if self.chain.len() > MAX_INCLUDE_DEPTH {
            return Err(inc.err(format!("includes nest deeper than {MAX_INCLUDE_DEPTH} files")));
        }
        let text = std::fs::read_to_string(&path)
            .map_err(|e| inc.err(format!("cannot read the included file \"{}\": {e}", path.display())))?;
        let sub_dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        self.chain.push(path.clone());
        let root = self.document(&text, &path, &sub_dir);
        self.chain.pop();
        let mut root = root?;
        if root.tag == "scene" {
            parent.children.append(&mut root.children);
        } else {
            root.attrs.retain(|(k, _)| k != "version" && k != "name");
            if let Some(n) = inc.attr("name") {
                root.attrs.push(("name".into(), n.into()));
            }
            parent.children.push(root);
        }
        Ok(())
    }

    /// `raw` with `$name`s replaced (the longest name that matches first) and `\$` made `$`.
    fn substitute(&mut self, at: &Elem, raw: &str) -> Result<String, XmlError> {
        if !raw.contains('$') {
            return Ok(raw.to_string());
        }
        let mut out = String::with_capacity(raw.len());
        let mut rest = raw;
        while let Some(i) = rest.find('$') {
            if rest[..i].ends_with('\\') {
                out.push_str(&rest[..i - 1]);
                out.push('$');
                rest = &rest[i + 1..];
                continue;
            }
            out.push_str(&rest[..i]);
            let after = &rest[i + 1..];
            let best = (0..self.vars.len())
                .filter(|&k| after.starts_with(self.vars[k].0.as_str()) && !self.vars[k].0.is_empty())
                .max_by_key(|&k| self.vars[k].0.len());
            let Some(k) = best else {
                let len = after.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(after.len());
                let name = &after[..len];
                return Err(at.err(format!(
                    "parameter '${name}' has no value: give it on the command line (-D {name}=...) \
                     or declare <default name=\"{name}\" value=\"...\"/> in the scene before it is used"
                )));
            };
            if k < self.defines {
                self.used[k] = true;
            }
            out.push_str(&self.vars[k].1);
            rest = &after[self.vars[k].0.len()..];
        }
        out.push_str(rest);
        Ok(out)
    }
}

/// Mitsuba's upgrade of a file older than 2.0.0, applied to every element.
fn upgrade(e: &mut Elem) {
    for (k, v) in &mut e.attrs {
        if k == "name" {
            *v = snake_case(v);
        }
    }
    for c in &mut e.children {
        upgrade(c);
    }
    if e.tag == "bsdf" && e.attr("type") == Some("diffuse") {
        for c in &mut e.children {
            for (k, v) in &mut c.attrs {
                if k == "name" && v == "diffuse_reflectance" {
                    *v = "reflectance".into();
                }
            }
        }
    }
    let mut uv: HashMap<String, String> = HashMap::new();
    for c in &e.children {
        if let (Some(n @ ("uoffset" | "voffset" | "uscale" | "vscale")), Some(v)) = (c.attr("name"), c.attr("value")) {
            uv.insert(n.to_string(), v.to_string());
        }
    }
    if !uv.is_empty() {
        let src = e.src.clone();
        e.children.retain(|c| !matches!(c.attr("name"), Some("uoffset" | "voffset" | "uscale" | "vscale")));
        let op = |tag: &str, x: &str, y: &str, z: &str| Elem {
            tag: tag.into(),
            attrs: vec![("x".into(), x.into()), ("y".into(), y.into()), ("z".into(), z.into())],
            children: Vec::new(),
            src: src.clone(),
        };
        let get = |k: &str, d: &str| uv.get(k).cloned().unwrap_or_else(|| d.to_string());
        e.children.push(Elem {
            tag: "transform".into(),
            attrs: vec![("name".into(), "to_uv".into())],
            children: vec![
                op("translate", &get("uoffset", "0"), &get("voffset", "0"), "0"),
                op("scale", &get("uscale", "1"), &get("vscale", "1"), "1"),
            ],
            src: src.clone(),
        });
    }
}

/// Mitsuba's camelCase → snake_case: an `_` before an upper-case letter that follows a
/// lower-case one, and the run of upper-case letters lowered (intIOR → int_ior).
fn snake_case(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 4);
    let mut prev_lower = false;
    let mut in_upper_run = false;
    for c in s.chars() {
        if c.is_ascii_uppercase() {
            if prev_lower {
                out.push('_');
                in_upper_run = true;
            }
            if in_upper_run {
                out.push(c.to_ascii_lowercase());
            } else {
                out.push(c);
            }
            prev_lower = false;
        } else {
            in_upper_run = false;
            prev_lower = c.is_ascii_lowercase();
            out.push(c);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mitsubas_snake_case_upgrade() {
        for (a, b) in [
            ("intIOR", "int_ior"),
            ("extIOR", "ext_ior"),
            ("sampleCount", "sample_count"),
            ("toWorld", "to_world"),
            ("maxDepth", "max_depth"),
            ("sRGB", "s_rgb"),
            ("aBC", "a_bc"),
            ("x_yZ", "x_y_z"),
            ("ABCdef", "ABCdef"),
            ("radius", "radius"),
        ] {
            assert_eq!(snake_case(a), b, "{a}");
        }
        assert_eq!(version("3.0.0"), Some((3, 0, 0)));
        assert_eq!(version("3.0"), None);
        assert!(version("0.6.0").unwrap() < (2, 0, 0));
    }
}
