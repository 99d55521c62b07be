//! A self-contained photon tracer (tests, benchmarks): the photon pass and the passes it
//! calls, on one backend, into host-visible buffers with a guard region after the capacity, so
//! that what a trace stores, and that it writes nothing past its capacity, can be checked.

use ash::vk;
use leakless::error::Result;
use leakless::gpu_scene::{gpu_light, GpuScene};
use leakless::gpu_types::Light;
use leakless::passes::photon_clearance::{Clearance, Needed};
use leakless::passes::photons::{
    self, photon_buffer_size, Photon, PhotonCounters, PhotonParams, COUNTER_BUFFER_USAGE, PHOTONS, PHOTON_BUFFER_USAGE,
};
use leakless::passes::{emission_order, names, photon_clearance, photon_dispatch, scan};
use leakless::photon_lights::{upload_lights, LightTable};
use leakless::pipelines::{ComputePassDef, Pipelines};
use leakless::scene_pose::ScenePose;
use leakless::trace::{Backend, TraceScene};
use leakless::tuning::{DeviceTuning, TuningChoice};
use leakless_device::{Buffer, BufferDesc, Gpu, MemoryLocation};
use leakless_graph::{Access, GraphRunner, Timing};
use leakless_scene::Scene;

/// Sorts photons by (path, bounce): a canonical order independent of scheduling.
pub fn canonical_order(photons: &mut [Photon]) {
    photons.sort_by_key(|p| (p.path, p.bounce));
}

/// Photons of one run, read back.
#[derive(Clone, Debug)]
pub struct PhotonTrace {
    /// The stored photons, in buffer order (see [`canonical_order`]).
    pub photons: Vec<Photon>,
    pub counters: PhotonCounters,
    /// Whether the guard region after the capacity still holds its fill pattern: nothing was
    /// written out of bounds.
    pub guard_intact: bool,
    /// Host wall time of the photon-tracing submission alone (ms).
    pub trace_ms: f64,
}

/// Photons per guard region after the capacity ([`PhotonTracer`]).
pub const GUARD_PHOTONS: u32 = 64;
const GUARD_WORD: u32 = 0xdead_beef;

/// The passes a [`PhotonTracer`] runs (a pass `add` calls must be listed here too).
static TRACER_PASSES: &[&ComputePassDef] = &[
    PHOTONS.def(),
    emission_order::EMISSION_CELLS.def(),
    scan::SCAN.def(),
    emission_order::EMISSION_ORDER.def(),
    photon_dispatch::PHOTON_DISPATCH.def(),
    photon_clearance::PHOTON_CLEARANCE.def(),
];

/// A self-contained photon tracer on one backend (tests, benchmarks): uploads the scene,
/// builds its trace structures, and traces into host-visible buffers with a guard region
/// after the capacity.
pub struct PhotonTracer<'g> {
    gpu: &'g Gpu,
    scene: GpuScene,
    trace: TraceScene,
    /// The scene at t = 0 (these tools do not play animations).
    pose: ScenePose,
    lights: Vec<leakless_scene::Light>,
    bounds: leakless_scene::Aabb,
    pipelines: Pipelines,
    backend: Backend,
    /// Paths per thread, when a test overrides the tuning's.
    paths_per_thread: Option<u32>,
    capacity: u32,
    photons: Buffer,
    counters: Buffer,
    runner: GraphRunner,
}

impl<'g> PhotonTracer<'g> {
    pub fn new(gpu: &'g Gpu, scene: &Scene, backend: Backend, capacity: u32) -> Result<Self> {
        let gpu_scene = GpuScene::upload(gpu, scene)?;
        let pose = ScenePose::new(scene, &gpu_scene.bvh.bvh);
        let trace = TraceScene::build(gpu, scene, &gpu_scene, &pose, backend)?;
        let photons = Buffer::new(
            gpu,
            &BufferDesc {
                name: "photons",
                size: photon_buffer_size(capacity + GUARD_PHOTONS),
                usage: PHOTON_BUFFER_USAGE,
                location: MemoryLocation::GpuToCpu,
            },
        )?;
        let counters = Buffer::new(
            gpu,
            &BufferDesc {
                name: "photon counters",
                size: std::mem::size_of::<PhotonCounters>() as u64,
                usage: COUNTER_BUFFER_USAGE,
                location: MemoryLocation::GpuToCpu,
            },
        )?;
        let mut runner = GraphRunner::new(gpu, 1)?;
        runner.set_timing(Timing::PerPassSubmit);
        Ok(PhotonTracer {
            gpu,
            scene: gpu_scene,
            trace,
            pose,
            lights: scene.lights.clone(),
            bounds: scene.bounds(),
            pipelines: Pipelines::new(
                gpu,
                TRACER_PASSES,
                backend,
                &DeviceTuning::choose(gpu.report(), TuningChoice::Auto),
            )?,
            backend,
            paths_per_thread: None,
            capacity,
            photons,
            counters,
            runner,
        })
    }

