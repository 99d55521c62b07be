//! Physical-device selection: what each device offers, why a device is rejected, and which
//! one is used (a discrete GPU first; `LEAKLESS_DEVICE` picks by index or name).

use std::ffi::CStr;

use ash::{khr, vk};

use crate::error::{DeviceError, Result, VkContext};

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum DeviceType {
    Discrete,
    Integrated,
    Virtual,
    Cpu,
    Other,
}

impl DeviceReport {
    /// The vendor's name from `vendor_id` (the PCI IDs of the GPU vendors, Khronos' IDs of
    /// the driver-only ones), or its number.
    pub fn vendor(&self) -> String {
        match self.vendor_id {
            0x10de => "NVIDIA".into(),
            0x1002 => "AMD".into(),
            0x8086 => "Intel".into(),
            0x13b5 => "ARM".into(),
            0x5143 => "Qualcomm".into(),
            0x106b => "Apple".into(),
            0x10005 => "Mesa".into(),
            id => format!("{id:#x}"),
        }
    }
}

impl DeviceType {
    fn from_vk(t: vk::PhysicalDeviceType) -> Self {
        match t {
            vk::PhysicalDeviceType::DISCRETE_GPU => Self::Discrete,
            vk::PhysicalDeviceType::INTEGRATED_GPU => Self::Integrated,
            vk::PhysicalDeviceType::VIRTUAL_GPU => Self::Virtual,
            vk::PhysicalDeviceType::CPU => Self::Cpu,
            _ => Self::Other,
        }
    }
}

/// What one physical device is and offers, as `leakless info` prints it.
#[derive(Clone, Debug)]
pub struct DeviceReport {
    pub index: usize,
    pub name: String,
    pub device_type: DeviceType,
    pub driver: String,
    pub api_version: (u32, u32, u32),
    /// `VK_KHR_ray_query` with the `rayQuery` feature.
    pub ray_query: bool,
    /// `VK_KHR_acceleration_structure` (+ deferred host operations, buffer device address).
    pub acceleration_structure: bool,
    pub push_descriptor: bool,
    pub timestamp_period_ns: f32,
    pub subgroup_size: u32,
    /// Subgroup ballot, arithmetic and shuffle operations in compute shaders: required (the
    /// modules with the tuning's subgroup counters and the gather's shared walk declare them
    /// even where the tuning leaves them off).
    pub subgroup_arithmetic: bool,
    /// `vendorID` (PCI vendor: 0x10de NVIDIA, 0x1002 AMD, 0x8086 Intel; 0x10005 Mesa).
    pub vendor_id: u32,
    /// `minAccelerationStructureScratchOffsetAlignment` (1 without acceleration structures).
    pub scratch_alignment: u64,
    /// The limits a render is checked against before it allocates anything.
    pub limits: DeviceLimits,
    /// Why the device cannot be used, if it cannot.
    pub rejected: Option<String>,
    pub(crate) physical: vk::PhysicalDevice,
    pub(crate) queue_family: u32,
}

/// What a device can hold and dispatch at most (the Vulkan limits a render can reach).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DeviceLimits {
    /// `maxImageDimension2D`: the widest and tallest image.
    pub max_image_dimension_2d: u32,
    /// `maxStorageBufferRange`: the largest storage buffer a shader can address.
    pub max_storage_buffer_range: u32,
    /// `maxBufferSize` (Vulkan 1.3): the largest buffer.
    pub max_buffer_size: u64,
    /// `maxComputeWorkGroupCount`.
    pub max_compute_work_group_count: [u32; 3],
    /// `maxComputeWorkGroupInvocations`.
    pub max_compute_work_group_invocations: u32,
    /// `maxComputeSharedMemorySize`: the bytes of workgroup-shared memory a compute shader may
    /// declare.
    pub max_compute_shared_memory_size: u32,
    /// `maxPrimitiveCount` of one BLAS geometry (0 without acceleration structures).
    pub max_primitive_count: u64,
    /// The largest device-local memory heap, in bytes.
    pub device_local_heap: u64,
    /// What one shader stage may bind across a pipeline layout's sets:
    /// `maxPerStageDescriptorStorageBuffers`, `…StorageImages`, `…UniformBuffers`, and
    /// `maxPerStageResources`.
    pub max_per_stage: PerStageLimits,
    /// `maxPushConstantsSize`.
    pub max_push_constants_size: u32,
}

/// Descriptors one shader stage may use across a pipeline layout.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PerStageLimits {
    pub storage_buffers: u32,
    pub storage_images: u32,
    pub uniform_buffers: u32,
    pub resources: u32,
}

pub(crate) const RAY_EXTENSIONS: [&CStr; 3] =
    [khr::acceleration_structure::NAME, khr::ray_query::NAME, khr::deferred_host_operations::NAME];

