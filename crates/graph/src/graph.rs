//! Building a frame: resources are imported or asked of the pool by name, passes declare their
//! uses and hand the graph a closure that records their commands once the frame executes.

use leakless_device::sync::Access;
use leakless_device::{
    Buffer, BufferDesc, ComputePipeline, DeviceError, FrameBinding, Gpu, Image, ImageDesc, MemoryLocation, Result,
};

use crate::bindings::{Bindings, PassContext};
use crate::history::{pair_name, History};
use crate::name::PassName;
use crate::pipelines::PipelineTable;
use crate::pool::PoolKey;
use crate::runner::{GraphRunner, Timing};
use crate::vk;

/// A buffer known to the graph. Not `Clone`: writing it takes `&mut`, so a call site shows
/// what a pass changes.
#[derive(Debug)]
pub struct BufferHandle {
    id: usize,
    size: u64,
}

/// An image known to the graph. Not `Clone`: writing it takes `&mut`.
#[derive(Debug)]
pub struct ImageHandle {
    id: usize,
    extent: vk::Extent2D,
    format: vk::Format,
}

impl BufferHandle {
    pub fn size(&self) -> u64 {
        self.size
    }
}

impl ImageHandle {
    pub fn extent(&self) -> vk::Extent2D {
        self.extent
    }
    pub fn format(&self) -> vk::Format {
        self.format
    }
}

/// A declared use of a buffer: what a pass's recording closure resolves to the buffer.
#[derive(Clone, Copy, Debug)]
pub struct Buf(pub(crate) usize);

/// A declared use of an image.
#[derive(Clone, Copy, Debug)]
pub struct Img(pub(crate) usize);

/// Where a resource of the graph lives.
pub(crate) enum Source<'r> {
    Buffer(&'r Buffer),
    Image(&'r Image),
    /// A swapchain image just acquired: its old contents are discarded, and its first use
    /// waits for the acquire semaphore's stage (`SubmitSync::wait`).
    Acquired(&'r Image, vk::PipelineStageFlags2),
    PoolBuffer(PoolKey),
    PoolImage(PoolKey),
}

impl Source<'_> {
    fn is_image(&self) -> bool {
        matches!(self, Source::Image(_) | Source::Acquired(..) | Source::PoolImage(_))
    }
}

type Record<'r> = Box<dyn FnOnce(&mut PassContext<'_, '_, '_>) -> Result<()> + 'r>;

pub(crate) struct Pass<'r> {
    pub name: String,
    /// The group of [`PassName`] it was made with.
    pub group: &'static str,
    pub uses: Vec<(usize, Access)>,
    pub record: Record<'r>,
}

/// One frame's passes, in execution order. Made by [`GraphRunner::graph`], run by
/// [`Graph::submit`].
pub struct Graph<'r> {
    pub(crate) gpu: &'r Gpu,
    pub(crate) runner: &'r mut GraphRunner,
    pub(crate) sources: Vec<Source<'r>>,
    pub(crate) passes: Vec<Pass<'r>>,
    /// The pipelines passes ask for ([`Graph::pipeline`]).
    pub(crate) pipelines: Option<&'r PipelineTable>,
    /// What the frame binds once, in set 0 of every pipeline ([`Graph::bind_frame_set`]).
    pub(crate) frame_set: Option<FrameSetUses<'r>>,
    /// How this frame is timed: the runner's, unless [`Graph::with_timing`] chose otherwise.
    pub(crate) timing: Timing,
}

/// The frame set a graph was given: its declaration, the groups that bind it, and the reads
/// of the resources behind it that each pass running a shader of the frame set makes.
pub(crate) struct FrameSetUses<'r> {
    pub frame: &'static [FrameBinding],
    pub groups: Box<dyn Bindings + 'r>,
    uses: Vec<(usize, Access)>,
}

