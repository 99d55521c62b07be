//! Bindings by name: a pass declares once what it binds, `check_bindings` compares that with
//! the shader's reflection, and dispatches name their resources.

use ash::vk;

use crate::error::{DeviceError, Result};
use crate::frame_set::FrameBinding;
use crate::layout::{compare, RustLayout};
use crate::shader::{BindingAccess, BindingKind, BlockLayout, ReflectedBinding, ShaderInfo};
use crate::{Buffer, Image};

/// How the data behind a buffer binding is checked.
#[derive(Clone, Copy, Debug)]
pub enum Contents {
    /// Not a buffer, or a buffer whose layout is not checked (plain `uint[]` words).
    Unchecked,
    /// A block of fixed size with named members.
    Block(RustLayout),
    /// A block holding only a runtime-sized array of this element.
    Array(RustLayout),
}

/// One resource a pass binds, declared once on the Rust side.
#[derive(Clone, Copy, Debug)]
pub struct BindingDecl {
    pub name: &'static str,
    pub kind: BindingKind,
    /// Whether the pass reads, writes or does both: must be what the shader's qualifiers say.
    pub access: BindingAccess,
    pub contents: Contents,
}

impl BindingDecl {
    pub const fn uniform(name: &'static str, layout: RustLayout) -> Self {
        let (kind, access) = (BindingKind::UniformBuffer, BindingAccess::Read);
        Self { name, kind, access, contents: Contents::Block(layout) }
    }
    pub const fn storage_array(name: &'static str, access: BindingAccess, element: RustLayout) -> Self {
        Self { name, kind: BindingKind::StorageBuffer, access, contents: Contents::Array(element) }
    }
    /// A storage buffer holding one fixed-size block (counters, bounds).
    pub const fn storage_block(name: &'static str, access: BindingAccess, layout: RustLayout) -> Self {
        Self { name, kind: BindingKind::StorageBuffer, access, contents: Contents::Block(layout) }
    }
    pub const fn storage_words(name: &'static str, access: BindingAccess) -> Self {
        Self { name, kind: BindingKind::StorageBuffer, access, contents: Contents::Unchecked }
    }
    pub const fn storage_image(name: &'static str, access: BindingAccess) -> Self {
        Self { name, kind: BindingKind::StorageImage, access, contents: Contents::Unchecked }
    }
    pub const fn acceleration_structure(name: &'static str) -> Self {
        let (kind, access) = (BindingKind::AccelerationStructure, BindingAccess::Read);
        Self { name, kind, access, contents: Contents::Unchecked }
    }
}

/// A resource given to a dispatch or draw, by the name its pass declared.
#[derive(Clone, Copy)]
pub enum Bound<'a> {
    Buffer(&'a Buffer),
    Image(&'a Image),
    Accel(vk::AccelerationStructureKHR),
}

/// A shader's bindings matched with a pass's declarations.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MatchedBindings {
    /// The binding number (in the pass's set 1) of each declaration, in order.
    pub numbers: Vec<u32>,
    /// The frame set's bindings the shader uses (set 0), which the pass does not declare.
    pub frame_uses: Vec<&'static str>,
}

