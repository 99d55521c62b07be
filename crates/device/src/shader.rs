//! Shader modules embedded at build time, with what reflection found in them, and the check
//! of a pass's declared bindings against that reflection.
//!
//! `crates/renderer/build.rs` compiles `shaders-glsl/` with glslang, reflects each module with
//! naga and generates one `ShaderInfo` static per module. A pass declares, once, what it binds
//! by name (`BindingDecl`); `check_bindings` compares both sides so that a renamed, retyped or
//! resized resource fails with a message naming shader, binding and pass.

/// Pipeline stage a module is compiled for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShaderStage {
    Vertex,
    Fragment,
    Compute,
}

/// Descriptor kinds the renderer uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BindingKind {
    UniformBuffer,
    StorageBuffer,
    StorageImage,
    SampledImage,
    Sampler,
    CombinedImageSampler,
    AccelerationStructure,
}

/// What a binding's shader may do with its data: storage buffers and images as their GLSL
/// `readonly` / `writeonly` qualifiers say; uniform buffers, sampled images, samplers and
/// acceleration structures are only read. A pass declares the same of each binding, and the
/// graph's reads and writes follow from it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BindingAccess {
    Read,
    Write,
    ReadWrite,
}

impl BindingAccess {
    pub fn reads(self) -> bool {
        self != BindingAccess::Write
    }
    pub fn writes(self) -> bool {
        self != BindingAccess::Read
    }
}

/// A member of a block or struct: name, byte offset.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Member {
    pub name: &'static str,
    pub offset: u32,
}

/// The layout of the data behind a buffer binding as the shader sees it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BlockLayout {
    /// Size of the fixed part of the block in bytes (without a trailing runtime array).
    pub size: u32,
    /// Members of the block, in declaration order.
    pub members: &'static [Member],
    /// Stride of the element of a trailing runtime array, if the block ends with one.
    pub array_stride: Option<u32>,
    /// Layout of that array element when it is a struct.
    pub element_members: &'static [Member],
}

/// One resource binding found by reflection.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReflectedBinding {
    /// The variable's instance name in GLSL (`uniform Frame { .. } frame;` → `frame`).
    pub name: &'static str,
    pub set: u32,
    pub binding: u32,
    pub kind: BindingKind,
    /// What the shader's qualifiers allow.
    pub access: BindingAccess,
    /// Block layout for uniform and storage buffers.
    pub layout: Option<BlockLayout>,
}

/// A specialization constant of a module: `layout(constant_id = 3) const uint RAY_QUEUE = 64u;`
/// is `{ name: "RAY_QUEUE", id: 3, default: 64 }`; a `local_size_x_id` workgroup size's are
/// named `local_size_x` (`_y`, `_z`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SpecConstant {
    pub name: &'static str,
    pub id: u32,
    /// The default value's bits (bools are 0 or 1).
    pub default: u32,
}

/// A compiled shader module.
#[derive(Clone, Copy, Debug)]
pub struct ShaderInfo {
    /// File name in `shaders-glsl/`, with the variant suffix for tracing shaders.
    pub name: &'static str,
    pub stage: ShaderStage,
    pub spirv: &'static [u32],
    /// Workgroup size for compute shaders (the defaults of a `local_size_x_id` one), `[1, 1, 1]`
    /// otherwise.
    pub workgroup_size: [u32; 3],
    /// Specialization constants, by id: what a pipeline may set by name
    /// ([`Specialization`](crate::Specialization)).
    pub spec_constants: &'static [SpecConstant],
    /// What reflection found (naga, or for ray-query modules, which naga's SPIR-V front end
    /// rejects, a SPIR-V scan plus the layouts of their compute-BVH twins), or why it could not
    /// run.
    pub reflection: Result<&'static [ReflectedBinding], &'static str>,
    /// The `layout(push_constant)` block, if the module declares one (for ray-query modules,
    /// the layout of their compute twin's block).
    pub push_constants: Option<BlockLayout>,
}
