//! Acceleration structures (`VK_KHR_acceleration_structure`): the objects, their build sizes
//! and the commands that build, measure and compact them. Which structures to build, and in
//! what order, is the acceleration-structure builder's business (crate `leakless-accel`).

use std::sync::Arc;

use ash::{khr, vk};

use crate::error::{DeviceError, Result, VkContext};
use crate::gpu::{Gpu, Shared};
use crate::memory::{Buffer, BufferDesc, MemoryLocation};
use crate::Cmd;

/// What a structure is built from.
#[derive(Clone, Copy)]
pub enum AccelGeometry<'a> {
    /// A triangle list of `triangle_count` triangles, vertex positions as three floats at the
    /// start of each `stride`-byte vertex. `opaque: false` makes every candidate hit visible
    /// to the shader (alpha-masked materials).
    Triangles { vertices: &'a Buffer, stride: u64, triangle_count: u32, opaque: bool },
    /// `count` instances (`vk::AccelerationStructureInstanceKHR`) for a top-level structure.
    Instances { instances: &'a Buffer, count: u32 },
}

impl<'a> AccelGeometry<'a> {
    fn level(&self) -> vk::AccelerationStructureTypeKHR {
        match self {
            AccelGeometry::Triangles { .. } => vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL,
            AccelGeometry::Instances { .. } => vk::AccelerationStructureTypeKHR::TOP_LEVEL,
        }
    }

    fn primitive_count(&self) -> u32 {
        match *self {
            AccelGeometry::Triangles { triangle_count, .. } => triangle_count,
            AccelGeometry::Instances { count, .. } => count,
        }
    }

    fn vk(&self) -> Result<vk::AccelerationStructureGeometryKHR<'a>> {
        let address = |b: &Buffer| {
            b.device_address()
                .ok_or_else(|| DeviceError::Unsupported(format!("buffer {} has no device address", b.name())))
        };
        Ok(match *self {
            AccelGeometry::Triangles { vertices, stride, triangle_count, opaque } => {
                vk::AccelerationStructureGeometryKHR::default()
                    .geometry_type(vk::GeometryTypeKHR::TRIANGLES)
                    .flags(if opaque { vk::GeometryFlagsKHR::OPAQUE } else { vk::GeometryFlagsKHR::empty() })
                    .geometry(vk::AccelerationStructureGeometryDataKHR {
                        triangles: vk::AccelerationStructureGeometryTrianglesDataKHR::default()
                            .vertex_format(vk::Format::R32G32B32_SFLOAT)
                            .vertex_data(vk::DeviceOrHostAddressConstKHR { device_address: address(vertices)? })
                            .vertex_stride(stride)
                            .max_vertex((3 * triangle_count).saturating_sub(1))
                            .index_type(vk::IndexType::NONE_KHR),
                    })
            }
            AccelGeometry::Instances { instances, .. } => vk::AccelerationStructureGeometryKHR::default()
                .geometry_type(vk::GeometryTypeKHR::INSTANCES)
                .geometry(vk::AccelerationStructureGeometryDataKHR {
                    instances: vk::AccelerationStructureGeometryInstancesDataKHR::default()
                        .data(vk::DeviceOrHostAddressConstKHR { device_address: address(instances)? }),
                }),
        })
    }
}

/// Sizes a build needs, from the driver (never constants: lavapipe and GPUs differ widely).
#[derive(Clone, Copy, Debug)]
pub struct AccelSizes {
    pub structure: u64,
    pub scratch: u64,
}

fn ext(shared: &Shared) -> Result<&khr::acceleration_structure::Device> {
    shared
        .accel
        .as_ref()
        .ok_or_else(|| DeviceError::Unsupported("acceleration structures are not enabled on this device".into()))
}

fn build_info<'a>(
    level: vk::AccelerationStructureTypeKHR,
    geometries: &'a [vk::AccelerationStructureGeometryKHR<'a>],
    allow_compaction: bool,
) -> vk::AccelerationStructureBuildGeometryInfoKHR<'a> {
    let mut flags = vk::BuildAccelerationStructureFlagsKHR::PREFER_FAST_TRACE;
    if allow_compaction {
        flags |= vk::BuildAccelerationStructureFlagsKHR::ALLOW_COMPACTION;
    }
    vk::AccelerationStructureBuildGeometryInfoKHR::default()
        .ty(level)
        .flags(flags)
        .mode(vk::BuildAccelerationStructureModeKHR::BUILD)
        .geometries(geometries)
}

