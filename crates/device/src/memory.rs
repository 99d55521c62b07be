//! Buffers and images, allocated through gpu-allocator and freed on drop.

use std::sync::{Arc, Mutex};

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
pub use gpu_allocator::MemoryLocation;

use crate::error::{DeviceError, Result, VkContext};
use crate::gpu::{Gpu, Shared};

fn allocate(
    shared: &Shared,
    name: &str,
    requirements: vk::MemoryRequirements,
    location: MemoryLocation,
    linear: bool,
) -> Result<Allocation> {
    let mut guard = shared.allocator.lock().expect("allocator lock poisoned");
    let allocator = guard.as_mut().expect("allocator alive while the device is");
    allocator
        .allocate(&AllocationCreateDesc {
            name,
            requirements,
            location,
            linear,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        })
        .map_err(|e| DeviceError::Alloc { what: name.to_string(), message: e.to_string() })
}

fn free(shared: &Shared, allocation: Allocation) {
    if let Ok(mut guard) = shared.allocator.lock() {
        if let Some(allocator) = guard.as_mut() {
            let _ = allocator.free(allocation);
        }
    }
}

#[derive(Clone, Debug)]
pub struct BufferDesc<'a> {
    pub name: &'a str,
    pub size: u64,
    pub usage: vk::BufferUsageFlags,
    pub location: MemoryLocation,
}

pub struct Buffer {
    shared: Arc<Shared>,
    raw: vk::Buffer,
    allocation: Option<Allocation>,
    size: u64,
    name: String,
    address: Option<vk::DeviceAddress>,
    /// Whether an earlier graph execution wrote it on the device: its first use in the next
    /// execution must then make those writes visible.
    device_written: std::sync::atomic::AtomicBool,
}

impl Buffer {
    pub fn new(gpu: &Gpu, desc: &BufferDesc<'_>) -> Result<Buffer> {
        let shared = &gpu.shared;
        // Zero-sized buffers are invalid in Vulkan; an empty list still gets a valid binding.
        let size = desc.size.max(16);
        let info =
            vk::BufferCreateInfo::default().size(size).usage(desc.usage).sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: valid device and create info.
        let raw = unsafe { shared.device.create_buffer(&info, None) }.vk("vkCreateBuffer")?;
        // SAFETY: `raw` was just created from this device.
        let requirements = unsafe { shared.device.get_buffer_memory_requirements(raw) };
        let allocation = match allocate(shared, desc.name, requirements, desc.location, true) {
            Ok(a) => a,
            Err(e) => {
                // SAFETY: unused buffer of this device.
                unsafe { shared.device.destroy_buffer(raw, None) };
                return Err(e);
            }
        };
        // SAFETY: memory and offset come from an allocation satisfying `requirements`.
        unsafe { shared.device.bind_buffer_memory(raw, allocation.memory(), allocation.offset()) }
            .vk("vkBindBufferMemory")?;
        shared.set_name(raw, desc.name);
        let address = desc.usage.contains(vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS).then(|| {
            // SAFETY: the buffer was created with the device-address usage and bound to memory.
            unsafe { shared.device.get_buffer_device_address(&vk::BufferDeviceAddressInfo::default().buffer(raw)) }
        });
        Ok(Buffer {
            shared: shared.clone(),
            raw,
            allocation: Some(allocation),
            size: desc.size,
            name: desc.name.to_string(),
            address,
            device_written: Default::default(),
        })
    }

    /// A device-local buffer holding `data` (written directly when the memory is mappable, as on
    /// lavapipe and integrated GPUs, else through a staging copy).
    pub fn with_data(gpu: &Gpu, name: &str, usage: vk::BufferUsageFlags, data: &[u8]) -> Result<Buffer> {
        let buffer = Buffer::new(
            gpu,
            &BufferDesc {
                name,
                size: data.len() as u64,
                usage: usage | vk::BufferUsageFlags::TRANSFER_DST,
                location: MemoryLocation::GpuOnly,
            },
        )?;
        if buffer.is_mapped() {
            buffer.write(0, data)?;
        } else if !data.is_empty() {
            let staging = Buffer::new(
                gpu,
                &BufferDesc {
                    name: "staging",
                    size: data.len() as u64,
                    usage: vk::BufferUsageFlags::TRANSFER_SRC,
                    location: MemoryLocation::CpuToGpu,
                },
            )?;
            staging.write(0, data)?;
            gpu.submit(|cmd| {
                cmd.copy_buffer(&staging, &buffer, data.len() as u64);
                Ok(())
            })?;
            buffer.set_device_written();
        }
        Ok(buffer)
    }

