//! Photon tracing (`photons.comp`, docs/architecture.md §1): N light paths from the scene's lights, each
//! storing a photon at every hit after the first (the first is direct light, the direct
//! pass's), at most `max_bounces` per path, appended to a fixed-capacity buffer through an
//! atomic counter that also counts what did not fit.
//!
//! Order: the photon buffer is an atomic append, so the ORDER of photons depends on how the
//! device schedules workgroups; the SET of photons (each tagged with its path and bounce) is a
//! pure function of the scene, the parameters and the seed. [`canonical_order`] sorts them.
//! When the buffer overflows, which photons are dropped depends on that order too.

use ash::vk;
use bytemuck::{Pod, Zeroable};
use leakless_device::{gpu_struct, GpuStruct};
use leakless_graph::{shader_bindings, BufferHandle, Fill, Graph, PassName};

use crate::error::{RenderError, Result};
use crate::gpu_types::Light;
use crate::passes::emission_order::{self, EmissionOrderParams};
use crate::passes::names::group;
use crate::photon_lights::LightHandles;
use crate::pipelines::{compute_pass, ComputePass};
use crate::shaders;
use crate::tuning::DeviceTuning;

gpu_struct! {
    /// `struct Photon` of photon.glsl: 64 bytes, std430.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct Photon {
        pub position: [f32; 3],
        /// The light path that stored it (0..paths).
        pub path: u32,
        /// Geometric normal of the surface hit, facing the incoming photon (unit).
        pub normal: [f32; 3],
        /// Reflections before this hit: 1 for the second hit of the path (the first stored),
        /// up to `max_bounces`; 0 only for first hits stored with `store_direct`.
        pub bounce: u32,
        /// ω_in: the unit direction the photon was travelling when it arrived (so
        /// `dot(normal, direction) < 0`).
        pub direction: [f32; 3],
        /// Index of the light that emitted it (the scene's light order).
        pub light: u32,
        /// RGB flux arriving at the surface (W).
        pub flux: [f32; 3],
        pub pad0: u32,
    }
}

gpu_struct! {
    /// `photon_counters` of photons.comp.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
    pub struct PhotonCounters {
        /// Photons written (at most the capacity).
        pub stored: u32,
        /// Photons dropped because the buffer was full.
        pub overflowed: u32,
        /// Closest-hit rays traced.
        pub rays: u32,
        /// Paths taken by threads whose first path ended (zeroed before the pass).
        pub next_path: u32,
    }
}

gpu_struct! {
    /// `struct PhotonLight` of photons.comp: one light's entry of the selection CDF.
    #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
    pub struct PhotonLight {
        /// power_rgb / p(light) (W): a path from this light carries `flux / paths`. For an
        /// emissive triangle 1 / p: the shader multiplies by the power where it emits.
        pub flux: [f32; 3],
        /// Σ p over the lights up to this one; the last emitting light's (and later ones') is 1.
        pub cdf: f32,
    }
}

gpu_struct! {
    /// The `PhotonParams` push constants of photons.comp.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct PhotonPush {
        pub scene_center: [f32; 3],
        pub scene_radius: f32,
        pub paths: u32,
        pub max_bounces: u32,
        pub seed: u32,
        pub capacity: u32,
        pub light_count: u32,
        pub store_direct: u32,
        pub path_offset: u32,
        /// Threads dispatched; paths beyond them are taken by threads whose path ended.
        pub threads: u32,
        /// 1: threads take paths in emission order (emission_order.rs); 0: in index order.
        pub ordered: u32,
        /// Punctual lights at the start of the light table; emissive triangles follow.
        pub punctual_count: u32,
        pub pad1: u32,
        pub pad2: u32,
    }
}

shader_bindings! {
    /// What photons.comp binds besides the scene and the trace structures.
    pub struct PhotonBindings {
        lights: read array(Light::LAYOUT),
        photon_lights: read array(PhotonLight::LAYOUT),
        photons: write array(Photon::LAYOUT),
        photon_counters: read_write block(PhotonCounters::LAYOUT),
        path_order: read words,
    }
    pub struct PhotonResources;
}

/// What one photon-tracing run does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PhotonParams {
    /// Light paths N.
    pub paths: u32,
    /// Stored hits per path at most (hits 2..=max_bounces + 1): the reference path tracer's
    /// indirect bounces.
    pub max_bounces: u32,
    /// Scrambles the low-discrepancy sequence: same seed, same photons.
    pub seed: u32,
    /// Diagnostic: also store the first hit (bounce 0), i.e. the emitted light arriving
    /// directly. Off in rendering, where the direct pass computes direct light.
    pub store_direct: bool,
    /// Index of path 0 in the low-discrepancy sequence: frame i of an accumulation traces
    /// paths i·N .. (i+1)·N of one sequence, so frames continue it rather than reseed.
    pub path_offset: u32,
    /// Threads take paths grouped by emission cell (emission_order.rs): the same photons,
    /// stored in another order, sooner. Off for `leakless-capped`, whose cap keeps the first
    /// photons of a list: in emission order they would come from one part of the light.
    pub emission_order: bool,
    /// Paths each thread traces; `None`: the device tuning's
    /// ([`DeviceTuning::paths_per_thread`]). Tests
    /// trace the same paths both ways on one device.
    pub paths_per_thread: Option<u32>,
}

