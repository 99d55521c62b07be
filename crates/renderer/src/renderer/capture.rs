//! Reading back what the last frame was made of: the G-buffer and the photons (tests compare
//! the gather with a brute-force splat over them; tools can inspect them).

use leakless_device::{BufferDesc, MemoryLocation};
use leakless_graph::{Access, Graph};

use super::Renderer;
use crate::error::Result;
use crate::passes::gbuffer::GBufferHandles;
use crate::passes::hierarchy::{HierarchyHandles, Shape};
use crate::passes::names;
use crate::passes::photon_order::ORDERED_PHOTONS;
use crate::passes::photons::{photon_buffer_size, Photon, PHOTON_BUFFER_USAGE};
use crate::passes::readback;
use crate::passes::splat::{self, LIST_BUFFER_USAGE, LIST_ENDS, LIST_PHOTONS};

/// The view samples and photons of the last frame, read back for tests and tools.
pub struct Capture {
    pub position: Vec<[f32; 4]>,
    pub normal: Vec<[f32; 4]>,
    pub albedo: Vec<[f32; 4]>,
    pub photons: Vec<Photon>,
    /// The same photons in the order the splat and the gather read them, grouped by cell
    /// (`passes::photon_order`); empty when `order_photons` is off or the gather is capped.
    pub ordered_photons: Vec<Photon>,
    /// For methods that splat: the box (min, max) around the valid view samples that
    /// `sample_bounds.comp` reduced on the GPU and the hierarchy was quantised to.
    pub sample_bounds: Option<[[f32; 3]; 2]>,
    /// For methods that splat, per pixel: the visible disk's mass, the sample's gather radius,
    /// the rays down the visible-disk pass traced, and the gather's lift on curved meshes
    /// (`passes::visible_disk::image`).
    pub disk_mass: Vec<[f32; 4]>,
    /// For methods that splat, the node lists the gather read (`passes::list_scatter`): per
    /// node, the end of its range, so that node n's photons are `list_photons[ends[n − 1] ..
    /// ends[n]]` (from 0 for node 0); and every node's photons, node after node (indices into
    /// the photons the splat read: `ordered_photons` where that is not empty).
    pub list_ends: Vec<u32>,
    pub list_photons: Vec<u32>,
}

/// The float a `sample_bounds.comp` order key stands for (the inverse of its `order_key`).
fn from_order_key(key: u32) -> f32 {
    f32::from_bits(if key & 0x8000_0000 != 0 { key & 0x7fff_ffff } else { !key })
}

/// Copies the first `bytes` of the pool's buffer `desc` (the last frame's) into a host-visible
/// frame buffer named `to`.
fn copy_to_host(g: &mut Graph<'_>, desc: &BufferDesc<'_>, bytes: u64, to: &'static str) -> Result<()> {
    let src = g.buffer(desc)?;
    let host = BufferDesc {
        name: to,
        size: bytes,
        usage: ash::vk::BufferUsageFlags::TRANSFER_DST,
        location: MemoryLocation::GpuToCpu,
    };
    let mut dst = g.frame_buffer(&host)?;
    let mut copy = g.pass(names::CAPTURE_COPY);
    let (from, into) = (copy.read(&src, Access::TransferRead), copy.write(&mut dst, Access::TransferWrite));
    copy.record(move |ctx| {
        ctx.cmd.copy_buffer(ctx.buffer(from), ctx.buffer(into), bytes);
        Ok(())
    });
    let mut to_host = g.pass(names::CAPTURE_TO_HOST);
    to_host.read(&dst, Access::HostRead);
    to_host.record(|_| Ok(()));
    Ok(())
}

const CAPTURE_BUFFER: &str = "capture readback";
const PHOTON_CAPTURE_BUFFER: &str = "photon capture readback";
const ORDERED_PHOTON_CAPTURE_BUFFER: &str = "ordered photon capture readback";
const BOUNDS_CAPTURE_BUFFER: &str = "sample bounds capture readback";
const DISK_CAPTURE_BUFFER: &str = "disk mass capture readback";
const LIST_ENDS_CAPTURE_BUFFER: &str = "list ends capture readback";
const LIST_PHOTONS_CAPTURE_BUFFER: &str = "list photons capture readback";

