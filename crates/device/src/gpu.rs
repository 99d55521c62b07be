//! The [`Gpu`]: one logical device with one graphics+compute queue, its allocator and the
//! extensions the renderer uses.

use std::sync::{Arc, Mutex};
use std::time::Duration;

use ash::{ext, khr, vk};
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};

use crate::error::{DeviceError, Result, VkContext};
use crate::instance::{self, InstanceParts};
use crate::select::{self, DeviceReport, RAY_EXTENSIONS};
use crate::Cmd;

/// How to open the device.
#[derive(Clone, Debug, Default)]
pub struct GpuOptions {
    /// Validation layers on or off; `None` follows `LEAKLESS_VALIDATION` (default off).
    pub validation: Option<bool>,
    /// Enable ray queries and acceleration structures when the device has them.
    pub ray_tracing: bool,
    /// A window to present to: the device is chosen among those that can, and gets a surface.
    pub window: Option<WindowHandles>,
}

/// The raw handles of a window (winit gives them through `raw-window-handle`). The window must
/// outlive the [`Gpu`].
#[derive(Clone, Copy, Debug)]
pub struct WindowHandles {
    pub display: raw_window_handle::RawDisplayHandle,
    pub window: raw_window_handle::RawWindowHandle,
}

/// See [`Gpu::raw`].
pub struct RawVulkan<'a> {
    pub instance: &'a ash::Instance,
    pub physical_device: vk::PhysicalDevice,
    pub device: &'a ash::Device,
    pub queue: vk::Queue,
    pub queue_family: u32,
}

/// A window surface and its instance-level functions.
pub(crate) struct Surface {
    pub loader: khr::surface::Instance,
    pub raw: vk::SurfaceKHR,
}

/// What the opened device can do.
#[derive(Clone, Copy, Debug)]
pub struct Capabilities {
    pub ray_query: bool,
    pub acceleration_structure: bool,
    pub validation: bool,
}

/// Device state shared by every resource (so resources can free themselves on drop).
pub(crate) struct Shared {
    pub instance: InstanceParts,
    pub device: ash::Device,
    pub allocator: Mutex<Option<Allocator>>,
    pub debug_utils: Option<ext::debug_utils::Device>,
    pub push_descriptor: khr::push_descriptor::Device,
    pub accel: Option<khr::acceleration_structure::Device>,
    pub surface: Option<Surface>,
}

impl Shared {
    pub fn set_name<H: vk::Handle>(&self, handle: H, name: &str) {
        if let Some(du) = &self.debug_utils {
            let name = std::ffi::CString::new(name.replace('\0', " ")).expect("no interior NUL");
            let info = vk::DebugUtilsObjectNameInfoEXT::default().object_handle(handle).object_name(&name);
            // SAFETY: `handle` is a live object of this device; naming is advisory.
            let _ = unsafe { du.set_debug_utils_object_name(&info) };
        }
    }
}

impl Drop for Shared {
    fn drop(&mut self) {
        // SAFETY: Shared is dropped last (every resource holds an Arc to it), so nothing of the
        // device is still alive; wait for idle in case a submission is in flight.
        unsafe {
            let _ = self.device.device_wait_idle();
            drop(self.allocator.lock().map(|mut a| a.take()));
            self.device.destroy_device(None);
            if let Some(surface) = &self.surface {
                surface.loader.destroy_surface(surface.raw, None);
            }
            self.instance.destroy();
        }
    }
}

pub struct Gpu {
    pub(crate) shared: Arc<Shared>,
    pub(crate) queue: vk::Queue,
    pub(crate) command_pool: vk::CommandPool,
    report: DeviceReport,
    caps: Capabilities,
    timeout: Duration,
    /// The command pool is externally synchronised: a Gpu is used from one thread at a time.
    _not_sync: std::marker::PhantomData<std::cell::Cell<()>>,
}

