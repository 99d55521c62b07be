//! Resources the graph owns across frames, by name (kajiya's temporal resources): a pass asks
//! for "indirect" with a description, and gets the image it used last frame, or a new one when
//! the description changed (a resize, more photons). Replaced resources are retired, and
//! dropped only once every frame that may still use them has completed.

use std::collections::HashMap;

use leakless_device::{Buffer, BufferDesc, Gpu, Image, ImageDesc, MemoryLocation, Result};

use crate::history::PairState;
use crate::vk;

/// How a buffer is made: what a changed description is compared on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct BufferKey {
    size: u64,
    usage: vk::BufferUsageFlags,
    location: MemoryLocation,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct ImageKey {
    extent: vk::Extent2D,
    format: vk::Format,
    usage: vk::ImageUsageFlags,
}

/// One resource slot of the pool: persistent, or one copy per frame in flight.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(crate) enum PoolKey {
    Persistent(String),
    PerFrame(String, usize),
}

#[allow(dead_code)] // held only to be dropped once no frame uses them
enum Retired {
    Buffer(Box<Buffer>),
    Image(Box<Image>),
}

#[derive(Default)]
pub struct ResourcePool {
    buffers: HashMap<PoolKey, (BufferKey, Box<Buffer>)>,
    images: HashMap<PoolKey, (ImageKey, Box<Image>)>,
    /// Replaced resources and the frame that was being built when they were replaced: frames
    /// before it may still read them.
    retired: Vec<(u64, Retired)>,
    /// The history pairs by name.
    pub(crate) histories: HashMap<String, PairState>,
}

impl ResourcePool {
    /// Forgets what every history pair holds (`GraphRunner::invalidate_histories`).
    pub(crate) fn invalidate_histories(&mut self) {
        self.histories.values_mut().for_each(PairState::invalidate);
    }

    /// Makes sure `key` names a buffer made from `desc`, creating or replacing it; `frame` is
    /// the frame being built.
    pub(crate) fn ensure_buffer(&mut self, gpu: &Gpu, key: PoolKey, desc: &BufferDesc<'_>, frame: u64) -> Result<()> {
        let want = BufferKey { size: desc.size, usage: desc.usage, location: desc.location };
        if matches!(self.buffers.get(&key), Some((have, _)) if *have == want) {
            return Ok(());
        }
        let buffer = Box::new(Buffer::new(gpu, desc)?);
        if let Some((_, old)) = self.buffers.insert(key, (want, buffer)) {
            self.retired.push((frame, Retired::Buffer(old)));
        }
        Ok(())
    }

    /// Makes sure `key` names an image made from `desc`; true when it was made now.
    pub(crate) fn ensure_image(&mut self, gpu: &Gpu, key: PoolKey, desc: &ImageDesc<'_>, frame: u64) -> Result<bool> {
        let want = ImageKey { extent: desc.extent, format: desc.format, usage: desc.usage };
        if matches!(self.images.get(&key), Some((have, _)) if *have == want) {
            return Ok(false);
        }
        let image = Box::new(Image::new(gpu, desc)?);
        if let Some((_, old)) = self.images.insert(key, (want, image)) {
            self.retired.push((frame, Retired::Image(old)));
        }
        Ok(true)
    }

    pub(crate) fn buffer(&self, key: &PoolKey) -> &Buffer {
        &self.buffers.get(key).expect("pool buffer ensured at declaration").1
    }

    pub(crate) fn image(&self, key: &PoolKey) -> &Image {
        &self.images.get(key).expect("pool image ensured at declaration").1
    }

    /// A persistent buffer by name, if a frame created it.
    pub fn persistent_buffer(&self, name: &str) -> Option<&Buffer> {
        self.buffers.get(&PoolKey::Persistent(name.into())).map(|(_, b)| &**b)
    }

    /// A persistent image by name, if a frame created it.
    pub fn persistent_image(&self, name: &str) -> Option<&Image> {
        self.images.get(&PoolKey::Persistent(name.into())).map(|(_, i)| &**i)
    }

    /// Slot `slot`'s copy of a per-frame buffer, if a frame created it.
    pub fn frame_buffer(&self, name: &str, slot: usize) -> Option<&Buffer> {
        self.buffers.get(&PoolKey::PerFrame(name.into(), slot)).map(|(_, b)| &**b)
    }

    /// Drops what was retired while building a frame after `completed_through`'s successor:
    /// every frame up to `completed_through` has completed, so nothing in flight uses them.
    pub(crate) fn collect(&mut self, completed_through: u64) {
        self.retired.retain(|(frame, _)| *frame > completed_through + 1);
    }

    /// How many resources were replaced and are waiting for their frames to finish.
    pub fn retired_count(&self) -> usize {
        self.retired.len()
    }
}