impl Renderer {
    /// Reads back the G-buffer and (for methods that splat) the photons of the last frame.
    pub fn capture(&mut self) -> Result<Capture> {
        self.wait_idle()?;
        let n = (self.settings.width * self.settings.height) as usize;
        let extent = self.extent();
        // The pool's resources of the last frame, asked for with the same descriptions.
        // The photon buffer holds the last frame's paths, every batch of them: an accumulation's
        // frames grow to several batches, and asking for one batch's size would name another
        // buffer than the one the photons are in.
        let photons = self.settings.photon_settings().map(|_| {
            let last = self.last.as_ref().and_then(|r| r.splat.as_ref());
            let capacity = last.map_or(0, |s| s.paths).saturating_mul(self.settings.max_bounces.max(1));
            (photon_buffer_size(capacity), last.map_or(0, |s| s.photons_stored))
        });
        // The splat read an ordered copy (not for a capped gather: splatting.rs says why).
        let ordered = self.settings.photon_settings().is_some_and(|s| s.order_photons && s.cap.is_none());
        let mut g = self.runner.graph(&self.gpu)?;
        let gbuffer = GBufferHandles::new(&mut g, extent)?;
        readback::add(&mut g, CAPTURE_BUFFER, &[&gbuffer.position, &gbuffer.normal, &gbuffer.albedo])?;
        let splats = photons.is_some();
        let mut photon_count = 0;
        if let Some((size, stored)) = photons.filter(|&(_, stored)| stored > 0) {
            photon_count = stored as usize;
            let desc =
                BufferDesc { name: "photons", size, usage: PHOTON_BUFFER_USAGE, location: MemoryLocation::GpuOnly };
            let bytes = photon_count as u64 * std::mem::size_of::<Photon>() as u64;
            copy_to_host(&mut g, &desc, bytes, PHOTON_CAPTURE_BUFFER)?;
            if ordered {
                copy_to_host(
                    &mut g,
                    &BufferDesc { name: ORDERED_PHOTONS, ..desc },
                    bytes,
                    ORDERED_PHOTON_CAPTURE_BUFFER,
                )?;
            }
        }
        // The lists' buffers, asked for as the splat made them: its node count and capacity.
        let lists = self.last.as_ref().and_then(|r| r.splat.as_ref()).and_then(|s| {
            let nodes = Shape::new(self.settings.width * self.settings.height, s.branching).ok()?.node_count();
            Some((splat::node_words(nodes), nodes, s.list_capacity, s.list_entries))
        });
        if let Some((words, nodes, capacity, entries)) = lists.filter(|_| splats) {
            let list =
                |name, size| BufferDesc { name, size, usage: LIST_BUFFER_USAGE, location: MemoryLocation::GpuOnly };
            copy_to_host(&mut g, &list(LIST_ENDS, 4 * words as u64), 4 * nodes as u64, LIST_ENDS_CAPTURE_BUFFER)?;
            if entries > 0 {
                let desc = list(LIST_PHOTONS, 4 * capacity.max(1) as u64);
                copy_to_host(&mut g, &desc, 4 * entries as u64, LIST_PHOTONS_CAPTURE_BUFFER)?;
            }
        }
        if splats {
            let desc = HierarchyHandles::sample_bounds_desc();
            copy_to_host(&mut g, &desc, desc.size, BOUNDS_CAPTURE_BUFFER)?;
            let disk = crate::passes::visible_disk::image(&mut g, extent)?;
            readback::add(&mut g, DISK_CAPTURE_BUFFER, &[&disk])?;
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
        let ordered_photons = match pool.frame_buffer(ORDERED_PHOTON_CAPTURE_BUFFER, done.slot) {
            Some(b) if photon_count > 0 && ordered => b.read_vec(photon_count)?,
            _ => vec![],
        };
        let sample_bounds = match pool.frame_buffer(BOUNDS_CAPTURE_BUFFER, done.slot) {
            Some(b) if splats => {
                let keys: Vec<u32> = b.read_vec(6)?;
                Some([0, 3].map(|at| [0, 1, 2].map(|axis| from_order_key(keys[at + axis]))))
            }
            _ => None,
        };
        let disk_mass = match pool.frame_buffer(DISK_CAPTURE_BUFFER, done.slot) {
            Some(b) if splats => b.read_vec(n)?,
            _ => vec![],
        };
        let (list_ends, list_photons) = match lists.filter(|_| splats) {
            Some((_, nodes, _, entries)) => (
                pool.frame_buffer(LIST_ENDS_CAPTURE_BUFFER, done.slot)
                    .expect("copied above")
                    .read_vec(nodes as usize)?,
                match pool.frame_buffer(LIST_PHOTONS_CAPTURE_BUFFER, done.slot) {
                    Some(b) if entries > 0 => b.read_vec(entries as usize)?,
                    _ => vec![],
                },
            ),
            None => (vec![], vec![]),
        };
        Ok(Capture {
            position: texels[..n].to_vec(),
            normal: texels[n..2 * n].to_vec(),
            albedo: texels[2 * n..].to_vec(),
            photons,
            ordered_photons,
            sample_bounds,
            disk_mass,
            list_ends,
            list_photons,
        })
    }
}
