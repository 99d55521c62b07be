//! The trace backends (docs/architecture.md §3): which one runs, the scene structures each needs, and how
//! a tracing pass binds them. Shaders see one interface (`trace.glsl`); the Rust side sees
//! [`TraceScene`], built once per scene, and [`TraceHandles`], imported once per frame.

use leakless_accel::rayquery::BlasInput;
use leakless_accel::{
    BvhStats, InstancedBvh, PartInput, RayQueryAccel, RayQueryStats, BVH_INSTANCE_LAYOUT, BVH_NODE_LAYOUT,
    BVH_TRIANGLE_LAYOUT,
};
use leakless_device::shader::ShaderInfo;
use leakless_device::{gpu_struct, vk, Buffer, Capabilities, DeviceType, Gpu, GpuStruct};
use leakless_graph::{shader_bindings, Access, BufferHandle, Graph, PassBuilder, Stage};
use leakless_scene::{Scene, Vertex};

use crate::device_address::address_words;
use crate::error::{RenderError, Result};
use crate::gpu_scene::GpuScene;
use crate::scene_pose::ScenePose;

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
    pub const ALL: [BackendChoice; 3] = [Self::Auto, Self::RayQuery, Self::Compute];

    /// Whether the device must be opened with ray tracing enabled.
    pub fn wants_ray_queries(self) -> bool {
        self != Self::Compute
    }

    /// The backend that runs on a device, and why. `auto` picks what the device is best at:
    /// ray queries on a GPU that has them; the compute BVH on a CPU device such as lavapipe,
    /// where it is faster than the device's ray queries (`leakless bench rays`: up to 2× on
    /// the sphere, and the leak scenes' visibility rays) and watertight where lavapipe's ray
    /// queries are not (tests/suite/trace.rs); the compute BVH on any device without ray queries.
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

crate::value_enum!(BackendChoice);
crate::value_enum!(Backend);

impl Backend {
    pub const ALL: [Backend; 2] = [Backend::RayQuery, Backend::Compute];

    /// What `--backend` calls it.
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
}

gpu_struct! {
    /// The `TraceScale` block of trace.glsl.
    #[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
    pub struct TraceScale {
        pub scene_scale: f32,
        /// Where the scene is one static part, its bottom-level root, else `u32::MAX`: the
        /// compute traversal then starts at it (trace_compute.glsl).
        pub static_root: u32,
        pub pad1: f32,
        pub pad2: f32,
        /// The device addresses of the BVH's nodes and triangles (bvh.glsl).
        pub bvh_nodes_address: [u32; 2],
        pub bvh_triangles_address: [u32; 2],
        /// That part's box (padded, as the top level holds it).
        pub static_min: [f32; 3],
        pub pad3: u32,
        pub static_max: [f32; 3],
        pub pad4: u32,
    }
}

shader_bindings! {
    /// What `trace.glsl` binds with `TRACE_RAYQUERY`.
    pub struct RayQueryTrace {
        tlas: read accel,
        trace_scale: read uniform(TraceScale::LAYOUT),
    }
    pub struct RayQueryTraceResources;
}

