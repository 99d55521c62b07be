//! Compute and graphics pipelines from embedded SPIR-V, their bindings checked against
//! reflection: the frame set in set 0 ([`FrameBinding`]) and the pass's own bindings in a
//! push-descriptor set 1.

use std::sync::Arc;

use ash::vk;

use crate::bind::{check_bindings, check_push_constants, BindingDecl, MatchedBindings};
use crate::error::{DeviceError, Result, VkContext};
use crate::frame_set::{check_stage_limits, frame_set_layout, FrameBinding, PUSH_RANGE};
use crate::gpu::{Gpu, Shared};
use crate::layout::RustLayout;
use crate::shader::{ShaderInfo, ShaderStage};

/// The descriptor-set layouts and pipeline layout a pass's bindings produce.
pub(crate) struct Layout {
    shared: Arc<Shared>,
    frame_layout: vk::DescriptorSetLayout,
    pub set_layout: vk::DescriptorSetLayout,
    pub pipeline_layout: vk::PipelineLayout,
    /// The pass's own bindings (set 1): (declaration, binding number), in declaration order.
    pub bindings: Vec<(BindingDecl, u32)>,
    /// The frame set's bindings the pipeline uses (set 0), by name.
    pub frame_uses: Vec<&'static str>,
    /// Bytes of the push-constant block (0: none), and the stages that see it.
    pub push_size: u32,
    pub push_stages: vk::ShaderStageFlags,
    pub pass: String,
}

impl Layout {
    fn new(
        gpu: &Gpu,
        pass: &str,
        frame: &[FrameBinding],
        decls: &[BindingDecl],
        matched: MatchedBindings,
        stages: vk::ShaderStageFlags,
        push_size: u32,
    ) -> Result<Layout> {
        if push_size > PUSH_RANGE {
            return Err(DeviceError::Limit(format!(
                "pass {pass}: a {push_size}-byte push-constant block; every layout's range holds {PUSH_RANGE}"
            )));
        }
        let device = gpu.device();
        check_stage_limits(gpu, pass, frame, decls)?;
        let MatchedBindings { numbers, frame_uses } = matched;
        let own: Vec<(BindingDecl, u32)> = decls.iter().copied().zip(numbers).collect();
        let vk_bindings: Vec<_> = own
            .iter()
            .map(|&(d, n)| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(n)
                    .descriptor_type(d.kind.descriptor_type())
                    .descriptor_count(1)
                    .stage_flags(stages)
            })
            .collect();
        let info = vk::DescriptorSetLayoutCreateInfo::default()
            .flags(vk::DescriptorSetLayoutCreateFlags::PUSH_DESCRIPTOR_KHR)
            .bindings(&vk_bindings);
        // SAFETY: valid device and create info.
        let set_layout =
            unsafe { device.create_descriptor_set_layout(&info, None) }.vk("vkCreateDescriptorSetLayout")?;
        let frame_layout = frame_set_layout(gpu, frame)?;
        let set_layouts = [frame_layout, set_layout];
        // One range in every layout of a bind point, whatever the pass pushes (see PUSH_RANGE).
        let ranges = [vk::PushConstantRange { stage_flags: stages, offset: 0, size: PUSH_RANGE }];
        let info = vk::PipelineLayoutCreateInfo::default().set_layouts(&set_layouts).push_constant_ranges(&ranges);
        // SAFETY: valid device and create info.
        let pipeline_layout = unsafe { device.create_pipeline_layout(&info, None) }.vk("vkCreatePipelineLayout")?;
        gpu.set_name(pipeline_layout, pass);
        Ok(Layout {
            shared: gpu.shared.clone(),
            frame_layout,
            set_layout,
            pipeline_layout,
            bindings: own,
            frame_uses,
            push_size,
            push_stages: stages,
            pass: pass.to_string(),
        })
    }
}

impl Drop for Layout {
    fn drop(&mut self) {
        // SAFETY: pipelines using the layout are destroyed first (field order in their owners).
        unsafe {
            self.shared.device.destroy_pipeline_layout(self.pipeline_layout, None);
            self.shared.device.destroy_descriptor_set_layout(self.set_layout, None);
            self.shared.device.destroy_descriptor_set_layout(self.frame_layout, None);
        }
    }
}

fn shader_module(gpu: &Gpu, shader: &ShaderInfo) -> Result<vk::ShaderModule> {
    let info = vk::ShaderModuleCreateInfo::default().code(shader.spirv);
    // SAFETY: the SPIR-V was produced by glslang at build time.
    let module = unsafe { gpu.device().create_shader_module(&info, None) }.vk("vkCreateShaderModule")?;
    gpu.set_name(module, shader.name);
    Ok(module)
}

