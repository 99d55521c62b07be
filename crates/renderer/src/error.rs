use leakless_device::DeviceError;
use leakless_scene::SceneError;

/// Everything rendering can fail with; each variant prints as one line.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error(transparent)]
    Device(#[from] DeviceError),
    #[error(transparent)]
    Scene(#[from] SceneError),
    #[error(transparent)]
    Accel(#[from] leakless_accel::AccelError),
    #[error("invalid setting: {0}")]
    Settings(String),
    /// A device limit the render would exceed, found before anything was allocated.
    #[error("{0}")]
    Limit(String),
    #[error("writing {path}: {message}")]
    Output { path: String, message: String },
}

pub type Result<T, E = RenderError> = std::result::Result<T, E>;
