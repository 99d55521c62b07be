//! Load errors: one clear line each, naming the file or scene, so that the binary
//! can print `error: {e}` and the user knows what to fix.

use std::path::PathBuf;

/// Why a scene could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The scene file does not exist.
    #[error("scene file {} not found", path.display())]
    NotFound { path: PathBuf },

    /// The file (or a buffer or image file it references) exists but cannot be read.
    #[error("cannot read {}: {source}", path.display())]
    Read {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },

    /// Not glTF: bad JSON, bad GLB container, or a document that fails glTF
    /// validation. `message` is the `gltf` crate's.
    #[error("{} is not a valid glTF 2.0 file: {message}", path.display())]
    Malformed { path: PathBuf, message: String },

    /// The file needs something this loader does not do (a required extension, a
    /// vertex format outside glTF core).
    #[error("{}: unsupported: {message}", path.display())]
    Unsupported { path: PathBuf, message: String },

    /// Buffer or accessor data is missing, too short or out of range.
    #[error("{}: bad buffer data: {message}", path.display())]
    Buffer { path: PathBuf, message: String },

    /// A base colour image could not be found or decoded (glTF allows only PNG
    /// and JPEG).
    #[error("{}: image {index}: {message}", path.display())]
    Image { path: PathBuf, index: usize, message: String },

    /// DESIGN.md §4: a scene without a light renders black, which is never what the
    /// user meant, so it is refused.
    #[error("scene {name} has no light: add a KHR_lights_punctual light")]
    NoLight { name: String },

    /// Nothing to render (no triangle primitive reachable from the scene's nodes).
    #[error("scene {name} has no triangles")]
    NoTriangles { name: String },

    /// A vertex position is NaN or infinite after its node transform.
    #[error("scene {name}: mesh {mesh} has a non-finite vertex position")]
    NonFinitePosition { name: String, mesh: String },
}
