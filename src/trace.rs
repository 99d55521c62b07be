//! The trace backends (docs/architecture.md §3): which one runs, the scene structures each needs, and how
//! a tracing pass binds them. Shaders see one interface (`trace.glsl`); the Rust side sees
//! [`TraceScene`], built once per scene, and [`TraceHandles`], imported once per frame.

use leakless_accel::{Bvh, BvhStats, RayQueryAccel, RayQueryStats, BVH_NODE_LAYOUT, BVH_TRIANGLE_LAYOUT};
use leakless_device::shader::ShaderInfo;
use leakless_device::{gpu_struct, vk, BindingDecl, Bound, Buffer, Capabilities, DeviceType, Gpu, GpuStruct};
use leakless_graph::{shader_bindings, Access, Bindings, BufferHandle, Graph, PassBuilder, Resolved};
use leakless_scene::{Scene, Vertex};

use crate::error::{RenderError, Result};
use crate::gpu_scene::GpuScene;

/// What the user asked for (`--backend`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BackendChoice {
    /// Ray queries when the device has them, else the compute BVH.
    #[default]
    Auto,
    RayQuery,
    Compute,
}

/// A backend choice resolved on a device.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ResolvedBackend {
    pub backend: Backend,
    /// Why this backend (for `leakless info`, the stats and the overlay).
    pub why: &'static str,
}

/// The backend that runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Backend {
    RayQuery,
    Compute,
}

impl BackendChoice {
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "auto" => Some(Self::Auto),
            "rayquery" => Some(Self::RayQuery),
            "compute" => Some(Self::Compute),
            _ => None,
        }
    }

    /// Whether the device must be opened with ray tracing enabled.
    pub fn wants_ray_queries(self) -> bool {
        self != Self::Compute
    }

    /// The backend that runs on a device, and why. `auto` picks what the device is best at:
    /// ray queries on a GPU that has them; the compute BVH on a CPU device such as lavapipe,
    /// where it is faster than the device's ray queries (`leakless bench rays`: up to 2× on
    /// the sphere, and the leak scenes' visibility rays) and watertight where lavapipe's ray
    /// queries are not (tests/trace.rs); the compute BVH on any device without ray queries.
    pub fn resolve(self, caps: Capabilities, device_type: DeviceType, device: &str) -> Result<ResolvedBackend> {
        let (backend, why) = match self {
            Self::Compute => (Backend::Compute, "forced by --backend compute"),
            Self::RayQuery if caps.ray_query => (Backend::RayQuery, "forced by --backend rayquery"),
            Self::RayQuery => {
                return Err(RenderError::Settings(format!(
                    "--backend rayquery: {device} has no VK_KHR_ray_query (use --backend compute or auto)"
                )))
            }
            Self::Auto if !caps.ray_query => (Backend::Compute, "auto: the device has no ray queries"),
            Self::Auto if device_type == DeviceType::Cpu => (
                Backend::Compute,
                "auto: a CPU device, where the compute BVH is faster than its ray queries and watertight",
            ),
            Self::Auto => (Backend::RayQuery, "auto: a GPU with ray queries"),
        };
        Ok(ResolvedBackend { backend, why })
    }

    /// What `--backend` calls it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::RayQuery => "rayquery",
            Self::Compute => "compute",
        }
    }
}

impl Backend {
    pub fn name(self) -> &'static str {
        match self {
            Backend::RayQuery => "rayquery",
            Backend::Compute => "compute",
        }
    }

    /// The variant of a tracing shader compiled for this backend.
    pub fn pick(self, rayquery: &'static ShaderInfo, compute: &'static ShaderInfo) -> &'static ShaderInfo {
        match self {
            Backend::RayQuery => rayquery,
            Backend::Compute => compute,
        }
    }

    /// What `trace.glsl` binds on this backend.
    pub fn bindings(self) -> &'static [BindingDecl] {
        match self {
            Backend::RayQuery => RayQueryTrace::DECLS,
            Backend::Compute => ComputeTrace::DECLS,
        }
    }
}

gpu_struct! {
    /// The `TraceScale` block of trace.glsl.
    #[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
    pub struct TraceScale {
        pub scene_scale: f32,
        pub pad0: f32,
        pub pad1: f32,
        pub pad2: f32,
    }
}

shader_bindings! {
    /// What `trace.glsl` binds with `TRACE_RAYQUERY`.
    pub struct RayQueryTrace {
        tlas: accel,
        trace_scale: uniform(TraceScale::LAYOUT),
    }
}

shader_bindings! {
    /// What `trace.glsl` binds with `TRACE_COMPUTE`.
    pub struct ComputeTrace {
        bvh_nodes: array(BVH_NODE_LAYOUT),
        bvh_triangles: array(BVH_TRIANGLE_LAYOUT),
        trace_scale: uniform(TraceScale::LAYOUT),
    }
}

/// A tracing pass's trace bindings, on whichever backend runs.
#[derive(Clone, Copy, Debug)]
pub enum TraceBindings {
    RayQuery(RayQueryTrace),
    Compute(ComputeTrace),
}

impl Bindings for TraceBindings {
    fn bind<'a>(&self, res: Resolved<'a>, out: &mut Vec<(&'static str, Bound<'a>)>) {
        match self {
            TraceBindings::RayQuery(b) => b.bind(res, out),
            TraceBindings::Compute(b) => b.bind(res, out),
        }
    }
}

/// The size offsets are relative to: the scene's bounding radius.
pub fn scene_scale(scene: &Scene) -> f32 {
    scene.bounds().bounding_radius().max(f32::MIN_POSITIVE)
}

