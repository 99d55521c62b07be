//! Tracing lists of rays on one backend: what the backend-agreement tests and `bench rays`
//! drive. Shares the scene upload, trace structures and pass machinery with the renderer.

use ash::vk;
use glam::Vec3;
use leakless_device::{Buffer, BufferDesc, Gpu, MemoryLocation};
use leakless_graph::GraphRunner;
use leakless_scene::Scene;

use crate::error::Result;
use crate::gpu_scene::GpuScene;
use crate::gpu_types::{GpuRay, RayHit};
use crate::passes::names;
use crate::passes::raycast::{self, RAYCAST};
use crate::pipelines::{ComputePassDef, Pipelines};
use crate::trace::{Backend, TraceScene};
use crate::tuning::{DeviceTuning, TuningChoice};

/// What a [`RayCaster`] runs.
static PASSES: &[&ComputePassDef] = &[&RAYCAST];

pub struct RayCaster<'g> {
    gpu: &'g Gpu,
    scene: GpuScene,
    trace: TraceScene,
    /// The scene at t = 0 (these tools do not play animations).
    pose: crate::scene_pose::ScenePose,
    pipelines: Pipelines,
    backend: Backend,
    runner: GraphRunner,
}

/// The hits of one batch, and how long the GPU took to trace it.
pub struct Cast {
    pub hits: Vec<RayHit>,
    /// Time of the raycast pass alone (upload and readback excluded), as the device tuning
    /// times: its own submission's host wall time on a CPU device, its GPU timestamps on a GPU.
    pub trace_ms: f64,
    /// Where the timed pass wrote its hits: device-local memory, copied for the host by a
    /// pass after it, so that the time is the traversal's and not a discrete GPU's writes
    /// across the bus to host memory (which timed 230–245 Mrays/s for every kind of ray).
    pub hits_written_to: MemoryLocation,
}

/// Where the raycast pass writes its hits (see [`Cast::hits_written_to`]).
const HITS_LOCATION: MemoryLocation = MemoryLocation::GpuOnly;

impl<'g> RayCaster<'g> {
    pub fn new(gpu: &'g Gpu, scene: &Scene, backend: Backend) -> Result<Self> {
        let gpu_scene = GpuScene::upload(gpu, scene)?;
        let pose = crate::scene_pose::ScenePose::new(scene, &gpu_scene.bvh.bvh);
        let trace = TraceScene::build(gpu, scene, &gpu_scene, &pose, backend)?;
        let tuning = DeviceTuning::choose(gpu.report(), TuningChoice::Auto);
        let mut runner = GraphRunner::new(gpu, 1)?;
        runner.set_timing(tuning.timing);
        Ok(RayCaster {
            gpu,
            scene: gpu_scene,
            trace,
            pose,
            pipelines: Pipelines::new(gpu, PASSES, backend, &tuning)?,
            backend,
            runner,
        })
    }

    pub fn trace_scene(&self) -> &TraceScene {
        &self.trace
    }

    /// Traces `rays`: closest hits, or occlusion (`occlusion`: triangle 0 = occluded).
    pub fn cast(&mut self, rays: &[GpuRay], occlusion: bool) -> Result<Cast> {
        let ray_buffer =
            Buffer::with_data(self.gpu, "rays", vk::BufferUsageFlags::STORAGE_BUFFER, bytemuck::cast_slice(rays))?;
        let hit_size = std::mem::size_of_val(rays) as u64 / 2;
        let desc = BufferDesc {
            name: "ray hits",
            size: hit_size,
            usage: vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC,
            location: HITS_LOCATION,
        };
        let hit_buffer = Buffer::new(self.gpu, &desc)?;
        let host_desc = BufferDesc {
            name: "ray hits for the host",
            usage: vk::BufferUsageFlags::TRANSFER_DST,
            location: MemoryLocation::GpuToCpu,
            ..desc
        };
        let host_buffer = Buffer::new(self.gpu, &host_desc)?;
        let mut graph = self.runner.graph(self.gpu)?.with_pipelines(self.pipelines.table(self.backend));
        let scene = self.scene.import(&mut graph);
        let trace = self.trace.import(&mut graph, &self.scene, &self.pose)?;
        let rays_h = graph.import_buffer(&ray_buffer);
        let mut hits_h = graph.import_buffer(&hit_buffer);
        let mut host_h = graph.import_buffer(&host_buffer);
        raycast::add(&mut graph, rays.len() as u32, occlusion, &scene, &trace, &rays_h, &mut hits_h);
        // The copy for the host is a pass of its own, outside the timed one.
        let mut copy = graph.pass(names::READBACK);
        let from = copy.read(&hits_h, leakless_graph::Access::TransferRead);
        let into = copy.write(&mut host_h, leakless_graph::Access::TransferWrite);
        copy.record(move |ctx| {
            ctx.cmd.copy_buffer(ctx.buffer(from), ctx.buffer(into), hit_size);
            Ok(())
        });
        let mut host = graph.pass(names::TO_HOST);
        host.read(&host_h, leakless_graph::Access::HostRead);
        host.record(|_| Ok(()));
        let submitted = graph.submit(&Default::default())?;
        let done = self.runner.wait_for(self.gpu, submitted)?;
        let trace_ms = done.timings.iter().find(|t| t.name == "raycast").map_or(0.0, |t| t.wall_ms.unwrap_or(t.ms));
        Ok(Cast { hits: host_buffer.read_vec(rays.len())?, trace_ms, hits_written_to: HITS_LOCATION })
    }
}

/// Moves `p` off its surface along `n` exactly as `offset_ray` in trace.glsl does (a fixed
/// number of float ULPs, a fixed fraction of `scene_scale` near the origin), so CPU-made rays
/// start where the GPU's would.
pub fn offset_ray(p: Vec3, n: Vec3, scene_scale: f32) -> Vec3 {
    let origin = scene_scale / 32.0;
    let float_scale = scene_scale / 65536.0;
    const INT_SCALE: f32 = 256.0;
    let axis = |p: f32, n: f32| {
        let of = (INT_SCALE * n) as i32;
        let moved = f32::from_bits((p.to_bits() as i32).wrapping_add(if p < 0.0 { -of } else { of }) as u32);
        if p.abs() < origin {
            p + float_scale * n
        } else {
            moved
        }
    };
    Vec3::new(axis(p.x, n.x), axis(p.y, n.y), axis(p.z, n.z))
}