/// The sizes of building `geometry`.
pub fn accel_build_sizes(gpu: &Gpu, geometry: &AccelGeometry<'_>, allow_compaction: bool) -> Result<AccelSizes> {
    let geometries = [geometry.vk()?];
    let info = build_info(geometry.level(), &geometries, allow_compaction);
    let mut sizes = vk::AccelerationStructureBuildSizesInfoKHR::default();
    // SAFETY: the extension is enabled; `info` describes one geometry with one count.
    unsafe {
        ext(&gpu.shared)?.get_acceleration_structure_build_sizes(
            vk::AccelerationStructureBuildTypeKHR::DEVICE,
            &info,
            &[geometry.primitive_count()],
            &mut sizes,
        )
    };
    Ok(AccelSizes { structure: sizes.acceleration_structure_size, scratch: sizes.build_scratch_size })
}

/// A bottom- or top-level acceleration structure and the buffer holding it.
pub struct AccelerationStructure {
    shared: Arc<Shared>,
    raw: vk::AccelerationStructureKHR,
    buffer: Buffer,
    address: vk::DeviceAddress,
    level: vk::AccelerationStructureTypeKHR,
}

impl AccelerationStructure {
    pub fn new(gpu: &Gpu, name: &str, top_level: bool, size: u64) -> Result<Self> {
        let level = if top_level {
            vk::AccelerationStructureTypeKHR::TOP_LEVEL
        } else {
            vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL
        };
        let buffer = Buffer::new(
            gpu,
            &BufferDesc {
                name,
                size,
                usage: vk::BufferUsageFlags::ACCELERATION_STRUCTURE_STORAGE_KHR
                    | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS,
                location: MemoryLocation::GpuOnly,
            },
        )?;
        let info = vk::AccelerationStructureCreateInfoKHR::default().buffer(buffer.raw()).size(size).ty(level);
        let ext = ext(&gpu.shared)?;
        // SAFETY: the buffer has the storage usage and `size` bytes.
        let raw = unsafe { ext.create_acceleration_structure(&info, None) }.vk("vkCreateAccelerationStructureKHR")?;
        gpu.set_name(raw, name);
        // SAFETY: `raw` is a live structure of this device.
        let address = unsafe {
            ext.get_acceleration_structure_device_address(
                &vk::AccelerationStructureDeviceAddressInfoKHR::default().acceleration_structure(raw),
            )
        };
        Ok(AccelerationStructure { shared: gpu.shared.clone(), raw, buffer, address, level })
    }

    pub fn raw(&self) -> vk::AccelerationStructureKHR {
        self.raw
    }
    /// The buffer behind the structure: what the pass graph orders accesses on.
    pub fn buffer(&self) -> &Buffer {
        &self.buffer
    }
    pub fn device_address(&self) -> vk::DeviceAddress {
        self.address
    }
    pub fn size(&self) -> u64 {
        self.buffer.size()
    }
    pub fn is_top_level(&self) -> bool {
        self.level == vk::AccelerationStructureTypeKHR::TOP_LEVEL
    }
}

impl Drop for AccelerationStructure {
    fn drop(&mut self) {
        if let Ok(ext) = ext(&self.shared) {
            // SAFETY: no pending work uses the structure (submissions are waited for).
            unsafe { ext.destroy_acceleration_structure(self.raw, None) };
        }
    }
}

/// An instance of `blas` in a top-level structure, with a row-major 3×4 transform.
pub fn accel_instance(
    blas: &AccelerationStructure,
    transform: [f32; 12],
    custom_index: u32,
) -> vk::AccelerationStructureInstanceKHR {
    vk::AccelerationStructureInstanceKHR {
        transform: vk::TransformMatrixKHR { matrix: transform },
        instance_custom_index_and_mask: vk::Packed24_8::new(custom_index, 0xff),
        instance_shader_binding_table_record_offset_and_flags: vk::Packed24_8::new(0, 0),
        acceleration_structure_reference: vk::AccelerationStructureReferenceKHR {
            device_handle: blas.device_address(),
        },
    }
}

/// A buffer holding `instances`, ready to build a top-level structure from.
pub fn accel_instances(gpu: &Gpu, instances: &[vk::AccelerationStructureInstanceKHR]) -> Result<Buffer> {
    // SAFETY: AccelerationStructureInstanceKHR is a repr(C) struct of 64 bytes without padding
    // (a 48-byte matrix, two packed u32 and a u64 handle), so its bytes are fully initialised.
    let bytes =
        unsafe { std::slice::from_raw_parts(instances.as_ptr().cast::<u8>(), std::mem::size_of_val(instances)) };
    Buffer::with_data(
        gpu,
        "tlas instances",
        vk::BufferUsageFlags::ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_KHR
            | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS,
        bytes,
    )
}

