//! The files the page may read: only below the folders given with `--data`, plus what the user
//! uploaded (kept in memory, size-limited, under the name `upload/N/NAME`).

use super::http::ApiError;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// What a file holds, by its extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A MERL `.binary` table.
    Merl,
    /// A tabulated `.csv`/`.txt` table.
    Tabulated,
    /// An `.obj` or `.ply` mesh.
    Mesh,
    /// An `.hdr` or `.exr` light probe.
    Probe,
}

impl Kind {
    /// The kind a file name's extension says, if any.
    pub fn of(name: &str) -> Option<Kind> {
        let ext = Path::new(name).extension()?.to_str()?.to_ascii_lowercase();
        Some(match ext.as_str() {
            "binary" => Kind::Merl,
            "csv" | "txt" => Kind::Tabulated,
            "obj" | "ply" => Kind::Mesh,
            "hdr" | "exr" => Kind::Probe,
            _ => return None,
        })
    }

    /// Its name in the API.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Merl => "merl",
            Kind::Tabulated => "tabulated",
            Kind::Mesh => "mesh",
            Kind::Probe => "probe",
        }
    }
}

/// Where a named file's bytes are.
#[derive(Clone, Debug)]
pub enum Source {
    /// A file below a data folder (canonical path).
    Disk(PathBuf),
    /// An uploaded file.
    Upload(Arc<Vec<u8>>),
}

/// The data folders and the uploads.
#[derive(Debug, Default)]
pub struct Files {
    roots: Vec<PathBuf>,
    uploads: Mutex<BTreeMap<u64, Upload>>,
    next: Mutex<u64>,
    /// The largest upload accepted, in bytes.
    pub upload_limit: u64,
}

/// An uploaded file: its name and bytes.
type Upload = (String, Arc<Vec<u8>>);

/// Uploads kept; older ones are dropped (a MERL table is 35 MB).
const KEPT_UPLOADS: usize = 6;
/// Entries a listing visits at most, so a huge folder cannot stall the page.
const LIST_LIMIT: usize = 5000;
/// Folder depth a listing descends to.
const LIST_DEPTH: usize = 4;

impl Files {
    /// The folders `--data` named (each must exist).
    pub fn new(dirs: &[PathBuf], upload_limit: u64) -> anyhow::Result<Self> {
        let mut roots = Vec::new();
        for d in dirs {
            let c = std::fs::canonicalize(d)
                .map_err(|e| anyhow::anyhow!("--data '{}': {e}; give an existing folder", d.display()))?;
            if !c.is_dir() {
                anyhow::bail!("--data '{}' is not a folder", d.display());
            }
            roots.push(c);
        }
        Ok(Files { roots, upload_limit, ..Default::default() })
    }

    /// The data folders.
    pub fn roots(&self) -> &[PathBuf] {
        &self.roots
    }

    /// Resolves a name the page sent (`upload/N/NAME`, a path relative to a data folder, or an
    /// absolute path below one) for query or model parameter `param`.
    pub fn resolve(&self, param: &str, name: &str) -> Result<Source, ApiError> {
        if let Some(rest) = name.strip_prefix("upload/") {
            let id = rest.split('/').next().and_then(|n| n.parse::<u64>().ok());
            let found = id.and_then(|id| self.uploads.lock().unwrap_or_else(|e| e.into_inner()).get(&id).cloned());
            return found.map(|(_, b)| Source::Upload(b)).ok_or_else(|| {
                ApiError::new(
                    404,
                    format!(
                        "no upload '{name}' (uploads are kept only while the server runs, the last {KEPT_UPLOADS})"
                    ),
                )
                .named(param)
            });
        }
        if self.roots.is_empty() {
            return Err(ApiError::new(
                403,
                format!("cannot open '{name}': no data folder was given; start `gonio explore --data DIR` or upload the file"),
            )
            .named(param));
        }
        let p = Path::new(name);
        let candidates: Vec<PathBuf> =
            if p.is_absolute() { vec![p.to_path_buf()] } else { self.roots.iter().map(|r| r.join(p)).collect() };
        for c in &candidates {
            if let Ok(canon) = std::fs::canonicalize(c) {
                if !self.roots.iter().any(|r| canon.starts_with(r)) {
                    return Err(self.outside(param, name));
                }
                if canon.is_file() {
                    return Ok(Source::Disk(canon));
                }
            }
        }
        if p.is_absolute() && !self.roots.iter().any(|r| p.starts_with(r)) {
            return Err(self.outside(param, name));
        }
        Err(ApiError::new(404, format!("no file '{name}' in the data folders ({})", self.roots_text())).named(param))
    }

