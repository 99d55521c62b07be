//! Acceleration structures for the ray-query backend: one BLAS over the scene's world-space
//! triangle list (the scene model is already flat, so there is nothing to instance), compacted
//! where the driver reports a smaller size, and a TLAS with its single instance. Every step
//! runs through the pass graph, which derives the barriers between build, size query,
//! compaction and the TLAS build.

use std::time::Instant;

use leakless_device::{
    accel_build_sizes, accel_instance, accel_instances, accel_scratch, AccelGeometry, AccelSizeQueries,
    AccelerationStructure, Buffer, Gpu,
};
use leakless_graph::{Access, GraphRunner};

use crate::AccelError;

/// What building cost, for `--stats`.
#[derive(Clone, Debug, Default)]
pub struct RayQueryStats {
    pub build_ms: f64,
    pub blas_bytes: u64,
    /// Size before compaction (equal to `blas_bytes` when compaction did not help).
    pub blas_uncompacted_bytes: u64,
    pub tlas_bytes: u64,
    pub scratch_bytes: u64,
}

pub struct RayQueryAccel {
    pub tlas: AccelerationStructure,
    pub blas: AccelerationStructure,
    /// The TLAS references its instances' memory only during the build, but keeping the
    /// buffer makes a rebuild (a moving camera never needs one; an edited scene would) cheap.
    _instances: Buffer,
    pub stats: RayQueryStats,
}

const IDENTITY: [f32; 12] = [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0];

impl RayQueryAccel {
    /// Builds over `vertices` (3 per triangle, positions at the start of each `stride` bytes;
    /// the buffer needs the build-input and device-address usages). `opaque: false` when any
    /// material is alpha-masked, so shaders see candidate hits.
    pub fn build(
        gpu: &Gpu,
        vertices: &Buffer,
        stride: u64,
        triangle_count: u32,
        opaque: bool,
    ) -> Result<Self, AccelError> {
        if triangle_count == 0 {
            return Err(AccelError::Empty);
        }
        let start = Instant::now();
        let mut runner = GraphRunner::new(gpu, 1)?;
        let geometry = AccelGeometry::Triangles { vertices, stride, triangle_count, opaque };
        let blas_sizes = accel_build_sizes(gpu, &geometry, true)?;
        let blas = AccelerationStructure::new(gpu, "blas", false, blas_sizes.structure)?;

        let instances = accel_instances(gpu, &[accel_instance(&blas, IDENTITY, 0)])?;
        let tlas_geometry = AccelGeometry::Instances { instances: &instances, count: 1 };
        let tlas_sizes = accel_build_sizes(gpu, &tlas_geometry, false)?;
        let scratch = accel_scratch(gpu, blas_sizes.scratch.max(tlas_sizes.scratch))?;
        let queries = AccelSizeQueries::new(gpu, 1)?;

        // 1. Build the BLAS and ask how small it can be.
        {
            let mut graph = runner.graph(gpu)?;
            let input = graph.import_buffer(vertices);
            let mut blas_h = graph.import_buffer(blas.buffer());
            let mut scratch_h = graph.import_buffer(&scratch);
            let mut pass = graph.pass("blas build");
            pass.read(&input, Access::AccelerationStructureBuildRead);
            pass.write(&mut blas_h, Access::AccelerationStructureBuildWrite);
            let scratch_use = pass.write(&mut scratch_h, Access::AccelerationStructureBuildWrite);
            let (blas_ref, geometry_ref) = (&blas, &geometry);
            pass.record(move |ctx| {
                ctx.cmd.build_acceleration_structure(blas_ref, geometry_ref, ctx.res.buffer(scratch_use), true)
            });
            let mut pass = graph.pass("blas compacted size");
            pass.read(&blas_h, Access::AccelerationStructureBuildRead);
            let queries_ref = &queries;
            pass.record(move |ctx| ctx.cmd.write_compacted_size(blas_ref, queries_ref, 0));
            let submitted = graph.submit(&Default::default())?;
            runner.wait_for(gpu, submitted)?;
        }
        let compacted_size = queries.read()?[0];
        let uncompacted = blas.size();

        // 2. Compact when it saves memory, then build the TLAS over the final BLAS.
        let blas = if compacted_size > 0 && compacted_size < uncompacted {
            let compact = AccelerationStructure::new(gpu, "blas (compacted)", false, compacted_size)?;
            {
                let mut graph = runner.graph(gpu)?;
                let src = graph.import_buffer(blas.buffer());
                let mut dst = graph.import_buffer(compact.buffer());
                let mut pass = graph.pass("blas compact");
                pass.read(&src, Access::AccelerationStructureBuildRead);
                pass.write(&mut dst, Access::AccelerationStructureBuildWrite);
                let (src_ref, dst_ref) = (&blas, &compact);
                pass.record(move |ctx| ctx.cmd.compact_acceleration_structure(src_ref, dst_ref));
                let submitted = graph.submit(&Default::default())?;
                runner.wait_for(gpu, submitted)?;
            }
            compact
        } else {
            blas
        };
        let tlas = AccelerationStructure::new(gpu, "tlas", true, tlas_sizes.structure)?;
        {
            let mut graph = runner.graph(gpu)?;
            let blas_h = graph.import_buffer(blas.buffer());
            let instances_h = graph.import_buffer(&instances);
            let mut tlas_h = graph.import_buffer(tlas.buffer());
            let mut scratch_h = graph.import_buffer(&scratch);
            let mut pass = graph.pass("tlas build");
            pass.read(&blas_h, Access::AccelerationStructureBuildRead);
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
            blas_bytes: blas.size(),
            blas_uncompacted_bytes: uncompacted,
            tlas_bytes: tlas.size(),
            scratch_bytes: scratch.size(),
        };
        Ok(RayQueryAccel { tlas, blas, _instances: instances, stats })
    }
}
