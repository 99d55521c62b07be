//! Readback: copies images into one per-frame host-visible buffer, one after another, and
//! makes the copy visible to the host once the frame completes. Only explicit requests
//! (captures, the CLI, tests) read back; a normal frame never does.

use ash::vk;
use leakless_device::{BufferDesc, MemoryLocation};
use leakless_graph::{Access, BufferHandle, Graph, ImageHandle, PassName};

use crate::error::{RenderError, Result};
use crate::passes::names;

/// Bytes per texel of the formats the renderer reads back.
pub fn texel_bytes(format: vk::Format) -> Result<u64> {
    match format {
        vk::Format::R32G32B32A32_SFLOAT => Ok(16),
        vk::Format::R8G8B8A8_UNORM | vk::Format::R8G8B8A8_SRGB | vk::Format::B8G8R8A8_UNORM => Ok(4),
        vk::Format::B8G8R8A8_SRGB => Ok(4),
        other => Err(RenderError::Settings(format!("reading back {other:?} images is not supported"))),
    }
}

/// Adds the copy of `images` (in order, tightly packed) into the per-frame buffer `name`,
/// readable on the host when the frame completed.
pub fn add(graph: &mut Graph<'_>, name: &str, images: &[&ImageHandle]) -> Result<BufferHandle> {
    let mut offsets = Vec::with_capacity(images.len());
    let mut size = 0;
    for image in images {
        offsets.push(size);
        let e = image.extent();
        size += e.width as u64 * e.height as u64 * texel_bytes(image.format())?;
    }
    let desc = BufferDesc { name, size, usage: vk::BufferUsageFlags::TRANSFER_DST, location: MemoryLocation::GpuToCpu };
    let mut buffer = graph.frame_buffer(&desc)?;
    let mut pass = graph.pass(names::READBACK);
    let sources: Vec<_> = images.iter().map(|h| pass.read(*h, Access::TransferRead)).collect();
    let dst = pass.write(&mut buffer, Access::TransferWrite);
    pass.record(move |ctx| {
        for (image, offset) in sources.into_iter().zip(offsets) {
            ctx.cmd.copy_image_to_buffer(ctx.image(image), ctx.buffer(dst), offset);
        }
        Ok(())
    });
    let mut host = graph.pass(names::TO_HOST);
    host.read(&buffer, Access::HostRead);
    host.record(|_| Ok(()));
    Ok(buffer)
}

/// Adds the copy of whole buffers into the per-frame buffer `name` (counters for the stats),
/// readable on the host when the frame completed, by the pass `pass`.
pub fn add_buffers(
    graph: &mut Graph<'_>,
    (name, pass): (&str, PassName),
    buffers: &[&BufferHandle],
) -> Result<BufferHandle> {
    let mut offsets = Vec::with_capacity(buffers.len());
    let mut size = 0;
    for b in buffers {
        offsets.push(size);
        size += b.size();
    }
    let desc = BufferDesc { name, size, usage: vk::BufferUsageFlags::TRANSFER_DST, location: MemoryLocation::GpuToCpu };
    let mut buffer = graph.frame_buffer(&desc)?;
    let mut pass = graph.pass(pass);
    let sources: Vec<_> = buffers.iter().map(|h| (pass.read(*h, Access::TransferRead), h.size())).collect();
    let dst = pass.write(&mut buffer, Access::TransferWrite);
    pass.record(move |ctx| {
        for ((src, size), offset) in sources.into_iter().zip(offsets) {
            ctx.cmd.copy_buffer_region(ctx.buffer(src), ctx.buffer(dst), offset, size);
        }
        Ok(())
    });
    let mut host = graph.pass(names::STATS_TO_HOST);
    host.read(&buffer, Access::HostRead);
    host.record(|_| Ok(()));
    Ok(buffer)
}
