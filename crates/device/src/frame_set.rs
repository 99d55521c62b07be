//! The frame set: descriptor set 0 of every pipeline, what a frame binds once (the scene's
//! surfaces, its emitters, the trace structures), at numbers every shader shares. A pass's
//! own bindings are pushed in set 1, numbered from 0 in each shader.
//!
//! Every pipeline layout has the same set 0 and the same push-constant range per bind point,
//! so its layouts are compatible for set 0: a command buffer binds the frame set once per bind
//! point and every pipeline bound after keeps it.

use std::sync::Arc;

use ash::vk;
use ash::vk::Handle;

use crate::bind::{BindingDecl, Bound};
use crate::error::{DeviceError, Result, VkContext};
use crate::gpu::{Gpu, Shared};
use crate::select::PerStageLimits;
use crate::shader::BindingKind;

/// One binding of the frame set: its declaration and the number every shader gives it.
#[derive(Clone, Copy, Debug)]
pub struct FrameBinding {
    pub binding: u32,
    pub decl: BindingDecl,
}

/// Bytes of every layout's push-constant range. The range must be the same in every layout
/// for set 0 to stay bound from one pipeline to the next; 128 bytes is what every Vulkan device
/// offers (`maxPushConstantsSize`).
pub const PUSH_RANGE: u32 = 128;

/// The stages the frame set is visible to, the same in every layout (compute passes and the
/// raster passes both read the scene).
const FRAME_STAGES: vk::ShaderStageFlags = vk::ShaderStageFlags::from_raw(
    vk::ShaderStageFlags::COMPUTE.as_raw()
        | vk::ShaderStageFlags::VERTEX.as_raw()
        | vk::ShaderStageFlags::FRAGMENT.as_raw(),
);

/// The bindings of `frame` this device can hold: an acceleration structure only where the
/// device has them (a frame on the compute backend leaves it unwritten; no shader of that
/// backend uses it).
fn supported<'f>(gpu: &Gpu, frame: &'f [FrameBinding]) -> impl Iterator<Item = &'f FrameBinding> {
    let accel = gpu.capabilities().acceleration_structure;
    frame.iter().filter(move |b| accel || b.decl.kind != BindingKind::AccelerationStructure)
}

/// Checks that one stage can use every binding of the frame set (as this device holds it) and
/// `own` together, and that the device takes the layouts' push-constant range.
pub(crate) fn check_stage_limits(gpu: &Gpu, pass: &str, frame: &[FrameBinding], own: &[BindingDecl]) -> Result<()> {
    let limits = &gpu.report().limits;
    let kinds = supported(gpu, frame).map(|b| b.decl.kind).chain(own.iter().map(|d| d.kind));
    stage_limits(&limits.max_per_stage, limits.max_push_constants_size, pass, kinds)
}

fn stage_limits(
    most: &PerStageLimits,
    push_size: u32,
    pass: &str,
    kinds: impl Iterator<Item = BindingKind>,
) -> Result<()> {
    let (mut buffers, mut images, mut uniforms, mut resources) = (0, 0, 0, 0);
    for kind in kinds {
        resources += 1;
        match kind {
            BindingKind::StorageBuffer => buffers += 1,
            BindingKind::StorageImage => images += 1,
            BindingKind::UniformBuffer => uniforms += 1,
            _ => {}
        }
    }
    let over = [
        (buffers, most.storage_buffers, "maxPerStageDescriptorStorageBuffers"),
        (images, most.storage_images, "maxPerStageDescriptorStorageImages"),
        (uniforms, most.uniform_buffers, "maxPerStageDescriptorUniformBuffers"),
        (resources, most.resources, "maxPerStageResources"),
        (PUSH_RANGE, push_size, "maxPushConstantsSize"),
    ];
    match over.into_iter().find(|(count, most, _)| count > most) {
        Some((count, most, limit)) => Err(DeviceError::Limit(format!(
            "pass {pass}: its pipeline layout (the frame set and its own bindings) needs {count} where the device's {limit} is {most}"
        ))),
        None => Ok(()),
    }
}

