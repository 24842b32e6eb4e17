//! The small HTTP vocabulary of the explorer's API: query strings, JSON replies and errors that
//! say which parameter was wrong and what would be right.

use brdf::ParamError;
use std::io::Cursor;
use tiny_http::{Header, Response};

/// A reply body held in memory.
pub type Reply = Response<Cursor<Vec<u8>>>;

/// A request's decoded `?a=1&b=2` pairs, in order (a key may repeat: `m=…&m=…`).
#[derive(Clone, Debug, Default)]
pub struct Query(pub Vec<(String, String)>);

/// `%41` and `+` decoded; malformed escapes are kept as written.
fn decode(s: &str) -> String {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b'+' => out.push(b' '),
            b'%' if i + 2 < b.len() => {
                match std::str::from_utf8(&b[i + 1..i + 3]).ok().and_then(|h| u8::from_str_radix(h, 16).ok()) {
                    Some(v) => {
                        out.push(v);
                        i += 2;
                    }
                    None => out.push(b'%'),
                }
            }
            c => out.push(c),
        }
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

impl Query {
    /// Splits a URL into its path and query.
    pub fn split(url: &str) -> (String, Query) {
        let (path, q) = url.split_once('?').unwrap_or((url, ""));
        let pairs = q
            .split('&')
            .filter(|p| !p.is_empty())
            .map(|p| {
                let (k, v) = p.split_once('=').unwrap_or((p, ""));
                (decode(k), decode(v))
            })
            .collect();
        (decode(path), Query(pairs))
    }

    /// The first value of `key`.
    pub fn get(&self, key: &str) -> Option<&str> {
        self.0.iter().find(|(k, _)| k == key).map(|(_, v)| v.as_str())
    }

    /// Every value of `key`, in order.
    pub fn all(&self, key: &str) -> Vec<&str> {
        self.0.iter().filter(|(k, _)| k == key).map(|(_, v)| v.as_str()).collect()
    }

    /// A number in [min, max], `default` when absent.
    pub fn number(&self, key: &str, min: f64, max: f64, default: f64) -> Result<f64, ApiError> {
        let Some(text) = self.get(key) else { return Ok(default) };
        match text.trim().parse::<f64>() {
            Ok(v) if v.is_finite() && (min..=max).contains(&v) => Ok(v),
            _ => Err(ApiError::param(key, text, &format!("a number in [{min}, {max}]"))),
        }
    }

    /// A stream name (`stream=`): absent, or not empty.
    pub fn stream(&self) -> Result<Option<&str>, ApiError> {
        match self.get("stream") {
            Some("") => Err(ApiError::param("stream", "", "a non-empty name")),
            other => Ok(other),
        }
    }

    /// A value that must be present.
    pub fn required(&self, key: &str, what: &str) -> Result<&str, ApiError> {
        self.get(key).ok_or_else(|| ApiError::new(400, format!("missing query parameter '{key}': {what}")).named(key))
    }
}

/// An API failure: the HTTP status and a JSON body `{error, parameter?, expected?}`.
#[derive(Clone, Debug, PartialEq)]
pub struct ApiError {
    /// HTTP status: 400 bad input, 403 outside the data folders, 404, 413 too large, 500.
    pub status: u16,
    /// What was wrong, in words.
    pub message: String,
    /// The query or model parameter at fault.
    pub parameter: Option<String>,
    /// What would have been right.
    pub expected: Option<String>,
}

impl ApiError {
    /// An error with a status and a message.
    pub fn new(status: u16, message: impl Into<String>) -> Self {
        ApiError { status, message: message.into(), parameter: None, expected: None }
    }

    /// A bad query parameter value.
    pub fn param(name: &str, value: &str, expected: &str) -> Self {
        ApiError {
            status: 400,
            message: format!("parameter '{name}': '{value}' is not valid; expected {expected}"),
            parameter: Some(name.into()),
            expected: Some(expected.into()),
        }
    }

    /// Names `param` when no parameter is named yet.
    pub fn or_param(mut self, param: &str) -> Self {
        if self.parameter.is_none() {
            self.parameter = Some(param.into());
        }
        self
    }

    /// The same error, naming `parameter`.
    pub fn named(mut self, parameter: &str) -> Self {
        self.parameter = Some(parameter.into());
        self
    }

    /// The reply.
    pub fn reply(&self) -> Reply {
        let mut body = serde_json::json!({ "error": self.message });
        if let Some(p) = &self.parameter {
            body["parameter"] = p.as_str().into();
        }
        if let Some(e) = &self.expected {
            body["expected"] = e.as_str().into();
        }
        json(self.status, &body)
    }
}

impl From<ParamError> for ApiError {
    fn from(e: ParamError) -> Self {
        let message = e.to_string();
        match e {
            ParamError::BadValue { name, expected, .. } => {
                ApiError { status: 400, message, parameter: Some(name), expected: Some(expected) }
            }
            ParamError::UnknownParam { name, valid, .. } => {
                ApiError { status: 400, message, parameter: Some(name), expected: Some(valid) }
            }
            ParamError::UnknownModel { valid, .. } => {
                ApiError { status: 400, message, parameter: Some("model".into()), expected: Some(valid) }
            }
            ParamError::Inconsistent(_) => ApiError::new(400, message),
        }
    }
}

impl From<anyhow::Error> for ApiError {
    fn from(e: anyhow::Error) -> Self {
        match e.downcast::<ParamError>() {
            Ok(p) => p.into(),
            Err(e) => ApiError::new(400, format!("{e:#}")),
        }
    }
}

/// The direction `key`=x,y,z (normalised), as `gonio eval` reads it.
pub fn direction(q: &Query, key: &str) -> Result<radiometry::Vec3, ApiError> {
    let text = q.required(key, "a direction x,y,z")?;
    crate::cmd::eval::parse_direction(key, text)
        .map_err(|_| ApiError::param(key, text, "three finite numbers x,y,z, not all zero"))
}

/// A header from constant parts.
pub fn header(name: &str, value: &str) -> Header {
    Header::from_bytes(name.as_bytes(), value.as_bytes()).expect("constant header text is valid")
}

/// A reply of `bytes` with a content type; nothing the API serves may be cached.
pub fn bytes(status: u16, content_type: &str, body: Vec<u8>) -> Reply {
    Response::from_data(body)
        .with_status_code(status)
        .with_header(header("Content-Type", content_type))
        .with_header(header("Cache-Control", "no-store"))
}

/// A JSON reply.
pub fn json(status: u16, value: &serde_json::Value) -> Reply {
    bytes(status, "application/json", value.to_string().into_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn queries_decode_and_keep_repeated_keys() {
        let (path, q) = Query::split("/api/views?m=ggx%3Aalpha%3D0.3&m=lambert&x=a+b&bad=%zz&end=%4");
        assert_eq!(path, "/api/views");
        assert_eq!(q.all("m"), vec!["ggx:alpha=0.3", "lambert"]);
        assert_eq!(q.get("x"), Some("a b"));
        assert_eq!(q.get("bad"), Some("%zz"));
        assert_eq!(q.get("end"), Some("%4"));
        let e = q.number("x", 0.0, 1.0, 0.5).unwrap_err();
        assert_eq!((e.status, e.parameter.as_deref()), (400, Some("x")));
        assert_eq!(q.number("absent", 0.0, 1.0, 0.5), Ok(0.5));
    }
}
