//! How a struct that Rust writes and a shader reads is declared once: a `#[repr(C)]` Rust struct
//! whose fields carry their GLSL types and docs, and a [`ShaderLayout`] describing it, from which
//! build.rs writes the GLSL side into "interface.glsl" and checks the Rust offsets against the
//! block's std140 or std430 rules (a mismatch stops the build).

/// One field: its GLSL type, its array length (the header's spelling and the value), its offset
/// in the Rust struct and its doc lines.
#[allow(dead_code)] // Read by build.rs, which writes and checks the GLSL side.
pub struct ShaderField {
    pub name: &'static str,
    pub glsl: &'static str,
    pub array: Option<(&'static str, usize)>,
    pub offset: usize,
    pub doc: &'static [&'static str],
}

/// The GLSL layout rules a struct is laid out by.
#[allow(dead_code)] // Read by build.rs.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum LayoutRules {
    /// Uniform blocks: arrays and structs aligned to 16 bytes.
    Std140,
    /// Push constants and storage buffers.
    Std430,
}

/// What the header makes of a layout.
#[allow(dead_code)] // Read by build.rs.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum LayoutForm {
    /// A GLSL `struct` type under the GLSL name, for blocks and buffers to hold.
    Struct,
    /// A block's members as the body of the define `<GLSL NAME>_FIELDS`, which the shader
    /// wraps in its own `layout(...) uniform <Name> { ... }`, choosing binding and instance name.
    Block,
}

/// A struct shared with the shaders, as build.rs reads it.
#[allow(dead_code)] // Read by build.rs.
pub struct ShaderLayout {
    /// The Rust struct's name.
    pub rust: &'static str,
    /// The GLSL struct's or block's name; the define is its UPPER_SNAKE form + `_FIELDS`.
    pub glsl: &'static str,
    pub form: LayoutForm,
    pub rules: LayoutRules,
    pub fields: &'static [ShaderField],
    /// `size_of` the Rust struct.
    pub size: usize,
}

/// Declares a `#[repr(C)]`, `Pod` struct shared with the shaders and its [`ShaderLayout`] as
/// `LAYOUT`. Invoked only in the modules directly under `shader_interface` (its paths start at
/// `super::`, the same in the library and in build.rs, which compiles the folder alone):
///
/// ```text
/// shader_layout! {
///     /// Docs and extra derives.
///     block std430 RustName as GlslName {        // or `record std140 ...`; `as` is optional
///         /// Field docs (copied into the header).
///         field: [f32; 4] => "vec4",
///         list: [u32; 15] => "uint" [MAX_LEVELS],  // array length as GLSL spells it
///     }
/// }
/// ```
macro_rules! shader_layout {
    (
        $(#[$attr:meta])*
        $form:ident $rules:ident $name:ident $(as $glsl_name:ident)? {
            $($(#[doc = $fdoc:literal])* $field:ident: $ty:ty => $glsl:literal $([$len:tt])?,)*
        }
    ) => {
        $(#[$attr])*
        #[repr(C)]
        #[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
        pub struct $name {
            $($(#[doc = $fdoc])* pub $field: $ty,)*
        }

        impl $name {
            /// Where each field lies, for build.rs's header and its layout check.
            #[allow(dead_code)] // Read by build.rs; the library uses the struct.
            pub(crate) const LAYOUT: super::ShaderLayout =
                super::ShaderLayout {
                    rust: stringify!($name),
                    glsl: shader_layout!(@glsl $name $($glsl_name)?),
                    form: shader_layout!(@form $form),
                    rules: shader_layout!(@rules $rules),
                    fields: &[$(super::ShaderField {
                        name: stringify!($field),
                        glsl: $glsl,
                        array: shader_layout!(@len $($len)?),
                        offset: std::mem::offset_of!($name, $field),
                        doc: &[$($fdoc),*],
                    }),*],
                    size: std::mem::size_of::<$name>(),
                };
        }
    };
    (@glsl $name:ident) => { stringify!($name) };
    (@glsl $name:ident $glsl_name:ident) => { stringify!($glsl_name) };
    (@form block) => { super::LayoutForm::Block };
    (@form record) => { super::LayoutForm::Struct };
    (@rules std140) => { super::LayoutRules::Std140 };
    (@rules std430) => { super::LayoutRules::Std430 };
    (@len) => { None };
    (@len $len:tt) => { Some((stringify!($len), $len as usize)) };
}