/// A descriptor-set layout of `frame`; identical for identical `frame`, so layouts made apart
/// are compatible.
pub(crate) fn frame_set_layout(gpu: &Gpu, frame: &[FrameBinding]) -> Result<vk::DescriptorSetLayout> {
    let bindings: Vec<_> = supported(gpu, frame)
        .map(|b| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(b.binding)
                .descriptor_type(b.decl.kind.descriptor_type())
                .descriptor_count(1)
                .stage_flags(FRAME_STAGES)
        })
        .collect();
    let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
    // SAFETY: valid device and create info.
    unsafe { gpu.device().create_descriptor_set_layout(&info, None) }.vk("vkCreateDescriptorSetLayout")
}

/// The frame set of one frame slot ([`CommandSlot::write_frame_set`](crate::CommandSlot)): a
/// pool holding one set, written anew by each frame that runs in the slot once the slot's
/// previous frame has completed.
pub(crate) struct FrameSet {
    shared: Arc<Shared>,
    frame: &'static [FrameBinding],
    layout: vk::DescriptorSetLayout,
    pool: vk::DescriptorPool,
}

impl FrameSet {
    pub(crate) fn new(gpu: &Gpu, frame: &'static [FrameBinding]) -> Result<FrameSet> {
        let layout = frame_set_layout(gpu, frame)?;
        let mut sizes: Vec<vk::DescriptorPoolSize> = Vec::new();
        for b in supported(gpu, frame) {
            let ty = b.decl.kind.descriptor_type();
            match sizes.iter_mut().find(|s| s.ty == ty) {
                Some(s) => s.descriptor_count += 1,
                None => sizes.push(vk::DescriptorPoolSize { ty, descriptor_count: 1 }),
            }
        }
        let info = vk::DescriptorPoolCreateInfo::default().max_sets(1).pool_sizes(&sizes);
        // SAFETY: valid device and create info.
        let pool = unsafe { gpu.device().create_descriptor_pool(&info, None) }.vk("vkCreateDescriptorPool");
        let pool = match pool {
            Ok(pool) => pool,
            Err(e) => {
                // SAFETY: the layout was just made and nothing uses it.
                unsafe { gpu.device().destroy_descriptor_set_layout(layout, None) };
                return Err(e);
            }
        };
        Ok(FrameSet { shared: gpu.shared.clone(), frame, layout, pool })
    }

    /// The declaration the set was made for.
    pub(crate) fn frame(&self) -> &'static [FrameBinding] {
        self.frame
    }

    /// Writes `bound` (each resource by its binding's name; a name bound twice must be the
    /// same resource) into a fresh set. Only its slot calls it, after waiting for the slot's
    /// last submission. Bindings left out stay unwritten: a pipeline that uses one fails when
    /// it binds the set.
    pub(crate) fn write(&mut self, gpu: &Gpu, bound: &[(&'static str, Bound<'_>)]) -> Result<BoundFrameSet> {
        let device = gpu.device();
        // SAFETY: the slot waited for its last submission, the only one that could use the set.
        unsafe { device.reset_descriptor_pool(self.pool, vk::DescriptorPoolResetFlags::empty()) }
            .vk("vkResetDescriptorPool")?;
        let layouts = [self.layout];
        let info = vk::DescriptorSetAllocateInfo::default().descriptor_pool(self.pool).set_layouts(&layouts);
        // SAFETY: the pool was sized for one set of this layout and was just reset.
        let set = unsafe { device.allocate_descriptor_sets(&info) }.vk("vkAllocateDescriptorSets")?[0];
        let mut entries = Vec::new();
        let mut held = Vec::new();
        for b in supported(gpu, self.frame) {
            let mut named = bound.iter().filter(|(n, _)| *n == b.decl.name).map(|&(_, r)| r);
            let Some(resource) = named.next() else { continue };
            let raw = raw_of(resource);
            if named.any(|other| raw_of(other) != raw) {
                return Err(DeviceError::Binding {
                    shader: "-",
                    binding: b.decl.name.into(),
                    pass: "frame set".into(),
                    problem: "bound twice to different resources".into(),
                });
            }
            entries.push((b.decl, b.binding, resource));
            held.push(b.decl.name);
        }
        write_descriptors(&entries, |writes| {
            let writes: Vec<_> = writes.iter().map(|w| w.dst_set(set)).collect();
            // SAFETY: every write targets a binding of the set's layout with its type; the set
            // is not in use.
            unsafe { device.update_descriptor_sets(&writes, &[]) };
        });
        Ok(BoundFrameSet { set, held })
    }
}

