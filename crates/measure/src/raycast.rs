//! Tracing lists of rays on one backend: what the backend-agreement tests and `bench rays`
//! drive. Shares the scene upload, trace structures and pass machinery with the renderer.

use ash::vk;
use glam::Vec3;
use leakless_device::{Buffer, BufferDesc, Gpu, MemoryLocation};
use leakless_graph::GraphRunner;
use leakless_scene::Scene;

use leakless::error::Result;
use leakless::gpu_scene::GpuScene;
use leakless::gpu_types::{GpuRay, RayHit};
use leakless::passes::names;
use leakless::passes::raycast::{self, RayWork, RaycastBindings, RaycastParams, RAYCAST, RAYCAST_COUNTING};
use leakless::pipelines::{ComputePass, ComputePassDef, Pipelines};
use leakless::trace::{Backend, TraceScene};
use leakless::tuning::{DeviceTuning, TuningChoice};

/// What a [`RayCaster`] runs: the timed pass, and in a set of its own the counting one.
static PASSES: &[&ComputePassDef] = &[RAYCAST.def()];
static COUNTING_PASSES: &[&ComputePassDef] = &[RAYCAST_COUNTING.def()];

pub struct RayCaster<'g> {
    gpu: &'g Gpu,
    scene: GpuScene,
    trace: TraceScene,
    /// The scene at t = 0 (these tools do not play animations).
    pose: leakless::scene_pose::ScenePose,
    pipelines: Pipelines,
    /// The compute backend's counting pass (`None` on ray queries, which count nothing).
    counting: Option<Pipelines>,
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
        let pose = leakless::scene_pose::ScenePose::new(scene, &gpu_scene.bvh.bvh);
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
            counting: match backend {
                Backend::Compute => Some(Pipelines::new(gpu, COUNTING_PASSES, backend, &tuning)?),
                Backend::RayQuery => None,
            },
            backend,
            runner,
        })
    }

    pub fn trace_scene(&self) -> &TraceScene {
        &self.trace
    }

    /// Traces `rays`: closest hits, or occlusion (`occlusion`: triangle 0 = occluded).
    pub fn cast(&mut self, rays: &[GpuRay], occlusion: bool) -> Result<Cast> {
        let (hits, _, trace_ms) = self.run(&RAYCAST, rays, occlusion)?;
        Ok(Cast { hits, trace_ms, hits_written_to: HITS_LOCATION })
    }

    /// What the compute traversal does for each of `rays` (nodes processed, triangles tested),
    /// traced again by the counting pass; `None` on ray queries.
    pub fn count_work(&mut self, rays: &[GpuRay], occlusion: bool) -> Result<Option<Vec<RayWork>>> {
        if self.counting.is_none() {
            return Ok(None);
        }
        Ok(Some(self.run(&RAYCAST_COUNTING, rays, occlusion)?.1))
    }

    /// Traces `rays` with the pass `def`: the hits, each ray's work (zeros unless `def` counts)
    /// and the pass's time.
    fn run(
        &mut self,
        def: &ComputePass<RaycastBindings, RaycastParams>,
        rays: &[GpuRay],
        occlusion: bool,
    ) -> Result<(Vec<RayHit>, Vec<RayWork>, f64)> {
        let ray_buffer =
            Buffer::with_data(self.gpu, "rays", vk::BufferUsageFlags::STORAGE_BUFFER, bytemuck::cast_slice(rays))?;
        let hit_size = std::mem::size_of_val(rays) as u64 / 2;
        let work_size = (rays.len().max(1) * std::mem::size_of::<RayWork>()) as u64;
        let device_local = |name, size| BufferDesc {
            name,
            size,
            usage: vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC,
            location: HITS_LOCATION,
        };
        let for_host = |name, size| BufferDesc {
            name,
            size,
            usage: vk::BufferUsageFlags::TRANSFER_DST,
            location: MemoryLocation::GpuToCpu,
        };
        let hit_buffer = Buffer::new(self.gpu, &device_local("ray hits", hit_size))?;
        let work_buffer = Buffer::new(self.gpu, &device_local("ray work", work_size))?;
        let hits_for_host = Buffer::new(self.gpu, &for_host("ray hits for the host", hit_size))?;
        let work_for_host = Buffer::new(self.gpu, &for_host("ray work for the host", work_size))?;
        let pipelines = if def.name == RAYCAST_COUNTING.name { self.counting.as_ref() } else { Some(&self.pipelines) };
        let pipelines = pipelines.expect("count_work checked the counting pipelines");
        let mut graph = self.runner.graph(self.gpu)?.with_pipelines(pipelines.table(self.backend));
        let scene = self.scene.import(&mut graph);
        let trace = self.trace.import(&mut graph, &self.scene, &self.pose)?;
        leakless::frame_set::bind(&mut graph, &scene, &trace);
        let rays_h = graph.import_buffer(&ray_buffer);
        let mut hits_h = graph.import_buffer(&hit_buffer);
        let mut work_h = graph.import_buffer(&work_buffer);
        let mut hits_host = graph.import_buffer(&hits_for_host);
        let mut work_host = graph.import_buffer(&work_for_host);
        let cast = (rays.len() as u32, occlusion);
        raycast::add(&mut graph, def, cast, &rays_h, &mut hits_h, &mut work_h);
        // The copies for the host are a pass of their own, outside the timed one.
        let mut copy = graph.pass(names::READBACK);
        let copies =
            [(&hits_h, &mut hits_host, hit_size), (&work_h, &mut work_host, work_size)].map(|(from, into, size)| {
                (
                    copy.read(from, leakless_graph::Access::TransferRead),
                    copy.write(into, leakless_graph::Access::TransferWrite),
                    size,
                )
            });
        copy.record(move |ctx| {
            for (from, into, size) in copies {
                ctx.cmd.copy_buffer(ctx.buffer(from), ctx.buffer(into), size);
            }
            Ok(())
        });
        let mut host = graph.pass(names::TO_HOST);
        host.read(&hits_host, leakless_graph::Access::HostRead);
        host.read(&work_host, leakless_graph::Access::HostRead);
        host.record(|_| Ok(()));
        let submitted = graph.submit(&Default::default())?;
        let done = self.runner.wait_for(self.gpu, submitted)?;
        let trace_ms =
            done.timings.iter().find(|t| t.name == def.name.label).map_or(0.0, |t| t.wall_ms.unwrap_or(t.ms));
        Ok((hits_for_host.read_vec(rays.len())?, work_for_host.read_vec(rays.len())?, trace_ms))
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
