//! The Rust side of data shared with shaders: a struct's size and member offsets, declared
//! once with the struct itself ([`gpu_struct!`](crate::gpu_struct)), so that pipeline creation
//! can compare them with the shader's reflection.

use crate::shader::Member;

/// Size and member offsets of a `#[repr(C)]` struct shared with a shader.
#[derive(Clone, Copy, Debug)]
pub struct RustLayout {
    pub size: u32,
    pub members: &'static [Member],
}

/// A `#[repr(C)]`, `Pod` struct with a twin in GLSL; its [`RustLayout`] is checked against
/// reflection wherever a pass binds it (buffer blocks, array elements, push constants).
pub trait GpuStruct: bytemuck::Pod {
    const LAYOUT: RustLayout;
}

/// A pass's push-constant block as a type: a [`GpuStruct`], or `()` for a pass without one.
pub trait PushConstants: bytemuck::NoUninit {
    /// The block's layout, checked against reflection; `None` for no block.
    const PUSH_LAYOUT: Option<RustLayout>;
}

impl PushConstants for () {
    const PUSH_LAYOUT: Option<RustLayout> = None;
}

impl<T: GpuStruct> PushConstants for T {
    const PUSH_LAYOUT: Option<RustLayout> = Some(T::LAYOUT);
}

/// A plain `uint` element (`uint keys[]`).
impl GpuStruct for u32 {
    const LAYOUT: RustLayout = RustLayout { size: 4, members: &[] };
}

/// A plain `float` element (`float xyz[]`).
impl GpuStruct for f32 {
    const LAYOUT: RustLayout = RustLayout { size: 4, members: &[] };
}

/// Declares a `#[repr(C)]` struct and its [`GpuStruct`] layout in one go, so the field list is
/// written once. Attributes (derives included) are passed through; the struct must derive
/// `bytemuck::Pod`.
///
/// ```ignore
/// gpu_struct! {
///     /// The `Level` struct of hierarchy.glsl.
///     #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
///     pub struct Level { pub offset: u32, pub count: u32, pub span: u32, pub pad0: u32 }
/// }
/// ```
#[macro_export]
macro_rules! gpu_struct {
    ($(#[$attr:meta])* $vis:vis struct $name:ident {
        $($(#[$fattr:meta])* $fvis:vis $field:ident : $ty:ty),* $(,)?
    }) => {
        $(#[$attr])*
        #[repr(C)]
        $vis struct $name { $($(#[$fattr])* $fvis $field: $ty),* }
        impl $crate::GpuStruct for $name {
            const LAYOUT: $crate::RustLayout = $crate::RustLayout {
                size: ::core::mem::size_of::<$name>() as u32,
                members: &[$($crate::shader::Member {
                    name: stringify!($field),
                    offset: ::core::mem::offset_of!($name, $field) as u32,
                }),*],
            };
        }
    };
}

/// The layout of a `#[repr(C)]` struct defined elsewhere (a type of another crate, which
/// cannot implement [`GpuStruct`] here): its size and the offsets of the named fields.
#[macro_export]
macro_rules! rust_layout {
    ($ty:ty { $($field:ident),* $(,)? }) => {
        $crate::RustLayout {
            size: ::core::mem::size_of::<$ty>() as u32,
            members: &[$($crate::shader::Member {
                name: stringify!($field),
                offset: ::core::mem::offset_of!($ty, $field) as u32,
            }),*],
        }
    };
}

/// Compares a Rust layout with a reflected block (`what` names it in messages): same size,
/// every member at the same offset, no member on one side only.
pub(crate) fn compare(
    what: &str,
    rust: &RustLayout,
    shader_size: u32,
    shader_members: &[Member],
) -> std::result::Result<(), String> {
    if rust.size != shader_size {
        return Err(format!("{what} size: Rust {} bytes, shader {} bytes", rust.size, shader_size));
    }
    if shader_members.is_empty() && rust.members.is_empty() {
        return Ok(());
    }
    for m in rust.members {
        match shader_members.iter().find(|s| s.name == m.name) {
            None => return Err(format!("{what} member {} is not in the shader", m.name)),
            Some(s) if s.offset != m.offset => {
                return Err(format!("{what} member {}: Rust offset {}, shader offset {}", m.name, m.offset, s.offset))
            }
            Some(_) => {}
        }
    }
    if let Some(s) = shader_members.iter().find(|s| !rust.members.iter().any(|m| m.name == s.name)) {
        return Err(format!("{what} member {} is in the shader but not in the Rust struct", s.name));
    }
    Ok(())
}
