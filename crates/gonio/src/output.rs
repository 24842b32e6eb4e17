//! Writing output files: atomically (a temporary file in the same folder, then a rename, so a
//! reader never sees half a file), and never over one of the command's inputs.

use anyhow::{bail, Context, Result};
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The output formats, chosen by file extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Scalable vector graphics, written as text.
    Svg,
    /// A PNG raster.
    Png,
}

impl Format {
    /// The format a path's extension names, or an error listing the valid ones.
    pub fn from_path(path: &Path) -> Result<Format> {
        match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
            Some("svg") => Ok(Format::Svg),
            Some("png") => Ok(Format::Png),
            _ => bail!("cannot tell the format of '{}': the output must end in .svg or .png", path.display()),
        }
    }
}

/// Writes `bytes` to `path` atomically, refusing to replace any of `inputs`.
pub fn write_atomic(path: &Path, bytes: &[u8], inputs: &[PathBuf]) -> Result<()> {
    if path.is_dir() {
        bail!("'{}' is a folder, not a file", path.display());
    }
    if let Ok(out) = fs::canonicalize(path) {
        for input in inputs {
            if fs::canonicalize(input).map(|i| i == out).unwrap_or(false) {
                bail!("refusing to overwrite the input '{}' with output", path.display());
            }
        }
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = path.file_name().with_context(|| format!("'{}' names no file", path.display()))?;
    let tmp = dir.join(format!(".{}.{}.tmp", name.to_string_lossy(), std::process::id()));
    let result = (|| -> std::io::Result<()> {
        let mut f = fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        fs::rename(&tmp, path)
    })();
    if let Err(e) = result {
        let _ = fs::remove_file(&tmp);
        return Err(e).with_context(|| format!("cannot write '{}'", path.display()));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_replace_whole_files_and_spare_inputs() {
        let dir = std::env::temp_dir().join(format!("gonio-output-test-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let p = dir.join("a.svg");
        write_atomic(&p, b"first", &[]).unwrap();
        write_atomic(&p, b"second", &[]).unwrap();
        assert_eq!(fs::read(&p).unwrap(), b"second");
        let e = write_atomic(&p, b"third", &[dir.join(".").join("a.svg")]).unwrap_err().to_string();
        assert!(e.contains("refusing"), "{e}");
        assert_eq!(fs::read(&p).unwrap(), b"second");
        assert!(write_atomic(&dir.join("missing").join("b.svg"), b"x", &[]).is_err());
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 1, "no temporary file left behind");
        fs::remove_dir_all(&dir).unwrap();
        assert_eq!(Format::from_path(Path::new("x.PNG")).unwrap(), Format::Png);
        assert!(Format::from_path(Path::new("x.pdf")).unwrap_err().to_string().contains(".svg or .png"));
    }
}
