//! Recording a pass: its declared uses resolve to resources, and its bindings are declared
//! once, as a struct whose field names are the shader's binding names
//! ([`shader_bindings!`](crate::shader_bindings)). The same struct gives the pipeline its
//! declarations (checked against reflection) and the dispatch its resources.

use leakless_device::sync::Access;
use leakless_device::{BindingAccess, Bound, Buffer, Cmd, ComputePipeline, GraphicsPipeline, Image, Result};

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

/// No group: a pass that binds only its own.
impl Bindings for () {
    fn bind<'a>(&self, _: Resolved<'a>, _: &mut Vec<(&'static str, Bound<'a>)>) {}
}

/// A group bound only where present (what a device without it leaves out).
impl<B: Bindings> Bindings for Option<B> {
    fn bind<'a>(&self, res: Resolved<'a>, out: &mut Vec<(&'static str, Bound<'a>)>) {
        if let Some(b) = self {
            b.bind(res, out);
        }
    }
}

/// The resources struct of a [`shader_bindings!`] group: it declares its handles' uses on a
/// pass and gives the bindings a dispatch binds. A compute pass's definition takes it, so that
/// adding the pass is one call with its resources (`COMPOSE.add(graph, ComposeResources { … },
/// params, threads)`).
pub trait DeclareBindings {
    /// The bindings struct the declaration returns.
    type Bindings: Bindings;
    /// Its declarations (the pipeline's), to check a pass against the group it is given.
    const DECLS: &'static [leakless_device::BindingDecl];
    fn declare_on(self, pass: &mut crate::PassBuilder<'_, '_>, stage: Stage) -> Self::Bindings;
}

/// A [`shader_bindings!`] group's bindings struct: what a typed pass definition names as its
/// own group.
pub trait BindingGroup: Bindings {
    const DECLS: &'static [leakless_device::BindingDecl];
}

/// Several groups bound together, in order.
macro_rules! tuple_bindings {
    ($($g:ident),+) => {
        impl<$($g: Bindings),+> Bindings for ($($g,)+) {
            #[allow(non_snake_case)]
            fn bind<'a>(&self, res: Resolved<'a>, out: &mut Vec<(&'static str, Bound<'a>)>) {
                let ($($g,)+) = self;
                $($g.bind(res, out);)+
            }
        }
    };
}
tuple_bindings!(A, B);
tuple_bindings!(A, B, C);
tuple_bindings!(A, B, C, D);

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

/// The shader stage a pass's bindings are used in: with a binding's [`BindingAccess`] it
/// gives the graph's [`Access`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    Compute,
    Vertex,
    Fragment,
}

impl Stage {
    /// How a binding of this stage uses its resource. Raster stages only read bindings (the
    /// renderer's raster passes write attachments, declared as such).
    pub fn access(self, access: BindingAccess, image: bool) -> Access {
        match (self, access) {
            (Stage::Compute, BindingAccess::Read) => Access::ComputeRead,
            (Stage::Compute, BindingAccess::Write) => Access::ComputeWrite,
            (Stage::Compute, BindingAccess::ReadWrite) => Access::ComputeReadWrite,
            (Stage::Vertex, BindingAccess::Read) if image => {
                panic!("a vertex stage reading a storage image has no Access with its layout (GENERAL)")
            }
            (Stage::Vertex, BindingAccess::Read) => Access::VertexShaderRead,
            (Stage::Fragment, BindingAccess::Read) if image => Access::FragmentStorageRead,
            (Stage::Fragment, BindingAccess::Read) => Access::FragmentRead,
            (stage, access) => panic!("{stage:?} bindings are read only, not {access:?}"),
        }
    }
}