/// Values for a module's specialization constants, by name (the GLSL's
/// `layout(constant_id = N) const uint NAME`; `local_size_x` for a `local_size_x_id` workgroup
/// size). A constant left out keeps its default.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Specialization {
    pub values: Vec<(&'static str, u32)>,
}

impl Specialization {
    pub fn new() -> Self {
        Self::default()
    }

    /// With `name` set to `value` (a bool as 0 or 1).
    pub fn with(mut self, name: &'static str, value: u32) -> Self {
        self.values.retain(|(n, _)| *n != name);
        self.values.push((name, value));
        self
    }

    /// The value `name` gets in `shader`: this specialization's, else the module's default.
    pub fn value(&self, shader: &ShaderInfo, name: &str) -> Option<u32> {
        let default = shader.spec_constants.iter().find(|c| c.name == name)?.default;
        Some(self.values.iter().find(|(n, _)| *n == name).map_or(default, |&(_, v)| v))
    }

    /// The (id, value) entries for `shader`; an error names a constant the module lacks.
    fn entries(&self, shader: &ShaderInfo, pass: &str) -> Result<Vec<(u32, u32)>> {
        self.values
            .iter()
            .map(|&(name, value)| match shader.spec_constants.iter().find(|c| c.name == name) {
                Some(c) => Ok((c.id, value)),
                None => Err(DeviceError::Binding {
                    shader: shader.name,
                    binding: name.to_string(),
                    pass: pass.to_string(),
                    problem: format!(
                        "no such specialization constant (the module has: {})",
                        shader.spec_constants.iter().map(|c| c.name).collect::<Vec<_>>().join(", ")
                    ),
                }),
            })
            .collect()
    }

    /// `shader`'s workgroup size under this specialization.
    pub fn workgroup_size(&self, shader: &ShaderInfo) -> [u32; 3] {
        let mut size = shader.workgroup_size;
        for (axis, name) in ["local_size_x", "local_size_y", "local_size_z"].into_iter().enumerate() {
            if let Some(v) = self.value(shader, name) {
                size[axis] = v;
            }
        }
        size
    }
}

pub struct ComputePipeline {
    raw: vk::Pipeline,
    pub(crate) layout: Layout,
    pub(crate) workgroup_size: [u32; 3],
    /// The pass it was built for, for messages.
    pub(crate) name: String,
}

impl ComputePipeline {
    /// Builds the pipeline of pass `pass` from `shader` specialized with `spec`, checking
    /// `decls` (in the frame set `frame` or the pass's own set) and the push-constant block
    /// `push` (`None`: the pass pushes nothing) against the shader's reflection.
    pub fn new(
        gpu: &Gpu,
        pass: &str,
        shader: &ShaderInfo,
        frame: &[FrameBinding],
        decls: &[BindingDecl],
        push: Option<&RustLayout>,
        spec: &Specialization,
    ) -> Result<Self> {
        assert_eq!(shader.stage, ShaderStage::Compute, "{} is not a compute shader", shader.name);
        let matched = check_bindings(shader, pass, frame, decls)?;
        let push_size = check_push_constants(shader, pass, push)?;
        let entries = spec.entries(shader, pass)?;
        let workgroup_size = spec.workgroup_size(shader);
        let most = gpu.report().limits.max_compute_work_group_invocations;
        if workgroup_size.iter().product::<u32>() > most {
            return Err(DeviceError::Limit(format!(
                "pass {pass}: workgroup size {workgroup_size:?} exceeds maxComputeWorkGroupInvocations ({most})"
            )));
        }
        let layout = Layout::new(gpu, pass, frame, decls, matched, vk::ShaderStageFlags::COMPUTE, push_size)?;
        let module = shader_module(gpu, shader)?;
        let map: Vec<vk::SpecializationMapEntry> = (0..entries.len() as u32)
            .map(|i| vk::SpecializationMapEntry { constant_id: entries[i as usize].0, offset: 4 * i, size: 4 })
            .collect();
        let data: Vec<u8> = entries.iter().flat_map(|(_, v)| v.to_ne_bytes()).collect();
        let spec_info = vk::SpecializationInfo::default().map_entries(&map).data(&data);
        let stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .module(module)
            .name(c"main")
            .specialization_info(&spec_info);
        let info = vk::ComputePipelineCreateInfo::default().stage(stage).layout(layout.pipeline_layout);
        // SAFETY: module and layout are valid; the module is destroyed after creation.
        let result = unsafe { gpu.device().create_compute_pipelines(vk::PipelineCache::null(), &[info], None) };
        // SAFETY: the module is no longer needed once the pipeline exists (or failed).
        unsafe { gpu.device().destroy_shader_module(module, None) };
        let raw = result.map_err(|(_, e)| e).vk("vkCreateComputePipelines")?[0];
        gpu.set_name(raw, pass);
        Ok(ComputePipeline { raw, layout, workgroup_size, name: pass.to_string() })
    }