    fn roots_text(&self) -> String {
        self.roots.iter().map(|r| r.display().to_string()).collect::<Vec<_>>().join(", ")
    }

    fn outside(&self, param: &str, name: &str) -> ApiError {
        ApiError::new(
            403,
            format!(
                "'{name}' is outside the folders given with --data ({}); only files below them can be opened",
                self.roots_text()
            ),
        )
        .named(param)
    }

    /// Keeps an upload; returns its name `upload/N/NAME`.
    pub fn add_upload(&self, name: &str, bytes: Arc<Vec<u8>>) -> String {
        let mut next = self.next.lock().unwrap_or_else(|e| e.into_inner());
        *next += 1;
        let id = *next;
        let clean: String = name
            .chars()
            .map(|c| if c.is_ascii_alphanumeric() || matches!(c, '.' | '-' | '_') { c } else { '_' })
            .collect();
        let mut up = self.uploads.lock().unwrap_or_else(|e| e.into_inner());
        up.insert(id, (clean.clone(), bytes));
        while up.len() > KEPT_UPLOADS {
            let first = *up.keys().next().expect("not empty");
            up.remove(&first);
        }
        format!("upload/{id}/{clean}")
    }

    /// Every file of a known kind below the data folders, as (name relative to its folder, kind).
    pub fn list(&self) -> Vec<(String, Kind)> {
        let mut out = Vec::new();
        let mut visited = 0;
        for root in &self.roots {
            let mut stack = vec![(root.clone(), 0usize)];
            while let Some((dir, depth)) = stack.pop() {
                let Ok(entries) = std::fs::read_dir(&dir) else { continue };
                // Symbolic links are not followed: a listing shows only what can be opened.
                let mut entries: Vec<_> = entries
                    .flatten()
                    .filter(|e| e.file_type().is_ok_and(|t| !t.is_symlink()))
                    .map(|e| e.path())
                    .collect();
                entries.sort();
                for p in entries {
                    visited += 1;
                    if visited > LIST_LIMIT {
                        return out;
                    }
                    let name = p.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
                    if name.starts_with('.') {
                        continue;
                    }
                    if p.is_dir() {
                        if depth + 1 < LIST_DEPTH {
                            stack.push((p, depth + 1));
                        }
                    } else if let Some(kind) = Kind::of(&name) {
                        let rel = p.strip_prefix(root).unwrap_or(&p).to_string_lossy().into_owned();
                        out.push((if self.roots.len() > 1 { p.to_string_lossy().into_owned() } else { rel }, kind));
                    }
                }
            }
        }
        out
    }
}

impl Source {
    /// The bytes, read whole (`param` is the parameter named in errors).
    pub fn read(&self, param: &str) -> Result<Arc<Vec<u8>>, ApiError> {
        match self {
            Source::Upload(b) => Ok(b.clone()),
            Source::Disk(p) => std::fs::read(p)
                .map(Arc::new)
                .map_err(|e| ApiError::new(404, format!("cannot read '{}': {e}", p.display())).named(param)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_are_confined_to_the_data_folders() {
        let base = std::env::temp_dir().join(format!("gonio-files-{}", std::process::id()));
        let data = base.join("data");
        std::fs::create_dir_all(data.join("sub")).unwrap();
        std::fs::write(data.join("sub/a.binary"), b"x").unwrap();
        std::fs::write(base.join("secret.csv"), b"x").unwrap();
        let f = Files::new(std::slice::from_ref(&data), 10).unwrap();
        assert!(matches!(f.resolve("m", "sub/a.binary"), Ok(Source::Disk(_))));
        assert!(matches!(f.resolve("m", data.join("sub/a.binary").to_str().unwrap()), Ok(Source::Disk(_))));
        for bad in ["../secret.csv", base.join("secret.csv").to_str().unwrap(), "/etc/passwd"] {
            let e = f.resolve("m", bad).unwrap_err();
            assert_eq!(e.status, 403, "{bad}: {e:?}");
            assert!(e.message.contains("--data"), "{}", e.message);
        }
        assert_eq!(f.resolve("m", "nosuch.binary").unwrap_err().status, 404);
        assert_eq!(f.list(), vec![("sub/a.binary".to_string(), Kind::Merl)]);
        let name = f.add_upload("my file.csv", Arc::new(vec![1, 2]));
        assert_eq!(name, "upload/1/my_file.csv");
        assert!(matches!(f.resolve("m", &name), Ok(Source::Upload(b)) if b.len() == 2));
        assert_eq!(f.resolve("m", "upload/9/x").unwrap_err().status, 404);
        let _ = std::fs::remove_dir_all(&base);
    }
}
