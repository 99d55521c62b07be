//! Instance vertices: the animated instances' world-space vertices of this frame, copied into
//! the tail of the scene's vertex buffer, where every pass that reads surfaces by triangle
//! (the G-buffer raster, materials, geometric normals, alpha masks) finds them.

use ash::vk;
use leakless_graph::{Access, BufferHandle, Graph};
use leakless_scene::Vertex;

use crate::error::Result;
use crate::passes::names;

/// Adds the copy of `vertices` to `scene_vertices` from vertex `first_vertex` on. The graph
/// orders it after every earlier use of the buffer, including the frame still in flight.
pub fn add(
    g: &mut Graph<'_>,
    vertices: &[Vertex],
    first_vertex: usize,
    scene_vertices: &mut BufferHandle,
) -> Result<()> {
    if vertices.is_empty() {
        return Ok(());
    }
    let bytes: &[u8] = bytemuck::cast_slice(vertices);
    let upload = g.upload("instance vertices", vk::BufferUsageFlags::TRANSFER_SRC, bytes)?;
    let offset = (first_vertex * std::mem::size_of::<Vertex>()) as u64;
    let size = bytes.len() as u64;
    let mut pass = g.pass(names::INSTANCE_VERTICES);
    let src = pass.read(&upload, Access::TransferRead);
    let dst = pass.write(scene_vertices, Access::TransferWrite);
    pass.record(move |ctx| {
        ctx.cmd.copy_buffer_region(ctx.res.buffer(src), ctx.res.buffer(dst), offset, size);
        Ok(())
    });
    Ok(())
}