    pub(crate) fn raw(&self) -> vk::Pipeline {
        self.raw
    }
    pub fn workgroup_size(&self) -> [u32; 3] {
        self.workgroup_size
    }

    /// The frame set's bindings its shader uses: a pass that runs it reads what they hold.
    pub fn frame_uses(&self) -> &[&'static str] {
        &self.layout.frame_uses
    }
}

impl Drop for ComputePipeline {
    fn drop(&mut self) {
        // SAFETY: no pending work uses the pipeline (submissions are waited for).
        unsafe { self.layout.shared.device.destroy_pipeline(self.raw, None) };
    }
}

/// Vertex input of a graphics pipeline: one interleaved buffer.
#[derive(Clone, Debug)]
pub struct VertexLayout {
    pub stride: u32,
    /// (location, format, offset)
    pub attributes: Vec<(u32, vk::Format, u32)>,
}

#[derive(Clone, Copy, Debug)]
pub struct ColorTarget {
    pub format: vk::Format,
}

/// What a graphics pass draws into and how.
#[derive(Clone, Debug)]
pub struct GraphicsDesc<'a> {
    pub vertex: &'a ShaderInfo,
    pub fragment: &'a ShaderInfo,
    /// `None`: the vertex shader makes its vertices (a full-screen triangle).
    pub vertex_layout: Option<VertexLayout>,
    pub colors: Vec<ColorTarget>,
    pub depth: Option<vk::Format>,
    /// Every surface is two-sided in leakless scenes, so the default is no culling.
    pub cull: vk::CullModeFlags,
    /// The push-constant block both stages share (`None`: none).
    pub push: Option<RustLayout>,
}

pub struct GraphicsPipeline {
    raw: vk::Pipeline,
    pub(crate) layout: Layout,
}

