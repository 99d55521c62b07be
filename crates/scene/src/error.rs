//! Load errors: one clear line each, naming the file or scene, so that the binary
//! can print `error: {e}` and the user knows what to fix.

use std::borrow::Cow;
use std::path::{Path, PathBuf};

/// Why a scene could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The scene file does not exist.
    #[error("scene file {} not found", shown(path))]
    NotFound { path: PathBuf },

    /// The file (or a buffer or image file it references) exists but cannot be read.
    #[error("cannot read {}: {source}", shown(path))]
    Read {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },

    /// Not glTF: bad JSON, bad GLB container, or a document that fails glTF
    /// validation. `message` is the `gltf` crate's.
    #[error("{} is not a valid glTF 2.0 file: {}", shown(path), one_line(message))]
    Malformed { path: PathBuf, message: String },

    /// The file needs something this loader does not do (a required extension, a
    /// vertex format outside glTF core).
    #[error("{}: unsupported: {}", shown(path), one_line(message))]
    Unsupported { path: PathBuf, message: String },

    /// Buffer or accessor data is missing, too short or out of range.
    #[error("{}: bad buffer data: {}", shown(path), one_line(message))]
    Buffer { path: PathBuf, message: String },

    /// A base colour image could not be found or decoded (glTF allows only PNG
    /// and JPEG).
    #[error("{}: image {index}: {}", shown(path), one_line(message))]
    Image { path: PathBuf, index: usize, message: String },

    /// docs/architecture.md §4: a scene without a light renders black, which is never what the
    /// user meant, so it is refused.
    #[error("scene {} has no light: add a KHR_lights_punctual light or an emissive material", one_line(name))]
    NoLight { name: String },

    /// Nothing to render (no triangle primitive reachable from the scene's nodes).
    #[error("scene {} has no triangles", one_line(name))]
    NoTriangles { name: String },

    /// A vertex position is NaN or infinite after its node transform.
    #[error("scene {}: mesh {} has a non-finite vertex position", one_line(name), one_line(mesh))]
    NonFinitePosition { name: String, mesh: String },

    /// An animation channel cannot be played: its sampler's data is inconsistent
    /// (times not finite and strictly increasing, an output count that does not
    /// match the input's, an accessor type glTF does not allow there) or its target
    /// node is missing or has a matrix. `animation` is its index (and name).
    #[error("{}: animation {}, channel {channel}: {}", shown(path), one_line(animation), one_line(message))]
    Animation { path: PathBuf, animation: String, channel: usize, message: String },
}

/// `s` as one line: trailing line breaks (some decoders end their messages with one)
/// dropped, other control characters escaped (`\n`, `\u{1b}`). Messages quote names,
/// URIs and extension names from the file, which may contain anything.
pub(crate) fn one_line(s: &str) -> Cow<'_, str> {
    let s = s.trim_end_matches(['\n', '\r']);
    let bad = |c: char| c.is_control() || c == '\u{2028}' || c == '\u{2029}';
    if !s.contains(bad) {
        return Cow::Borrowed(s);
    }
    Cow::Owned(s.chars().map(|c| if bad(c) { c.escape_default().to_string() } else { c.to_string() }).collect())
}

fn shown(path: &Path) -> String {
    one_line(&path.display().to_string()).into_owned()
}
