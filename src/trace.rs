//! The trace backends (docs/architecture.md §3): which one runs, the scene structures each needs, and how
//! a tracing pass binds them. Shaders see one interface (`trace.glsl`); the Rust side sees
//! [`TraceScene`], built once per scene, and [`TraceHandles`], imported once per frame.

use leakless_accel::{Bvh, BvhStats, RayQueryAccel, RayQueryStats, BVH_NODE_LAYOUT, BVH_TRIANGLE_LAYOUT};
use leakless_device::shader::ShaderInfo;
use leakless_device::{gpu_struct, vk, BindingDecl, Bound, Buffer, Capabilities, Gpu, GpuStruct};
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

    pub fn resolve(self, caps: Capabilities, device: &str) -> Result<Backend> {
        match self {
            Self::Auto if caps.ray_query => Ok(Backend::RayQuery),
            Self::Auto | Self::Compute => Ok(Backend::Compute),
            Self::RayQuery if caps.ray_query => Ok(Backend::RayQuery),
            Self::RayQuery => Err(RenderError::Settings(format!(
                "--backend rayquery: {device} has no VK_KHR_ray_query (use --backend compute or auto)"
            ))),
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

// One per scene, built once and never moved in a hot path: no need to box the larger one.
#[allow(clippy::large_enum_variant)]
enum Structures {
    RayQuery(RayQueryAccel),
    Compute { nodes: Buffer, triangles: Buffer },
}

/// The scene's trace structures for one backend.
pub struct TraceScene {
    backend: Backend,
    structures: Structures,
    /// The `trace_scale` uniform.
    scale: Buffer,
    stats: TraceStats,
}

impl TraceScene {
    pub fn build(gpu: &Gpu, scene: &Scene, gpu_scene: &GpuScene, backend: Backend) -> Result<TraceScene> {
        let triangles = scene.triangle_count() as u32;
        let (structures, stats) = match backend {
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
                (Structures::RayQuery(accel), stats)
            }
            Backend::Compute => {
                let bvh = Bvh::build(&scene.vertices)?;
                let BvhStats { build_ms, node_count, bytes, sah_cost, .. } = bvh.stats.clone();
                let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
                let nodes = Buffer::with_data(gpu, "bvh nodes", storage, bytemuck::cast_slice(&bvh.nodes))?;
                let tris = Buffer::with_data(gpu, "bvh triangles", storage, bytemuck::cast_slice(&bvh.triangles))?;
                let stats = TraceStats {
                    backend,
                    build_ms,
                    bytes: bytes as u64,
                    detail: format!("{node_count} nodes, {triangles} triangles, SAH cost {sah_cost:.1}"),
                };
                (Structures::Compute { nodes, triangles: tris }, stats)
            }
        };
        let scale = TraceScale { scene_scale: scene_scale(scene), ..Default::default() };
        let scale =
            Buffer::with_data(gpu, "trace scale", vk::BufferUsageFlags::UNIFORM_BUFFER, bytemuck::bytes_of(&scale))?;
        Ok(TraceScene { backend, structures, scale, stats })
    }

    pub fn backend(&self) -> Backend {
        self.backend
    }

    pub fn stats(&self) -> &TraceStats {
        &self.stats
    }

    pub fn import<'r>(&'r self, graph: &mut Graph<'r>) -> TraceHandles {
        let structures = match &self.structures {
            Structures::RayQuery(accel) => HandledStructures::RayQuery {
                tlas: accel.tlas.raw(),
                tlas_buffer: graph.import_buffer(accel.tlas.buffer()),
                blas_buffer: graph.import_buffer(accel.blas.buffer()),
            },
            Structures::Compute { nodes, triangles } => HandledStructures::Compute {
                nodes: graph.import_buffer(nodes),
                triangles: graph.import_buffer(triangles),
            },
        };
        TraceHandles { structures, scale: graph.import_buffer(&self.scale) }
    }
}

enum HandledStructures {
    RayQuery { tlas: vk::AccelerationStructureKHR, tlas_buffer: BufferHandle, blas_buffer: BufferHandle },
    Compute { nodes: BufferHandle, triangles: BufferHandle },
}

/// The trace structures of one frame's graph.
pub struct TraceHandles {
    structures: HandledStructures,
    scale: BufferHandle,
}

impl TraceHandles {
    /// Declares that `pass` traces rays.
    pub fn declare(&self, pass: &mut PassBuilder<'_, '_>) -> TraceBindings {
        let trace_scale = pass.read(&self.scale, Access::ComputeRead);
        match &self.structures {
            HandledStructures::RayQuery { tlas, tlas_buffer, blas_buffer } => {
                // Traversal reads the BLAS through the TLAS: both are declared, only the TLAS
                // is bound.
                pass.read(tlas_buffer, Access::RayQueryRead);
                pass.read(blas_buffer, Access::RayQueryRead);
                TraceBindings::RayQuery(RayQueryTrace { tlas: *tlas, trace_scale })
            }
            HandledStructures::Compute { nodes, triangles } => TraceBindings::Compute(ComputeTrace {
                bvh_nodes: pass.read(nodes, Access::ComputeRead),
                bvh_triangles: pass.read(triangles, Access::ComputeRead),
                trace_scale,
            }),
        }
    }
}