impl Gpu {
    /// Reports on every device the loader sees, without opening one.
    pub fn list_devices() -> Result<Vec<DeviceReport>> {
        let mut parts = instance::create(false, &[])?;
        let reports = select::enumerate(&parts.instance, None);
        // SAFETY: nothing was created from this instance.
        unsafe { parts.destroy() };
        reports
    }

    /// Opens the chosen device (headless, or able to present to `options.window`).
    pub fn new(options: &GpuOptions) -> Result<Gpu> {
        let validation = options.validation.unwrap_or_else(|| instance::validation_wanted(false));
        let window_extensions = match &options.window {
            Some(w) => ash_window::enumerate_required_extensions(w.display)
                .map_err(|e| DeviceError::Unsupported(format!("the window system needs {e}")))?,
            None => &[],
        };
        let mut parts = instance::create(validation, window_extensions)?;
        let surface = match &options.window {
            Some(w) => match create_surface(&parts, w) {
                Ok(s) => Some(s),
                Err(e) => {
                    // SAFETY: nothing was created from this instance.
                    unsafe { parts.destroy() };
                    return Err(e);
                }
            },
            None => None,
        };
        // Undoes the surface and the instance when a later step fails.
        let abandon = |parts: &mut InstanceParts, surface: &Option<Surface>| {
            // SAFETY: no device exists; the surface belongs to this instance.
            unsafe {
                if let Some(s) = surface {
                    s.loader.destroy_surface(s.raw, None);
                }
                parts.destroy();
            }
        };
        let present = surface.as_ref().map(|s| select::PresentTo { loader: &s.loader, surface: s.raw });
        let result =
            select::enumerate(&parts.instance, present.as_ref()).and_then(|reports| select::choose(&reports).cloned());
        let report = match result {
            Ok(r) => r,
            Err(e) => {
                abandon(&mut parts, &surface);
                return Err(e);
            }
        };
        let ray_tracing = options.ray_tracing && report.ray_query;
        let device = match create_device(&parts.instance, &report, ray_tracing, surface.is_some()) {
            Ok(d) => d,
            Err(e) => {
                abandon(&mut parts, &surface);
                return Err(e);
            }
        };
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: parts.instance.clone(),
            device: device.clone(),
            physical_device: report.physical,
            debug_settings: Default::default(),
            buffer_device_address: true,
            allocation_sizes: Default::default(),
        })
        .map_err(|e| DeviceError::Alloc { what: "the allocator".into(), message: e.to_string() })?;
        let debug_utils = parts.debug_utils.as_ref().map(|_| ext::debug_utils::Device::new(&parts.instance, &device));
        let push_descriptor = khr::push_descriptor::Device::new(&parts.instance, &device);
        let accel = ray_tracing.then(|| khr::acceleration_structure::Device::new(&parts.instance, &device));
        let caps =
            Capabilities { ray_query: ray_tracing, acceleration_structure: ray_tracing, validation: parts.validation };
        let shared = Arc::new(Shared {
            instance: parts,
            device,
            allocator: Mutex::new(Some(allocator)),
            debug_utils,
            push_descriptor,
            accel,
            surface,
        });
        // SAFETY: the queue family index was validated during selection.
        let queue = unsafe { shared.device.get_device_queue(report.queue_family, 0) };
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(report.queue_family)
            .flags(vk::CommandPoolCreateFlags::TRANSIENT | vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: valid device and create info.
        let command_pool = unsafe { shared.device.create_command_pool(&pool_info, None) }.vk("vkCreateCommandPool")?;
        let timeout = std::env::var("LEAKLESS_GPU_TIMEOUT")
            .ok()
            .and_then(|s| s.parse::<u64>().ok())
            .map(Duration::from_secs)
            .unwrap_or(Duration::from_secs(600));
        Ok(Gpu { shared, queue, command_pool, report, caps, timeout, _not_sync: Default::default() })
    }

    pub fn report(&self) -> &DeviceReport {
        &self.report
    }

    pub fn capabilities(&self) -> Capabilities {
        self.caps
    }

    /// Raw handles for a library that records its own commands on this device (the app's
    /// UI renderer). Whatever it creates must be destroyed before the `Gpu` is dropped, and
    /// whatever it records must go through the pass graph like any pass.
    pub fn raw(&self) -> RawVulkan<'_> {
        RawVulkan {
            instance: &self.shared.instance.instance,
            physical_device: self.report.physical,
            device: &self.shared.device,
            queue: self.queue,
            queue_family: self.report.queue_family,
        }
    }

    /// A gpu-allocator of its own for such a library (its memory stays apart from the
    /// renderer's). Drop it before the `Gpu`.
    pub fn new_allocator(&self) -> Result<Allocator> {
        Allocator::new(&AllocatorCreateDesc {
            instance: self.shared.instance.instance.clone(),
            device: self.shared.device.clone(),
            physical_device: self.report.physical,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        })
        .map_err(|e| DeviceError::Alloc { what: "an allocator".into(), message: e.to_string() })
    }

    /// Device memory the renderer's allocator holds, in bytes: (allocated to live buffers and
    /// images, reserved in its memory blocks). Libraries' own allocators (`new_allocator`) and
    /// driver-internal memory are not counted.
    pub fn memory_in_use(&self) -> (u64, u64) {
        let guard = self.shared.allocator.lock().unwrap_or_else(|e| e.into_inner());
        guard.as_ref().map_or((0, 0), |a| {
            let report = a.generate_report();
            (report.total_allocated_bytes, report.total_capacity_bytes)
        })
    }

    /// How long a submission may run before it counts as a lost device (`LEAKLESS_GPU_TIMEOUT`).
    pub fn timeout(&self) -> Duration {
        self.timeout
    }

    /// Alignment of acceleration-structure scratch addresses, as the device reports it.
    pub fn scratch_alignment(&self) -> u64 {
        self.report.scratch_alignment
    }

    /// Records commands with `record`, submits them and waits for completion.
    pub fn submit<T>(&self, record: impl FnOnce(&mut Cmd<'_>) -> Result<T>) -> Result<T> {
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(self.command_pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        let device = &self.shared.device;
        // SAFETY: the pool belongs to this device and is only used from this thread (Gpu is
        // not Sync).
        let cmd_raw = unsafe { device.allocate_command_buffers(&alloc) }.vk("vkAllocateCommandBuffers")?[0];
        let result = (|| {
            let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            // SAFETY: freshly allocated command buffer.
            unsafe { device.begin_command_buffer(cmd_raw, &begin) }.vk("vkBeginCommandBuffer")?;
            let mut cmd = Cmd { gpu: self, raw: cmd_raw, frame: None, frame_bound: [false; 2] };
            let value = record(&mut cmd)?;
            // SAFETY: recording state.
            unsafe { device.end_command_buffer(cmd_raw) }.vk("vkEndCommandBuffer")?;
            // SAFETY: valid device.
            let fence = unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) }.vk("vkCreateFence")?;
            let cmds = [cmd_raw];
            let submit = vk::SubmitInfo::default().command_buffers(&cmds);
            // SAFETY: the command buffer is executable and the fence unsignalled.
            let waited =
                unsafe { device.queue_submit(self.queue, &[submit], fence) }.vk("vkQueueSubmit").and_then(|_| {
                    // SAFETY: the fence is from this device.
                    match unsafe { device.wait_for_fences(&[fence], true, self.timeout.as_nanos() as u64) } {
                        Ok(()) => Ok(()),
                        Err(vk::Result::TIMEOUT) => Err(DeviceError::DeviceLost {
                            at: String::new(),
                            cause: format!("no progress within {} s, LEAKLESS_GPU_TIMEOUT", self.timeout.as_secs()),
                        }),
                        Err(e) => Err(e).vk("vkWaitForFences"),
                    }
                });
            // SAFETY: the fence is signalled or the device is lost; either way it is unused now.
            unsafe { device.destroy_fence(fence, None) };
            waited?;
            Ok(value)
        })();
        if !matches!(result, Err(DeviceError::DeviceLost { .. })) {
            // SAFETY: the submission completed (or never happened).
            unsafe { device.free_command_buffers(self.command_pool, &[cmd_raw]) };
        }
        result
    }

    /// Fails if validation reported errors since the last call (and clears them).
    pub fn check_validation(&self) -> Result<()> {
        let mut errors =
            self.shared.instance.log.errors.lock().map(|mut e| std::mem::take(&mut *e)).unwrap_or_default();
        if errors.is_empty() {
            Ok(())
        } else {
            Err(DeviceError::Validation { count: errors.len(), first: errors.swap_remove(0) })
        }
    }

    /// Gives a Vulkan object a debug name (shown by validation messages and capture tools).
    pub fn set_name<H: vk::Handle>(&self, handle: H, name: &str) {
        self.shared.set_name(handle, name)
    }

    pub(crate) fn device(&self) -> &ash::Device {
        &self.shared.device
    }

    /// Waits until the device is idle (used before tearing resources down).
    pub fn wait_idle(&self) -> Result<()> {
        // SAFETY: valid device.
        unsafe { self.shared.device.device_wait_idle() }.vk("vkDeviceWaitIdle")
    }
}

