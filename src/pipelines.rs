//! Compute pipelines, made from the passes' definitions and kept by shader module: a pass is
//! a function over the graph and this cache, with no pipeline of its own to construct and no
//! field to add to the renderer. Every pass of a frame is listed in [`passes::FRAME_PASSES`];
//! the cache makes them all for a backend when the backend is first used, and the bindings
//! test checks the same list against reflection.
//!
//! [`passes::FRAME_PASSES`]: crate::passes::FRAME_PASSES

use std::collections::HashMap;

use leakless_device::shader::ShaderInfo;
use leakless_device::{BindingDecl, ComputePipeline, Gpu, RustLayout};
use leakless_graph::PassName;

use crate::error::{RenderError, Result};
use crate::trace::Backend;

/// The module a compute pass runs.
#[derive(Clone, Copy, Debug)]
pub enum PassShader {
    /// One module for every backend: the pass traces no rays.
    Any(&'static ShaderInfo),
    /// A module that traces (it includes `trace.glsl`), compiled once per backend.
    PerBackend { rayquery: &'static ShaderInfo, compute: &'static ShaderInfo },
}

/// What pipeline creation, the bindings test and the timing tables know of a compute pass.
#[derive(Debug)]
pub struct ComputePassDef {
    /// The pass's name in the graph (some defs run under several names, as the scan does).
    pub name: PassName,
    pub shader: PassShader,
    /// Its binding groups, matched with the shader by name in any order; a pass whose shader
    /// traces also binds its backend's trace structures.
    pub bindings: &'static [&'static [BindingDecl]],
    pub push: Option<RustLayout>,
    /// The workgroup size the pass's dispatch arithmetic assumes, checked when the pipeline is
    /// made; `None` when it adapts to the shader's.
    pub workgroup: Option<[u32; 3]>,
}

impl ComputePassDef {
    /// A pass that traces no rays, running `shader` on every backend.
    pub const fn any(name: PassName, shader: &'static ShaderInfo, bindings: &'static [&'static [BindingDecl]]) -> Self {
        ComputePassDef { name, shader: PassShader::Any(shader), bindings, push: None, workgroup: None }
    }

    /// A pass that traces rays, with one module per backend (`rayquery`, `compute`).
    pub const fn traced(
        name: PassName,
        (rayquery, compute): (&'static ShaderInfo, &'static ShaderInfo),
        bindings: &'static [&'static [BindingDecl]],
    ) -> Self {
        let shader = PassShader::PerBackend { rayquery, compute };
        ComputePassDef { name, shader, bindings, push: None, workgroup: None }
    }

    /// With a push-constant block of this layout.
    pub const fn push(self, layout: RustLayout) -> Self {
        ComputePassDef { push: Some(layout), ..self }
    }

    /// Checked to have this workgroup size when its pipeline is made.
    pub const fn workgroup(self, size: [u32; 3]) -> Self {
        ComputePassDef { workgroup: Some(size), ..self }
    }

    /// The module this pass runs on `backend`.
    pub fn shader(&self, backend: Backend) -> &'static ShaderInfo {
        match self.shader {
            PassShader::Any(shader) => shader,
            PassShader::PerBackend { rayquery, compute } => backend.pick(rayquery, compute),
        }
    }

    /// Every binding the pass declares on `backend`.
    pub fn decls(&self, backend: Backend) -> Vec<BindingDecl> {
        let trace: &[BindingDecl] = match self.shader {
            PassShader::Any(_) => &[],
            PassShader::PerBackend { .. } => backend.bindings(),
        };
        self.bindings.iter().copied().chain([trace]).flatten().copied().collect()
    }

    /// Makes the pass's pipeline for `backend`, its bindings checked against reflection.
    pub fn create(&self, gpu: &Gpu, backend: Backend) -> Result<ComputePipeline> {
        let shader = self.shader(backend);
        let pipeline = ComputePipeline::new(gpu, self.name.label, shader, &self.decls(backend), self.push.as_ref())?;
        match self.workgroup {
            Some(want) if pipeline.workgroup_size() != want => Err(RenderError::Settings(format!(
                "{} has workgroup size {:?}; the {} pass dispatches for {want:?}",
                shader.name,
                pipeline.workgroup_size(),
                self.name
            ))),
            _ => Ok(pipeline),
        }
    }
}

/// The pipelines of a set of passes, by shader module, made for each backend when first asked.
pub struct Pipelines {
    defs: &'static [&'static ComputePassDef],
    by_module: HashMap<&'static str, ComputePipeline>,
}

impl Pipelines {
    /// The pipelines of `defs` on `backend`.
    pub fn new(gpu: &Gpu, defs: &'static [&'static ComputePassDef], backend: Backend) -> Result<Pipelines> {
        let mut pipelines = Pipelines { defs, by_module: HashMap::new() };
        pipelines.prepare(gpu, backend)?;
        Ok(pipelines)
    }

    /// Makes what `backend` needs and is not made yet (the tracing passes of a backend used
    /// for the first time).
    pub fn prepare(&mut self, gpu: &Gpu, backend: Backend) -> Result<()> {
        for def in self.defs {
            let module = def.shader(backend).name;
            if !self.by_module.contains_key(module) {
                self.by_module.insert(module, def.create(gpu, backend)?);
            }
        }
        Ok(())
    }

    /// The pipelines as the passes of one frame on `backend` use them.
    pub fn on(&self, backend: Backend) -> PipelineSet<'_> {
        PipelineSet { pipelines: self, backend }
    }
}

/// The pipelines of one backend.
#[derive(Clone, Copy)]
pub struct PipelineSet<'a> {
    pipelines: &'a Pipelines,
    backend: Backend,
}

impl<'a> PipelineSet<'a> {
    /// The pipeline of `def`. Panics when `def` is not among the cache's passes, or the
    /// backend was not prepared: both are bugs the renderer's tests find at once.
    pub fn get(&self, def: &ComputePassDef) -> &'a ComputePipeline {
        let module = def.shader(self.backend).name;
        self.pipelines
            .by_module
            .get(module)
            .unwrap_or_else(|| panic!("no pipeline for {module} (pass {}): list it in passes::FRAME_PASSES", def.name))
    }

    pub fn backend(&self) -> Backend {
        self.backend
    }
}
