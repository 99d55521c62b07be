//! Instance vertices: the animated instances' world-space vertices of this frame, copied into
//! the tail of the scene's vertex buffers (one per attribute), where every pass that reads
//! surfaces by triangle (the G-buffer raster, materials, geometric normals, alpha masks) finds
//! them.

use ash::vk;
use leakless_graph::{Access, BufferHandle, Graph};
use leakless_scene::Vertex;

use crate::error::Result;
use crate::gpu_scene::{SceneHandles, VertexStreams};
use crate::passes::names;

/// Adds the copy of `vertices` to the scene's vertex buffers from vertex `first_vertex` on. The
/// graph orders it after every earlier use of the buffers, including the frame still in flight.
pub fn add(g: &mut Graph<'_>, vertices: &[Vertex], first_vertex: usize, scene: &mut SceneHandles) -> Result<()> {
    if vertices.is_empty() {
        return Ok(());
    }
    let streams = VertexStreams::split(vertices);
    let sources: [(&str, &[u8], usize, &mut BufferHandle); 3] = [
        ("instance positions", bytemuck::cast_slice(&streams.positions), 12, &mut scene.positions),
        ("instance normals", bytemuck::cast_slice(&streams.normals), 12, &mut scene.normals),
        ("instance uvs", bytemuck::cast_slice(&streams.uvs), 8, &mut scene.uvs),
    ];
    let mut copies = Vec::new();
    for (name, bytes, stride, _) in &sources {
        let upload = g.upload(name, vk::BufferUsageFlags::TRANSFER_SRC, bytes)?;
        copies.push((upload, (first_vertex * stride) as u64, bytes.len() as u64));
    }
    let mut pass = g.pass(names::INSTANCE_VERTICES);
    let mut recorded = Vec::new();
    for ((upload, offset, size), (_, _, _, dst)) in copies.iter().zip(sources) {
        let src = pass.read(upload, Access::TransferRead);
        let dst = pass.write(dst, Access::TransferWrite);
        recorded.push((src, dst, *offset, *size));
    }
    pass.record(move |ctx| {
        for &(src, dst, offset, size) in &recorded {
            ctx.cmd.copy_buffer_region(ctx.res.buffer(src), ctx.res.buffer(dst), offset, size);
        }
        Ok(())
    });
    Ok(())
}