/// Why the graph refuses a second handle to a pool resource: two handles of one resource would
/// track its hazards apart, and the graph would derive no barrier between their uses.
fn asked_twice(key: &PoolKey) -> DeviceError {
    let name = match key {
        PoolKey::Persistent(name) | PoolKey::PerFrame(name, _) => name,
    };
    DeviceError::Unsupported(format!(
        "the frame's graph was asked twice for the resource {name:?}; pass the first handle on instead"
    ))
}

impl<'r> Graph<'r> {
    pub fn gpu(&self) -> &'r Gpu {
        self.gpu
    }

    /// Lends the graph the pipelines its passes ask for.
    pub fn with_pipelines(mut self, pipelines: &'r PipelineTable) -> Self {
        self.pipelines = Some(pipelines);
        self
    }

    /// Times this frame as `timing` says instead of as the runner does: one frame timed pass by
    /// pass among frames submitted at once, with nothing to restore whichever way it ends.
    pub fn with_timing(mut self, timing: Timing) -> Self {
        self.timing = timing;
        self
    }

    /// The compute pipeline of the pass `name`. Panics when the graph's table has none: a pass
    /// missing from the renderer's list, which every test of that pass finds at once.
    pub fn pipeline(&self, name: PassName) -> &'r ComputePipeline {
        let table = self.pipelines.unwrap_or_else(|| panic!("pass {name}: the graph was lent no pipelines"));
        table.get(name).unwrap_or_else(|| panic!("pass {name}: no pipeline in the graph's table (list it)"))
    }

    /// The frames the runner keeps in flight; per-frame resources have this many copies.
    pub fn frames_in_flight(&self) -> usize {
        self.runner.frames_in_flight()
    }

    /// The device address of the buffer behind `handle`, where it was made with
    /// `SHADER_DEVICE_ADDRESS` usage. A pass that reads a buffer through its address still binds
    /// it: the binding is what the graph orders the pass by and what reflection checks.
    pub fn buffer_address(&self, handle: &BufferHandle) -> Option<vk::DeviceAddress> {
        match &self.sources[handle.id] {
            Source::Buffer(b) => b.device_address(),
            Source::PoolBuffer(key) => self.runner.pool.buffer(key).device_address(),
            _ => None,
        }
    }

    pub fn import_buffer(&mut self, buffer: &'r Buffer) -> BufferHandle {
        self.sources.push(Source::Buffer(buffer));
        BufferHandle { id: self.sources.len() - 1, size: buffer.size() }
    }

    pub fn import_image(&mut self, image: &'r Image) -> ImageHandle {
        self.sources.push(Source::Image(image));
        ImageHandle { id: self.sources.len() - 1, extent: image.extent(), format: image.format() }
    }

    /// A swapchain image acquired for this frame. Its contents are discarded, and its first
    /// use is ordered after `wait_stage`, the stage at which the submission waits for the
    /// acquire semaphore (so the layout transition cannot run before the image is ready).
    pub fn import_acquired_image(&mut self, image: &'r Image, wait_stage: vk::PipelineStageFlags2) -> ImageHandle {
        self.sources.push(Source::Acquired(image, wait_stage));
        ImageHandle { id: self.sources.len() - 1, extent: image.extent(), format: image.format() }
    }

    /// The pool's buffer named `desc.name`, kept from frame to frame and made anew when the
    /// description changes. Its contents persist: a pass that relies on them says so.
    pub fn buffer(&mut self, desc: &BufferDesc<'_>) -> Result<BufferHandle> {
        self.pool_buffer(PoolKey::Persistent(desc.name.into()), desc)
    }

    /// The pool's image named `desc.name`, kept from frame to frame (see [`Graph::buffer`]).
    pub fn image(&mut self, desc: &ImageDesc<'_>) -> Result<ImageHandle> {
        let key = PoolKey::Persistent(desc.name.into());
        self.check_first(&key, true)?;
        let frame = self.runner.frame_index();
        self.runner.pool.ensure_image(self.gpu, key.clone(), desc, frame)?;
        self.sources.push(Source::PoolImage(key));
        Ok(ImageHandle { id: self.sources.len() - 1, extent: desc.extent, format: desc.format })
    }

    /// The history pair named `desc.name` ([`History`]): this frame writes `current`, and
    /// `previous` holds what the last frame that asked for the pair wrote, when `valid`.
    pub fn history_image(&mut self, desc: &ImageDesc<'_>) -> Result<History> {
        let name = desc.name;
        let keys = [0, 1].map(|i| PoolKey::Persistent(pair_name(name, i)));
        for key in &keys {
            self.check_first(key, true)?;
        }
        let frame = self.runner.frame_index();
        let mut remade = false;
        for key in &keys {
            remade |= self.runner.pool.ensure_image(self.gpu, key.clone(), desc, frame)?;
        }
        let (current, valid) = self.runner.pool.histories.entry(name.to_string()).or_default().advance(remade);
        let [a, b] = keys;
        let (current_key, previous_key) = if current == 0 { (a, b) } else { (b, a) };
        let mut handle = |key| {
            self.sources.push(Source::PoolImage(key));
            ImageHandle { id: self.sources.len() - 1, extent: desc.extent, format: desc.format }
        };
        let current = handle(current_key);
        let previous = handle(previous_key);
        Ok(History { current, previous, valid })
    }

    /// A buffer with one copy per frame in flight: this frame's copy is not used by any frame
    /// still running, so the host may write it now, or read it once this frame completed.
    pub fn frame_buffer(&mut self, desc: &BufferDesc<'_>) -> Result<BufferHandle> {
        self.pool_buffer(PoolKey::PerFrame(desc.name.into(), self.runner.slot()), desc)
    }

    /// Host data for this frame's passes (parameters, per-frame scene data), in a per-frame
    /// buffer written now. Host writes before a submission are visible to it: no barrier.
    pub fn upload(&mut self, name: &str, usage: vk::BufferUsageFlags, data: &[u8]) -> Result<BufferHandle> {
        let desc = BufferDesc { name, size: data.len() as u64, usage, location: MemoryLocation::CpuToGpu };
        let handle = self.frame_buffer(&desc)?;
        self.runner.pool.buffer(&PoolKey::PerFrame(name.into(), self.runner.slot())).write(0, data)?;
        Ok(handle)
    }

    fn pool_buffer(&mut self, key: PoolKey, desc: &BufferDesc<'_>) -> Result<BufferHandle> {
        self.check_first(&key, false)?;
        let frame = self.runner.frame_index();
        self.runner.pool.ensure_buffer(self.gpu, key.clone(), desc, frame)?;
        self.sources.push(Source::PoolBuffer(key));
        Ok(BufferHandle { id: self.sources.len() - 1, size: desc.size })
    }

    /// Errs when the frame already has a handle to the pool's buffer (or, `image`, image) `key`.
    fn check_first(&self, key: &PoolKey, image: bool) -> Result<()> {
        let asked = |s: &Source<'_>| match s {
            Source::PoolBuffer(k) => !image && k == key,
            Source::PoolImage(k) => image && k == key,
            _ => false,
        };
        if self.sources.iter().any(asked) {
            return Err(asked_twice(key));
        }
        Ok(())
    }

    /// Starts a pass; `name` gives its debug label, timing key and crash marker, the group its
    /// time counts under, and the pipeline its dispatch runs ([`PassBuilder::runs`] names
    /// another).
    pub fn pass<'g>(&'g mut self, name: PassName) -> PassBuilder<'g, 'r> {
        self.builder(name.label.to_string(), name.group, Some(name))
    }

    fn builder<'g>(
        &'g mut self,
        label: String,
        group: &'static str,
        pipeline: Option<PassName>,
    ) -> PassBuilder<'g, 'r> {
        PassBuilder { graph: self, name: label, group, pipeline, uses: Vec::new(), extends: None }
    }

    /// Starts pass number `index` of a repeated pass ("sort histogram 2"), running `name`'s
    /// pipeline.
    pub fn pass_numbered<'g>(&'g mut self, name: PassName, index: u32) -> PassBuilder<'g, 'r> {
        self.builder(format!("{} {index}", name.label), name.group, Some(name))
    }

    /// Continues the last pass labelled `label`: what the builder declares joins its uses, and what
    /// it records runs after the pass's own commands, inside its label, timestamps and crash
    /// markers. `None` when the graph has no such pass. Fault injection uses it to stall a
    /// named pass.
    pub fn extend_pass<'g>(&'g mut self, label: &str) -> Option<PassBuilder<'g, 'r>> {
        let index = self.passes.iter().rposition(|p| p.name == label)?;
        let (uses, group) = (self.passes[index].uses.clone(), self.passes[index].group);
        Some(PassBuilder { uses, extends: Some(index), ..self.builder(label.to_string(), group, None) })
    }

    /// Binds the groups `declare` returns as the frame set `frame` (set 0 of every pipeline),
    /// written once before the frame records and bound once per command buffer. The reads
    /// `declare` declares become every later pass's whose shader uses the frame set, so the
    /// graph derives their barriers (a TLAS rebuilt, vertices placed earlier in the frame).
    pub fn bind_frame_set<G: Bindings + 'r>(
        &mut self,
        frame: &'static [FrameBinding],
        declare: impl FnOnce(&mut PassBuilder<'_, 'r>) -> G,
    ) {
        let mut builder = self.builder("frame set".into(), "frame set", None);
        let groups = Box::new(declare(&mut builder));
        let uses = builder.uses;
        assert!(uses.iter().all(|(_, a)| !a.info().writes), "the frame set is read only");
        self.frame_set = Some(FrameSetUses { frame, groups, uses });
    }

    pub fn pass_names(&self) -> impl Iterator<Item = &str> {
        self.passes.iter().map(|p| p.name.as_str())
    }
}

