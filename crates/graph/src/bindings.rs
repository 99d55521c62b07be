//! Recording a pass: its declared uses resolve to resources, and its bindings are declared
//! once, as a struct whose field names are the shader's binding names
//! ([`shader_bindings!`](crate::shader_bindings)). The same struct gives the pipeline its
//! declarations (checked against reflection) and the dispatch its resources.

use leakless_device::{Bound, Buffer, Cmd, ComputePipeline, GraphicsPipeline, Image, Result};

use crate::graph::{Buf, Img};

/// A resolved resource of the executing graph.
#[derive(Clone, Copy)]
pub(crate) enum Resource<'a> {
    Buffer(&'a Buffer),
    Image(&'a Image),
}

/// The executing graph's resources, by declared use.
#[derive(Clone, Copy)]
pub struct Resolved<'a> {
    pub(crate) resources: &'a [Resource<'a>],
}

impl<'a> Resolved<'a> {
    pub fn buffer(&self, b: Buf) -> &'a Buffer {
        match self.resources[b.0] {
            Resource::Buffer(b) => b,
            Resource::Image(_) => unreachable!("a Buf names a buffer"),
        }
    }

    pub fn image(&self, i: Img) -> &'a Image {
        match self.resources[i.0] {
            Resource::Image(i) => i,
            Resource::Buffer(_) => unreachable!("an Img names an image"),
        }
    }
}

/// A group of shader bindings that can name its resources (see [`shader_bindings!`]).
pub trait Bindings {
    fn bind<'a>(&self, res: Resolved<'a>, out: &mut Vec<(&'static str, Bound<'a>)>);
}

/// What a pass's recording closure gets: the command buffer and its resources.
pub struct PassContext<'c, 'g, 'a> {
    pub cmd: &'c mut Cmd<'g>,
    pub res: Resolved<'a>,
}

impl<'a> PassContext<'_, '_, 'a> {
    pub fn buffer(&self, b: Buf) -> &'a Buffer {
        self.res.buffer(b)
    }

    pub fn image(&self, i: Img) -> &'a Image {
        self.res.image(i)
    }

    fn bound(&self, groups: &[&dyn Bindings]) -> Vec<(&'static str, Bound<'a>)> {
        let mut bound = Vec::new();
        for g in groups {
            g.bind(self.res, &mut bound);
        }
        bound
    }

    /// Dispatches `pipeline` over `threads` invocations with the bindings of `groups` and
    /// `push` as its push constants (`&()` when it has none).
    pub fn dispatch<P: bytemuck::NoUninit>(
        &mut self,
        pipeline: &ComputePipeline,
        groups: &[&dyn Bindings],
        push: &P,
        threads: [u32; 3],
    ) -> Result<()> {
        let bound = self.bound(groups);
        self.cmd.dispatch(pipeline, &bound, bytemuck::bytes_of(push), threads)
    }

    /// Dispatches `pipeline` with the workgroup counts in `args` at `offset`, never more than
    /// `most_threads` need (see [`Cmd::dispatch_indirect`]); the pass declares `args` with
    /// [`Access::IndirectCommandRead`](leakless_device::sync::Access::IndirectCommandRead).
    pub fn dispatch_indirect<P: bytemuck::NoUninit>(
        &mut self,
        pipeline: &ComputePipeline,
        groups: &[&dyn Bindings],
        push: &P,
        (args, offset): (Buf, u64),
        most_threads: [u32; 3],
    ) -> Result<()> {
        let bound = self.bound(groups);
        let args = self.buffer(args);
        self.cmd.dispatch_indirect(pipeline, &bound, bytemuck::bytes_of(push), args, offset, most_threads)
    }

    /// Draws (see [`Cmd::draw`]) with the bindings of `groups`.
    #[allow(clippy::too_many_arguments)]
    pub fn draw<P: bytemuck::NoUninit>(
        &mut self,
        pipeline: &GraphicsPipeline,
        groups: &[&dyn Bindings],
        push: &P,
        colors: &[(Img, [f32; 4])],
        depth: Option<Img>,
        vertices: Option<Buf>,
        vertex_count: u32,
    ) -> Result<()> {
        let bound = self.bound(groups);
        let colors: Vec<_> = colors.iter().map(|&(i, clear)| (self.image(i), clear)).collect();
        let depth = depth.map(|d| self.image(d));
        let vertices = vertices.map(|v| self.buffer(v));
        self.cmd.draw(pipeline, &bound, bytemuck::bytes_of(push), &colors, depth, vertices, vertex_count)
    }
}

/// Declares the bindings of a shader (or a group shared by several) once: a struct whose
/// fields are named like the shader's bindings and hold their declared uses, its
/// `DECLS` (the pipeline's declarations, checked against reflection down to member offsets),
/// and its [`Bindings`] impl (what a dispatch binds, by the same names).
///
/// Kinds: `uniform(LAYOUT)`, `block(LAYOUT)` (a storage buffer holding one struct),
/// `array(LAYOUT)` (a storage buffer of a runtime array), `words` (a storage buffer whose
/// layout is not checked), `image` (a storage image), `accel` (a top-level acceleration
/// structure).
///
/// ```ignore
/// shader_bindings! {
///     /// What splat.comp binds.
///     pub struct SplatBindings {
///         photons: array(Photon::LAYOUT),
///         splat_counters: block(SplatCounters::LAYOUT),
///         node_heads: words,
///     }
/// }
/// ```
#[macro_export]
macro_rules! shader_bindings {
    ($(#[$attr:meta])* $vis:vis struct $name:ident {
        $($field:ident : $kind:ident $(($layout:expr))?),* $(,)?
    }) => {
        $(#[$attr])*
        #[derive(Clone, Copy, Debug)]
        $vis struct $name { $(pub $field: $crate::shader_bindings!(@type $kind)),* }
        impl $name {
            /// The shader's bindings as this struct declares them.
            pub const DECLS: &'static [$crate::BindingDecl] =
                &[$($crate::shader_bindings!(@decl $field $kind $(($layout))?)),*];
        }
        impl $crate::Bindings for $name {
            fn bind<'a>(&self, res: $crate::Resolved<'a>, out: &mut Vec<(&'static str, $crate::Bound<'a>)>) {
                $(out.push((stringify!($field), $crate::shader_bindings!(@bound res, self.$field, $kind)));)*
            }
        }
    };
    (@type uniform) => { $crate::Buf };
    (@type block) => { $crate::Buf };
    (@type array) => { $crate::Buf };
    (@type words) => { $crate::Buf };
    (@type image) => { $crate::Img };
    (@type accel) => { $crate::vk::AccelerationStructureKHR };
    (@decl $f:ident uniform ($l:expr)) => { $crate::BindingDecl::uniform(stringify!($f), $l) };
    (@decl $f:ident block ($l:expr)) => { $crate::BindingDecl::storage_block(stringify!($f), $l) };
    (@decl $f:ident array ($l:expr)) => { $crate::BindingDecl::storage_array(stringify!($f), $l) };
    (@decl $f:ident words) => { $crate::BindingDecl::storage_words(stringify!($f)) };
    (@decl $f:ident image) => { $crate::BindingDecl::storage_image(stringify!($f)) };
    (@decl $f:ident accel) => { $crate::BindingDecl::acceleration_structure(stringify!($f)) };
    (@bound $res:ident, $v:expr, image) => { $crate::Bound::Image($res.image($v)) };
    (@bound $res:ident, $v:expr, accel) => { $crate::Bound::Accel($v) };
    (@bound $res:ident, $v:expr, $buffer:ident) => { $crate::Bound::Buffer($res.buffer($v)) };
}
