//! Compute passes' definitions, and their pipelines made from them: a pass is a function over
//! the graph, which lends it its pipeline ([`Graph::pipeline`](leakless_graph::Graph::pipeline)),
//! with no pipeline of its own to construct and no field to add to the renderer. Every pass of a
//! frame collects itself into [`passes::FRAME_PASSES`]; [`Pipelines`] makes them for a backend
//! when the backend is first used (those marked on demand when a frame first runs them), and
//! the bindings test checks the same collection against reflection.
//!
//! [`passes::FRAME_PASSES`]: crate::passes::FRAME_PASSES

mod add;

pub use add::Threads;

use std::collections::HashMap;
use std::marker::PhantomData;
use std::rc::Rc;

use leakless_device::shader::ShaderInfo;
use leakless_device::{BindingDecl, ComputePipeline, Gpu, PushConstants, RustLayout, Specialization};
use leakless_graph::{BindingGroup, PassName, PipelineTable};

use crate::error::{RenderError, Result};
use crate::frame_set::FRAME_SET;
use crate::trace::Backend;
use crate::tuning::DeviceTuning;

/// The module a compute pass runs.
#[derive(Clone, Copy, Debug)]
pub enum PassShader {
    /// One module for every backend: the pass traces no rays.
    Any(&'static ShaderInfo),
    /// A module that traces (it includes `trace.glsl`), compiled once per backend.
    PerBackend { rayquery: &'static ShaderInfo, compute: &'static ShaderInfo },
}

/// What pipeline creation, the bindings test and the timing tables know of a compute pass,
/// whatever its types: the collections hold these ([`ComputePass::def`]).
#[derive(Debug)]
pub struct ComputePassDef {
    /// The pass's name in the graph (some defs run under several names, as the scan does).
    pub name: PassName,
    pub shader: PassShader,
    /// Its own binding group, the one the resources it is added with declare.
    pub own: &'static [BindingDecl],
    /// The groups it shares with other passes (the frame and lights, the G-buffer), declared
    /// where it is added; bindings are matched with the shader by name in any order. What the
    /// frame set holds (the scene, the emitters, the trace structures) is no pass's to declare.
    pub shared: &'static [&'static [BindingDecl]],
    pub push: Option<RustLayout>,
    /// The workgroup size the pass's dispatch arithmetic assumes, checked when the pipeline is
    /// made; `None` when it adapts to the shader's.
    pub workgroup: Option<[u32; 3]>,
    /// The values of its specialization constants under a device tuning (`None`: the
    /// module's defaults).
    pub specialize: Option<fn(&DeviceTuning) -> Specialization>,
    /// Made only when a frame asks for it ([`Pipelines::prepare`]'s `wanted`), not with the
    /// others: a large module that some methods never run (the gather's estimators, the path
    /// tracer), whose pipeline lavapipe takes about 0.1 s to make.
    pub on_demand: bool,
}

/// A compute pass's definition, typed by its own group's bindings `B` and its push constants
/// `P`: the pass is added with resources that declare `B` and a `P`, which the compiler checks
/// ([`ComputePass::add`]). Declared with [`compute_pass!`], which also collects it.
///
/// ```
/// use leakless::passes::scan::{ScanResources, SCAN};
/// fn add<'r>(graph: &mut leakless_graph::Graph<'r>, histograms: &'r mut leakless_graph::BufferHandle) {
///     SCAN.add(graph, ScanResources { histograms }, Default::default(), [1, 1, 1]);
/// }
/// ```
///
/// The same call with another pass's definition does not compile:
///
/// ```compile_fail
/// use leakless::passes::{compose::COMPOSE, scan::ScanResources};
/// fn add<'r>(graph: &mut leakless_graph::Graph<'r>, histograms: &'r mut leakless_graph::BufferHandle) {
///     COMPOSE.add(graph, ScanResources { histograms }, Default::default(), [1, 1, 1]);
/// }
/// ```
pub struct ComputePass<B, P> {
    def: ComputePassDef,
    types: PhantomData<fn(B, P)>,
}

impl<B: BindingGroup, P: PushConstants> ComputePass<B, P> {
    const fn new(name: PassName, shader: PassShader, shared: &'static [&'static [BindingDecl]]) -> Self {
        let def = ComputePassDef {
            name,
            shader,
            own: B::DECLS,
            shared,
            push: P::PUSH_LAYOUT,
            workgroup: None,
            specialize: None,
            on_demand: false,
        };
        ComputePass { def, types: PhantomData }
    }

    /// A pass that traces no rays, running `shader` on every backend.
    pub const fn any(name: PassName, shader: &'static ShaderInfo, shared: &'static [&'static [BindingDecl]]) -> Self {
        Self::new(name, PassShader::Any(shader), shared)
    }

    /// A pass that traces rays, with one module per backend (`rayquery`, `compute`).
    pub const fn traced(
        name: PassName,
        (rayquery, compute): (&'static ShaderInfo, &'static ShaderInfo),
        shared: &'static [&'static [BindingDecl]],
    ) -> Self {
        Self::new(name, PassShader::PerBackend { rayquery, compute }, shared)
    }

    /// Checked to have this workgroup size when its pipeline is made.
    pub const fn workgroup(self, size: [u32; 3]) -> Self {
        let ComputePass { def, types } = self;
        ComputePass { def: ComputePassDef { workgroup: Some(size), ..def }, types }
    }

    /// Made when a frame first asks for it, not with the rest ([`ComputePassDef::on_demand`]).
    pub const fn on_demand(self) -> Self {
        let ComputePass { def, types } = self;
        ComputePass { def: ComputePassDef { on_demand: true, ..def }, types }
    }

    /// Specialized per device tuning by `specialize`.
    pub const fn specialize(self, specialize: fn(&DeviceTuning) -> Specialization) -> Self {
        let ComputePass { def, types } = self;
        ComputePass { def: ComputePassDef { specialize: Some(specialize), ..def }, types }
    }
}