    /// Paths each thread traces, overriding the device tuning's ([`PhotonParams`]).
    pub fn set_paths_per_thread(&mut self, paths_per_thread: u32) {
        self.paths_per_thread = Some(paths_per_thread.max(1));
    }

    /// The light table photons are emitted from.
    pub fn light_table(&self) -> LightTable {
        let lights: Vec<Light> = self.lights.iter().map(gpu_light).collect();
        LightTable::new(&lights, &self.scene.emitter_table, &self.bounds)
    }

    pub fn trace(&mut self, params: &PhotonParams) -> Result<PhotonTrace> {
        Ok(self.run(params, None)?.0)
    }

    /// Traces, then computes the stored photons' clearance (photon_clearance.comp) searching
    /// up to `max_radius`, and reads both back: the clearance in photon order.
    pub fn trace_with_clearance(
        &mut self,
        params: &PhotonParams,
        max_radius: f32,
    ) -> Result<(PhotonTrace, Vec<Clearance>)> {
        let (trace, clearance) = self.run(params, Some(max_radius))?;
        Ok((trace, clearance.unwrap_or_default()))
    }

    fn run(
        &mut self,
        params: &PhotonParams,
        clearance_radius: Option<f32>,
    ) -> Result<(PhotonTrace, Option<Vec<Clearance>>)> {
        let capacity = self.capacity;
        // Fill the whole buffer (photons and guard) with the pattern: no stale photon of an
        // earlier run can pass for a new one, and the guard shows any write past the capacity.
        let words = (capacity + GUARD_PHOTONS) as usize * std::mem::size_of::<Photon>() / 4;
        self.photons.write(0, bytemuck::cast_slice(&vec![GUARD_WORD; words]))?;
        let clearance_buffer = match clearance_radius {
            Some(_) => Some(Buffer::new(
                self.gpu,
                &BufferDesc {
                    name: "photon clearance",
                    size: capacity.max(1) as u64 * std::mem::size_of::<Clearance>() as u64,
                    usage: vk::BufferUsageFlags::STORAGE_BUFFER,
                    location: MemoryLocation::GpuToCpu,
                },
            )?),
            None => None,
        };
        let mut graph = self.runner.graph(self.gpu)?.with_pipelines(self.pipelines.table(self.backend));
        let scene = self.scene.import(&mut graph);
        let trace = self.trace.import(&mut graph, &self.scene, &self.pose)?;
        leakless::frame_set::bind(&mut graph, &scene, &trace);
        let lights = upload_lights(&mut graph, &self.lights, &self.scene.emitter_table, &self.bounds)?;
        let mut photons = graph.import_buffer(&self.photons);
        let mut counters = graph.import_buffer(&self.counters);
        // The pass writes up to the capacity, never into the guard after it.
        let params = PhotonParams { paths_per_thread: params.paths_per_thread.or(self.paths_per_thread), ..*params };
        photons::add(&mut graph, &params, self.pipelines.tuning(), &lights, &mut photons, capacity, &mut counters)?;
        let mut clearance = clearance_buffer.as_ref().map(|b| graph.import_buffer(b));
        if let (Some(out), Some(radius)) = (&mut clearance, clearance_radius) {
            let dispatch = photon_dispatch::add(&mut graph, &counters, capacity)?;
            photon_clearance::add(&mut graph, &photons, &counters, &dispatch, radius, Needed::All, out)?;
        }
        let mut host = graph.pass(names::TO_HOST);
        host.read(&photons, Access::HostRead);
        host.read(&counters, Access::HostRead);
        if let Some(c) = &clearance {
            host.read(c, Access::HostRead);
        }
        host.record(|_| Ok(()));
        let submitted = graph.submit(&Default::default())?;
        let done = self.runner.wait_for(self.gpu, submitted)?;
        let trace_ms =
            done.timings.iter().find(|t| t.name == PHOTONS.name.label).and_then(|t| t.wall_ms).unwrap_or(0.0);
        let counters: PhotonCounters = self.counters.read_vec(1)?[0];
        let all: Vec<Photon> = self.photons.read_vec((capacity + GUARD_PHOTONS) as usize)?;
        let stored = (counters.stored.min(capacity)) as usize;
        let guard_intact =
            bytemuck::cast_slice::<Photon, u32>(&all[capacity as usize..]).iter().all(|&w| w == GUARD_WORD);
        let clearance = match &clearance_buffer {
            Some(b) => Some(b.read_vec::<Clearance>(stored)?),
            None => None,
        };
        Ok((PhotonTrace { photons: all[..stored].to_vec(), counters, guard_intact, trace_ms }, clearance))
    }
}
/// Traces `params` once in `scene` on `backend` with room for `capacity` photons.
pub fn trace_photons(
    gpu: &Gpu,
    scene: &Scene,
    backend: Backend,
    params: &PhotonParams,
    capacity: u32,
) -> Result<PhotonTrace> {
    PhotonTracer::new(gpu, scene, backend, capacity)?.trace(params)
}
