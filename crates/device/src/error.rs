use ash::vk;

/// Everything the device layer can fail with. Each variant prints as one line.
#[derive(Debug, thiserror::Error)]
pub enum DeviceError {
    #[error("no Vulkan loader found ({0}); install libvulkan1 and a driver (tools/install-deps)")]
    Loader(String),
    #[error("no usable Vulkan device: {0}")]
    NoDevice(String),
    #[error("LEAKLESS_DEVICE={wanted:?} matches no usable device (usable: {usable})")]
    DeviceNotFound { wanted: String, usable: String },
    #[error("{call} failed: {result}")]
    Vk { call: &'static str, result: vk::Result },
    #[error("GPU memory allocation for {what} failed: {message}")]
    Alloc { what: String, message: String },
    /// `at` says where in the frame (" during pass gather"), or is empty when unknown.
    #[error("device lost{at} ({cause})")]
    DeviceLost { at: String, cause: String },
    #[error("shader {shader}, binding {binding:?}, pass {pass}: {problem}")]
    Binding { shader: &'static str, binding: String, pass: String, problem: String },
    #[error("{count} Vulkan validation error(s); first: {first}")]
    Validation { count: usize, first: String },
    #[error("{0}")]
    Unsupported(String),
    /// A device limit a request would exceed (the message names the limit and the value).
    #[error("{0}")]
    Limit(String),
    #[error("buffer {name} holds {capacity} bytes, {requested} requested")]
    Capacity { name: String, capacity: u64, requested: u64 },
}

pub type Result<T, E = DeviceError> = std::result::Result<T, E>;

/// Wraps a raw Vulkan result with the name of the call that produced it.
pub(crate) trait VkContext<T> {
    fn vk(self, call: &'static str) -> Result<T>;
}

impl<T> VkContext<T> for std::result::Result<T, vk::Result> {
    fn vk(self, call: &'static str) -> Result<T> {
        self.map_err(|result| match result {
            vk::Result::ERROR_DEVICE_LOST => {
                DeviceError::DeviceLost { at: String::new(), cause: format!("{call} returned VK_ERROR_DEVICE_LOST") }
            }
            result => DeviceError::Vk { call, result },
        })
    }
}
