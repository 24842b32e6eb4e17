//! What can be wrong with a measured-data file; every message names the file.

use std::path::PathBuf;

/// A measured-data file that cannot be read or written, and why.
#[derive(Debug, thiserror::Error)]
pub enum MeasuredError {
    /// The operating system refused (missing file, permissions, disk full).
    #[error("'{path}': {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// What the system said.
        #[source]
        source: std::io::Error,
    },
    /// Fewer or more bytes than the header's dimensions call for.
    #[error("'{path}': {what}: expected {expected} bytes for a {dims} MERL table, found {found}")]
    Size {
        /// The file.
        path: PathBuf,
        /// "truncated" or "trailing bytes".
        what: &'static str,
        /// Bytes a full table takes.
        expected: u64,
        /// Bytes the file holds.
        found: u64,
        /// The dimensions, written "90 × 90 × 180".
        dims: String,
    },
    /// The header's dimensions are not the MERL ones.
    #[error("'{path}': dimensions {dims:?} in the header; a MERL file has 90 θh × 90 θd × 180 φd")]
    Dimensions {
        /// The file.
        path: PathBuf,
        /// The three int32 read.
        dims: [i64; 3],
    },
    /// The header reads right only byte-swapped: written big-endian.
    #[error(
        "'{path}': wrong endianness: the header reads 90 × 90 × 180 only byte-swapped; MERL files are little-endian"
    )]
    Endianness {
        /// The file.
        path: PathBuf,
    },
    /// A value that is NaN or infinite (negative values are allowed: "not measured").
    #[error("'{path}': value {value} at {channel} channel, θh index {theta_h}, θd index {theta_d}, φd index {phi_d} is not a finite number")]
    NotFinite {
        /// The file.
        path: PathBuf,
        /// The value read.
        value: f64,
        /// "red", "green" or "blue".
        channel: &'static str,
        /// Table indices.
        theta_h: usize,
        /// Table indices.
        theta_d: usize,
        /// Table indices.
        phi_d: usize,
    },
    /// A malformed line of a text table.
    #[error("'{path}', line {line}: {message}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// 1-based line number (0 for the file as a whole).
        line: usize,
        /// What is wrong.
        message: String,
    },
}

impl MeasuredError {
    /// An I/O error on `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        MeasuredError::Io { path: path.into(), source }
    }
}