impl Default for PhotonParams {
    fn default() -> Self {
        PhotonParams {
            paths: 10_000,
            max_bounces: 8,
            seed: 0,
            store_direct: false,
            path_offset: 0,
            emission_order: true,
            paths_per_thread: None,
        }
    }
}

/// Bytes of a photon buffer holding `capacity` photons.
pub fn photon_buffer_size(capacity: u32) -> u64 {
    capacity as u64 * std::mem::size_of::<Photon>() as u64
}

/// Usages of the photon buffer: storage, plus transfer source so tests and tools can read the
/// photons back. The counters are also zeroed by a transfer and copied out for the stats.
pub const PHOTON_BUFFER_USAGE: vk::BufferUsageFlags = vk::BufferUsageFlags::from_raw(
    vk::BufferUsageFlags::STORAGE_BUFFER.as_raw()
        | vk::BufferUsageFlags::TRANSFER_SRC.as_raw()
        | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS.as_raw(),
);
pub const COUNTER_BUFFER_USAGE: vk::BufferUsageFlags = vk::BufferUsageFlags::from_raw(
    vk::BufferUsageFlags::STORAGE_BUFFER.as_raw()
        | vk::BufferUsageFlags::TRANSFER_DST.as_raw()
        | vk::BufferUsageFlags::TRANSFER_SRC.as_raw(),
);

const PHOTON_COUNTERS: PassName = PassName::new("photon counters", group::PHOTONS);

compute_pass! {
    pub static PHOTONS in FRAME_PASSES: ComputePass<PhotonBindings, PhotonPush> =
        ComputePass::traced(
            PassName::new("photons", group::PHOTONS),
            (&shaders::PHOTONS_COMP_RAYQUERY, &shaders::PHOTONS_COMP_COMPUTE),
            &[],
        ).specialize(DeviceTuning::counters);
}

/// Adds two passes: "photon counters" zeroes `counters` (a transfer), then "photons"
/// traces `params.paths` light paths, appending at most `capacity` photons to `photons`
/// and counting them in `counters` ([`PhotonCounters`]), `tuning.paths_per_thread` paths a
/// thread unless `params` says otherwise.
#[allow(clippy::too_many_arguments)]
pub fn add<'r>(
    graph: &mut Graph<'r>,
    params: &PhotonParams,
    tuning: &DeviceTuning,
    lights: &LightHandles,
    photons: &mut BufferHandle,
    capacity: u32,
    counters: &mut BufferHandle,
) -> Result<()> {
    let table = &lights.table;
    if photons.size() < photon_buffer_size(capacity) {
        return Err(RenderError::Settings(format!(
            "photon buffer holds {} bytes; capacity {capacity} needs {}",
            photons.size(),
            photon_buffer_size(capacity)
        )));
    }
    let counter_size = std::mem::size_of::<PhotonCounters>() as u64;
    if counters.size() < counter_size {
        return Err(RenderError::Settings(format!(
            "photon counter buffer holds {} bytes; it needs {counter_size}",
            counters.size()
        )));
    }
    let per_thread = params.paths_per_thread.unwrap_or(tuning.paths_per_thread).max(1);
    // No emitting light, or no path: nothing to trace (the counters still read zero).
    let paths = if table.emits() { params.paths } else { 0 };
    let push = PhotonPush {
        scene_center: table.center.to_array(),
        scene_radius: table.radius,
        paths,
        max_bounces: params.max_bounces,
        seed: params.seed,
        capacity,
        light_count: table.entries.len() as u32,
        store_direct: params.store_direct as u32,
        path_offset: params.path_offset,
        threads: paths.div_ceil(per_thread),
        ordered: params.emission_order as u32,
        punctual_count: table.punctual as u32,
        ..Default::default()
    };

    graph.fill(PHOTON_COUNTERS, &mut [(&mut *counters, &[Fill::range(0, counter_size, 0)])]);

    // Without the order the buffer is bound but not read.
    let ordered_paths = if params.emission_order { paths } else { 0 };
    let order =
        EmissionOrderParams { paths: ordered_paths, path_offset: params.path_offset, seed: params.seed, pad0: 0 };
    let path_order = emission_order::add(graph, order)?;

    let resources = PhotonResources {
        path_order: &path_order,
        lights: &lights.lights,
        photon_lights: &lights.photon_lights,
        photons,
        photon_counters: counters,
    };
    PHOTONS.add(graph, resources, push, [push.threads, 1, 1]);
    Ok(())
}