/// A pool of compacted-size queries.
pub struct AccelSizeQueries {
    shared: Arc<Shared>,
    raw: vk::QueryPool,
    count: u32,
}

impl AccelSizeQueries {
    pub fn new(gpu: &Gpu, count: u32) -> Result<Self> {
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::ACCELERATION_STRUCTURE_COMPACTED_SIZE_KHR)
            .query_count(count);
        // SAFETY: valid device; the query type is available with the extension.
        let raw = unsafe { gpu.device().create_query_pool(&info, None) }.vk("vkCreateQueryPool")?;
        // SAFETY: hostQueryReset is enabled; nothing uses the new pool.
        unsafe { gpu.device().reset_query_pool(raw, 0, count) };
        Ok(AccelSizeQueries { shared: gpu.shared.clone(), raw, count })
    }

    /// The compacted sizes, after the work that wrote them completed.
    pub fn read(&self) -> Result<Vec<u64>> {
        let mut sizes = vec![0u64; self.count as usize];
        // SAFETY: every query was written by completed work.
        unsafe {
            self.shared.device.get_query_pool_results(
                self.raw,
                0,
                &mut sizes,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .vk("vkGetQueryPoolResults")?;
        Ok(sizes)
    }
}

impl Drop for AccelSizeQueries {
    fn drop(&mut self) {
        // SAFETY: no pending work uses the pool.
        unsafe { self.shared.device.destroy_query_pool(self.raw, None) };
    }
}

/// Scratch memory aligned as the device requires.
pub fn accel_scratch(gpu: &Gpu, size: u64) -> Result<Buffer> {
    let align = gpu.scratch_alignment();
    Buffer::new(
        gpu,
        &BufferDesc {
            name: "acceleration structure scratch",
            size: size + align,
            usage: vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS,
            location: MemoryLocation::GpuOnly,
        },
    )
}

impl Cmd<'_> {
    /// Builds `dst` from `geometry` using `scratch` (from [`accel_scratch`]).
    pub fn build_acceleration_structure(
        &mut self,
        dst: &AccelerationStructure,
        geometry: &AccelGeometry<'_>,
        scratch: &Buffer,
        allow_compaction: bool,
    ) -> Result<()> {
        let geometries = [geometry.vk()?];
        let align = self.gpu.scratch_alignment();
        let scratch_address = scratch
            .device_address()
            .ok_or_else(|| DeviceError::Unsupported("scratch buffer has no device address".into()))?;
        let info = build_info(geometry.level(), &geometries, allow_compaction)
            .dst_acceleration_structure(dst.raw)
            .scratch_data(vk::DeviceOrHostAddressKHR { device_address: scratch_address.div_ceil(align) * align });
        let range = [vk::AccelerationStructureBuildRangeInfoKHR::default().primitive_count(geometry.primitive_count())];
        // SAFETY: dst, scratch and inputs are live, sized from accel_build_sizes, and ordered by
        // the pass graph's barriers.
        unsafe { ext(&self.gpu.shared)?.cmd_build_acceleration_structures(self.raw, &[info], &[&range]) };
        Ok(())
    }

    /// Writes the compacted size of `src` into query `index` of `queries`.
    pub fn write_compacted_size(
        &mut self,
        src: &AccelerationStructure,
        queries: &AccelSizeQueries,
        index: u32,
    ) -> Result<()> {
        // SAFETY: the build of `src` completed before this (graph barrier); the query was reset.
        unsafe {
            ext(&self.gpu.shared)?.cmd_write_acceleration_structures_properties(
                self.raw,
                &[src.raw],
                vk::QueryType::ACCELERATION_STRUCTURE_COMPACTED_SIZE_KHR,
                queries.raw,
                index,
            )
        };
        Ok(())
    }

    /// Copies `src` into the smaller `dst`, compacting it.
    pub fn compact_acceleration_structure(
        &mut self,
        src: &AccelerationStructure,
        dst: &AccelerationStructure,
    ) -> Result<()> {
        let info = vk::CopyAccelerationStructureInfoKHR::default()
            .src(src.raw)
            .dst(dst.raw)
            .mode(vk::CopyAccelerationStructureModeKHR::COMPACT);
        // SAFETY: `src` was built with compaction allowed and `dst` holds its compacted size.
        unsafe { ext(&self.gpu.shared)?.cmd_copy_acceleration_structure(self.raw, &info) };
        Ok(())
    }
}
