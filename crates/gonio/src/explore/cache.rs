//! Loaded files kept by name (tables, meshes, probes), so that dragging a knob does not read
//! them again; cleared whole when full, since a page uses a handful at a time.

use super::http::ApiError;
use std::collections::HashMap;
use std::sync::Mutex;

/// Up to `N` values by key.
#[derive(Debug)]
pub struct Cache<T, const N: usize>(Mutex<HashMap<String, T>>);

impl<T, const N: usize> Default for Cache<T, N> {
    fn default() -> Self {
        Cache(Mutex::new(HashMap::new()))
    }
}

impl<T: Clone, const N: usize> Cache<T, N> {
    /// Keeps `value` under `key`.
    pub fn insert(&self, key: String, value: T) {
        let mut m = self.0.lock().unwrap_or_else(|e| e.into_inner());
        if m.len() >= N {
            m.clear();
        }
        m.insert(key, value);
    }

    /// The value under `key`, made by `make` (outside the lock) when absent.
    pub fn get_or(&self, key: &str, make: impl FnOnce() -> Result<T, ApiError>) -> Result<T, ApiError> {
        if let Some(v) = self.0.lock().unwrap_or_else(|e| e.into_inner()).get(key) {
            return Ok(v.clone());
        }
        let v = make()?;
        self.insert(key.to_string(), v.clone());
        Ok(v)
    }
}
