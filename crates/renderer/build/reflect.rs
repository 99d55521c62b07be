//! Reflection of a compiled module: naga's buffer layouts, the SPIR-V scan's bindings, kinds,
//! access and specialization constants, and their agreement.

use naga::{AddressSpace, ArraySize, Handle, ImageClass, Module, Type, TypeInner};

use crate::spirv_scan;
use crate::{Stage, DIR};

/// What reflection found for one module.
pub(crate) struct Info {
    pub(crate) workgroup_size: [u32; 3],
    /// `SpecConstant { .. }` literals, by id.
    pub(crate) spec_constants: Vec<String>,
    /// Ordered by (set, binding).
    pub(crate) bindings: Vec<Binding>,
    /// Why naga could not parse the module: its bindings come from the SPIR-V scan alone,
    /// without buffer layouts.
    pub(crate) naga_error: Option<String>,
    /// Whether the module declares a push-constant block (from the scan).
    pub(crate) has_push_constants: bool,
    /// `Some(BlockLayout { .. })` literal of that block, once reflected (naga, or the twin).
    pub(crate) push_constants: Option<String>,
}

/// One resource binding, to become a `ReflectedBinding` literal.
pub(crate) struct Binding {
    pub(crate) name: String,
    pub(crate) set: u32,
    pub(crate) binding: u32,
    /// `BindingKind` variant.
    pub(crate) kind: &'static str,
    /// `Some(BlockLayout { .. })` literal: buffers naga reflected.
    pub(crate) layout: Option<String>,
    /// `BindingAccess` variant, from the scan's `readonly` / `writeonly` decorations.
    pub(crate) access: &'static str,
}

impl Binding {
    pub(crate) fn id(&self) -> (&str, u32, u32, &str) {
        (&self.name, self.set, self.binding, self.kind)
    }
}

pub(crate) fn reflect(spirv: &[u32], stage: Stage, file: &str) -> Result<Info, String> {
    let scan = spirv_scan::scan(spirv).map_err(|e| format!("{DIR}/{file}: {e}"))?;
    let spec_constants = scan
        .spec_constants
        .iter()
        .map(|c| format!("SpecConstant {{ name: {:?}, id: {}, default: {} }}", c.name, c.id, c.default))
        .collect();
    // The scan's size: naga's ignores a `local_size_x_id` composite's defaults.
    let workgroup_size = match stage {
        Stage::Compute => scan.local_size,
        _ => [1, 1, 1],
    };
    let scanned: Vec<Binding> = scan
        .resources
        .into_iter()
        .map(|r| Binding { name: r.name, set: r.set, binding: r.binding, kind: r.kind, layout: None, access: r.access })
        .collect();
    let options = naga::front::spv::Options {
        adjust_coordinate_space: false,
        strict_capabilities: false,
        block_ctx_dump_prefix: None,
    };
    let module = match naga::front::spv::Frontend::new(spirv.iter().copied(), &options).parse() {
        Ok(module) => module,
        Err(e) => {
            // Expected for ray-query modules; their TRACE_COMPUTE twin lends them its layouts.
            let mut msg = format!("naga: {}", e.to_string().lines().next().unwrap_or_default());
            if scanned.iter().any(|b| b.kind == "CombinedImageSampler") {
                msg += " (naga cannot parse sampling through a combined image sampler; \
                        use a texture and a sampler)";
            }
            let naga_error = Some(msg);
            let has_push_constants = scan.push_constants;
            return Ok(Info {
                workgroup_size,
                spec_constants,
                bindings: scanned,
                naga_error,
                has_push_constants,
                push_constants: None,
            });
        }
    };
    let mut bindings = Vec::new();
    let mut push_constants = None;
    for (_, var) in module.global_variables.iter() {
        // naga calls push constants "immediates".
        if var.space == AddressSpace::Immediate {
            push_constants = Some(block_layout(&module, var.ty));
            continue;
        }
        let Some(rb) = &var.binding else { continue };
        let (set, binding) = (rb.group, rb.binding);
        let (kind, layout) = match var.space {
            AddressSpace::Uniform => ("UniformBuffer", Some(block_layout(&module, var.ty))),
            AddressSpace::Storage { .. } => ("StorageBuffer", Some(block_layout(&module, var.ty))),
            AddressSpace::Handle => {
                // naga folds a combined image sampler into its image type.
                let combined =
                    scanned.iter().any(|b| (b.set, b.binding, b.kind) == (set, binding, "CombinedImageSampler"));
                (handle_kind(&module, var.ty, combined), None)
            }
            _ => continue,
        };
        // glslang names the variable of `buffer Photons { .. } photons;` "photons" (the scan
        // has already rejected blocks without an instance name).
        let name = var.name.clone().unwrap_or_default();
        let access = scanned.iter().find(|b| (b.set, b.binding) == (set, binding)).map_or("ReadWrite", |b| b.access);
        bindings.push(Binding { name, set, binding, kind, layout, access });
    }
    bindings.sort_by(|a, b| (a.set, a.binding, &a.name).cmp(&(b.set, b.binding, &b.name)));
    // The scan stands in for naga where naga cannot parse, so it must agree where it can.
    let ids = |bs: &[Binding]| bs.iter().map(|b| format!("{:?}", b.id())).collect::<Vec<_>>().join(", ");
    if ids(&bindings) != ids(&scanned) {
        return Err(format!(
            "{DIR}/{file}: crates/renderer/build.rs bug: the SPIR-V scan (crates/renderer/build/spirv_scan.rs) disagrees with naga:\n  \
             scan: {}\n  naga: {}",
            ids(&scanned),
            ids(&bindings)
        ));
    }
    if push_constants.is_some() != scan.push_constants {
        return Err(format!(
            "{DIR}/{file}: crates/renderer/build.rs bug: the SPIR-V scan and naga disagree on push constants"
        ));
    }
    let has_push_constants = scan.push_constants;
    Ok(Info { workgroup_size, spec_constants, bindings, naga_error: None, has_push_constants, push_constants })
}

