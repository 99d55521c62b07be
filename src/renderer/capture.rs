//! Reading back what the last frame was made of: the G-buffer and the photons (tests compare
//! the gather with a brute-force splat over them; tools can inspect them).

use leakless_device::{BufferDesc, MemoryLocation};
use leakless_graph::Access;

use super::Renderer;
use crate::error::Result;
use crate::passes::gbuffer::GBufferHandles;
use crate::passes::photons::{photon_buffer_size, Photon, PHOTON_BUFFER_USAGE};
use crate::passes::readback;

/// The view samples and photons of the last frame, read back for tests and tools.
pub struct Capture {
    pub position: Vec<[f32; 4]>,
    pub normal: Vec<[f32; 4]>,
    pub albedo: Vec<[f32; 4]>,
    pub photons: Vec<Photon>,
}

const CAPTURE_BUFFER: &str = "capture readback";
const PHOTON_CAPTURE_BUFFER: &str = "photon capture readback";

impl Renderer {
    /// Reads back the G-buffer and (for methods that splat) the photons of the last frame.
    pub fn capture(&mut self) -> Result<Capture> {
        self.wait_idle()?;
        let n = (self.settings.width * self.settings.height) as usize;
        let extent = self.extent();
        // The pool's resources of the last frame, asked for with the same descriptions.
        let photons = self.settings.photon_settings().map(|s| {
            let capacity = s.paths.saturating_mul(self.settings.max_bounces.max(1));
            let stored = self.last.as_ref().and_then(|r| r.splat.as_ref()).map_or(0, |s| s.photons_stored);
            (photon_buffer_size(capacity), stored)
        });
        let mut g = self.runner.graph(&self.gpu)?;
        let gbuffer = GBufferHandles::new(&mut g, extent)?;
        readback::add(&mut g, CAPTURE_BUFFER, &[&gbuffer.position, &gbuffer.normal, &gbuffer.albedo])?;
        let mut photon_count = 0;
        if let Some((size, stored)) = photons.filter(|&(_, stored)| stored > 0) {
            photon_count = stored as usize;
            let desc =
                BufferDesc { name: "photons", size, usage: PHOTON_BUFFER_USAGE, location: MemoryLocation::GpuOnly };
            let src = g.buffer(&desc)?;
            let bytes = photon_count as u64 * std::mem::size_of::<Photon>() as u64;
            let host = BufferDesc {
                name: PHOTON_CAPTURE_BUFFER,
                size: bytes,
                usage: ash::vk::BufferUsageFlags::TRANSFER_DST,
                location: MemoryLocation::GpuToCpu,
            };
            let mut dst = g.frame_buffer(&host)?;
            let mut copy = g.pass("capture photons");
            let (from, to) = (copy.read(&src, Access::TransferRead), copy.write(&mut dst, Access::TransferWrite));
            copy.record(move |ctx| {
                ctx.cmd.copy_buffer(ctx.buffer(from), ctx.buffer(to), bytes);
                Ok(())
            });
            let mut to_host = g.pass("photons to host");
            to_host.read(&dst, Access::HostRead);
            to_host.record(|_| Ok(()));
        }
        let submitted = g.submit(&Default::default())?;
        let done = self.runner.wait_for(&self.gpu, submitted)?;
        let pool = self.runner.pool();
        let texels: Vec<[f32; 4]> =
            pool.frame_buffer(CAPTURE_BUFFER, done.slot).expect("copied above").read_vec(3 * n)?;
        let photons = match pool.frame_buffer(PHOTON_CAPTURE_BUFFER, done.slot) {
            Some(b) if photon_count > 0 => b.read_vec(photon_count)?,
            _ => vec![],
        };
        Ok(Capture {
            position: texels[..n].to_vec(),
            normal: texels[n..2 * n].to_vec(),
            albedo: texels[2 * n..].to_vec(),
            photons,
        })
    }
}