shader_bindings! {
    /// What `trace.glsl` binds with `TRACE_COMPUTE`.
    pub struct ComputeTrace {
        bvh_nodes: read array(BVH_NODE_LAYOUT),
        bvh_triangles: read array(BVH_TRIANGLE_LAYOUT),
        trace_scale: read uniform(TraceScale::LAYOUT),
        bvh_top: read array(BVH_NODE_LAYOUT),
        bvh_instances: read array(BVH_INSTANCE_LAYOUT),
    }
    pub struct ComputeTraceResources;
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

/// The scene's trace structures for one backend: the ray-query backend's BLASes (the static
/// part in the scene's vertex buffer, each instance's from its own buffer of mesh-space
/// vertices) and TLAS; the compute backend needs nothing beyond the BVH every `GpuScene` has.
pub struct TraceScene {
    backend: Backend,
    accel: Option<RayQueryAccel>,
    /// Mesh-space vertices of each instance, the input of its BLAS.
    _instance_vertices: Vec<Buffer>,
    /// The pose version the TLAS was last built for (see `ScenePose::version`).
    tlas_version: std::cell::Cell<u64>,
    stats: TraceStats,
}

impl TraceScene {
    pub fn build(
        gpu: &Gpu,
        scene: &Scene,
        gpu_scene: &GpuScene,
        pose: &ScenePose,
        backend: Backend,
    ) -> Result<TraceScene> {
        let triangles = scene.triangle_count() as u32;
        let mut instance_vertices = Vec::new();
        let (accel, stats) = match backend {
            Backend::RayQuery => {
                let opaque = scene.materials.iter().all(|m| m.alpha_cutoff.is_none());
                let usage = vk::BufferUsageFlags::ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_KHR
                    | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS;
                for i in &scene.instances {
                    let bytes = bytemuck::cast_slice(&i.local_vertices);
                    instance_vertices.push(Buffer::with_data(gpu, &format!("{} vertices", i.name), usage, bytes)?);
                }
                // The instances' mesh-space `Vertex`es, and the static part's positions alone.
                let stride = std::mem::size_of::<Vertex>() as u64;
                let static_count = scene.static_triangle_count() as u32;
                let static_part = (static_count > 0).then_some(BlasInput {
                    vertices: &gpu_scene.vertices.positions,
                    stride: std::mem::size_of::<[f32; 3]>() as u64,
                    triangle_count: static_count,
                    first_triangle: 0,
                });
                let parts: Vec<BlasInput> = static_part
                    .into_iter()
                    .chain(scene.instances.iter().zip(&instance_vertices).map(|(i, v)| BlasInput {
                        vertices: v,
                        stride,
                        triangle_count: i.triangle_count,
                        first_triangle: i.first_triangle,
                    }))
                    .collect();
                let accel = RayQueryAccel::build(gpu, &parts, &pose.tlas_transforms(), opaque)?;
                let RayQueryStats {
                    build_ms,
                    blas_bytes,
                    blas_uncompacted_bytes,
                    tlas_bytes,
                    scratch_bytes,
                    blas_count,
                } = accel.stats.clone();
                let stats = TraceStats {
                    backend,
                    build_ms,
                    bytes: blas_bytes + tlas_bytes,
                    detail: format!(
                        "{blas_count} BLAS {blas_bytes} B (uncompacted {blas_uncompacted_bytes} B), TLAS {tlas_bytes} B, scratch {scratch_bytes} B"
                    ),
                };
                (Some(accel), stats)
            }
            Backend::Compute => {
                let BvhStats { build_ms, node_count, bytes, sah_cost, .. } = gpu_scene.bvh.bvh.stats.clone();
                let parts = gpu_scene.bvh.bvh.parts.len();
                let stats = TraceStats {
                    backend,
                    build_ms,
                    bytes: bytes as u64,
                    detail: format!("{node_count} nodes, {triangles} triangles, {parts} parts, SAH cost {sah_cost:.1}"),
                };
                (None, stats)
            }
        };
        let tlas_version = std::cell::Cell::new(pose.version);
        Ok(TraceScene { backend, accel, _instance_vertices: instance_vertices, tlas_version, stats })
    }

    pub fn backend(&self) -> Backend {
        self.backend
    }

    pub fn stats(&self) -> &TraceStats {
        &self.stats
    }

    /// The structures in one frame's graph, with the scene's BVH (`gpu_scene`) that the
    /// compute backend traverses and every backend's clearance pass searches. The top level of
    /// `pose` goes up with the frame; when the pose changed since the TLAS was built, the frame
    /// rebuilds it first.
    pub fn import<'r>(
        &'r self,
        graph: &mut Graph<'r>,
        gpu_scene: &'r GpuScene,
        pose: &ScenePose,
    ) -> Result<TraceHandles> {
        let rayquery = match &self.accel {
            Some(accel) => {
                let mut tlas_buffer = graph.import_buffer(accel.tlas.buffer());
                let blas_buffers: Vec<BufferHandle> =
                    accel.blases.iter().map(|b| graph.import_buffer(b.buffer())).collect();
                if self.tlas_version.get() != pose.version {
                    accel.add_rebuild(graph, &pose.tlas_transforms(), &mut tlas_buffer, &blas_buffers)?;
                    self.tlas_version.set(pose.version);
                }
                Some(RayQueryHandles { tlas: accel.tlas.raw(), tlas_buffer, blas_buffers })
            }
            None => None,
        };
        let bvh = &gpu_scene.bvh;
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        Ok(TraceHandles {
            rayquery,
            nodes: graph.import_buffer(&bvh.nodes),
            triangles: graph.import_buffer(&bvh.triangles),
            scale: graph.import_buffer(&bvh.scale),
            top: graph.upload("bvh top", storage, bytemuck::cast_slice(&pose.top.nodes))?,
            instances: graph.upload("bvh instances", storage, bytemuck::cast_slice(&pose.top.instances))?,
        })
    }
}