impl Drop for Gpu {
    fn drop(&mut self) {
        // SAFETY: all command buffers from the pool completed (submit waits) or the device is lost.
        unsafe {
            let _ = self.shared.device.device_wait_idle();
            self.shared.device.destroy_command_pool(self.command_pool, None);
        }
    }
}

fn create_surface(parts: &InstanceParts, window: &WindowHandles) -> Result<Surface> {
    // SAFETY: the handles come from a live window that outlives the Gpu (GpuOptions contract);
    // the instance was created with the extensions ash-window asked for.
    let raw = unsafe { ash_window::create_surface(&parts.entry, &parts.instance, window.display, window.window, None) }
        .vk("vkCreate*SurfaceKHR")?;
    Ok(Surface { loader: khr::surface::Instance::new(&parts.entry, &parts.instance), raw })
}

fn create_device(
    instance: &ash::Instance,
    report: &DeviceReport,
    ray_tracing: bool,
    swapchain: bool,
) -> Result<ash::Device> {
    let priorities = [1.0f32];
    let queues =
        [vk::DeviceQueueCreateInfo::default().queue_family_index(report.queue_family).queue_priorities(&priorities)];
    let mut ext_names = vec![khr::push_descriptor::NAME.as_ptr()];
    if ray_tracing {
        ext_names.extend(RAY_EXTENSIONS.iter().map(|n| n.as_ptr()));
    }
    if swapchain {
        ext_names.push(khr::swapchain::NAME.as_ptr());
    }
    let base = vk::PhysicalDeviceFeatures::default()
        .shader_storage_image_write_without_format(true)
        .shader_int64(true)
        .fragment_stores_and_atomics(false);
    let mut f12 = vk::PhysicalDeviceVulkan12Features::default()
        .host_query_reset(true)
        .buffer_device_address(true)
        .scalar_block_layout(false);
    // maintenance4: the gather's workgroup size is a specialization constant (LocalSizeId in SPIR-V 1.6).
    let mut f13 =
        vk::PhysicalDeviceVulkan13Features::default().dynamic_rendering(true).synchronization2(true).maintenance4(true);
    let mut fas = vk::PhysicalDeviceAccelerationStructureFeaturesKHR::default().acceleration_structure(true);
    let mut frq = vk::PhysicalDeviceRayQueryFeaturesKHR::default().ray_query(true);
    let mut info = vk::DeviceCreateInfo::default()
        .queue_create_infos(&queues)
        .enabled_extension_names(&ext_names)
        .enabled_features(&base)
        .push_next(&mut f12)
        .push_next(&mut f13);
    if ray_tracing {
        info = info.push_next(&mut fas).push_next(&mut frq);
    }
    // SAFETY: the physical device comes from this instance; all pointers outlive the call.
    unsafe { instance.create_device(report.physical, &info, None) }.vk("vkCreateDevice")
}
