//! How a pass uses a resource, in Vulkan's terms: the pipeline stage, the memory access and
//! (for images) the layout. The pass graph derives barriers from pairs of these.

use ash::vk;

/// One way a pass can touch a buffer or an image.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Access {
    /// Not used yet (content undefined).
    Nothing,
    ComputeRead,
    ComputeWrite,
    ComputeReadWrite,
    /// Sampled read (or a buffer read) in a fragment shader.
    FragmentRead,
    /// Storage-image read in a fragment shader (storage images stay in the general layout).
    FragmentStorageRead,
    /// Storage buffer or image read in a vertex shader.
    VertexShaderRead,
    VertexBuffer,
    ColorAttachmentWrite,
    DepthAttachmentWrite,
    TransferRead,
    TransferWrite,
    HostRead,
    HostWrite,
    AccelerationStructureBuildRead,
    AccelerationStructureBuildWrite,
    /// A compute shader traversing an acceleration structure with ray queries.
    RayQueryRead,
    /// The workgroup counts of an indirect dispatch.
    IndirectCommandRead,
    /// Handed to the presentation engine.
    Present,
}

/// The Vulkan meaning of an [`Access`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AccessInfo {
    pub stage: vk::PipelineStageFlags2,
    pub access: vk::AccessFlags2,
    /// The layout an image must be in for this access.
    pub layout: vk::ImageLayout,
    pub writes: bool,
}

impl Access {
    pub fn info(self) -> AccessInfo {
        use vk::AccessFlags2 as A;
        use vk::ImageLayout as L;
        use vk::PipelineStageFlags2 as S;
        let (stage, access, layout, writes) = match self {
            Access::Nothing => (S::NONE, A::NONE, L::UNDEFINED, false),
            Access::ComputeRead => (
                S::COMPUTE_SHADER,
                A::SHADER_STORAGE_READ | A::SHADER_SAMPLED_READ | A::UNIFORM_READ,
                L::GENERAL,
                false,
            ),
            Access::ComputeWrite => (S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE, L::GENERAL, true),
            Access::ComputeReadWrite => {
                (S::COMPUTE_SHADER, A::SHADER_STORAGE_READ | A::SHADER_STORAGE_WRITE, L::GENERAL, true)
            }
            Access::FragmentRead => (
                S::FRAGMENT_SHADER,
                A::SHADER_STORAGE_READ | A::SHADER_SAMPLED_READ | A::UNIFORM_READ,
                L::SHADER_READ_ONLY_OPTIMAL,
                false,
            ),
            Access::FragmentStorageRead => (S::FRAGMENT_SHADER, A::SHADER_STORAGE_READ, L::GENERAL, false),
            Access::VertexShaderRead => {
                (S::VERTEX_SHADER, A::SHADER_STORAGE_READ | A::UNIFORM_READ, L::SHADER_READ_ONLY_OPTIMAL, false)
            }
            Access::VertexBuffer => (S::VERTEX_ATTRIBUTE_INPUT, A::VERTEX_ATTRIBUTE_READ, L::UNDEFINED, false),
            Access::ColorAttachmentWrite => (
                S::COLOR_ATTACHMENT_OUTPUT,
                A::COLOR_ATTACHMENT_WRITE | A::COLOR_ATTACHMENT_READ,
                L::COLOR_ATTACHMENT_OPTIMAL,
                true,
            ),
            Access::DepthAttachmentWrite => (
                S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS,
                A::DEPTH_STENCIL_ATTACHMENT_READ | A::DEPTH_STENCIL_ATTACHMENT_WRITE,
                L::DEPTH_ATTACHMENT_OPTIMAL,
                true,
            ),
            Access::TransferRead => (S::TRANSFER, A::TRANSFER_READ, L::TRANSFER_SRC_OPTIMAL, false),
            Access::TransferWrite => (S::TRANSFER, A::TRANSFER_WRITE, L::TRANSFER_DST_OPTIMAL, true),
            Access::HostRead => (S::HOST, A::HOST_READ, L::GENERAL, false),
            Access::HostWrite => (S::HOST, A::HOST_WRITE, L::GENERAL, true),
            Access::AccelerationStructureBuildRead => (
                S::ACCELERATION_STRUCTURE_BUILD_KHR,
                A::ACCELERATION_STRUCTURE_READ_KHR | A::SHADER_READ,
                L::UNDEFINED,
                false,
            ),
            Access::AccelerationStructureBuildWrite => (
                S::ACCELERATION_STRUCTURE_BUILD_KHR,
                A::ACCELERATION_STRUCTURE_WRITE_KHR | A::ACCELERATION_STRUCTURE_READ_KHR,
                L::UNDEFINED,
                true,
            ),
            Access::RayQueryRead => (S::COMPUTE_SHADER, A::ACCELERATION_STRUCTURE_READ_KHR, L::UNDEFINED, false),
            Access::IndirectCommandRead => (S::DRAW_INDIRECT, A::INDIRECT_COMMAND_READ, L::UNDEFINED, false),
            Access::Present => (S::NONE, A::NONE, L::PRESENT_SRC_KHR, false),
        };
        AccessInfo { stage, access, layout, writes }
    }
}
