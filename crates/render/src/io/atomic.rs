//! Atomic file output: write a temporary file in the destination's directory, then rename
//! it over the destination, so a reader never sees a half-written image.

use crate::error::{Error, Result};
use std::path::{Path, PathBuf};

/// The temporary path beside `path` (same directory, so the rename stays on one file system).
fn temp_path(path: &Path) -> PathBuf {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let tmp = format!(".{name}.{}.tmp", std::process::id());
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir.join(tmp),
        _ => PathBuf::from(tmp),
    }
}

/// Calls `write` with a temporary path beside `path`, then renames the result to `path`;
/// the temporary file is removed if `write` fails.
pub fn write_atomically(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    let tmp = temp_path(path);
    let result = write(&tmp).and_then(|()| std::fs::rename(&tmp, path).map_err(|e| Error::io(path, e)));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}