/// Build cost of the trace structures, for `--stats`.
#[derive(Clone, Debug)]
pub struct TraceStats {
    pub backend: Backend,
    pub build_ms: f64,
    pub bytes: u64,
    pub detail: String,
}

/// The scene's trace structures for one backend: the ray-query backend's BLAS and TLAS; the
/// compute backend needs nothing beyond the BVH every `GpuScene` has.
pub struct TraceScene {
    backend: Backend,
    accel: Option<RayQueryAccel>,
    stats: TraceStats,
}

impl TraceScene {
    pub fn build(gpu: &Gpu, scene: &Scene, gpu_scene: &GpuScene, backend: Backend) -> Result<TraceScene> {
        let triangles = scene.triangle_count() as u32;
        let (accel, stats) = match backend {
            Backend::RayQuery => {
                let opaque = scene.materials.iter().all(|m| m.alpha_cutoff.is_none());
                let accel = RayQueryAccel::build(
                    gpu,
                    &gpu_scene.vertices,
                    std::mem::size_of::<Vertex>() as u64,
                    triangles,
                    opaque,
                )?;
                let RayQueryStats { build_ms, blas_bytes, blas_uncompacted_bytes, tlas_bytes, scratch_bytes } =
                    accel.stats.clone();
                let stats = TraceStats {
                    backend,
                    build_ms,
                    bytes: blas_bytes + tlas_bytes,
                    detail: format!(
                        "BLAS {blas_bytes} B (uncompacted {blas_uncompacted_bytes} B), TLAS {tlas_bytes} B, scratch {scratch_bytes} B"
                    ),
                };
                (Some(accel), stats)
            }
            Backend::Compute => {
                let BvhStats { build_ms, node_count, bytes, sah_cost, .. } = gpu_scene.bvh.stats.clone();
                let stats = TraceStats {
                    backend,
                    build_ms,
                    bytes: bytes as u64,
                    detail: format!("{node_count} nodes, {triangles} triangles, SAH cost {sah_cost:.1}"),
                };
                (None, stats)
            }
        };
        Ok(TraceScene { backend, accel, stats })
    }

    pub fn backend(&self) -> Backend {
        self.backend
    }

    pub fn stats(&self) -> &TraceStats {
        &self.stats
    }

    /// The structures in one frame's graph, with the scene's BVH (`gpu_scene`) that the
    /// compute backend traverses and every backend's clearance pass searches.
    pub fn import<'r>(&'r self, graph: &mut Graph<'r>, gpu_scene: &'r GpuScene) -> TraceHandles {
        let rayquery = self.accel.as_ref().map(|accel| RayQueryHandles {
            tlas: accel.tlas.raw(),
            tlas_buffer: graph.import_buffer(accel.tlas.buffer()),
            blas_buffer: graph.import_buffer(accel.blas.buffer()),
        });
        let bvh = &gpu_scene.bvh;
        TraceHandles {
            rayquery,
            nodes: graph.import_buffer(&bvh.nodes),
            triangles: graph.import_buffer(&bvh.triangles),
            scale: graph.import_buffer(&bvh.scale),
        }
    }
}

/// The scene's BVH on the GPU (what the compute backend traverses), and the `trace_scale`
/// uniform every tracing pass binds.
pub struct SceneBvh {
    pub nodes: Buffer,
    pub triangles: Buffer,
    pub scale: Buffer,
    pub stats: BvhStats,
}

impl SceneBvh {
    pub fn build(gpu: &Gpu, scene: &Scene) -> Result<SceneBvh> {
        let bvh = Bvh::build(&scene.vertices)?;
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let nodes = Buffer::with_data(gpu, "bvh nodes", storage, bytemuck::cast_slice(&bvh.nodes))?;
        let triangles = Buffer::with_data(gpu, "bvh triangles", storage, bytemuck::cast_slice(&bvh.triangles))?;
        let scale = TraceScale { scene_scale: scene_scale(scene), ..Default::default() };
        let scale =
            Buffer::with_data(gpu, "trace scale", vk::BufferUsageFlags::UNIFORM_BUFFER, bytemuck::bytes_of(&scale))?;
        Ok(SceneBvh { nodes, triangles, scale, stats: bvh.stats.clone() })
    }
}

struct RayQueryHandles {
    tlas: vk::AccelerationStructureKHR,
    tlas_buffer: BufferHandle,
    blas_buffer: BufferHandle,
}

/// The trace structures of one frame's graph.
pub struct TraceHandles {
    rayquery: Option<RayQueryHandles>,
    nodes: BufferHandle,
    triangles: BufferHandle,
    scale: BufferHandle,
}

impl TraceHandles {
    /// Declares that `pass` traces rays.
    pub fn declare(&self, pass: &mut PassBuilder<'_, '_>) -> TraceBindings {
        match &self.rayquery {
            Some(rq) => {
                let trace_scale = pass.read(&self.scale, Access::ComputeRead);
                // Traversal reads the BLAS through the TLAS: both are declared, only the TLAS
                // is bound.
                pass.read(&rq.tlas_buffer, Access::RayQueryRead);
                pass.read(&rq.blas_buffer, Access::RayQueryRead);
                TraceBindings::RayQuery(RayQueryTrace { tlas: rq.tlas, trace_scale })
            }
            None => TraceBindings::Compute(self.declare_bvh(pass)),
        }
    }

    /// Declares that `pass` searches the scene's BVH (on any backend).
    pub fn declare_bvh(&self, pass: &mut PassBuilder<'_, '_>) -> ComputeTrace {
        ComputeTrace {
            bvh_nodes: pass.read(&self.nodes, Access::ComputeRead),
            bvh_triangles: pass.read(&self.triangles, Access::ComputeRead),
            trace_scale: pass.read(&self.scale, Access::ComputeRead),
        }
    }
}
