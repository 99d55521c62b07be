//! [`Cmd`]: a command buffer being recorded, with the few commands the renderer records.
//! Barriers are recorded only by the pass graph (`barriers`), never by pass code.

use ash::vk;

use crate::bind::{Bound, FRAME_SET, PASS_SET};
use crate::error::{DeviceError, Result};
use crate::frame_set::{write_descriptors, BoundFrameSet};
use crate::pipeline::{ComputePipeline, GraphicsPipeline, Layout};
use crate::{Buffer, Gpu, Image, TimestampPool};

pub struct Cmd<'a> {
    pub(crate) gpu: &'a Gpu,
    pub(crate) raw: vk::CommandBuffer,
    /// The frame set of the frame being recorded ([`Cmd::use_frame_set`]).
    pub(crate) frame: Option<BoundFrameSet>,
    /// Whether it is bound at the compute and at the graphics bind point.
    pub(crate) frame_bound: [bool; 2],
}

impl<'a> Cmd<'a> {
    pub fn gpu(&self) -> &'a Gpu {
        self.gpu
    }

    fn device(&self) -> &ash::Device {
        self.gpu.device()
    }

    /// The raw command buffer, for libraries that record their own commands (the overlay's UI
    /// renderer). Everything they record must be declared to the pass graph like any pass.
    /// Their pipelines may disturb the frame set, which the next pass that uses it binds again.
    pub fn raw(&mut self) -> vk::CommandBuffer {
        self.frame_bound = [false; 2];
        self.raw
    }

    /// Pushes `bytes` as the pipeline's push-constant block (checked against its size).
    fn push_constants(&self, layout: &Layout, bytes: &[u8]) -> Result<()> {
        if bytes.len() as u32 != layout.push_size {
            return Err(DeviceError::Binding {
                shader: "-",
                binding: "push constants".into(),
                pass: layout.pass.clone(),
                problem: format!("{} bytes pushed; the pipeline's block holds {}", bytes.len(), layout.push_size),
            });
        }
        if !bytes.is_empty() {
            // SAFETY: recording state; the range matches the layout's push-constant range.
            unsafe { self.device().cmd_push_constants(self.raw, layout.pipeline_layout, layout.push_stages, 0, bytes) };
        }
        Ok(())
    }

    /// Binds the frame set `set` for the pipelines recorded from now on (bound at each bind
    /// point the first time a pipeline there uses it).
    pub fn use_frame_set(&mut self, set: &BoundFrameSet) {
        self.frame = Some(set.clone());
        self.frame_bound = [false; 2];
    }

    /// Pushes the descriptors of `layout`, each resource found by its declared name, and binds
    /// the frame set if the pipeline uses it and it is not bound at `bind_point` yet; the set
    /// must hold every binding of it the pipeline uses.
    fn push_bindings(
        &mut self,
        bind_point: vk::PipelineBindPoint,
        layout: &Layout,
        bound: &[(&str, Bound<'_>)],
    ) -> Result<()> {
        let problem = |binding: &str, problem: &str| DeviceError::Binding {
            shader: "-",
            binding: binding.into(),
            pass: layout.pass.clone(),
            problem: problem.into(),
        };
        if let Some((name, _)) = bound.iter().find(|(n, _)| !layout.bindings.iter().any(|(d, _)| d.name == *n)) {
            return Err(problem(name, "bound at record time but not declared by the pass"));
        }
        let held = |name: &&str| self.frame.as_ref().is_some_and(|f| f.holds(name));
        if let Some(name) = layout.frame_uses.iter().find(|n| !held(n)) {
            return Err(problem(name, "used by the shader, but the frame's graph binds no frame set holding it"));
        }
        let mut entries = Vec::with_capacity(layout.bindings.len());
        for &(decl, number) in &layout.bindings {
            let resource = bound
                .iter()
                .find(|(n, _)| *n == decl.name)
                .map(|(_, r)| *r)
                .ok_or_else(|| problem(decl.name, "declared but not bound"))?;
            entries.push((decl, number, resource));
        }
        let point = usize::from(bind_point == vk::PipelineBindPoint::GRAPHICS);
        if !layout.frame_uses.is_empty() && !self.frame_bound[point] {
            let set = self.frame.as_ref().expect("checked above: the pass's frame bindings are held").set;
            // SAFETY: recording state; the set was written for a layout identical to set 0 of
            // every pipeline layout (frame_set.rs), and outlives the frame's command buffers.
            unsafe {
                self.device().cmd_bind_descriptor_sets(
                    self.raw,
                    bind_point,
                    layout.pipeline_layout,
                    FRAME_SET,
                    &[set],
                    &[],
                )
            };
            self.frame_bound[point] = true;
        }
        let push_descriptor = &self.gpu.shared.push_descriptor;
        let (raw, pipeline_layout) = (self.raw, layout.pipeline_layout);
        write_descriptors(&entries, |writes| {
            // SAFETY: set 1 of the layout was created with the push-descriptor flag; every write
            // targets a binding of it with the declared type, and the infos outlive the call.
            unsafe { push_descriptor.cmd_push_descriptor_set(raw, bind_point, pipeline_layout, PASS_SET, writes) };
        });
        Ok(())
    }

    /// Dispatches `pipeline` over `threads` invocations (rounded up to whole workgroups), with
    /// `push` as its push-constant block (empty when it has none).
    pub fn dispatch(
        &mut self,
        pipeline: &ComputePipeline,
        bound: &[(&str, Bound<'_>)],
        push: &[u8],
        threads: [u32; 3],
    ) -> Result<()> {
        let groups = self.workgroups(pipeline, threads)?;
        if groups.contains(&0) {
            return Ok(());
        }
        self.bind_compute(pipeline, bound, push)?;
        // SAFETY: pipeline and descriptors bound above.
        unsafe { self.device().cmd_dispatch(self.raw, groups[0], groups[1], groups[2]) };
        Ok(())
    }

    /// Dispatches `pipeline` with the workgroup counts the device finds at `offset` in `args`
    /// (a `VkDispatchIndirectCommand`, written by an earlier pass), which are never more than
    /// `most_threads` need: that bound is checked against the device's limit here, since the
    /// counts themselves are not known on the host. `args` must have been created with
    /// `INDIRECT_BUFFER` usage, which a [`Buffer`] does not record, so it is not checked here
    /// (the validation layers do).
    pub fn dispatch_indirect(
        &mut self,
        pipeline: &ComputePipeline,
        bound: &[(&str, Bound<'_>)],
        push: &[u8],
        args: &Buffer,
        offset: u64,
        most_threads: [u32; 3],
    ) -> Result<()> {
        self.workgroups(pipeline, most_threads)?;
        // Vulkan: a multiple of 4, and the command's 12 bytes inside the buffer.
        if offset % 4 != 0 || offset.checked_add(12).is_none_or(|end| end > args.size()) {
            return Err(DeviceError::Limit(format!(
                "{}: indirect dispatch arguments at byte {offset} are misaligned or beyond the {}-byte buffer",
                pipeline.name,
                args.size()
            )));
        }
        self.bind_compute(pipeline, bound, push)?;
        // SAFETY: pipeline and descriptors bound above; the arguments lie inside the buffer,
        // which the caller created with INDIRECT_BUFFER usage.
        unsafe { self.device().cmd_dispatch_indirect(self.raw, args.raw(), offset) };
        Ok(())
    }

    /// The workgroups that cover `threads`, checked against the device's limit.
    fn workgroups(&self, pipeline: &ComputePipeline, threads: [u32; 3]) -> Result<[u32; 3]> {
        let wg = pipeline.workgroup_size;
        let groups = [0, 1, 2].map(|i| threads[i].div_ceil(wg[i].max(1)));
        let max = self.gpu.report().limits.max_compute_work_group_count;
        if let Some(axis) = (0..3).find(|&i| groups[i] > max[i]) {
            return Err(DeviceError::Limit(format!(
                "{}: {} workgroups along axis {axis} exceed the device's maxComputeWorkGroupCount ({})",
                pipeline.name, groups[axis], max[axis]
            )));
        }
        Ok(groups)
    }

    fn bind_compute(&mut self, pipeline: &ComputePipeline, bound: &[(&str, Bound<'_>)], push: &[u8]) -> Result<()> {
        // SAFETY: recording state; pipeline from this device.
        unsafe { self.device().cmd_bind_pipeline(self.raw, vk::PipelineBindPoint::COMPUTE, pipeline.raw()) };
        self.push_bindings(vk::PipelineBindPoint::COMPUTE, &pipeline.layout, bound)?;
        self.push_constants(&pipeline.layout, push)
    }

    /// Draws `vertex_count` vertices (of `vertices`, or generated by the vertex shader when
    /// `None`) into `colors` (+ `depth`), clearing them first.
    #[allow(clippy::too_many_arguments)]
    pub fn draw(
        &mut self,
        pipeline: &GraphicsPipeline,
        bound: &[(&str, Bound<'_>)],
        push: &[u8],
        colors: &[(&Image, [f32; 4])],
        depth: Option<&Image>,
        vertices: Option<&Buffer>,
        vertex_count: u32,
    ) -> Result<()> {
        let extent =
            colors.first().map(|(i, _)| i.extent()).or(depth.map(|d| d.extent())).expect("a draw needs a target");
        let color_attachments: Vec<_> = colors
            .iter()
            .map(|(image, clear)| {
                vk::RenderingAttachmentInfo::default()
                    .image_view(image.view())
                    .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                    .load_op(vk::AttachmentLoadOp::CLEAR)
                    .store_op(vk::AttachmentStoreOp::STORE)
                    .clear_value(vk::ClearValue { color: vk::ClearColorValue { float32: *clear } })
            })
            .collect();
        let depth_attachment = depth.map(|d| {
            vk::RenderingAttachmentInfo::default()
                .image_view(d.view())
                .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
                .load_op(vk::AttachmentLoadOp::CLEAR)
                .store_op(vk::AttachmentStoreOp::STORE)
                // Reversed depth: 0 is the far plane (see the depth test in pipeline.rs).
                .clear_value(vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: 0.0, stencil: 0 } })
        });
        let area = vk::Rect2D { offset: vk::Offset2D::default(), extent };
        let mut info =
            vk::RenderingInfo::default().render_area(area).layer_count(1).color_attachments(&color_attachments);
        if let Some(d) = &depth_attachment {
            info = info.depth_attachment(d);
        }
        let viewport = vk::Viewport {
            x: 0.0,
            y: 0.0,
            width: extent.width as f32,
            height: extent.height as f32,
            min_depth: 0.0,
            max_depth: 1.0,
        };
        let device = self.gpu.device();
        // SAFETY: recording state outside any rendering; attachments are in the layouts the
        // pass graph transitioned them to; pipeline formats match the attachments.
        unsafe {
            device.cmd_begin_rendering(self.raw, &info);
            device.cmd_bind_pipeline(self.raw, vk::PipelineBindPoint::GRAPHICS, pipeline.raw());
            device.cmd_set_viewport(self.raw, 0, &[viewport]);
            device.cmd_set_scissor(self.raw, 0, &[area]);
            if let Some(vertices) = vertices {
                device.cmd_bind_vertex_buffers(self.raw, 0, &[vertices.raw()], &[0]);
            }
        }
        let pushed = self
            .push_bindings(vk::PipelineBindPoint::GRAPHICS, &pipeline.layout, bound)
            .and_then(|()| self.push_constants(&pipeline.layout, push));
        // SAFETY: inside the rendering begun above; always ended, even on a binding error.
        unsafe {
            if pushed.is_ok() {
                device.cmd_draw(self.raw, vertex_count, 1, 0, 0);
            }
            device.cmd_end_rendering(self.raw);
        }
        pushed
    }

    /// Records `record` (raw commands of a library with its own pipeline, such as the UI
    /// renderer) inside a dynamic rendering into `target` that keeps what it holds.
    pub fn draw_over(&mut self, target: &Image, record: impl FnOnce(vk::CommandBuffer) -> Result<()>) -> Result<()> {
        let attachment = [vk::RenderingAttachmentInfo::default()
            .image_view(target.view())
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::LOAD)
            .store_op(vk::AttachmentStoreOp::STORE)];
        let area = vk::Rect2D { offset: vk::Offset2D::default(), extent: target.extent() };
        let info = vk::RenderingInfo::default().render_area(area).layer_count(1).color_attachments(&attachment);
        // SAFETY: recording state outside any rendering; the graph put `target` in the
        // attachment layout.
        unsafe { self.device().cmd_begin_rendering(self.raw, &info) };
        let recorded = record(self.raw());
        // SAFETY: ends the rendering begun above, whatever `record` did.
        unsafe { self.device().cmd_end_rendering(self.raw) };
        recorded
    }

    pub fn copy_buffer(&mut self, src: &Buffer, dst: &Buffer, size: u64) {
        self.copy_buffer_region(src, dst, 0, size);
    }

    /// Copies the first `size` bytes of `src` to `dst` at `dst_offset`.
    pub fn copy_buffer_region(&mut self, src: &Buffer, dst: &Buffer, dst_offset: u64, size: u64) {
        let region = vk::BufferCopy { src_offset: 0, dst_offset, size };
        // SAFETY: both buffers have the transfer usages and hold the range (caller).
        unsafe { self.device().cmd_copy_buffer(self.raw, src.raw(), dst.raw(), &[region]) };
    }

    /// Copies an image (in TRANSFER_SRC_OPTIMAL) tightly packed into `dst` at `offset`.
    pub fn copy_image_to_buffer(&mut self, src: &Image, dst: &Buffer, offset: u64) {
        let e = src.extent();
        let region = vk::BufferImageCopy::default()
            .buffer_offset(offset)
            .image_subresource(vk::ImageSubresourceLayers::default().aspect_mask(src.aspect()).layer_count(1))
            .image_extent(vk::Extent3D { width: e.width, height: e.height, depth: 1 });
        // SAFETY: the graph put `src` in TRANSFER_SRC_OPTIMAL; `dst` is large enough (caller).
        unsafe {
            self.device().cmd_copy_image_to_buffer(
                self.raw,
                src.raw(),
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                dst.raw(),
                &[region],
            )
        };
    }

    pub fn fill_buffer(&mut self, dst: &Buffer, offset: u64, size: u64, value: u32) {
        // SAFETY: offset and size are multiples of 4 within the buffer (caller).
        unsafe { self.device().cmd_fill_buffer(self.raw, dst.raw(), offset, size, value) };
    }

    /// Records one pipeline barrier. Only the pass graph calls this.
    pub fn barriers(&mut self, buffers: &[vk::BufferMemoryBarrier2<'_>], images: &[vk::ImageMemoryBarrier2<'_>]) {
        if buffers.is_empty() && images.is_empty() {
            return;
        }
        let info = vk::DependencyInfo::default().buffer_memory_barriers(buffers).image_memory_barriers(images);
        // SAFETY: synchronization2 is enabled; the barriers name live resources.
        unsafe { self.device().cmd_pipeline_barrier2(self.raw, &info) };
    }

    pub fn begin_label(&mut self, name: &str) {
        if let Some(du) = &self.gpu.shared.debug_utils {
            let name = std::ffi::CString::new(name).unwrap_or_default();
            // SAFETY: debug utils is enabled; the label outlives the call.
            unsafe { du.cmd_begin_debug_utils_label(self.raw, &vk::DebugUtilsLabelEXT::default().label_name(&name)) };
        }
    }

    pub fn end_label(&mut self) {
        if let Some(du) = &self.gpu.shared.debug_utils {
            // SAFETY: matches a begin_label in the same command buffer.
            unsafe { du.cmd_end_debug_utils_label(self.raw) };
        }
    }

    pub fn write_timestamp(&mut self, pool: &TimestampPool, index: u32) {
        // SAFETY: the index is below the pool's capacity (TimestampPool checks) and was reset.
        unsafe {
            self.device().cmd_write_timestamp2(self.raw, vk::PipelineStageFlags2::ALL_COMMANDS, pool.raw(), index)
        };
    }
}