/// Declares the bindings of a shader (or a group shared by several) once, each with its
/// access, kind and layout. It makes two structs and what joins them:
///
/// * the bindings struct, whose fields are named like the shader's bindings and hold their
///   declared uses; its `DECLS` (the pipeline's declarations, checked against reflection down
///   to member offsets and to the GLSL's `readonly` / `writeonly`) and its [`Bindings`] impl
///   (what a dispatch binds, by the same names);
/// * the resources struct, the same fields holding the graph's handles: `&` for what is read,
///   `&mut` for what is written, so a call site shows what a pass changes;
/// * `declare(pass, stage, resources)` on the bindings struct, which declares each resource's
///   read or write on the pass (the graph derives barriers from these) and returns the uses.
///
/// Access: `read`, `write`, `read_write`. Kinds: `uniform(LAYOUT)`, `block(LAYOUT)` (a storage
/// buffer holding one struct), `array(LAYOUT)` (a storage buffer of a runtime array), `words`
/// (a storage buffer whose layout is not checked), `image` (a storage image), `accel` (a
/// top-level acceleration structure, bound by its raw handle; the buffers behind it are the
/// caller's to declare).
///
/// ```ignore
/// shader_bindings! {
///     /// What splat.comp binds.
///     pub struct SplatBindings {
///         photons: read array(Photon::LAYOUT),
///         splat_counters: read_write block(SplatCounters::LAYOUT),
///         node_counts: read_write words,
///     }
///     /// The graph's resources behind them.
///     pub struct SplatResources;
/// }
/// ```
#[macro_export]
macro_rules! shader_bindings {
    ($(#[$attr:meta])* $vis:vis struct $name:ident {
        $($field:ident : $access:ident $kind:ident $(($layout:expr))?),* $(,)?
    }
    $(#[$rattr:meta])* $rvis:vis struct $resources:ident;) => {
        $(#[$attr])*
        #[derive(Clone, Copy, Debug)]
        $vis struct $name { $(pub $field: $crate::shader_bindings!(@use $kind)),* }

        $(#[$rattr])*
        $rvis struct $resources<'h> { $(pub $field: $crate::shader_bindings!(@handle 'h, $access $kind)),* }

        impl $name {
            /// The shader's bindings as this struct declares them.
            pub const DECLS: &'static [$crate::BindingDecl] =
                &[$($crate::shader_bindings!(@decl $field $access $kind $(($layout))?)),*];

            /// Declares on `pass` the use of each resource in `stage`, as its binding's access
            /// says, and returns the uses a dispatch binds.
            #[allow(unused_variables)]
            pub fn declare(pass: &mut $crate::PassBuilder<'_, '_>, stage: $crate::Stage, resources: $resources<'_>) -> Self {
                $name { $($field: $crate::shader_bindings!(@declare pass, stage, resources.$field, $access $kind)),* }
            }
        }
        impl $crate::Bindings for $name {
            fn bind<'a>(&self, res: $crate::Resolved<'a>, out: &mut Vec<(&'static str, $crate::Bound<'a>)>) {
                $(out.push((stringify!($field), $crate::shader_bindings!(@bound res, self.$field, $kind)));)*
            }
        }
        impl $crate::BindingGroup for $name {
            const DECLS: &'static [$crate::BindingDecl] = $name::DECLS;
        }
        impl $crate::DeclareBindings for $resources<'_> {
            type Bindings = $name;
            const DECLS: &'static [$crate::BindingDecl] = $name::DECLS;
            fn declare_on(self, pass: &mut $crate::PassBuilder<'_, '_>, stage: $crate::Stage) -> $name {
                $name::declare(pass, stage, self)
            }
        }
    };
    (@use image) => { $crate::Img };
    (@use accel) => { $crate::vk::AccelerationStructureKHR };
    (@use $buffer:ident) => { $crate::Buf };
    (@handle $h:lifetime, read accel) => { $crate::vk::AccelerationStructureKHR };
    (@handle $h:lifetime, read image) => { &$h $crate::ImageHandle };
    (@handle $h:lifetime, $access:ident image) => { &$h mut $crate::ImageHandle };
    (@handle $h:lifetime, read $buffer:ident) => { &$h $crate::BufferHandle };
    (@handle $h:lifetime, $access:ident $buffer:ident) => { &$h mut $crate::BufferHandle };
    (@access read) => { $crate::BindingAccess::Read };
    (@access write) => { $crate::BindingAccess::Write };
    (@access read_write) => { $crate::BindingAccess::ReadWrite };
    (@decl $f:ident read uniform ($l:expr)) => { $crate::BindingDecl::uniform(stringify!($f), $l) };
    (@decl $f:ident read accel) => { $crate::BindingDecl::acceleration_structure(stringify!($f)) };
    (@decl $f:ident $a:ident block ($l:expr)) => {
        $crate::BindingDecl::storage_block(stringify!($f), $crate::shader_bindings!(@access $a), $l)
    };
    (@decl $f:ident $a:ident array ($l:expr)) => {
        $crate::BindingDecl::storage_array(stringify!($f), $crate::shader_bindings!(@access $a), $l)
    };
    (@decl $f:ident $a:ident words) => {
        $crate::BindingDecl::storage_words(stringify!($f), $crate::shader_bindings!(@access $a))
    };
    (@decl $f:ident $a:ident image) => {
        $crate::BindingDecl::storage_image(stringify!($f), $crate::shader_bindings!(@access $a))
    };
    (@declare $pass:ident, $stage:ident, $v:expr, read accel) => { $v };
    (@declare $pass:ident, $stage:ident, $v:expr, read image) => {
        $pass.read($v, $stage.access($crate::BindingAccess::Read, true))
    };
    (@declare $pass:ident, $stage:ident, $v:expr, read $buffer:ident) => {
        $pass.read($v, $stage.access($crate::BindingAccess::Read, false))
    };
    (@declare $pass:ident, $stage:ident, $v:expr, $a:ident image) => {
        $pass.write($v, $stage.access($crate::shader_bindings!(@access $a), true))
    };
    (@declare $pass:ident, $stage:ident, $v:expr, $a:ident $buffer:ident) => {
        $pass.write($v, $stage.access($crate::shader_bindings!(@access $a), false))
    };
    (@bound $res:ident, $v:expr, image) => { $crate::Bound::Image($res.image($v)) };
    (@bound $res:ident, $v:expr, accel) => { $crate::Bound::Accel($v) };
    (@bound $res:ident, $v:expr, $buffer:ident) => { $crate::Bound::Buffer($res.buffer($v)) };
}
