//! A minimal SPIR-V reader for crates/renderer/build.rs: the descriptor bindings of a module (name, set,
//! binding, kind, access qualifiers), its specialization constants and its workgroup size, read straight from the words. It covers what naga
//! cannot: modules naga's SPIR-V front end rejects (ray queries), and combined image samplers,
//! which naga folds into the image type. Buffer layouts are left to naga.
//!
//! Only the instructions below are decoded (their numbers from the `spirv` crate, the
//! specification's grammar); everything else is skipped by its word count.

use std::collections::HashMap;

use spirv::{BuiltIn, Decoration, Dim, ExecutionMode, Op, StorageClass};

const MAGIC: u32 = spirv::MAGIC_NUMBER;

// Opcodes.
const OP_NAME: u32 = Op::Name as u32;
const OP_EXECUTION_MODE: u32 = Op::ExecutionMode as u32;
const OP_CONSTANT: u32 = Op::Constant as u32;
const OP_EXECUTION_MODE_ID: u32 = Op::ExecutionModeId as u32;
const OP_SPEC_CONSTANT_TRUE: u32 = Op::SpecConstantTrue as u32;
const OP_SPEC_CONSTANT_FALSE: u32 = Op::SpecConstantFalse as u32;
const OP_SPEC_CONSTANT: u32 = Op::SpecConstant as u32;
const OP_SPEC_CONSTANT_COMPOSITE: u32 = Op::SpecConstantComposite as u32;
const OP_TYPE_IMAGE: u32 = Op::TypeImage as u32;
const OP_TYPE_SAMPLER: u32 = Op::TypeSampler as u32;
const OP_TYPE_SAMPLED_IMAGE: u32 = Op::TypeSampledImage as u32;
const OP_TYPE_ARRAY: u32 = Op::TypeArray as u32;
const OP_TYPE_RUNTIME_ARRAY: u32 = Op::TypeRuntimeArray as u32;
const OP_TYPE_STRUCT: u32 = Op::TypeStruct as u32;
const OP_TYPE_POINTER: u32 = Op::TypePointer as u32;
const OP_VARIABLE: u32 = Op::Variable as u32;
const OP_DECORATE: u32 = Op::Decorate as u32;
const OP_MEMBER_DECORATE: u32 = Op::MemberDecorate as u32;
const OP_TYPE_ACCELERATION_STRUCTURE_KHR: u32 = Op::TypeAccelerationStructureKHR as u32;

// Execution modes.
const LOCAL_SIZE: u32 = ExecutionMode::LocalSize as u32;
const LOCAL_SIZE_ID: u32 = ExecutionMode::LocalSizeId as u32;

// Image dimensions that are not images to leakless.
const DIM_BUFFER: u32 = Dim::DimBuffer as u32;
const DIM_SUBPASS_DATA: u32 = Dim::DimSubpassData as u32;

// Storage classes.
const UNIFORM_CONSTANT: u32 = StorageClass::UniformConstant as u32;
const UNIFORM: u32 = StorageClass::Uniform as u32;
const PUSH_CONSTANT: u32 = StorageClass::PushConstant as u32;
const STORAGE_BUFFER: u32 = StorageClass::StorageBuffer as u32;

// Decorations.
const SPEC_ID: u32 = Decoration::SpecId as u32;
const BLOCK: u32 = Decoration::Block as u32;
const BUILT_IN: u32 = Decoration::BuiltIn as u32;
const BUFFER_BLOCK: u32 = Decoration::BufferBlock as u32;
const BINDING: u32 = Decoration::Binding as u32;
const DESCRIPTOR_SET: u32 = Decoration::DescriptorSet as u32;
const NON_WRITABLE: u32 = Decoration::NonWritable as u32;
const NON_READABLE: u32 = Decoration::NonReadable as u32;

// Built-ins.
const WORKGROUP_SIZE: u32 = BuiltIn::WorkgroupSize as u32;

