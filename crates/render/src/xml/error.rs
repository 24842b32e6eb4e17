//! The loader's error: which file, where in it (line:column as roxmltree counts them, from 1),
//! which element, and what would have been accepted.

use std::fmt;
use std::path::PathBuf;

/// A line and column in the XML text (1-based).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Pos {
    /// Line, from 1.
    pub line: u32,
    /// Column, from 1.
    pub col: u32,
}

/// A scene file that cannot be loaded, with where and why.
#[derive(Debug)]
pub struct XmlError {
    /// The scene file (or `<string>` for text loaded without one).
    pub file: PathBuf,
    /// Where in it; None when the problem is the file as a whole (e.g. it cannot be read).
    pub pos: Option<Pos>,
    /// The element, as written (`<shape type="ply">`), when one is at fault.
    pub element: Option<String>,
    /// What is wrong, and the accepted values where there is a list of them.
    pub message: String,
}

impl XmlError {
    /// An error at `pos` in element `element`.
    pub fn at(file: impl Into<PathBuf>, pos: Pos, element: impl Into<String>, message: impl Into<String>) -> Self {
        XmlError { file: file.into(), pos: Some(pos), element: Some(element.into()), message: message.into() }
    }

    /// An error about the file as a whole.
    pub fn file(file: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        XmlError { file: file.into(), pos: None, element: None, message: message.into() }
    }
}

impl fmt::Display for XmlError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some(p) = self.pos {
            write!(f, ":{}:{}", p.line, p.col)?;
        }
        if let Some(e) = &self.element {
            write!(f, ": {e}")?;
        }
        write!(f, ": {}", self.message)
    }
}

impl std::error::Error for XmlError {}
