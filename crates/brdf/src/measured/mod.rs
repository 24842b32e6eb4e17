//! Measured reflectance: the MERL binary format (`merl`), a plain-text gonio-reflectometer table
//! (`tabulated`), the sampler of tabulated data (`sampling`), and the `merl` model that renders
//! and checks a MERL file like any analytic model.
//!
//! The `merl` model: ρ(wi, wo) = the MERL table at the half/difference angles of (wi, wo),
//! trilinearly interpolated between entries (`interpolation = linear`, the default) or read as the
//! reference reader does (`nearest`). Sampling draws from per-θo piecewise-constant tables of
//! ρ·cos θi mixed with cosine sampling (see `sampling`).
//! Source: W. Matusik, H. Pfister, M. Brand, L. McMillan, "A Data-Driven Reflectance Model",
//! SIGGRAPH 2003; format as in the MERL BRDF database's `BRDFRead.cpp`.
//!
//! Claims: reciprocal (the lookup is symmetric by construction) and isotropic (the table is);
//! energy conservation is not claimed, since measured data carries no such guarantee (`check`
//! still measures it).

pub mod error;
pub mod heightfield;
pub mod merl;
pub mod microsurface;
pub mod sampling;
pub mod tabulated;
pub mod tabulated_model;

pub use error::MeasuredError;
pub use merl::MerlTable;
pub use sampling::TableSampler;
pub use tabulated::Tabulated;
pub use tabulated_model::TabulatedBrdf;

use crate::model::{same_upper_hemisphere, Brdf, BrdfSample, Claims};
use crate::params::{ParamError, ParamSource, ParamSpec};
use crate::registry::ModelSpec;
use radiometry::{Rgb, Vec2, Vec3};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::SystemTime;

/// Writes `bytes` to `path` through a temporary file in the same folder and a rename.
pub(crate) fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), MeasuredError> {
    use std::io::Write;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let tmp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    let result = (|| -> std::io::Result<()> {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    result.map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        MeasuredError::io(path, e)
    })
}

/// A MERL table with its sampler, shared between models built from the same file.
#[derive(Debug)]
pub struct MerlData {
    /// The table.
    pub table: MerlTable,
    /// The sampling distributions built from it.
    pub sampler: TableSampler,
}

impl MerlData {
    /// Builds the sampler for a table.
    pub fn new(table: MerlTable) -> Self {
        let sampler = TableSampler::build(&|wi, wo| {
            let c = table.lookup(wi, wo);
            c.0[0] + c.0[1] + c.0[2]
        });
        MerlData { table, sampler }
    }
}

/// How `eval` reads the table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    /// Trilinear between entries.
    Linear,
    /// The entry whose interval holds the point (the reference reader).
    Nearest,
}

/// A measured BRDF read from a MERL file.
#[derive(Clone, Debug)]
pub struct Merl {
    /// The table and its sampler.
    pub data: Arc<MerlData>,
    /// How `eval` reads the table.
    pub interpolation: Interpolation,
}

impl Merl {
    /// A model from an in-memory table.
    pub fn from_table(table: MerlTable, interpolation: Interpolation) -> Self {
        Merl { data: Arc::new(MerlData::new(table)), interpolation }
    }

    /// Loads `path` (or reuses it from the cache when the file is unchanged).
    pub fn open(path: &Path, interpolation: Interpolation) -> Result<Self, MeasuredError> {
        Ok(Merl { data: load_cached(path)?, interpolation })
    }
}

impl Brdf for Merl {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if !same_upper_hemisphere(wi, wo) {
            return Rgb::ZERO;
        }
        match self.interpolation {
            Interpolation::Linear => self.data.table.lookup(wi, wo),
            Interpolation::Nearest => self.data.table.lookup_nearest(wi, wo),
        }
    }

    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        self.data.sampler.pdf(wi, wo)
    }

    fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BrdfSample> {
        self.data.sampler.sample_brdf(self, wo, uc, u)
    }

    fn claims(&self) -> Claims {
        Claims { reciprocal: true, energy_conserving: false, isotropic: true }
    }
}

/// Key of a cached file: where it is, its size and modification time.
type CacheKey = (PathBuf, u64, Option<SystemTime>);

/// Files kept loaded; a MERL table with its sampler takes ~20 MB.
const CACHE_FILES: usize = 8;

fn cache() -> &'static Mutex<HashMap<CacheKey, Arc<MerlData>>> {
    static CACHE: std::sync::OnceLock<Mutex<HashMap<CacheKey, Arc<MerlData>>>> = std::sync::OnceLock::new();
    CACHE.get_or_init(|| Mutex::new(HashMap::new()))
}

/// Loads a MERL file once per (path, size, mtime): a scene that names one file for many
/// objects, or a check that builds the model repeatedly, reads the 35 MB only once.
pub fn load_cached(path: &Path) -> Result<Arc<MerlData>, MeasuredError> {
    let meta = std::fs::metadata(path).map_err(|e| MeasuredError::io(path, e))?;
    let canon = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
    let key = (canon, meta.len(), meta.modified().ok());
    if let Some(d) = cache().lock().unwrap_or_else(|e| e.into_inner()).get(&key) {
        return Ok(d.clone());
    }
    let data = Arc::new(MerlData::new(MerlTable::read(path)?));
    let mut c = cache().lock().unwrap_or_else(|e| e.into_inner());
    if c.len() >= CACHE_FILES {
        c.clear();
    }
    c.insert(key, data.clone());
    Ok(data)
}

fn params() -> Vec<ParamSpec> {
    vec![
        ParamSpec::path("filename", "the MERL .binary file (90 θh × 90 θd × 180 φd, float64 RGB)"),
        ParamSpec::choice(
            "interpolation",
            &["linear", "nearest"],
            "linear",
            "trilinear between table entries, or the reference reader's nearest entry",
        ),
    ]
}

/// Opens, with `open`, the file that file-backed model `model` names in its `filename`
/// parameter; `example` says what to give when it is missing, `kind` names the file in a load
/// error.
pub(crate) fn open_filename<T, E: std::fmt::Display>(
    p: &dyn ParamSource,
    model: &str,
    example: &str,
    kind: &str,
    open: impl FnOnce(&Path) -> Result<T, E>,
) -> Result<T, ParamError> {
    let file = p.path("filename");
    if file.is_empty() {
        return Err(ParamError::Inconsistent(format!("model '{model}' needs a file: give --filename {example}")));
    }
    open(Path::new(file))
        .map_err(|e| ParamError::Inconsistent(format!("parameter 'filename': cannot load the {kind} file {e}")))
}

fn build(p: &dyn ParamSource) -> Result<Box<dyn Brdf>, ParamError> {
    let interpolation =
        if p.choice("interpolation") == "nearest" { Interpolation::Nearest } else { Interpolation::Linear };
    let m = open_filename(p, "merl", "FILE.binary (a MERL BRDF file)", "MERL", |f| Merl::open(f, interpolation))?;
    Ok(Box::new(m))
}

/// Registry entry.
pub const SPEC: ModelSpec = ModelSpec {
    name: "merl",
    summary: "measured BRDF from a MERL .binary file, interpolated",
    reference: "Matusik et al. 2003, A Data-Driven Reflectance Model",
    params,
    build: crate::registry::boxed!(build),
    showcase: &[],
};
