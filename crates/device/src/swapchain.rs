//! Presenting to a window: the swapchain on the [`Gpu`]'s surface, its images (as [`Image`]s
//! the pass graph can import), and the semaphores around acquiring and presenting them.
//!
//! One acquire semaphore per frame in flight (a frame's slot is waited for before its
//! semaphore is reused), one render-finished semaphore per swapchain image (an image is
//! acquired again only after its last present consumed its semaphore).

use ash::{khr, vk};

use crate::commands::Semaphore;
use crate::error::{DeviceError, Result, VkContext};
use crate::gpu::Gpu;
use crate::memory::Image;

/// How presented images reach the screen (`--present`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PresentMode {
    /// Wait for vertical blank; never tears; always supported.
    #[default]
    Fifo,
    /// Replace the queued image; no tearing, lowest latency where supported.
    Mailbox,
    /// Present at once; may tear.
    Immediate,
}

impl PresentMode {
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "fifo" => Some(Self::Fifo),
            "mailbox" => Some(Self::Mailbox),
            "immediate" => Some(Self::Immediate),
            _ => None,
        }
    }

    fn vk(self) -> vk::PresentModeKHR {
        match self {
            Self::Fifo => vk::PresentModeKHR::FIFO,
            Self::Mailbox => vk::PresentModeKHR::MAILBOX,
            Self::Immediate => vk::PresentModeKHR::IMMEDIATE,
        }
    }
}

/// An acquired image and what its submission waits for and signals.
pub struct Acquired<'a> {
    pub index: u32,
    pub image: &'a Image,
    /// Signalled when the image may be written (the frame's submission waits for it).
    pub ready: &'a Semaphore,
    /// To signal when the frame is rendered (the present waits for it).
    pub rendered: &'a Semaphore,
}

/// What presenting found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PresentOutcome {
    Presented,
    /// Presented, but the swapchain no longer matches the surface exactly: recreate it.
    Suboptimal,
    /// Not presented: the swapchain must be recreated (a resize).
    OutOfDate,
}

pub struct Swapchain {
    loader: khr::swapchain::Device,
    raw: vk::SwapchainKHR,
    images: Vec<Image>,
    format: vk::Format,
    extent: vk::Extent2D,
    mode: PresentMode,
    ready: Vec<Semaphore>,
    rendered: Vec<Semaphore>,
}

