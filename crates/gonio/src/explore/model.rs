//! A model the page names, `NAME[:PARAM=VALUE]...` as on the command line (`ggx:alpha=0.3`),
//! checked against the registry and built; measured models read their file only from the data
//! folders or the uploads, and keep the table so that it can be fitted.

use super::cache::Cache;
use super::files::{Files, Source};
use super::http::ApiError;
use crate::modelarg::ModelArg;
use brdf::fit::{self, Sample};
use brdf::measured::{Interpolation, Merl, MerlData, MerlTable, Tabulated, TabulatedBrdf};
use brdf::{Brdf, ParamKind};
use std::path::Path;
use std::sync::Arc;

/// Measured data behind a model.
#[derive(Clone, Debug)]
pub enum Measured {
    /// A MERL table with its sampler.
    Merl(Arc<MerlData>),
    /// A tabulated file as a model.
    Tabulated(TabulatedBrdf),
}

impl Measured {
    /// Samples to fit: `n` entries of a MERL table, or every tabulated point.
    pub fn samples(&self, n: usize, seed: u64) -> Vec<Sample> {
        match self {
            Measured::Merl(d) => fit::merl_samples(&d.table, n, seed),
            Measured::Tabulated(t) => fit::tabulated_samples(&t.table),
        }
    }
}

/// A model resolved and built.
#[derive(Clone, Debug)]
pub struct Resolved {
    /// The model and the parameters given.
    pub arg: ModelArg,
    /// The built model.
    pub brdf: Arc<dyn Brdf>,
    /// The data, for a measured model.
    pub measured: Option<Measured>,
}

/// Tables read, by file identity, so a slider move does not reread 35 MB.
pub type TableCache = Cache<Measured, 6>;

fn source_key(name: &str, src: &Source) -> String {
    match src {
        Source::Upload(_) => name.to_string(),
        Source::Disk(p) => {
            let meta = std::fs::metadata(p).ok();
            format!("{}|{:?}|{:?}", p.display(), meta.as_ref().map(|m| m.len()), meta.and_then(|m| m.modified().ok()))
        }
    }
}

/// Parses the measured data `src` (named `name`) for model `model` (`merl` or `tabulated`).
pub fn read_measured(model: &str, name: &str, src: &Source) -> Result<Measured, ApiError> {
    let bytes = src.read("filename")?;
    let shown = Path::new(name);
    let bad = |e: brdf::measured::MeasuredError| ApiError::new(400, e.to_string()).named("filename");
    Ok(if model == "merl" {
        Measured::Merl(Arc::new(MerlData::new(MerlTable::parse(&bytes, shown).map_err(bad)?)))
    } else {
        let text = std::str::from_utf8(&bytes).map_err(|_| {
            ApiError::new(400, format!("'{name}' is not UTF-8 text, so not a tabulated file")).named("filename")
        })?;
        Measured::Tabulated(TabulatedBrdf::new(Tabulated::parse(text, shown).map_err(bad)?))
    })
}

/// Parses and builds `item` (query parameter `param`).
pub fn resolve(files: &Files, tables: &TableCache, param: &str, item: &str) -> Result<Resolved, ApiError> {
    let arg = ModelArg::parse_item(item).map_err(|e| ApiError::from(e).or_param(param))?;
    // The registry keeps the last of repeated values; the file read must be the one it names.
    if let Some((k, _)) =
        arg.given.iter().enumerate().find(|(i, (k, _))| arg.given[..*i].iter().any(|(j, _)| j == k)).map(|(_, kv)| kv)
    {
        return Err(ApiError::new(400, format!("parameter '{k}' is given twice in '{item}'; give it once")).named(k));
    }
    let specs = (arg.spec.params)();
    let path_given = |name: &str| arg.given.iter().find(|(k, _)| k == name).map(|(_, v)| v.clone());
    let file_param = specs.iter().find(|s| s.kind == ParamKind::Path);
    let Some(file_param) = file_param else {
        let brdf: Arc<dyn Brdf> = Arc::from(arg.build().map_err(|e| ApiError::from(e).or_param(param))?);
        return Ok(Resolved { arg, brdf, measured: None });
    };
    let name = path_given(file_param.name).filter(|v| !v.is_empty()).ok_or_else(|| {
        ApiError::new(
            400,
            format!(
                "model '{}' needs a file: give {}=FILE (open one from the data folders or upload it)",
                arg.spec.name, file_param.name
            ),
        )
        .named(file_param.name)
    })?;
    let src = files.resolve(file_param.name, &name)?;
    let measured = tables.get_or(&source_key(&name, &src), || read_measured(arg.spec.name, &name, &src))?;
    let brdf: Arc<dyn Brdf> = match &measured {
        Measured::Merl(data) => {
            let nearest = arg.resolved()?.iter().any(|(k, v)| k == "interpolation" && v.to_string() == "nearest");
            let interpolation = if nearest { Interpolation::Nearest } else { Interpolation::Linear };
            Arc::new(Merl { data: data.clone(), interpolation })
        }
        Measured::Tabulated(t) => Arc::new(t.clone()),
    };
    Ok(Resolved { arg, brdf, measured: Some(measured) })
}

/// Every `m=` of a query resolved; at least one.
pub fn resolve_all(files: &Files, tables: &TableCache, items: &[&str]) -> Result<Vec<Resolved>, ApiError> {
    if items.is_empty() {
        return Err(
            ApiError::new(400, "give at least one model: m=NAME[:PARAM=VALUE]..., e.g. m=ggx:alpha=0.3").named("m")
        );
    }
    items.iter().map(|i| resolve(files, tables, "m", i)).collect()
}
