//! Acceleration structures for the ray-query backend: one BLAS per part of the scene (the
//! static triangles, merged, in world space; each animated instance in its mesh space), built
//! once and compacted where the driver reports a smaller size, and a TLAS with one instance per
//! part. Every step runs through the pass graph, which derives the barriers between build, size
//! query, compaction and the TLAS build. A scene that moves rebuilds the TLAS inside the frame's
//! graph ([`RayQueryAccel::add_rebuild`]); rebuilding a handful of instances costs less than
//! the bookkeeping of an update would save.

use std::time::Instant;

use leakless_device::{
    accel_build_sizes, accel_instance, accel_instances, accel_scratch, vk, AccelGeometry, AccelSizeQueries,
    AccelerationStructure, Buffer, Gpu,
};
use leakless_graph::{Access, BufferHandle, Graph, GraphRunner, PassName};

use crate::AccelError;

/// The passes that build and move acceleration structures; their time counts as the scene's.
const SCENE: &str = "scene";
pub const BLAS_BUILD: PassName = PassName::new("blas build", SCENE);
pub const BLAS_COMPACTED_SIZE: PassName = PassName::new("blas compacted size", SCENE);
pub const BLAS_COMPACT: PassName = PassName::new("blas compact", SCENE);
pub const TLAS_BUILD: PassName = PassName::new("tlas build", SCENE);
pub const TLAS_REBUILD: PassName = PassName::new("tlas rebuild", SCENE);

/// What building cost, for `--stats`.
#[derive(Clone, Debug, Default)]
pub struct RayQueryStats {
    pub build_ms: f64,
    /// All BLASes together.
    pub blas_bytes: u64,
    /// Size before compaction (equal to `blas_bytes` when compaction did not help).
    pub blas_uncompacted_bytes: u64,
    pub tlas_bytes: u64,
    pub scratch_bytes: u64,
    pub blas_count: u32,
}

/// One part's triangles for its BLAS: `triangle_count` triangles, positions at the start of each
/// `stride` bytes of `vertices` (which needs the build-input and device-address usages).
pub struct BlasInput<'a> {
    pub vertices: &'a Buffer,
    pub stride: u64,
    pub triangle_count: u32,
    /// The part's first triangle in the scene's list: the instance's custom index, which
    /// `trace.glsl` adds to the primitive index so that hits name scene triangles.
    pub first_triangle: u32,
}

pub struct RayQueryAccel {
    pub tlas: AccelerationStructure,
    /// One per part, in part order.
    pub blases: Vec<AccelerationStructure>,
    first_triangles: Vec<u32>,
    /// For rebuilding the TLAS every frame the scene moves.
    tlas_scratch: Buffer,
    pub stats: RayQueryStats,
}

/// A row-major 3×4 transform that leaves a part where it is (the static part).
pub const IDENTITY: [f32; 12] = [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0];