/// A window surface devices must be able to present to.
pub(crate) struct PresentTo<'a> {
    pub loader: &'a khr::surface::Instance,
    pub surface: vk::SurfaceKHR,
}

pub(crate) fn enumerate(instance: &ash::Instance, present: Option<&PresentTo<'_>>) -> Result<Vec<DeviceReport>> {
    // SAFETY: queries on a valid instance.
    let physicals = unsafe { instance.enumerate_physical_devices() }.vk("vkEnumeratePhysicalDevices")?;
    physicals.iter().enumerate().map(|(index, &pd)| describe(instance, index, pd, present)).collect()
}

fn describe(
    instance: &ash::Instance,
    index: usize,
    pd: vk::PhysicalDevice,
    present: Option<&PresentTo<'_>>,
) -> Result<DeviceReport> {
    // SAFETY: valid physical device.
    let exts =
        unsafe { instance.enumerate_device_extension_properties(pd) }.vk("vkEnumerateDeviceExtensionProperties")?;
    let has = |n: &CStr| exts.iter().any(|e| e.extension_name_as_c_str() == Ok(n));
    let ray_exts = RAY_EXTENSIONS.iter().all(|n| has(n));

    let mut driver = vk::PhysicalDeviceDriverProperties::default();
    let mut subgroup = vk::PhysicalDeviceSubgroupProperties::default();
    let mut accel_props = vk::PhysicalDeviceAccelerationStructurePropertiesKHR::default();
    let mut p13 = vk::PhysicalDeviceVulkan13Properties::default();
    let mut props2 =
        vk::PhysicalDeviceProperties2::default().push_next(&mut driver).push_next(&mut subgroup).push_next(&mut p13);
    if ray_exts {
        props2 = props2.push_next(&mut accel_props);
    }
    // SAFETY: valid physical device; the chained structs outlive the call.
    unsafe { instance.get_physical_device_properties2(pd, &mut props2) };
    let props = props2.properties;
    let name = props.device_name_as_c_str().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let driver_name = format!(
        "{} {}",
        driver.driver_name_as_c_str().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default(),
        driver.driver_info_as_c_str().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default()
    );
    let v = props.api_version;
    let api_version = (vk::api_version_major(v), vk::api_version_minor(v), vk::api_version_patch(v));

    let mut f12 = vk::PhysicalDeviceVulkan12Features::default();
    let mut f13 = vk::PhysicalDeviceVulkan13Features::default();
    let mut fas = vk::PhysicalDeviceAccelerationStructureFeaturesKHR::default();
    let mut frq = vk::PhysicalDeviceRayQueryFeaturesKHR::default();
    let mut features2 = vk::PhysicalDeviceFeatures2::default().push_next(&mut f12).push_next(&mut f13);
    if ray_exts {
        features2 = features2.push_next(&mut fas).push_next(&mut frq);
    }
    // SAFETY: valid physical device; the chained structs outlive the call.
    unsafe { instance.get_physical_device_features2(pd, &mut features2) };
    let base = features2.features;

    // SAFETY: valid physical device.
    let families = unsafe { instance.get_physical_device_queue_family_properties(pd) };
    let wanted = vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE;
    let presents = |family: usize| {
        present.is_none_or(|p| {
            // SAFETY: valid physical device, family index and surface of this instance.
            unsafe { p.loader.get_physical_device_surface_support(pd, family as u32, p.surface) }.unwrap_or(false)
        })
    };
    let queue_family = families
        .iter()
        .enumerate()
        .position(|(i, f)| f.queue_flags.contains(wanted) && f.timestamp_valid_bits > 0 && presents(i));

    let acceleration_structure =
        ray_exts && fas.acceleration_structure == vk::TRUE && f12.buffer_device_address == vk::TRUE;
    let ray_query = acceleration_structure && frq.ray_query == vk::TRUE;

    let subgroup_arithmetic = subgroup.supported_stages.contains(vk::ShaderStageFlags::COMPUTE)
        && subgroup.supported_operations.contains(
            vk::SubgroupFeatureFlags::BALLOT | vk::SubgroupFeatureFlags::ARITHMETIC | vk::SubgroupFeatureFlags::SHUFFLE,
        );
    let mut missing = Vec::new();
    if api_version < (1, 3, 0) {
        missing.push(format!("Vulkan {}.{} < 1.3", api_version.0, api_version.1));
    }
    if f13.dynamic_rendering != vk::TRUE {
        missing.push("dynamicRendering".into());
    }
    if f13.synchronization2 != vk::TRUE {
        missing.push("synchronization2".into());
    }
    if f13.maintenance4 != vk::TRUE {
        missing.push("maintenance4".into());
    }
    if !subgroup_arithmetic {
        // counters.glsl and gather.comp declare the capabilities even where the tuning leaves
        // them unused.
        missing.push("subgroup ballot, arithmetic and shuffle in compute shaders".into());
    }
    if f12.buffer_device_address != vk::TRUE {
        // The compute BVH's nodes and triangles are read through their addresses (bvh.glsl).
        missing.push("bufferDeviceAddress".into());
    }
    if f12.host_query_reset != vk::TRUE {
        missing.push("hostQueryReset".into());
    }
    if base.shader_int64 != vk::TRUE {
        // The gather's order-independent fixed-point sums.
        missing.push("shaderInt64".into());
    }
    if base.shader_storage_image_write_without_format != vk::TRUE {
        missing.push("shaderStorageImageWriteWithoutFormat".into());
    }
    if !has(khr::push_descriptor::NAME) {
        missing.push("VK_KHR_push_descriptor".into());
    }
    if queue_family.is_none() {
        missing.push(if present.is_some() {
            "a graphics+compute queue with timestamps that presents to the window".into()
        } else {
            "a graphics+compute queue with timestamps".into()
        });
    }
    if present.is_some() && !has(khr::swapchain::NAME) {
        missing.push("VK_KHR_swapchain".into());
    }
    let rejected = (!missing.is_empty()).then(|| format!("lacks {}", missing.join(", ")));

    Ok(DeviceReport {
        index,
        name,
        device_type: DeviceType::from_vk(props.device_type),
        driver: driver_name.trim().to_string(),
        api_version,
        ray_query,
        acceleration_structure,
        push_descriptor: has(khr::push_descriptor::NAME),
        timestamp_period_ns: props.limits.timestamp_period,
        subgroup_size: subgroup.subgroup_size,
        subgroup_arithmetic,
        vendor_id: props.vendor_id,
        scratch_alignment: (accel_props.min_acceleration_structure_scratch_offset_alignment as u64).max(1),
        limits: DeviceLimits {
            max_image_dimension_2d: props.limits.max_image_dimension2_d,
            max_storage_buffer_range: props.limits.max_storage_buffer_range,
            max_buffer_size: p13.max_buffer_size,
            max_compute_work_group_count: props.limits.max_compute_work_group_count,
            max_compute_work_group_invocations: props.limits.max_compute_work_group_invocations,
            max_compute_shared_memory_size: props.limits.max_compute_shared_memory_size,
            max_primitive_count: if ray_exts { accel_props.max_primitive_count } else { 0 },
            device_local_heap: device_local_heap(instance, pd),
            max_per_stage: PerStageLimits {
                storage_buffers: props.limits.max_per_stage_descriptor_storage_buffers,
                storage_images: props.limits.max_per_stage_descriptor_storage_images,
                uniform_buffers: props.limits.max_per_stage_descriptor_uniform_buffers,
                resources: props.limits.max_per_stage_resources,
            },
            max_push_constants_size: props.limits.max_push_constants_size,
        },
        rejected,
        physical: pd,
        queue_family: queue_family.unwrap_or(0) as u32,
    })
}