/// One descriptor binding of a module.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Resource {
    /// The variable's `OpName`: glslang names the variable of `buffer Photons { .. } photons;`
    /// "photons". Never empty (an unnamed block instance is an error).
    pub name: String,
    pub set: u32,
    pub binding: u32,
    /// Name of the `leakless_device::shader::BindingKind` variant.
    pub kind: &'static str,
    /// Name of the `leakless_device::shader::BindingAccess` variant: what the GLSL's
    /// `readonly` / `writeonly` allow (uniforms, samplers and acceleration structures are read).
    pub access: &'static str,
}

/// A specialization constant of a module (`layout(constant_id = N) const uint NAME = D;`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SpecConstant {
    /// Its `OpName`; the workgroup size's components (`local_size_x_id`) are named
    /// `local_size_x`, `local_size_y`, `local_size_z`.
    pub name: String,
    pub id: u32,
    /// The default value's bits (a bool is 0 or 1).
    pub default: u32,
}

/// What [`scan`] found.
pub struct Scan {
    /// Variables decorated with both `DescriptorSet` and `Binding` in the `UniformConstant`,
    /// `Uniform` and `StorageBuffer` storage classes, ordered by (set, binding).
    pub resources: Vec<Resource>,
    /// `LocalSize` execution mode, `[1, 1, 1]` without one; a `WorkgroupSize` built-in (from
    /// `local_size_x_id`) overrides it with its components' defaults.
    pub local_size: [u32; 3],
    /// Specialization constants, by id.
    pub spec_constants: Vec<SpecConstant>,
    /// Whether the module declares a `push_constant` block.
    pub push_constants: bool,
}

/// Resource types, after arrays of them are looked through.
#[derive(Clone, Copy)]
enum Ty {
    Image { dim: u32, sampled: u32 },
    Sampler,
    SampledImage,
    AccelerationStructure,
    Struct,
}