    pub fn raw(&self) -> vk::Buffer {
        self.raw
    }
    pub fn size(&self) -> u64 {
        self.size
    }
    pub fn name(&self) -> &str {
        &self.name
    }
    pub fn device_address(&self) -> Option<vk::DeviceAddress> {
        self.address
    }
    /// Whether a previous graph execution wrote this buffer on the device.
    pub fn device_written(&self) -> bool {
        self.device_written.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// Recorded by the pass graph after an execution that wrote the buffer.
    pub fn set_device_written(&self) {
        self.device_written.store(true, std::sync::atomic::Ordering::Relaxed)
    }

    pub fn is_mapped(&self) -> bool {
        self.allocation.as_ref().and_then(|a| a.mapped_ptr()).is_some()
    }

    fn check_range(&self, offset: u64, len: usize) -> Result<()> {
        if offset + len as u64 > self.size {
            return Err(DeviceError::Capacity {
                name: self.name.clone(),
                capacity: self.size,
                requested: offset + len as u64,
            });
        }
        Ok(())
    }

    /// Writes host data into a mapped buffer. The caller orders it against GPU use (the pass
    /// graph, or a completed submission).
    pub fn write(&self, offset: u64, data: &[u8]) -> Result<()> {
        self.check_range(offset, data.len())?;
        let ptr = self.mapped_ptr()?;
        // SAFETY: the range was checked against the buffer size, and the mapping covers the
        // whole allocation; no GPU work touches it concurrently (caller contract above).
        unsafe { std::ptr::copy_nonoverlapping(data.as_ptr(), ptr.add(offset as usize), data.len()) };
        Ok(())
    }

    /// Stores one word into a mapped buffer while GPU work may be reading it (with atomic
    /// loads): a host-to-device signal, such as the release of a fault-injection stall.
    /// Host-visible memory on the devices we run on is coherent (gpu-allocator's CpuToGpu);
    /// a device whose isn't would see the word at the next flush.
    pub fn store_word(&self, offset: u64, value: u32) -> Result<()> {
        self.check_range(offset, 4)?;
        if offset % 4 != 0 {
            return Err(DeviceError::Unsupported(format!("store_word at unaligned offset {offset}")));
        }
        let ptr = self.mapped_ptr()?;
        // SAFETY: in range and 4-byte aligned (the mapping is at least 4-aligned); an atomic
        // store, so a concurrent device read sees the old or the new word, never a torn one.
        let word = unsafe { &*(ptr.add(offset as usize) as *const std::sync::atomic::AtomicU32) };
        word.store(value, std::sync::atomic::Ordering::Release);
        Ok(())
    }

    /// Reads a mapped buffer's bytes (after the GPU work writing them has completed).
    pub fn read(&self, offset: u64, out: &mut [u8]) -> Result<()> {
        self.check_range(offset, out.len())?;
        let ptr = self.mapped_ptr()?;
        // SAFETY: as in `write`; host-coherent or gpu-allocator-mapped memory after a fence wait.
        unsafe { std::ptr::copy_nonoverlapping(ptr.add(offset as usize), out.as_mut_ptr(), out.len()) };
        Ok(())
    }

    /// Reads the whole buffer as a vector of `T`.
    pub fn read_vec<T: bytemuck::Pod>(&self, count: usize) -> Result<Vec<T>> {
        let mut out = vec![T::zeroed(); count];
        self.read(0, bytemuck::cast_slice_mut(&mut out))?;
        Ok(out)
    }

    fn mapped_ptr(&self) -> Result<*mut u8> {
        self.allocation
            .as_ref()
            .and_then(|a| a.mapped_ptr())
            .map(|p| p.as_ptr() as *mut u8)
            .ok_or_else(|| DeviceError::Unsupported(format!("buffer {} is not host-visible", self.name)))
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        // SAFETY: the owner guarantees no pending GPU work uses the buffer (submissions are
        // waited for before the resources they use can be dropped).
        unsafe { self.shared.device.destroy_buffer(self.raw, None) };
        if let Some(a) = self.allocation.take() {
            free(&self.shared, a);
        }
    }
}

#[derive(Clone, Debug)]
pub struct ImageDesc<'a> {
    pub name: &'a str,
    pub extent: vk::Extent2D,
    pub format: vk::Format,
    pub usage: vk::ImageUsageFlags,
}

pub struct Image {
    shared: Arc<Shared>,
    raw: vk::Image,
    view: vk::ImageView,
    allocation: Option<Allocation>,
    desc_name: String,
    extent: vk::Extent2D,
    format: vk::Format,
    aspect: vk::ImageAspectFlags,
    /// The layout the image is in between graph executions.
    layout: Mutex<vk::ImageLayout>,
}