/// Matches a pass's declarations against a shader's reflection. Set 0 is the frame set's:
/// each binding the shader has there must be one of `frame`, at its number, and match its
/// declaration; the pass declares exactly the shader's set 1.
pub fn check_bindings(
    shader: &ShaderInfo,
    pass: &str,
    frame: &[FrameBinding],
    decls: &[BindingDecl],
) -> Result<MatchedBindings> {
    let err = |binding: &str, problem: String| DeviceError::Binding {
        shader: shader.name,
        binding: binding.to_string(),
        pass: pass.to_string(),
        problem,
    };
    let reflected: &[ReflectedBinding] = shader.reflection.map_err(|why| err("*", format!("no reflection: {why}")))?;
    let mut frame_uses = Vec::new();
    for r in reflected {
        let in_frame = frame.iter().find(|f| f.decl.name == r.name);
        match (r.set, in_frame) {
            (FRAME_SET, Some(f)) if f.binding == r.binding => {
                check_decl(&f.decl, r).map_err(|p| err(r.name, format!("{p} (the frame set's declaration)")))?;
                frame_uses.push(f.decl.name);
            }
            (FRAME_SET, Some(f)) => {
                return Err(err(
                    r.name,
                    format!("is binding {} of set 0; the frame set has it at {}", r.binding, f.binding),
                ))
            }
            (FRAME_SET, None) => {
                return Err(err(r.name, "is in set 0, which holds only the frame set's bindings".into()))
            }
            (PASS_SET, Some(_)) => {
                return Err(err(r.name, "is a binding of the frame set; the shader puts it in the pass's set 1".into()))
            }
            (PASS_SET, None) if !decls.iter().any(|d| d.name == r.name) => {
                return Err(err(r.name, "used by the shader but not declared by the pass".into()))
            }
            (PASS_SET, None) => {}
            (set, _) => {
                return Err(err(
                    r.name,
                    format!("uses descriptor set {set}; shaders use 0 (the frame set) and 1 (the pass's)"),
                ))
            }
        }
    }
    let mut numbers = Vec::with_capacity(decls.len());
    for d in decls {
        let r = reflected
            .iter()
            .find(|r| r.name == d.name)
            .ok_or_else(|| err(d.name, "declared by the pass but not in the shader".into()))?;
        if r.set != PASS_SET {
            return Err(err(d.name, "is the frame set's (set 0): the pass binds only its own".into()));
        }
        check_decl(d, r).map_err(|p| err(d.name, p))?;
        numbers.push(r.binding);
    }
    Ok(MatchedBindings { numbers, frame_uses })
}

/// The declaration `d` against the shader's binding `r`: kind, access, contents.
fn check_decl(d: &BindingDecl, r: &ReflectedBinding) -> std::result::Result<(), String> {
    if r.kind != d.kind {
        return Err(format!("the pass declares {:?}, the shader has {:?}", d.kind, r.kind));
    }
    if r.access != d.access {
        let qualifier = match r.access {
            BindingAccess::Read => "readonly",
            BindingAccess::Write => "writeonly",
            BindingAccess::ReadWrite => "neither readonly nor writeonly",
        };
        return Err(format!("the pass declares {:?} access, the shader's binding is {qualifier}", d.access));
    }
    check_contents(d, r.layout)
}

/// The descriptor set of what a frame binds once ([`FrameBinding`]).
pub const FRAME_SET: u32 = 0;
/// The descriptor set of a pass's own bindings, pushed with each dispatch or draw.
pub const PASS_SET: u32 = 1;

fn check_contents(decl: &BindingDecl, layout: Option<BlockLayout>) -> std::result::Result<(), String> {
    let (rust, shader_size, shader_members, what) = match (decl.contents, layout) {
        (Contents::Unchecked, _) => return Ok(()),
        (_, None) => return Err("the shader side has no block layout".into()),
        (Contents::Block(rust), Some(l)) => {
            if l.array_stride.is_some() {
                return Err("the shader block ends in a runtime array; declare it with storage_array".into());
            }
            (rust, l.size, l.members, "block")
        }
        (Contents::Array(rust), Some(l)) => {
            let stride = l.array_stride.ok_or("the shader block has no runtime array")?;
            if l.size != 0 {
                return Err(format!("the shader block has {} bytes before its array; Rust declares none", l.size));
            }
            (rust, stride, l.element_members, "array element")
        }
    };
    compare(what, &rust, shader_size, shader_members)
}

/// Matches the push-constant block a pass declares (`None`: it pushes nothing) with the
/// shader's. Returns the block size.
pub fn check_push_constants(shader: &ShaderInfo, pass: &str, rust: Option<&RustLayout>) -> Result<u32> {
    let err = |problem: String| DeviceError::Binding {
        shader: shader.name,
        binding: "push constants".into(),
        pass: pass.to_string(),
        problem,
    };
    match (rust, shader.push_constants) {
        (None, None) => Ok(0),
        (Some(_), None) => Err(err("the pass pushes constants; the shader declares no push_constant block".into())),
        (None, Some(_)) => Err(err("the shader declares a push_constant block; the pass pushes none".into())),
        (Some(rust), Some(block)) => {
            compare("push-constant block", rust, block.size, block.members).map_err(err)?;
            Ok(block.size)
        }
    }
}