/// Declares what one pass reads and writes; each declaration returns the use for the
/// recording closure to resolve.
pub struct PassBuilder<'g, 'r> {
    graph: &'g mut Graph<'r>,
    name: String,
    group: &'static str,
    /// The compute pipeline a dispatch runs, from the graph's table (`None`: a pass continued
    /// by [`Graph::extend_pass`], which records its own commands).
    pipeline: Option<PassName>,
    uses: Vec<(usize, Access)>,
    /// The pass this builder continues ([`Graph::extend_pass`]).
    extends: Option<usize>,
}

/// Handles the graph can declare uses of.
pub trait Handle {
    /// What a declaration hands back ([`Buf`] or [`Img`]).
    type Use: Copy;
    #[doc(hidden)]
    fn id(&self) -> usize;
    #[doc(hidden)]
    fn make_use(id: usize) -> Self::Use;
}

/// `Handle` for a handle type and the use its declarations hand back.
macro_rules! handle {
    ($($handle:ident => $use:ident),*) => {$(
        impl Handle for $handle {
            type Use = $use;
            fn id(&self) -> usize {
                self.id
            }
            fn make_use(id: usize) -> $use {
                $use(id)
            }
        }
    )*};
}
handle!(BufferHandle => Buf, ImageHandle => Img);