impl Image {
    pub fn new(gpu: &Gpu, desc: &ImageDesc<'_>) -> Result<Image> {
        let shared = &gpu.shared;
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(desc.format)
            .extent(vk::Extent3D { width: desc.extent.width, height: desc.extent.height, depth: 1 })
            .mip_levels(1)
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(desc.usage)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: valid device and create info.
        let raw = unsafe { shared.device.create_image(&info, None) }.vk("vkCreateImage")?;
        // SAFETY: `raw` was just created from this device.
        let requirements = unsafe { shared.device.get_image_memory_requirements(raw) };
        let allocation = match allocate(shared, desc.name, requirements, MemoryLocation::GpuOnly, false) {
            Ok(a) => a,
            Err(e) => {
                // SAFETY: unused image of this device.
                unsafe { shared.device.destroy_image(raw, None) };
                return Err(e);
            }
        };
        // SAFETY: memory from an allocation satisfying `requirements`.
        unsafe { shared.device.bind_image_memory(raw, allocation.memory(), allocation.offset()) }
            .vk("vkBindImageMemory")?;
        let aspect = match desc.format {
            vk::Format::D32_SFLOAT | vk::Format::D16_UNORM => vk::ImageAspectFlags::DEPTH,
            _ => vk::ImageAspectFlags::COLOR,
        };
        let view_info = vk::ImageViewCreateInfo::default()
            .image(raw)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(desc.format)
            .subresource_range(vk::ImageSubresourceRange::default().aspect_mask(aspect).level_count(1).layer_count(1));
        // SAFETY: the image is bound to memory; the view matches its format and aspect.
        let view = unsafe { shared.device.create_image_view(&view_info, None) }.vk("vkCreateImageView")?;
        shared.set_name(raw, desc.name);
        shared.set_name(view, desc.name);
        Ok(Image {
            shared: shared.clone(),
            raw,
            view,
            allocation: Some(allocation),
            desc_name: desc.name.to_string(),
            extent: desc.extent,
            format: desc.format,
            aspect,
            layout: Mutex::new(vk::ImageLayout::UNDEFINED),
        })
    }

    /// A view on an image this crate did not allocate (a swapchain's): dropping it destroys
    /// the view, not the image.
    pub(crate) fn external(
        gpu: &Gpu,
        raw: vk::Image,
        name: &str,
        extent: vk::Extent2D,
        format: vk::Format,
    ) -> Result<Image> {
        let shared = &gpu.shared;
        let aspect = vk::ImageAspectFlags::COLOR;
        let view_info = vk::ImageViewCreateInfo::default()
            .image(raw)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format)
            .subresource_range(vk::ImageSubresourceRange::default().aspect_mask(aspect).level_count(1).layer_count(1));
        // SAFETY: `raw` is a live image of this device with this format.
        let view = unsafe { shared.device.create_image_view(&view_info, None) }.vk("vkCreateImageView")?;
        shared.set_name(view, name);
        Ok(Image {
            shared: shared.clone(),
            raw,
            view,
            allocation: None,
            desc_name: name.to_string(),
            extent,
            format,
            aspect,
            layout: Mutex::new(vk::ImageLayout::UNDEFINED),
        })
    }

    pub fn raw(&self) -> vk::Image {
        self.raw
    }
    pub fn view(&self) -> vk::ImageView {
        self.view
    }
    pub fn extent(&self) -> vk::Extent2D {
        self.extent
    }
    pub fn format(&self) -> vk::Format {
        self.format
    }
    pub fn aspect(&self) -> vk::ImageAspectFlags {
        self.aspect
    }
    pub fn name(&self) -> &str {
        &self.desc_name
    }
    /// The layout the image was left in by the last graph execution.
    pub fn layout(&self) -> vk::ImageLayout {
        *self.layout.lock().expect("layout lock")
    }
    /// Records the layout a graph execution left the image in.
    pub fn set_layout(&self, layout: vk::ImageLayout) {
        *self.layout.lock().expect("layout lock") = layout;
    }
}

impl Drop for Image {
    fn drop(&mut self) {
        // SAFETY: no pending GPU work uses the image (see Buffer::drop). An image without an
        // allocation belongs to someone else (a swapchain), which destroys it.
        unsafe {
            self.shared.device.destroy_image_view(self.view, None);
            if let Some(a) = self.allocation.take() {
                self.shared.device.destroy_image(self.raw, None);
                free(&self.shared, a);
            }
        }
    }
}
