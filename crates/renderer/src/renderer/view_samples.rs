//! How a frame finds its view samples (docs/architecture.md §1.1): the G-buffer rasterised, or
//! found by a ray a pixel (`Primary`).

use bytemuck::Zeroable;
use leakless_graph::{BufferHandle, Graph};

use crate::gpu_scene::SceneHandles;
use crate::gpu_types::Frame;
use crate::passes::gbuffer::{GBufferHandles, GBufferPass};
use crate::passes::primary_rays::{self, PrimaryRaysParams};
use crate::settings::Primary;

/// How a frame finds its view samples: rasterised by `raster` (`vertex_count` corners), or by
/// a ray a pixel with `rays`' camera.
pub(super) enum ViewSamples<'p> {
    Raster(&'p GBufferPass, u32),
    Rays(PrimaryRaysParams),
}

impl<'p> ViewSamples<'p> {
    /// The frame's view samples into `gbuffer`.
    pub(super) fn add(
        self,
        g: &mut Graph<'p>,
        (frame, scene): (&BufferHandle, &SceneHandles),
        gbuffer: &mut GBufferHandles,
    ) {
        match self {
            ViewSamples::Raster(pass, vertex_count) => pass.add(g, frame, scene, vertex_count, gbuffer),
            ViewSamples::Rays(params) => primary_rays::add(g, params, frame, gbuffer),
        }
    }

    /// How a frame finds them: `primary`'s way (resolved: `Auto` rasterises), with `raster`
    /// over `vertex_count` corners or by rays through `constants`' camera (`finite_far`: its
    /// projection has a far plane).
    pub(super) fn new(
        primary: Primary,
        (raster, vertex_count): (&'p GBufferPass, u32),
        constants: &Frame,
        finite_far: bool,
    ) -> Self {
        match primary {
            Primary::Raster | Primary::Auto => ViewSamples::Raster(raster, vertex_count),
            Primary::Rays => ViewSamples::Rays(PrimaryRaysParams {
                world_from_clip: glam::Mat4::from_cols_array_2d(&constants.view_proj).inverse().to_cols_array_2d(),
                finite_far: finite_far as u32,
                ..Zeroable::zeroed()
            }),
        }
    }
}