impl<B, P> ComputePass<B, P> {
    /// The definition without its types, as the collections hold it.
    pub const fn def(&'static self) -> &'static ComputePassDef {
        &self.def
    }
}

impl<B, P> std::ops::Deref for ComputePass<B, P> {
    type Target = ComputePassDef;
    fn deref(&self) -> &ComputePassDef {
        &self.def
    }
}

/// Declares compute passes: each `NAME`, a [`ComputePass`], is collected into
/// `passes::SLICE` (`FRAME_PASSES` or `TOOL_PASSES`), so no list names it again.
///
/// ```ignore
/// compute_pass! {
///     pub static COMPOSE in FRAME_PASSES: ComputePass<ComposeBindings, ComposeParams> =
///         ComputePass::any(PassName::new("compose", group::COMPOSE), &shaders::COMPOSE_COMP, &[]);
/// }
/// ```
macro_rules! compute_pass {
    ($($(#[$attr:meta])* $vis:vis static $name:ident in $slice:ident: $ty:ty = $def:expr;)+) => {$(
        $(#[$attr])*
        $vis static $name: $ty = $def;
        const _: () = {
            #[linkme::distributed_slice($crate::passes::$slice)]
            static DEF: &$crate::pipelines::ComputePassDef = $name.def();
        };
    )+};
}
pub(crate) use compute_pass;

impl ComputePassDef {
    /// Its specialization under `tuning`.
    pub fn specialization(&self, tuning: &DeviceTuning) -> Specialization {
        self.specialize.map_or_else(Specialization::new, |f| f(tuning))
    }

    /// The module this pass runs on `backend`.
    pub fn shader(&self, backend: Backend) -> &'static ShaderInfo {
        match self.shader {
            PassShader::Any(shader) => shader,
            PassShader::PerBackend { rayquery, compute } => backend.pick(rayquery, compute),
        }
    }

    /// Every binding the pass declares: its own group and the shared ones it is added with
    /// (the frame set's are not a pass's: `frame_set.rs`).
    pub fn decls(&self) -> Vec<BindingDecl> {
        [self.own].into_iter().chain(self.shared.iter().copied()).flatten().copied().collect()
    }

    /// Makes the pass's pipeline for `backend` under `tuning`, its bindings checked against
    /// reflection.
    pub fn create(&self, gpu: &Gpu, backend: Backend, tuning: &DeviceTuning) -> Result<ComputePipeline> {
        let shader = self.shader(backend);
        let spec = self.specialization(tuning);
        let (label, decls, push) = (self.name.label, self.decls(), self.push.as_ref());
        let pipeline = ComputePipeline::new(gpu, label, shader, FRAME_SET, &decls, push, &spec)?;
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

/// The pipelines of a set of passes: one table per backend (what a frame's graph is lent),
/// each pass's pipeline made once per shader module, so the passes that trace nothing share
/// theirs between the backends' tables. Two passes may run one module under different
/// specializations (the gather's estimators): each makes, and is checked with, its own. A pass
/// marked [`on_demand`](ComputePassDef::on_demand) is made when a frame first names it.
pub struct Pipelines {
    defs: Vec<&'static ComputePassDef>,
    tuning: DeviceTuning,
    /// Each (module, pass)'s pipeline.
    by_module: HashMap<(&'static str, PassName), Rc<ComputePipeline>>,
    tables: [PipelineTable; 2],
}

impl Pipelines {
    /// The pipelines of `defs` on `backend`, specialized for `tuning`.
    pub fn new(
        gpu: &Gpu,
        defs: &[&'static ComputePassDef],
        backend: Backend,
        tuning: &DeviceTuning,
    ) -> Result<Pipelines> {
        let defs = defs.to_vec();
        let mut pipelines =
            Pipelines { defs, tuning: tuning.clone(), by_module: HashMap::new(), tables: Default::default() };
        pipelines.prepare(gpu, backend, &[])?;
        Ok(pipelines)
    }

    /// Makes what `backend` needs and is not made yet (a backend used for the first time, an
    /// on-demand pass that `wanted` names for the first time).
    pub fn prepare(&mut self, gpu: &Gpu, backend: Backend, wanted: &[PassName]) -> Result<()> {
        let table = &mut self.tables[backend as usize];
        for &def in &self.defs {
            if table.contains(def.name) || (def.on_demand && !wanted.contains(&def.name)) {
                continue;
            }
            let key = (def.shader(backend).name, def.name);
            let pipeline = match self.by_module.get(&key) {
                Some(made) => made.clone(),
                None => Rc::new(def.create(gpu, backend, &self.tuning)?),
            };
            self.by_module.insert(key, pipeline.clone());
            table.insert(def.name, pipeline);
        }
        Ok(())
    }

    /// The tuning they were specialized for.
    pub fn tuning(&self) -> &DeviceTuning {
        &self.tuning
    }

    /// The pipelines of the passes on `backend`, for a frame's graph
    /// ([`Graph::with_pipelines`](leakless_graph::Graph::with_pipelines)).
    pub fn table(&self, backend: Backend) -> &PipelineTable {
        &self.tables[backend as usize]
    }
}