/// Reads the resources of a SPIR-V module. Fails on a module that is not SPIR-V, on a block
/// instance without a name, and on resource types that are not a `BindingKind`.
pub fn scan(words: &[u32]) -> Result<Scan, String> {
    if words.len() < 5 || words[0] != MAGIC {
        return Err("not a SPIR-V module (bad header)".into());
    }
    let mut names: HashMap<u32, String> = HashMap::new();
    let (mut types, mut element, mut pointee) = (HashMap::new(), HashMap::new(), HashMap::new());
    let (mut sets, mut bindings, mut blocks) = (HashMap::new(), HashMap::new(), HashMap::new());
    let (mut vars, mut local_size) = (Vec::new(), [1; 3]);
    // `readonly` / `writeonly`: on the variable (images), or on every member of a block.
    let (mut qualified, mut members, mut member_count) = (HashMap::new(), HashMap::new(), HashMap::new());
    // Specialization constants: id -> default, SpecId decorations, plain constants' values,
    // the WorkgroupSize built-in's composite.
    let (mut spec_values, mut spec_ids, mut constants) = (HashMap::new(), HashMap::new(), HashMap::new());
    let (mut builtin_workgroup, mut composites) = (None, HashMap::new());
    let mut local_size_ids: Option<Vec<u32>> = None;
    let mut i = 5; // after the header
    while i < words.len() {
        let (len, opcode) = ((words[i] >> 16) as usize, words[i] & 0xffff);
        if len == 0 || i + len > words.len() {
            return Err(format!("malformed instruction at word {i}"));
        }
        let w = &words[i + 1..i + len];
        match (opcode, w) {
            (OP_NAME, [id, s @ ..]) => _ = names.insert(*id, string(s)),
            (OP_EXECUTION_MODE, [_, LOCAL_SIZE, x, y, z]) => local_size = [*x, *y, *z],
            (OP_CONSTANT, [_, id, value, ..]) => _ = constants.insert(*id, *value),
            (OP_SPEC_CONSTANT, [_, id, value, ..]) => _ = spec_values.insert(*id, *value),
            (OP_SPEC_CONSTANT_TRUE, [_, id]) => _ = spec_values.insert(*id, 1),
            (OP_SPEC_CONSTANT_FALSE, [_, id]) => _ = spec_values.insert(*id, 0),
            (OP_SPEC_CONSTANT_COMPOSITE, [_, id, parts @ ..]) => _ = composites.insert(*id, parts.to_vec()),
            (OP_DECORATE, [id, SPEC_ID, spec]) => _ = spec_ids.insert(*id, *spec),
            (OP_DECORATE, [id, BUILT_IN, WORKGROUP_SIZE]) => builtin_workgroup = Some(*id),
            // SPIR-V >= 1.2 names the workgroup size's constants in the execution mode.
            (OP_EXECUTION_MODE_ID, [_, LOCAL_SIZE_ID, x, y, z]) => local_size_ids = Some(vec![*x, *y, *z]),
            (OP_TYPE_IMAGE, [id, _, dim, _depth, _arrayed, _ms, sampled, ..]) => {
                _ = types.insert(*id, Ty::Image { dim: *dim, sampled: *sampled })
            }
            (OP_TYPE_SAMPLER, [id]) => _ = types.insert(*id, Ty::Sampler),
            (OP_TYPE_SAMPLED_IMAGE, [id, _]) => _ = types.insert(*id, Ty::SampledImage),
            (OP_TYPE_ARRAY | OP_TYPE_RUNTIME_ARRAY, [id, el, ..]) => _ = element.insert(*id, *el),
            (OP_TYPE_STRUCT, [id, m @ ..]) => {
                types.insert(*id, Ty::Struct);
                member_count.insert(*id, m.len());
            }
            (OP_TYPE_POINTER, [id, _, ty]) => _ = pointee.insert(*id, *ty),
            (OP_VARIABLE, [ptr, id, class, ..]) => vars.push((*id, *ptr, *class)),
            (OP_DECORATE, [id, DESCRIPTOR_SET, set]) => _ = sets.insert(*id, *set),
            (OP_DECORATE, [id, BINDING, b]) => _ = bindings.insert(*id, *b),
            (OP_DECORATE, [id, d @ (BLOCK | BUFFER_BLOCK)]) => _ = blocks.insert(*id, *d),
            (OP_DECORATE, [id, d @ (NON_WRITABLE | NON_READABLE)]) => {
                qualified.entry(*id).or_insert_with(Vec::new).push(*d)
            }
            (OP_MEMBER_DECORATE, [id, m, d @ (NON_WRITABLE | NON_READABLE)]) => {
                members.entry((*id, *d)).or_insert_with(std::collections::HashSet::new).insert(*m);
            }
            (OP_TYPE_ACCELERATION_STRUCTURE_KHR, [id]) => _ = types.insert(*id, Ty::AccelerationStructure),
            _ => {}
        }
        i += len;
    }

    // One entry per SpecId: glslang may declare one id twice (SPIR-V 1.6 keeps the
    // `gl_WorkGroupSize` composite besides the LocalSizeId operands), named once at most.
    let mut spec_constants: Vec<SpecConstant> = Vec::new();
    for (&id, &spec) in &spec_ids {
        let Some(&default) = spec_values.get(&id) else {
            return Err(format!("SpecId {spec} decorates something other than a scalar spec constant"));
        };
        let name = names.get(&id).cloned().unwrap_or_default();
        match spec_constants.iter_mut().find(|c| c.id == spec) {
            Some(c) if c.default != default => {
                return Err(format!("SpecId {spec} has two defaults, {} and {default}", c.default))
            }
            Some(c) if c.name.is_empty() => c.name = name,
            Some(_) => {}
            None => spec_constants.push(SpecConstant { name, id: spec, default }),
        }
    }
    let workgroup_parts = builtin_workgroup.and_then(|id| composites.get(&id).cloned()).or(local_size_ids);
    if let Some(parts) = workgroup_parts {
        for (axis, part) in parts.iter().enumerate().take(3) {
            local_size[axis] = match (spec_values.get(part), constants.get(part)) {
                (Some(&v), _) | (None, Some(&v)) => v,
                _ => return Err("the WorkgroupSize built-in has a component that is not a constant".into()),
            };
            if let Some(&spec) = spec_ids.get(part) {
                let name = format!("local_size_{}", ["x", "y", "z"][axis]);
                if let Some(c) = spec_constants.iter_mut().find(|c| c.id == spec) {
                    c.name = name;
                }
            }
        }
    }
    if let Some(c) = spec_constants.iter().find(|c| c.name.is_empty()) {
        return Err(format!("specialization constant {} has no name", c.id));
    }
    spec_constants.sort_by_key(|c| c.id);

    let mut resources = Vec::new();
    let push_constants = vars.iter().any(|&(_, _, class)| class == PUSH_CONSTANT);
    for (id, ptr, class) in vars {
        if !matches!(class, UNIFORM_CONSTANT | UNIFORM | STORAGE_BUFFER) {
            continue; // push constants, inputs, outputs, workgroup and function memory
        }
        let (Some(&set), Some(&binding)) = (sets.get(&id), bindings.get(&id)) else {
            continue; // not a descriptor (naga skips these too)
        };
        let mut ty = pointee.get(&ptr).copied().unwrap_or(0);
        while let Some(&el) = element.get(&ty) {
            ty = el; // arrays of resources
        }
        let name = names.get(&id).cloned().unwrap_or_default();
        let at = || format!("`{name}` (set {set}, binding {binding})");
        let kind = match (class, types.get(&ty), blocks.get(&ty)) {
            (UNIFORM, Some(Ty::Struct), Some(&BLOCK)) => "UniformBuffer",
            (UNIFORM, Some(Ty::Struct), Some(&BUFFER_BLOCK)) => "StorageBuffer",
            (STORAGE_BUFFER, Some(Ty::Struct), Some(&BLOCK)) => "StorageBuffer",
            (UNIFORM_CONSTANT, Some(Ty::AccelerationStructure), _) => "AccelerationStructure",
            (UNIFORM_CONSTANT, Some(Ty::Sampler), _) => "Sampler",
            (UNIFORM_CONSTANT, Some(Ty::SampledImage), _) => "CombinedImageSampler",
            (UNIFORM_CONSTANT, Some(&Ty::Image { dim, sampled }), _) => match (dim, sampled) {
                (DIM_BUFFER, _) => return Err(format!("{} is a texel buffer; leakless binds none", at())),
                (DIM_SUBPASS_DATA, _) => return Err(format!("{} is an input attachment; leakless binds none", at())),
                (_, 1) => "SampledImage",
                (_, 2) => "StorageImage",
                _ => return Err(format!("{}: image with Sampled = {sampled} (unknown at compile time)", at())),
            },
            _ => return Err(format!("{}: unsupported resource type (storage class {class})", at())),
        };
        if name.is_empty() {
            let block = names.get(&ty).cloned().unwrap_or_default();
            return Err(format!(
                "block {block} (set {set}, binding {binding}) has no instance name; block instances \
                 must be named (`{block} {{ .. }} {};`)",
                block.to_lowercase()
            ));
        }
        let has = |d: u32| {
            qualified.get(&id).is_some_and(|ds| ds.contains(&d))
                || members
                    .get(&(ty, d))
                    .is_some_and(|m| m.len() == member_count.get(&ty).copied().unwrap_or(usize::MAX))
        };
        let access = match kind {
            "StorageBuffer" | "StorageImage" => match (has(NON_WRITABLE), has(NON_READABLE)) {
                (true, true) => return Err(format!("{} is both readonly and writeonly", at())),
                (true, false) => "Read",
                (false, true) => "Write",
                (false, false) => "ReadWrite",
            },
            _ => "Read",
        };
        resources.push(Resource { name, set, binding, kind, access });
    }
    resources.sort_by(|a, b| (a.set, a.binding, &a.name).cmp(&(b.set, b.binding, &b.name)));
    Ok(Scan { resources, local_size, spec_constants, push_constants })
}

/// A SPIR-V literal string: UTF-8, nul-terminated, packed little-end first into words.
fn string(words: &[u32]) -> String {
    let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).take_while(|&b| b != 0).collect();
    String::from_utf8_lossy(&bytes).into_owned()
}
