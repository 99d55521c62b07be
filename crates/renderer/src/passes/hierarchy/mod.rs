//! The view-sample cluster hierarchy (Moreau et al. 2016), rebuilt every frame from the
//! G-buffer: the bounds of the view samples, their Morton codes, a radix sort, then the node
//! levels bottom up. Every pixel is a sample (pixels without a surface sort last and leave
//! their nodes empty), so the tree's shape depends only on the image size and the branching
//! factor, and is known on the CPU.

pub mod build;
pub mod morton;
pub mod sample_bounds;

use ash::vk;
use bytemuck::{Pod, Zeroable};
use leakless_device::{gpu_struct, BufferDesc, MemoryLocation};
use leakless_graph::{BufferHandle, Graph, ImageHandle};

use crate::error::{RenderError, Result};
use crate::passes::gbuffer::GBufferHandles;
use crate::passes::sort;

gpu_struct! {
    /// `struct SamplePosition` of hierarchy.glsl: a sorted sample's position, `valid` 0 where
    /// its pixel has no surface.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct SamplePosition {
        pub position: [f32; 3],
        pub valid: u32,
    }
}

gpu_struct! {
    /// `struct Node` of hierarchy.glsl.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct Node {
        pub bounds_min: [f32; 3],
        pub first_child: u32,
        pub bounds_max: [f32; 3],
        pub child_count: u32,
        pub cone_axis: [f32; 3],
        pub cone_angle: f32,
        pub level: u32,
        pub valid_samples: u32,
        /// The largest gather radius of its valid samples (each sample's own:
        /// visible_disk.comp grows or shrinks it where the sample's disk is partial).
        pub radius_max: f32,
        pub pad0: u32,
    }
}

gpu_struct! {
    /// `struct Level` of hierarchy.glsl.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
    pub struct Level {
        pub offset: u32,
        pub count: u32,
        pub span: u32,
        pub pad0: u32,
    }
}

/// Pending nodes the splat's stack holds (`SPLAT_STACK` in splat.comp).
pub const SPLAT_STACK: u32 = 192;

/// The tree's shape for `sample_count` samples and branching factor B.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Shape {
    pub branching: u32,
    pub sample_count: u32,
    /// Level 0 = leaves; the last level holds the root alone.
    pub levels: Vec<Level>,
}

impl Shape {
    pub fn new(sample_count: u32, branching: u32) -> Result<Shape> {
        if !(2..=64).contains(&branching) {
            return Err(RenderError::Settings(format!("--branching {branching} must be within 2..=64")));
        }
        let mut levels = Vec::new();
        let (mut count, mut span, mut offset) = (sample_count.div_ceil(branching).max(1), branching as u64, 0u32);
        loop {
            levels.push(Level { offset, count, span: span.min(u32::MAX as u64) as u32, pad0: 0 });
            offset += count;
            if count == 1 {
                break;
            }
            count = count.div_ceil(branching);
            span *= branching as u64;
        }
        let shape = Shape { branching, sample_count, levels };
        let pending = shape.levels.len() as u32 * (branching - 1) + 1;
        if pending > SPLAT_STACK {
            return Err(RenderError::Settings(format!(
                "a {}-level hierarchy of branching {branching} needs {pending} stack entries in the splat; it has {SPLAT_STACK}",
                shape.levels.len()
            )));
        }
        Ok(shape)
    }

    pub fn node_count(&self) -> u32 {
        self.levels.iter().map(|l| l.count).sum()
    }

    pub fn root(&self) -> u32 {
        self.node_count() - 1
    }
}

/// The hierarchy of one frame (buffers of the graph's pool).
pub struct HierarchyHandles {
    /// Morton keys in sorted order (`INVALID_SAMPLE_KEY` last).
    pub keys: BufferHandle,
    /// Pixel index of each sorted sample.
    pub samples: BufferHandle,
    /// Position of each sorted sample ([`SamplePosition`]), written by the leaves' build where the
    /// splat tests a wide leaf's samples (`DeviceTuning::leaf_samples`); unwritten otherwise.
    pub positions: BufferHandle,
    pub bounds: BufferHandle,
    pub levels: BufferHandle,
    pub nodes: BufferHandle,
}

const HIERARCHY_BUFFER_USAGE: vk::BufferUsageFlags = vk::BufferUsageFlags::from_raw(
    vk::BufferUsageFlags::STORAGE_BUFFER.as_raw()
        | vk::BufferUsageFlags::TRANSFER_DST.as_raw()
        | vk::BufferUsageFlags::TRANSFER_SRC.as_raw()
        | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS.as_raw(),
);

impl HierarchyHandles {
    /// The sample bounds buffer (min keys, then max keys, three words each), as the pool
    /// knows it: the capture reads the last frame's through it.
    pub fn sample_bounds_desc() -> BufferDesc<'static> {
        BufferDesc { name: "sample bounds", size: 24, usage: HIERARCHY_BUFFER_USAGE, location: MemoryLocation::GpuOnly }
    }

    pub fn new(graph: &mut Graph<'_>, shape: &Shape) -> Result<HierarchyHandles> {
        let n = shape.sample_count as u64;
        let mut storage = |name, size| {
            graph.buffer(&BufferDesc { name, size, usage: HIERARCHY_BUFFER_USAGE, location: MemoryLocation::GpuOnly })
        };
        let keys = storage("morton keys", 4 * n)?;
        let samples = storage("sorted samples", 4 * n)?;
        let positions = storage("sorted sample positions", std::mem::size_of::<SamplePosition>() as u64 * n)?;
        let nodes = storage("hierarchy nodes", shape.node_count() as u64 * std::mem::size_of::<Node>() as u64)?;
        let bounds = graph.buffer(&Self::sample_bounds_desc())?;
        let levels = graph.upload(
            "hierarchy levels",
            vk::BufferUsageFlags::STORAGE_BUFFER,
            bytemuck::cast_slice(&shape.levels),
        )?;
        Ok(HierarchyHandles { keys, samples, positions, bounds, levels, nodes })
    }
}

/// Adds the passes that rebuild the hierarchy of `shape` from the G-buffer and each sample's
/// gather radius (`disk_mass`'s `.g`, visible_disk.rs).
pub fn add<'r>(
    graph: &mut Graph<'r>,
    frame: &BufferHandle,
    gbuffer: &GBufferHandles,
    disk_mass: &ImageHandle,
    shape: &Shape,
    h: &mut HierarchyHandles,
) -> Result<()> {
    sample_bounds::add(graph, frame, gbuffer, &mut h.bounds);
    morton::add(graph, frame, gbuffer, &h.bounds, &mut h.keys, &mut h.samples);
    sort::add(graph, shape.sample_count, 30, &mut h.keys, &mut h.samples)?;
    build::add(graph, shape, gbuffer, disk_mass, h);
    Ok(())
}