/// The scene's BVH on the GPU (what the compute backend traverses): the bottom level of every
/// part, built once; and the `trace_scale` uniform every tracing pass binds.
pub struct SceneBvh {
    pub nodes: Buffer,
    pub triangles: Buffer,
    pub scale: Buffer,
    /// The host side: the parts, which every frame's top level is built over.
    pub bvh: InstancedBvh,
}

impl SceneBvh {
    pub fn build(gpu: &Gpu, scene: &Scene) -> Result<SceneBvh> {
        let static_end = scene.static_triangle_count() * 3;
        let static_part =
            (static_end > 0).then(|| PartInput { vertices: &scene.vertices[..static_end], first_triangle: 0 });
        let instances: Vec<PartInput> = scene
            .instances
            .iter()
            .map(|i| PartInput { vertices: &i.local_vertices, first_triangle: i.first_triangle })
            .collect();
        let b = scene.animated_bounds();
        let magnitude = b.min.abs().max(b.max.abs()).max_element();
        let mut bvh = InstancedBvh::build(static_part, &instances, magnitude)?;
        // limits::check bounded the triangles; the node count is known only now (about one a
        // triangle, at most two).
        let range = gpu.report().limits.max_storage_buffer_range as usize;
        let node_bytes = std::mem::size_of_val(&bvh.nodes[..]);
        if node_bytes > range {
            return Err(RenderError::Limit(format!(
                "the scene's BVH needs {node_bytes} bytes of nodes ({} triangles), above the device's maxStorageBufferRange ({range})",
                scene.triangle_count()
            )));
        }
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS;
        let nodes = Buffer::with_data(gpu, "bvh nodes", storage, bytemuck::cast_slice(&bvh.nodes))?;
        let triangles = Buffer::with_data(gpu, "bvh triangles", storage, bytemuck::cast_slice(&bvh.triangles))?;
        // Only the parts are needed from here on.
        (bvh.nodes, bvh.triangles) = (Vec::new(), Vec::new());
        // A scene of one static part: the compute traversal starts at that part (trace_compute.glsl).
        let static_part = match &bvh.parts[..] {
            [only] if only.identity => Some(only),
            _ => None,
        };
        let scale = TraceScale {
            scene_scale: scene_scale(scene),
            static_root: static_part.map_or(u32::MAX, |p| p.root),
            static_min: static_part.map_or([0.0; 3], |p| p.bounds_min),
            static_max: static_part.map_or([0.0; 3], |p| p.bounds_max),
            bvh_nodes_address: address_words(nodes.device_address()),
            bvh_triangles_address: address_words(triangles.device_address()),
            ..Default::default()
        };
        let scale =
            Buffer::with_data(gpu, "trace scale", vk::BufferUsageFlags::UNIFORM_BUFFER, bytemuck::bytes_of(&scale))?;
        Ok(SceneBvh { nodes, triangles, scale, bvh })
    }
}

struct RayQueryHandles {
    tlas: vk::AccelerationStructureKHR,
    tlas_buffer: BufferHandle,
    blas_buffers: Vec<BufferHandle>,
}

/// The trace structures of one frame's graph.
pub struct TraceHandles {
    rayquery: Option<RayQueryHandles>,
    nodes: BufferHandle,
    triangles: BufferHandle,
    scale: BufferHandle,
    top: BufferHandle,
    instances: BufferHandle,
}

impl TraceHandles {
    /// Declares what the frame set holds of the trace structures: the TLAS where the frame
    /// has one (and the BLASes its traversal reads, declared only), and the BVH that the
    /// compute backend traverses and every backend's clearance pass searches.
    pub fn declare_frame_set(&self, set: &mut PassBuilder<'_, '_>) -> (Option<RayQueryTrace>, ComputeTrace) {
        let rayquery = self.rayquery.as_ref().map(|rq| {
            set.read(&rq.tlas_buffer, Access::RayQueryRead);
            for b in &rq.blas_buffers {
                set.read(b, Access::RayQueryRead);
            }
            let resources = RayQueryTraceResources { tlas: rq.tlas, trace_scale: &self.scale };
            RayQueryTrace::declare(set, Stage::Compute, resources)
        });
        let resources = ComputeTraceResources {
            bvh_nodes: &self.nodes,
            bvh_triangles: &self.triangles,
            trace_scale: &self.scale,
            bvh_top: &self.top,
            bvh_instances: &self.instances,
        };
        (rayquery, ComputeTrace::declare(set, Stage::Compute, resources))
    }
}