impl Drop for FrameSet {
    fn drop(&mut self) {
        // SAFETY: its slot waited for its last submission (in `drop`, or before replacing it).
        unsafe {
            self.shared.device.destroy_descriptor_pool(self.pool, None);
            self.shared.device.destroy_descriptor_set_layout(self.layout, None);
        }
    }
}

/// A written frame set, and the names of the bindings written.
#[derive(Clone, Debug)]
pub struct BoundFrameSet {
    pub(crate) set: vk::DescriptorSet,
    pub(crate) held: Vec<&'static str>,
}

impl BoundFrameSet {
    /// Whether the binding `name` was written.
    pub(crate) fn holds(&self, name: &str) -> bool {
        self.held.contains(&name)
    }
}

/// The raw Vulkan handle behind a bound resource: what identifies it in a descriptor.
fn raw_of(resource: Bound<'_>) -> u64 {
    match resource {
        Bound::Buffer(b) => b.raw().as_raw(),
        Bound::Image(i) => i.view().as_raw(),
        Bound::Accel(a) => a.as_raw(),
    }
}

/// Descriptor writes for `entries` (declaration, binding number, resource) with no set named
/// yet, handed to `use_writes` while the infos they point to live.
pub(crate) fn write_descriptors(
    entries: &[(BindingDecl, u32, Bound<'_>)],
    use_writes: impl FnOnce(&[vk::WriteDescriptorSet<'_>]),
) {
    let buffers: Vec<_> = entries
        .iter()
        .map(|e| match e.2 {
            Bound::Buffer(b) => vk::DescriptorBufferInfo::default().buffer(b.raw()).range(vk::WHOLE_SIZE),
            _ => vk::DescriptorBufferInfo::default(),
        })
        .collect();
    let images: Vec<_> = entries
        .iter()
        .map(|e| match e.2 {
            Bound::Image(i) => {
                vk::DescriptorImageInfo::default().image_view(i.view()).image_layout(vk::ImageLayout::GENERAL)
            }
            _ => vk::DescriptorImageInfo::default(),
        })
        .collect();
    let accels: Vec<_> = entries
        .iter()
        .map(|e| match e.2 {
            Bound::Accel(a) => a,
            _ => vk::AccelerationStructureKHR::null(),
        })
        .collect();
    let mut accel_writes: Vec<_> = accels
        .iter()
        .map(|a| {
            vk::WriteDescriptorSetAccelerationStructureKHR::default().acceleration_structures(std::slice::from_ref(a))
        })
        .collect();
    let writes: Vec<_> = entries
        .iter()
        .zip(buffers.iter().zip(&images))
        .zip(accel_writes.iter_mut())
        .map(|((&(decl, number, resource), (buffer, image)), accel)| {
            let write =
                vk::WriteDescriptorSet::default().dst_binding(number).descriptor_type(decl.kind.descriptor_type());
            match resource {
                Bound::Buffer(_) => write.buffer_info(std::slice::from_ref(buffer)),
                Bound::Image(_) => write.image_info(std::slice::from_ref(image)),
                // ash 0.38 does not derive the count from a pushed-next struct.
                Bound::Accel(_) => write.descriptor_count(1).push_next(accel),
            }
        })
        .collect();
    use_writes(&writes);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A layout over any per-stage limit, or a device whose push constants are smaller than the
    /// layouts' range, is refused naming the limit; at the limit it is not.
    #[test]
    fn a_layout_over_a_per_stage_limit_is_refused_by_name() {
        let most = PerStageLimits { storage_buffers: 2, storage_images: 1, uniform_buffers: 1, resources: 4 };
        let (sb, si, ub) = (BindingKind::StorageBuffer, BindingKind::StorageImage, BindingKind::UniformBuffer);
        assert!(stage_limits(&most, 128, "p", [sb, sb, si, ub].into_iter()).is_ok());
        for (kinds, limit) in [
            (vec![sb, sb, sb], "StorageBuffers"),
            (vec![si, si], "StorageImages"),
            (vec![ub, ub], "UniformBuffers"),
            (vec![sb, sb, si, ub, BindingKind::AccelerationStructure], "maxPerStageResources"),
        ] {
            let e = stage_limits(&most, 128, "p", kinds.into_iter()).unwrap_err().to_string();
            assert!(e.contains(limit) && e.contains("pass p"), "{e}");
        }
        let e = stage_limits(&most, 64, "p", [sb].into_iter()).unwrap_err().to_string();
        assert!(e.contains("maxPushConstantsSize"), "{e}");
    }
}