fn device_local_heap(instance: &ash::Instance, pd: vk::PhysicalDevice) -> u64 {
    // SAFETY: valid physical device.
    let memory = unsafe { instance.get_physical_device_memory_properties(pd) };
    let heaps = &memory.memory_heaps[..memory.memory_heap_count as usize];
    heaps.iter().filter(|h| h.flags.contains(vk::MemoryHeapFlags::DEVICE_LOCAL)).map(|h| h.size).max().unwrap_or(0)
}

/// Picks the device to use: `LEAKLESS_DEVICE` (an index, or a case-insensitive part of the
/// name) if set, else the usable device of the most capable type.
pub(crate) fn choose(reports: &[DeviceReport]) -> Result<&DeviceReport> {
    let usable: Vec<&DeviceReport> = reports.iter().filter(|r| r.rejected.is_none()).collect();
    if usable.is_empty() {
        let why: Vec<String> =
            reports.iter().map(|r| format!("{} ({})", r.name, r.rejected.as_deref().unwrap_or("?"))).collect();
        return Err(DeviceError::NoDevice(if why.is_empty() {
            "the Vulkan loader sees no device (install mesa-vulkan-drivers: tools/install-deps)".into()
        } else {
            format!("rejected: {}", why.join("; "))
        }));
    }
    if let Ok(wanted) = std::env::var("LEAKLESS_DEVICE") {
        let found = match wanted.parse::<usize>() {
            Ok(i) => usable.iter().find(|r| r.index == i),
            Err(_) => usable.iter().find(|r| r.name.to_lowercase().contains(&wanted.to_lowercase())),
        };
        return found.copied().ok_or_else(|| DeviceError::DeviceNotFound {
            wanted,
            usable: usable.iter().map(|r| format!("{}: {}", r.index, r.name)).collect::<Vec<_>>().join(", "),
        });
    }
    Ok(usable.into_iter().min_by_key(|r| (r.device_type, r.index)).expect("non-empty"))
}
