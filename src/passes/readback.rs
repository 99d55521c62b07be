//! Readback: copies output images into one host-visible buffer, one after another, and makes
//! the copies visible to the host.

use leakless_graph::{Access, BufferHandle, Graph, ImageHandle};

/// Adds the copy of `images` (in order, tightly packed) into `buffer`, then the host read.
pub fn add<'r>(graph: &mut Graph<'r>, images: &[&ImageHandle], buffer: &mut BufferHandle) {
    let mut pass = graph.pass("readback");
    let sources: Vec<_> = images.iter().map(|h| pass.read(*h, Access::TransferRead)).collect();
    let dst = pass.write(buffer, Access::TransferWrite);
    pass.record(move |cmd| {
        let mut offset = 0;
        for image in sources {
            cmd.copy_image_to_buffer(image, dst, offset);
            let e = image.extent();
            offset += e.width as u64 * e.height as u64 * 16;
        }
        Ok(())
    });
    let mut host = graph.pass("to host");
    host.read(buffer, Access::HostRead);
    host.record(|_| Ok(()));
}