impl<'r> PassBuilder<'_, 'r> {
    fn declare<H: Handle>(&mut self, handle: &H, access: Access) -> H::Use {
        // Several reads of one resource are fine (a vertex buffer also read as storage); a
        // write, or two image layouts, must be one combined declaration.
        let is_image = self.graph.sources[handle.id()].is_image();
        let clash = self.uses.iter().any(|&(id, prev)| {
            id == handle.id()
                && (prev.info().writes
                    || access.info().writes
                    || (is_image && prev.info().layout != access.info().layout))
        });
        assert!(
            !clash,
            "pass {}: conflicting declarations of one resource; declare its combined use once (e.g. ComputeReadWrite)",
            self.name
        );
        self.uses.push((handle.id(), access));
        H::make_use(handle.id())
    }

    /// Declares a read. Panics if `access` writes: that is a bug in the pass.
    pub fn read<H: Handle>(&mut self, handle: &H, access: Access) -> H::Use {
        assert!(!access.info().writes, "pass {}: read() with writing access {access:?}", self.name);
        self.declare(handle, access)
    }

    /// Declares a write (or read-write); the handle is borrowed mutably to show it changes.
    pub fn write<H: Handle>(&mut self, handle: &mut H, access: Access) -> H::Use {
        assert!(access.info().writes, "pass {}: write() with read-only access {access:?}", self.name);
        self.declare(handle, access)
    }

    /// Runs the pipeline of the pass `name` instead of its own (one shader under several
    /// labels, as the prefix sum of each photon ordering).
    pub fn runs(self, name: PassName) -> Self {
        PassBuilder { pipeline: Some(name), ..self }
    }

    /// The compute pipeline the pass runs ([`Graph::pipeline`]).
    pub fn pipeline(&self) -> &'r ComputePipeline {
        let name = self.pipeline.unwrap_or_else(|| panic!("pass {} runs no pipeline of the graph's table", self.name));
        self.graph.pipeline(name)
    }

    /// Ends the declaration with one dispatch of the pass's pipeline over `threads`
    /// invocations, binding `groups` (a bindings struct, or a tuple of them) and pushing `push`
    /// (`()` when the shader has no push constants).
    pub fn dispatch<G, P>(self, groups: G, push: P, threads: [u32; 3])
    where
        G: Bindings + 'r,
        P: bytemuck::NoUninit + 'r,
    {
        let pipeline = self.pipeline();
        self.record(move |ctx| ctx.dispatch(pipeline, &[&groups], &push, threads));
    }

    /// Like [`PassBuilder::dispatch`], with the workgroup counts in `args` (see
    /// [`PassContext::dispatch_indirect`]).
    pub fn dispatch_indirect<G, P>(self, groups: G, push: P, args: (Buf, u64), most_threads: [u32; 3])
    where
        G: Bindings + 'r,
        P: bytemuck::NoUninit + 'r,
    {
        let pipeline = self.pipeline();
        self.record(move |ctx| ctx.dispatch_indirect(pipeline, &[&groups], &push, args, most_threads));
    }

    /// Declares the frame set's reads when the pass's pipeline uses the frame set.
    fn declare_frame_set_reads(&mut self) {
        let pipeline = self.pipeline.and_then(|name| self.graph.pipelines.and_then(|t| t.get(name)));
        if pipeline.is_none_or(|p| p.frame_uses().is_empty()) {
            return;
        }
        let Some(frame_set) = &self.graph.frame_set else {
            panic!(
                "pass {}: its shader reads the frame set, which its graph was not given (Graph::bind_frame_set)",
                self.name
            )
        };
        for &(id, access) in &frame_set.uses {
            if !self.uses.iter().any(|&(own, _)| own == id) {
                self.uses.push((id, access));
            }
        }
    }

    /// Ends the declaration with the commands the pass records when the frame executes.
    pub fn record(mut self, record: impl FnOnce(&mut PassContext<'_, '_, '_>) -> Result<()> + 'r) {
        self.declare_frame_set_reads();
        match self.extends {
            None => self.graph.passes.push(Pass {
                name: self.name,
                group: self.group,
                uses: self.uses,
                record: Box::new(record),
            }),
            Some(index) => {
                let pass = &mut self.graph.passes[index];
                let first = std::mem::replace(&mut pass.record, Box::new(|_| Ok(())));
                pass.uses = self.uses;
                pass.record = Box::new(move |ctx: &mut PassContext<'_, '_, '_>| {
                    first(ctx)?;
                    record(ctx)
                });
            }
        }
    }
}
