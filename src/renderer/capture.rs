//! Reading back what a frame was made of: the G-buffer and the photons (tests compare the
//! gather with a brute-force splat over them; tools can inspect them).

use ash::vk;
use leakless_device::{Buffer, BufferDesc, MemoryLocation};
use leakless_graph::{Access, Graph};

use super::Renderer;
use crate::error::Result;
use crate::passes::photons::Photon;
use crate::passes::readback;

/// The view samples and photons of the last frame, read back for tests and tools.
pub struct Capture {
    pub position: Vec<[f32; 4]>,
    pub normal: Vec<[f32; 4]>,
    pub albedo: Vec<[f32; 4]>,
    pub photons: Vec<Photon>,
}

impl Renderer {
    /// Reads back the G-buffer and (for methods that splat) the photons of the last frame.
    pub fn capture(&mut self) -> Result<Capture> {
        let n = (self.settings.width * self.settings.height) as usize;
        let (photon_buffer, photon_count) = match &self.splatting {
            Some(s) => {
                let (b, count) = s.photons()?;
                (Some(b), count)
            }
            None => (None, 0),
        };
        let photon_bytes = photon_count as u64 * std::mem::size_of::<Photon>() as u64;
        let host = Buffer::new(
            &self.gpu,
            &BufferDesc {
                name: "photon capture",
                size: photon_bytes,
                usage: vk::BufferUsageFlags::TRANSFER_DST,
                location: MemoryLocation::GpuToCpu,
            },
        )?;
        let mut graph = Graph::new();
        let t = &self.targets;
        let images = [
            graph.import_image(&t.gbuffer.position),
            graph.import_image(&t.gbuffer.normal),
            graph.import_image(&t.gbuffer.albedo),
        ];
        let mut readback = graph.import_buffer(&self.readback);
        readback::add(&mut graph, &[&images[0], &images[1], &images[2]], &mut readback);
        if let Some(photons) = photon_buffer.filter(|_| photon_bytes > 0) {
            let src = graph.import_buffer(photons);
            let mut dst = graph.import_buffer(&host);
            let mut copy = graph.pass("capture photons");
            let (from, to) = (copy.read(&src, Access::TransferRead), copy.write(&mut dst, Access::TransferWrite));
            copy.record(move |cmd| {
                cmd.copy_buffer(from, to, photon_bytes);
                Ok(())
            });
            let mut to_host = graph.pass("photons to host");
            to_host.read(&dst, Access::HostRead);
            to_host.record(|_| Ok(()));
        }
        self.runner.run(&self.gpu, graph)?;
        let texels: Vec<[f32; 4]> = self.readback.read_vec(3 * n)?;
        Ok(Capture {
            position: texels[..n].to_vec(),
            normal: texels[n..2 * n].to_vec(),
            albedo: texels[2 * n..].to_vec(),
            photons: if photon_count > 0 { host.read_vec(photon_count as usize)? } else { vec![] },
        })
    }
}
