//! Spatial reuse: an edge-aware à-trous filter over a moving frame's demodulated indirect
//! irradiance, which keeps exact zeros and never crosses to another plane
//! (`spatial.comp`; docs/architecture.md §1, "Motion").

use ash::vk;
use bytemuck::{Pod, Zeroable};
use leakless_device::{gpu_struct, GpuStruct, ImageDesc};
use leakless_graph::{shader_bindings, BufferHandle, Graph, ImageHandle, PassName};

use crate::error::Result;
use crate::gpu_types::Frame;
use crate::passes::gbuffer::{self, GBufferBindings, GBufferHandles};
use crate::passes::names::group;
use crate::pipelines::{compute_pass, ComputePass, Threads};
use crate::shaders;

gpu_struct! {
    /// The `SpatialParams` push constants of spatial.comp.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct SpatialParams {
        pub step: i32,
        /// 1: the iteration reads the frame's indirect layer and demodulates it.
        pub first: u32,
        pub plane_tolerance: f32,
        /// The gather kernel's radius in pixels, one metre from the camera.
        pub kernel_pixels: f32,
    }
}

/// The filter's iterations: taps 1, 2 and 4 pixels apart, a 17×17 footprint at most. A pixel
/// takes an iteration only while its reach (twice the step) is within the gather kernel's
/// projected radius there, the first always: within a kernel a frame's noise is pixel-scale
/// grain, which the filter averages; beyond it the noise is the kernel's own blotches, which
/// the history averages without the blur that the filter would leave as bias. Measured: five
/// iterations reaching three kernel radii raised the flicker they were to lower (`bench motion`
/// at 128×72, on/off: the door 0.68× → 0.91×, the atrium pan 0.61× → 0.69×) and the door's
/// last-frame relMSE (0.36× → 0.47×); the filter's bias correction follows a wide blur too slowly.
pub const ITERATIONS: u32 = 3;

/// How far from a pixel's plane a tap may lie, per metre from the camera: about the raster's
/// depth precision and a gentle curvature, far below any wall or slab.
pub const PLANE_TOLERANCE: f32 = 0.01;

shader_bindings! {
    pub struct SpatialBindings {
        frame: read uniform(Frame::LAYOUT),
        indirect: read image,
        source: read image,
        filtered: write image,
    }
    pub struct SpatialResources;
}

compute_pass! {
    pub static SPATIAL in FRAME_PASSES: ComputePass<SpatialBindings, SpatialParams> =
        ComputePass::any(
            PassName::new("spatial reuse", group::REUSE),
            &shaders::SPATIAL_COMP,
            &[GBufferBindings::DECLS],
        );
}

/// The filter's two working images (pool images by name); the result is in `result`.
pub struct SpatialImages {
    pub result: ImageHandle,
    scratch: ImageHandle,
}

impl SpatialImages {
    pub fn new(graph: &mut Graph<'_>, extent: vk::Extent2D) -> Result<Self> {
        let usage = vk::ImageUsageFlags::STORAGE;
        let mut image = |name| graph.image(&ImageDesc { name, extent, format: gbuffer::FORMAT, usage });
        Ok(SpatialImages { result: image("spatial reuse")?, scratch: image("spatial reuse scratch")? })
    }
}

/// Filters `indirect` (radiance, demodulated by the G-buffer's albedo) into `images.result`
/// (irradiance), in [`ITERATIONS`] passes; `kernel_pixels`: the gather kernel's radius in pixels
/// one metre from the camera.
pub fn add<'r>(
    graph: &mut Graph<'r>,
    frame: &BufferHandle,
    gbuffer: &GBufferHandles,
    indirect: &ImageHandle,
    images: &mut SpatialImages,
    kernel_pixels: f32,
) {
    let extent = indirect.extent();
    // Odd iterations write the scratch image, even ones the result: the last (the third)
    // writes the result.
    for i in 0..ITERATIONS {
        let params =
            SpatialParams { step: 1 << i, first: (i == 0) as u32, plane_tolerance: PLANE_TOLERANCE, kernel_pixels };
        let (source, filtered) =
            if i % 2 == 1 { (&images.result, &mut images.scratch) } else { (&images.scratch, &mut images.result) };
        let resources = SpatialResources { frame, indirect, source, filtered };
        let threads = Threads::Fixed([extent.width, extent.height, 1]);
        SPATIAL.add_as(graph, (SPATIAL.name, Some(i)), resources, |pass| gbuffer.declare(pass), params, threads);
    }
}