impl BindingKind {
    pub(crate) fn descriptor_type(self) -> vk::DescriptorType {
        match self {
            BindingKind::UniformBuffer => vk::DescriptorType::UNIFORM_BUFFER,
            BindingKind::StorageBuffer => vk::DescriptorType::STORAGE_BUFFER,
            BindingKind::StorageImage => vk::DescriptorType::STORAGE_IMAGE,
            BindingKind::SampledImage => vk::DescriptorType::SAMPLED_IMAGE,
            BindingKind::Sampler => vk::DescriptorType::SAMPLER,
            BindingKind::CombinedImageSampler => vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
            BindingKind::AccelerationStructure => vk::DescriptorType::ACCELERATION_STRUCTURE_KHR,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shader::{Member, ShaderStage};

    #[repr(C)]
    struct Frame {
        a: [f32; 4],
        b: u32,
        c: u32,
        _pad: [u32; 2],
    }

    const MEMBERS: &[Member] = &[
        Member { name: "a", offset: 0 },
        Member { name: "b", offset: 16 },
        Member { name: "c", offset: 20 },
        Member { name: "_pad", offset: 24 },
    ];
    const REFLECTED: &[ReflectedBinding] = &[ReflectedBinding {
        name: "frame",
        set: PASS_SET,
        binding: 3,
        kind: BindingKind::UniformBuffer,
        access: BindingAccess::Read,
        layout: Some(BlockLayout { size: 32, members: MEMBERS, array_stride: None, element_members: &[] }),
    }];
    pub(super) const SHADER: ShaderInfo = ShaderInfo {
        name: "t.comp",
        stage: ShaderStage::Compute,
        spirv: &[],
        workgroup_size: [8, 8, 1],
        spec_constants: &[],
        reflection: Ok(REFLECTED),
        push_constants: Some(BlockLayout { size: 32, members: MEMBERS, array_stride: None, element_members: &[] }),
    };

    #[test]
    fn matching_declaration_gives_the_shader_binding_number() {
        let decl = [BindingDecl::uniform("frame", crate::rust_layout!(Frame { a, b, c, _pad }))];
        assert_eq!(check_bindings(&SHADER, "p", &[], &decl).unwrap().numbers, vec![3]);
    }

    #[test]
    fn mismatches_name_shader_binding_and_pass() {
        let wrong_kind = [BindingDecl::storage_words("frame", BindingAccess::Read)];
        let e = check_bindings(&SHADER, "direct", &[], &wrong_kind).unwrap_err().to_string();
        assert!(e.contains("t.comp") && e.contains("\"frame\"") && e.contains("direct"), "{e}");
        let missing = [
            BindingDecl::uniform("frame", crate::rust_layout!(Frame { a, b, c, _pad })),
            BindingDecl::storage_words("extra", BindingAccess::Read),
        ];
        assert!(check_bindings(&SHADER, "p", &[], &missing).unwrap_err().to_string().contains("not in the shader"));
        assert!(check_bindings(&SHADER, "p", &[], &[]).unwrap_err().to_string().contains("not declared by the pass"));
        #[repr(C)]
        struct Shifted {
            b: u32,
            a: [f32; 4],
            c: u32,
            _pad: [u32; 2],
        }
        let shifted = [BindingDecl::uniform("frame", crate::rust_layout!(Shifted { a, b, c, _pad }))];
        let e = check_bindings(&SHADER, "p", &[], &shifted).unwrap_err().to_string();
        assert!(e.contains("offset"), "{e}");
    }

    /// A pass that declares a read of what the shader writes (or the reverse) would get the
    /// wrong barriers from the graph: the declaration must say what the GLSL qualifiers say.
    #[test]
    fn access_must_match_the_shaders_qualifiers() {
        let image = |access| ReflectedBinding {
            name: "out",
            set: PASS_SET,
            binding: 0,
            kind: BindingKind::StorageImage,
            access,
            layout: None,
        };
        for (shader_access, qualifier) in [
            (BindingAccess::Write, "writeonly"),
            (BindingAccess::Read, "readonly"),
            (BindingAccess::ReadWrite, "neither"),
        ] {
            let reflected = [image(shader_access)];
            let shader = ShaderInfo { reflection: Ok(Box::leak(Box::new(reflected))), ..SHADER };
            for declared in [BindingAccess::Read, BindingAccess::Write, BindingAccess::ReadWrite] {
                let result = check_bindings(&shader, "p", &[], &[BindingDecl::storage_image("out", declared)]);
                if declared == shader_access {
                    assert_eq!(result.unwrap().numbers, vec![0]);
                } else {
                    let e = result.unwrap_err().to_string();
                    assert!(e.contains(qualifier) && e.contains(&format!("{declared:?}")), "{e}");
                }
            }
        }
    }
}

#[cfg(test)]
mod frame_set_tests {
    use super::*;

    fn words(name: &'static str, set: u32, binding: u32) -> ReflectedBinding {
        let (kind, access) = (BindingKind::StorageBuffer, BindingAccess::Read);
        ReflectedBinding { name, set, binding, kind, access, layout: None }
    }

    fn shader(reflected: Vec<ReflectedBinding>) -> ShaderInfo {
        ShaderInfo { reflection: Ok(Box::leak(reflected.into_boxed_slice())), ..super::tests::SHADER }
    }

    const FRAME: &[FrameBinding] =
        &[FrameBinding { binding: 4, decl: BindingDecl::storage_words("texels", BindingAccess::Read) }];

    /// Set 0 holds the frame set's bindings at the frame set's numbers, which the pass does not
    /// declare; set 1 the pass's own. Any other arrangement is refused with the binding's name.
    #[test]
    fn set_zero_is_the_frame_sets_and_set_one_the_passes() {
        let decls = [BindingDecl::storage_words("out", BindingAccess::Read)];
        let good = shader(vec![words("texels", 0, 4), words("out", 1, 0)]);
        let matched = check_bindings(&good, "p", FRAME, &decls).unwrap();
        assert_eq!(matched, MatchedBindings { numbers: vec![0], frame_uses: vec!["texels"] });
        for (reflected, problem) in [
            (vec![words("texels", 0, 5), words("out", 1, 0)], "frame set has it at 4"),
            (vec![words("texels", 0, 4), words("out", 0, 0)], "only the frame set's"),
            (vec![words("texels", 1, 4), words("out", 1, 0)], "binding of the frame set"),
            (vec![words("texels", 0, 4), words("out", 2, 0)], "descriptor set 2"),
        ] {
            let e = check_bindings(&shader(reflected), "p", FRAME, &decls).unwrap_err().to_string();
            assert!(e.contains(problem), "{e}");
        }
        let declared = [decls[0], FRAME[0].decl];
        let e = check_bindings(&good, "p", FRAME, &declared).unwrap_err().to_string();
        assert!(e.contains("\"texels\"") && e.contains("binds only its own"), "{e}");
        let writes = [FrameBinding { binding: 4, decl: BindingDecl::storage_words("texels", BindingAccess::Write) }];
        let e = check_bindings(&good, "p", &writes, &decls).unwrap_err().to_string();
        assert!(e.contains("readonly") && e.contains("frame set's declaration"), "{e}");
    }
}

#[cfg(test)]
mod push_tests {
    use super::*;
    use crate::shader::Member;

    const MEMBERS: &[Member] = &[Member { name: "radius", offset: 0 }, Member { name: "count", offset: 4 }];
    const SHADER: ShaderInfo = ShaderInfo {
        reflection: Ok(&[]),
        push_constants: Some(BlockLayout { size: 8, members: MEMBERS, array_stride: None, element_members: &[] }),
        ..super::tests::SHADER
    };

    #[test]
    fn push_constants_are_checked_like_blocks() {
        let good = RustLayout { size: 8, members: MEMBERS };
        assert_eq!(check_push_constants(&SHADER, "p", Some(&good)).unwrap(), 8);
        let swapped = RustLayout {
            size: 8,
            members: &[Member { name: "radius", offset: 4 }, Member { name: "count", offset: 0 }],
        };
        let e = check_push_constants(&SHADER, "p", Some(&swapped)).unwrap_err().to_string();
        assert!(e.contains("push constants") && e.contains("offset"), "{e}");
        assert!(check_push_constants(&SHADER, "p", None).is_err());
        let none = ShaderInfo { push_constants: None, ..SHADER };
        assert!(check_push_constants(&none, "p", Some(&good)).is_err());
        assert_eq!(check_push_constants(&none, "p", None).unwrap(), 0);
    }
}