/// Gives a `:rayquery` module naga could not parse the buffer layouts of its `:compute` twin,
/// matched by binding name, after checking that every binding the two variants share has the
/// same set, number and kind. Bindings of the ray-query variant alone (`tlas`) keep `None`.
pub(crate) fn take_twin_layouts(file: &str, rq: (&str, &mut Info), twin: (&str, &Info)) -> Result<(), String> {
    let ((rq_name, rq), (twin_name, twin)) = (rq, twin);
    let mut mismatches = Vec::new();
    for b in &mut rq.bindings {
        let Some(t) = twin.bindings.iter().find(|t| t.name == b.name) else {
            if b.layout.is_none() && b.kind.ends_with("Buffer") {
                println!("cargo:warning={rq_name}: `{}` is not in {twin_name}, so its layout is not checked", b.name);
            }
            continue;
        };
        if (t.set, t.binding, t.kind, t.access) != (b.set, b.binding, b.kind, b.access) {
            mismatches.push(format!(
                "{DIR}/{file}: binding `{}` is set {}, binding {}, {} {} in {rq_name} but set {}, binding {}, {} {} \
                 in {twin_name}; trace variants must agree on every binding they share",
                b.name, b.set, b.binding, b.access, b.kind, t.set, t.binding, t.access, t.kind
            ));
        } else if rq.naga_error.is_some() {
            b.layout.clone_from(&t.layout);
        }
    }
    if rq.has_push_constants != twin.has_push_constants {
        mismatches.push(format!(
            "{DIR}/{file}: {rq_name} and {twin_name} disagree on whether there is a push_constant block"
        ));
    } else if rq.naga_error.is_some() {
        rq.push_constants.clone_from(&twin.push_constants);
    }
    if mismatches.is_empty() {
        Ok(())
    } else {
        Err(mismatches.join("\n"))
    }
}

pub(crate) fn handle_kind(module: &Module, ty: Handle<Type>, combined: bool) -> &'static str {
    match &module.types[ty].inner {
        TypeInner::BindingArray { base, .. } => handle_kind(module, *base, combined),
        TypeInner::Image { class, .. } => match class {
            ImageClass::Storage { .. } => "StorageImage",
            _ if combined => "CombinedImageSampler",
            _ => "SampledImage",
        },
        TypeInner::Sampler { .. } => "Sampler",
        TypeInner::AccelerationStructure { .. } => "AccelerationStructure",
        other => panic!("unexpected resource type {other:?}"),
    }
}

/// `Some(BlockLayout { .. })` literal for a uniform or storage block.
pub(crate) fn block_layout(module: &Module, ty: Handle<Type>) -> String {
    let members_of = |ty: Handle<Type>| match &module.types[ty].inner {
        TypeInner::Struct { members, .. } => {
            let members = members.iter().map(|m| {
                let name = m.name.as_deref().unwrap_or_default();
                format!("Member {{ name: {name:?}, offset: {} }}", m.offset)
            });
            format!("&[{}]", members.collect::<Vec<_>>().join(", "))
        }
        _ => "&[]".to_string(),
    };
    let TypeInner::Struct { members, span } = &module.types[ty].inner else {
        panic!("buffer block is not a struct: {:?}", module.types[ty]);
    };
    let last = members.last().map(|m| (m.offset, &module.types[m.ty].inner));
    let (size, stride, element) = match last {
        // A trailing runtime array: the fixed part ends where the array starts.
        Some((offset, TypeInner::Array { base, size, stride })) if *size == ArraySize::Dynamic => {
            (offset, Some(stride), members_of(*base))
        }
        // naga's span: the last member's end rounded up to the block's alignment, as the
        // size of a `#[repr(C)]` mirror of it.
        _ => (*span, None, "&[]".into()),
    };
    format!(
        "Some(BlockLayout {{ size: {size}, members: {}, array_stride: {stride:?}, \
         element_members: {element} }})",
        members_of(ty)
    )
}