impl RayQueryAccel {
    /// Builds a BLAS per part and the TLAS over them, placed by `transforms` (row-major 3×4,
    /// one per part). `opaque: false` when any material is alpha-masked, so shaders see
    /// candidate hits.
    pub fn build(
        gpu: &Gpu,
        parts: &[BlasInput<'_>],
        transforms: &[[f32; 12]],
        opaque: bool,
    ) -> Result<Self, AccelError> {
        if parts.is_empty() || parts.iter().any(|p| p.triangle_count == 0) {
            return Err(AccelError::Empty);
        }
        let start = Instant::now();
        let mut runner = GraphRunner::new(gpu, 1)?;
        let geometries: Vec<AccelGeometry> = parts
            .iter()
            .map(|p| AccelGeometry::Triangles {
                vertices: p.vertices,
                stride: p.stride,
                triangle_count: p.triangle_count,
                opaque,
            })
            .collect();
        let mut scratch_size = 0;
        let mut built = Vec::with_capacity(parts.len());
        for g in &geometries {
            let sizes = accel_build_sizes(gpu, g, true)?;
            scratch_size = scratch_size.max(sizes.scratch);
            built.push(AccelerationStructure::new(gpu, "blas", false, sizes.structure)?);
        }
        // One scratch per BLAS would let the builds overlap; one shared keeps memory low, and
        // the graph orders the builds on it.
        let scratch = accel_scratch(gpu, scratch_size)?;
        let queries = AccelSizeQueries::new(gpu, parts.len() as u32)?;

        // 1. Build every BLAS and ask how small each can be.
        {
            let mut graph = runner.graph(gpu)?;
            let mut scratch_h = graph.import_buffer(&scratch);
            for (index, (blas, geometry)) in built.iter().zip(&geometries).enumerate() {
                let input = graph.import_buffer(parts[index].vertices);
                let mut blas_h = graph.import_buffer(blas.buffer());
                let mut pass = graph.pass(BLAS_BUILD);
                pass.read(&input, Access::AccelerationStructureBuildRead);
                pass.write(&mut blas_h, Access::AccelerationStructureBuildWrite);
                let scratch_use = pass.write(&mut scratch_h, Access::AccelerationStructureBuildWrite);
                pass.record(move |ctx| {
                    ctx.cmd.build_acceleration_structure(blas, geometry, ctx.res.buffer(scratch_use), true)
                });
                let mut pass = graph.pass(BLAS_COMPACTED_SIZE);
                pass.read(&blas_h, Access::AccelerationStructureBuildRead);
                let queries_ref = &queries;
                pass.record(move |ctx| ctx.cmd.write_compacted_size(blas, queries_ref, index as u32));
            }
            let submitted = graph.submit(&Default::default())?;
            runner.wait_for(gpu, submitted)?;
        }
        let compacted = queries.read()?;
        let uncompacted: u64 = built.iter().map(|b| b.size()).sum();

        // 2. Compact those it helps, then build the TLAS over the final BLASes.
        let mut blases = Vec::with_capacity(built.len());
        let mut copies = Vec::new();
        for (blas, &size) in built.into_iter().zip(&compacted) {
            if size > 0 && size < blas.size() {
                let compact = AccelerationStructure::new(gpu, "blas (compacted)", false, size)?;
                copies.push((blas, blases.len()));
                blases.push(compact);
            } else {
                blases.push(blas);
            }
        }
        if !copies.is_empty() {
            let mut graph = runner.graph(gpu)?;
            for (src, index) in &copies {
                let dst = &blases[*index];
                let src_h = graph.import_buffer(src.buffer());
                let mut dst_h = graph.import_buffer(dst.buffer());
                let mut pass = graph.pass(BLAS_COMPACT);
                pass.read(&src_h, Access::AccelerationStructureBuildRead);
                pass.write(&mut dst_h, Access::AccelerationStructureBuildWrite);
                pass.record(move |ctx| ctx.cmd.compact_acceleration_structure(src, dst));
            }
            let submitted = graph.submit(&Default::default())?;
            runner.wait_for(gpu, submitted)?;
        }
        drop(copies);

        let first_triangles: Vec<u32> = parts.iter().map(|p| p.first_triangle).collect();
        let instances = accel_instances(gpu, &instance_records(&blases, &first_triangles, transforms))?;
        let tlas_geometry = AccelGeometry::Instances { instances: &instances, count: blases.len() as u32 };
        let tlas_sizes = accel_build_sizes(gpu, &tlas_geometry, false)?;
        let tlas = AccelerationStructure::new(gpu, "tlas", true, tlas_sizes.structure)?;
        let tlas_scratch = accel_scratch(gpu, tlas_sizes.scratch)?;
        {
            let mut graph = runner.graph(gpu)?;
            let blas_h: Vec<BufferHandle> = blases.iter().map(|b| graph.import_buffer(b.buffer())).collect();
            let instances_h = graph.import_buffer(&instances);
            let mut tlas_h = graph.import_buffer(tlas.buffer());
            let mut scratch_h = graph.import_buffer(&tlas_scratch);
            let mut pass = graph.pass(TLAS_BUILD);
            for b in &blas_h {
                pass.read(b, Access::AccelerationStructureBuildRead);
            }
            pass.read(&instances_h, Access::AccelerationStructureBuildRead);
            pass.write(&mut tlas_h, Access::AccelerationStructureBuildWrite);
            let scratch_use = pass.write(&mut scratch_h, Access::AccelerationStructureBuildWrite);
            let (tlas_ref, geometry_ref) = (&tlas, &tlas_geometry);
            pass.record(move |ctx| {
                ctx.cmd.build_acceleration_structure(tlas_ref, geometry_ref, ctx.res.buffer(scratch_use), false)
            });
            let submitted = graph.submit(&Default::default())?;
            runner.wait_for(gpu, submitted)?;
        }
        let stats = RayQueryStats {
            build_ms: start.elapsed().as_secs_f64() * 1e3,
            blas_bytes: blases.iter().map(|b| b.size()).sum(),
            blas_uncompacted_bytes: uncompacted,
            tlas_bytes: tlas.size(),
            scratch_bytes: scratch.size().max(tlas_scratch.size()),
            blas_count: blases.len() as u32,
        };
        Ok(RayQueryAccel { tlas, blases, first_triangles, tlas_scratch, stats })
    }

    /// Adds a pass to `graph` that rebuilds the TLAS with the parts placed by `transforms` (one
    /// per part, row-major 3×4). The instance records go up with the frame; the graph orders
    /// the build after every earlier use of the TLAS (the frame before may still trace it) and
    /// before this frame's rays. `tlas` is the frame's handle of [`RayQueryAccel::tlas`]'s buffer.
    pub fn add_rebuild<'r>(
        &'r self,
        graph: &mut Graph<'r>,
        transforms: &[[f32; 12]],
        tlas: &mut BufferHandle,
        blases: &[BufferHandle],
    ) -> Result<(), AccelError> {
        let records = instance_records(&self.blases, &self.first_triangles, transforms);
        // SAFETY: AccelerationStructureInstanceKHR is a repr(C) struct of 64 bytes without
        // padding (a 48-byte matrix, two packed u32 and a u64 handle): its bytes are initialised.
        let bytes = unsafe {
            std::slice::from_raw_parts(records.as_ptr().cast::<u8>(), std::mem::size_of_val(records.as_slice()))
        };
        let usage = vk::BufferUsageFlags::ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_KHR
            | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS;
        let instances = graph.upload("tlas instances", usage, bytes)?;
        let mut scratch = graph.import_buffer(&self.tlas_scratch);
        let count = records.len() as u32;
        let mut pass = graph.pass(TLAS_REBUILD);
        for b in blases {
            pass.read(b, Access::AccelerationStructureBuildRead);
        }
        let instances_use = pass.read(&instances, Access::AccelerationStructureBuildRead);
        pass.write(tlas, Access::AccelerationStructureBuildWrite);
        let scratch_use = pass.write(&mut scratch, Access::AccelerationStructureBuildWrite);
        pass.record(move |ctx| {
            let geometry = AccelGeometry::Instances { instances: ctx.res.buffer(instances_use), count };
            ctx.cmd.build_acceleration_structure(&self.tlas, &geometry, ctx.res.buffer(scratch_use), false)
        });
        Ok(())
    }
}

fn instance_records(
    blases: &[AccelerationStructure],
    first_triangles: &[u32],
    transforms: &[[f32; 12]],
) -> Vec<vk::AccelerationStructureInstanceKHR> {
    blases
        .iter()
        .zip(first_triangles)
        .enumerate()
        .map(|(i, (blas, &first))| accel_instance(blas, transforms.get(i).copied().unwrap_or(IDENTITY), first))
        .collect()
}