impl Swapchain {
    /// A swapchain of `extent` (clamped to what the surface allows) presenting with `mode`,
    /// replacing `old` if given. Fails when the surface does not support `mode`.
    pub fn new(
        gpu: &Gpu,
        extent: vk::Extent2D,
        mode: PresentMode,
        frames_in_flight: usize,
        old: Option<Swapchain>,
    ) -> Result<Swapchain> {
        let surface = gpu
            .shared
            .surface
            .as_ref()
            .ok_or_else(|| DeviceError::Unsupported("the device was opened without a window".into()))?;
        let pd = gpu.report().physical;
        // SAFETY: valid physical device and surface of this instance.
        let (caps, formats, modes) = unsafe {
            (
                surface
                    .loader
                    .get_physical_device_surface_capabilities(pd, surface.raw)
                    .vk("vkGetPhysicalDeviceSurfaceCapabilitiesKHR")?,
                surface
                    .loader
                    .get_physical_device_surface_formats(pd, surface.raw)
                    .vk("vkGetPhysicalDeviceSurfaceFormatsKHR")?,
                surface
                    .loader
                    .get_physical_device_surface_present_modes(pd, surface.raw)
                    .vk("vkGetPhysicalDeviceSurfacePresentModesKHR")?,
            )
        };
        if !modes.contains(&mode.vk()) {
            return Err(DeviceError::Unsupported(format!(
                "present mode {mode:?} is not supported by this window (supported: {modes:?})"
            )));
        }
        // 8-bit sRGB-encoding formats first (the tonemap then writes linear values), then UNORM
        // (the tonemap encodes itself).
        let preferred = [
            vk::Format::B8G8R8A8_SRGB,
            vk::Format::R8G8B8A8_SRGB,
            vk::Format::B8G8R8A8_UNORM,
            vk::Format::R8G8B8A8_UNORM,
        ];
        let format = preferred
            .iter()
            .find_map(|&f| {
                formats.iter().find(|s| s.format == f && s.color_space == vk::ColorSpaceKHR::SRGB_NONLINEAR).copied()
            })
            .ok_or_else(|| DeviceError::Unsupported(format!("no 8-bit sRGB surface format among {formats:?}")))?;
        let extent = if caps.current_extent.width != u32::MAX {
            caps.current_extent
        } else {
            vk::Extent2D {
                width: extent.width.clamp(caps.min_image_extent.width, caps.max_image_extent.width),
                height: extent.height.clamp(caps.min_image_extent.height, caps.max_image_extent.height),
            }
        };
        let mut count = caps.min_image_count + 1;
        if caps.max_image_count > 0 {
            count = count.min(caps.max_image_count);
        }
        let loader = khr::swapchain::Device::new(&gpu.shared.instance.instance, gpu.device());
        let old_raw = old.as_ref().map_or(vk::SwapchainKHR::null(), |o| o.raw);
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(surface.raw)
            .min_image_count(count)
            .image_format(format.format)
            .image_color_space(format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(vk::ImageUsageFlags::COLOR_ATTACHMENT)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(caps.current_transform)
            .composite_alpha(vk::CompositeAlphaFlagsKHR::OPAQUE)
            .present_mode(mode.vk())
            .clipped(true)
            .old_swapchain(old_raw);
        // SAFETY: the surface and the old swapchain (retired by this call) belong to this device.
        let raw = unsafe { loader.create_swapchain(&info, None) }.vk("vkCreateSwapchainKHR")?;
        drop(old);
        // SAFETY: `raw` was just created.
        let raw_images = unsafe { loader.get_swapchain_images(raw) }.vk("vkGetSwapchainImagesKHR")?;
        let mut swapchain = Swapchain {
            loader,
            raw,
            images: Vec::new(),
            format: format.format,
            extent,
            mode,
            ready: Vec::new(),
            rendered: Vec::new(),
        };
        for (i, &image) in raw_images.iter().enumerate() {
            swapchain.images.push(Image::external(gpu, image, &format!("swapchain image {i}"), extent, format.format)?);
            swapchain.rendered.push(Semaphore::new(gpu, &format!("rendered {i}"))?);
        }
        for i in 0..frames_in_flight {
            swapchain.ready.push(Semaphore::new(gpu, &format!("image ready {i}"))?);
        }
        Ok(swapchain)
    }

    pub fn format(&self) -> vk::Format {
        self.format
    }

    pub fn extent(&self) -> vk::Extent2D {
        self.extent
    }

    pub fn mode(&self) -> PresentMode {
        self.mode
    }

    /// Acquires the next image for frame slot `slot`; `None` when the swapchain is out of
    /// date (recreate it and try again).
    pub fn acquire(&self, slot: usize) -> Result<Option<Acquired<'_>>> {
        let ready = &self.ready[slot % self.ready.len()];
        // SAFETY: the semaphore is unsignalled: its last acquire was waited for by the frame of
        // this slot, whose fence the caller waited for.
        let result = unsafe { self.loader.acquire_next_image(self.raw, u64::MAX, ready.raw(), vk::Fence::null()) };
        match result {
            Ok((index, _suboptimal)) => Ok(Some(Acquired {
                index,
                image: &self.images[index as usize],
                ready,
                rendered: &self.rendered[index as usize],
            })),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(None),
            Err(e) => Err(e).vk("vkAcquireNextImageKHR"),
        }
    }

    /// Presents image `index` once `rendered` is signalled.
    pub fn present(&self, gpu: &Gpu, index: u32) -> Result<PresentOutcome> {
        let waits = [self.rendered[index as usize].raw()];
        let swapchains = [self.raw];
        let indices = [index];
        let info =
            vk::PresentInfoKHR::default().wait_semaphores(&waits).swapchains(&swapchains).image_indices(&indices);
        // SAFETY: the image was acquired and its frame submitted, signalling `rendered`; the
        // queue is used from this thread only.
        match unsafe { self.loader.queue_present(gpu.queue, &info) } {
            Ok(false) => Ok(PresentOutcome::Presented),
            Ok(true) => Ok(PresentOutcome::Suboptimal),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(PresentOutcome::OutOfDate),
            Err(e) => Err(e).vk("vkQueuePresentKHR"),
        }
    }
}

impl Drop for Swapchain {
    fn drop(&mut self) {
        // The image views go first (the images belong to the swapchain).
        self.images.clear();
        // SAFETY: the owner waits for the device to be idle before dropping a swapchain.
        unsafe { self.loader.destroy_swapchain(self.raw, None) };
    }
}