impl GraphicsPipeline {
    pub fn new(
        gpu: &Gpu,
        pass: &str,
        desc: &GraphicsDesc<'_>,
        frame: &[FrameBinding],
        decls: &[BindingDecl],
    ) -> Result<Self> {
        // Each declaration must be found in the stage(s) that use it; a binding may appear in
        // both stages, so check per stage the subset that stage reflects.
        let matched = merged_bindings(desc, pass, frame, decls)?;
        // A block declared in either stage must match the pass's; a stage may omit it.
        let mut push_size = 0;
        for shader in [desc.vertex, desc.fragment] {
            if shader.push_constants.is_some() {
                push_size = check_push_constants(shader, pass, desc.push.as_ref())?;
            }
        }
        if push_size == 0 && desc.push.is_some() {
            check_push_constants(desc.fragment, pass, desc.push.as_ref())?;
        }
        let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
        let layout = Layout::new(gpu, pass, frame, decls, matched, stages, push_size)?;
        let vs = shader_module(gpu, desc.vertex)?;
        let fs = shader_module(gpu, desc.fragment)?;
        let stages = [
            vk::PipelineShaderStageCreateInfo::default().stage(vk::ShaderStageFlags::VERTEX).module(vs).name(c"main"),
            vk::PipelineShaderStageCreateInfo::default().stage(vk::ShaderStageFlags::FRAGMENT).module(fs).name(c"main"),
        ];
        let no_vertices = VertexLayout { stride: 0, attributes: vec![] };
        let vertex_layout = desc.vertex_layout.as_ref().unwrap_or(&no_vertices);
        let vb = [vk::VertexInputBindingDescription::default()
            .binding(0)
            .stride(vertex_layout.stride)
            .input_rate(vk::VertexInputRate::VERTEX)];
        let vb = if desc.vertex_layout.is_some() { &vb[..] } else { &[] };
        let attrs: Vec<_> = vertex_layout
            .attributes
            .iter()
            .map(|&(location, format, offset)| {
                vk::VertexInputAttributeDescription::default()
                    .location(location)
                    .binding(0)
                    .format(format)
                    .offset(offset)
            })
            .collect();
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
            .vertex_binding_descriptions(vb)
            .vertex_attribute_descriptions(&attrs);
        let assembly =
            vk::PipelineInputAssemblyStateCreateInfo::default().topology(vk::PrimitiveTopology::TRIANGLE_LIST);
        let viewport = vk::PipelineViewportStateCreateInfo::default().viewport_count(1).scissor_count(1);
        let raster = vk::PipelineRasterizationStateCreateInfo::default()
            .polygon_mode(vk::PolygonMode::FILL)
            .cull_mode(desc.cull)
            .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
            .line_width(1.0);
        let multisample =
            vk::PipelineMultisampleStateCreateInfo::default().rasterization_samples(vk::SampleCountFlags::TYPE_1);
        let depth = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(desc.depth.is_some())
            .depth_write_enable(desc.depth.is_some())
            // Reversed depth (1 near, 0 far; the renderer's projection): nearer is greater.
            .depth_compare_op(vk::CompareOp::GREATER);
        let blend_attachments: Vec<_> = desc
            .colors
            .iter()
            .map(|_| vk::PipelineColorBlendAttachmentState::default().color_write_mask(vk::ColorComponentFlags::RGBA))
            .collect();
        let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachments);
        let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
        let color_formats: Vec<_> = desc.colors.iter().map(|c| c.format).collect();
        let mut rendering = vk::PipelineRenderingCreateInfo::default()
            .color_attachment_formats(&color_formats)
            .depth_attachment_format(desc.depth.unwrap_or(vk::Format::UNDEFINED));
        let info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&assembly)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth)
            .color_blend_state(&blend)
            .dynamic_state(&dynamic)
            .layout(layout.pipeline_layout)
            .push_next(&mut rendering);
        // SAFETY: all state structs outlive the call; modules are destroyed after creation.
        let result = unsafe { gpu.device().create_graphics_pipelines(vk::PipelineCache::null(), &[info], None) };
        // SAFETY: the modules are no longer needed.
        unsafe {
            gpu.device().destroy_shader_module(vs, None);
            gpu.device().destroy_shader_module(fs, None);
        }
        let raw = result.map_err(|(_, e)| e).vk("vkCreateGraphicsPipelines")?[0];
        gpu.set_name(raw, pass);
        Ok(GraphicsPipeline { raw, layout })
    }

    pub(crate) fn raw(&self) -> vk::Pipeline {
        self.raw
    }
}

/// Bindings for a graphics pass: every declaration must be bound in at least one stage with
/// one number, and every binding of either stage must be declared or the frame set's.
fn merged_bindings(
    desc: &GraphicsDesc<'_>,
    pass: &str,
    frame: &[FrameBinding],
    decls: &[BindingDecl],
) -> Result<MatchedBindings> {
    let mut numbers = vec![None; decls.len()];
    let mut frame_uses: Vec<&'static str> = Vec::new();
    for shader in [desc.vertex, desc.fragment] {
        let reflected = shader.reflection.unwrap_or(&[]);
        let used: Vec<BindingDecl> =
            decls.iter().copied().filter(|d| reflected.iter().any(|r| r.name == d.name)).collect();
        let found = check_bindings(shader, pass, frame, &used)?;
        for name in found.frame_uses {
            if !frame_uses.contains(&name) {
                frame_uses.push(name);
            }
        }
        for (d, n) in used.iter().zip(found.numbers) {
            let i = decls.iter().position(|x| x.name == d.name).expect("subset");
            match numbers[i] {
                Some(prev) if prev != n => {
                    return Err(crate::DeviceError::Binding {
                        shader: shader.name,
                        binding: d.name.into(),
                        pass: pass.into(),
                        problem: format!("binding {n} here, {prev} in the other stage"),
                    })
                }
                _ => numbers[i] = Some(n),
            }
        }
    }
    let numbers = decls
        .iter()
        .zip(numbers)
        .map(|(d, n)| {
            n.ok_or_else(|| crate::DeviceError::Binding {
                shader: desc.fragment.name,
                binding: d.name.into(),
                pass: pass.into(),
                problem: "declared by the pass but in neither stage".into(),
            })
        })
        .collect::<Result<_>>()?;
    Ok(MatchedBindings { numbers, frame_uses })
}

impl Drop for GraphicsPipeline {
    fn drop(&mut self) {
        // SAFETY: no pending work uses the pipeline.
        unsafe { self.layout.shared.device.destroy_pipeline(self.raw, None) };
    }
}
