//! Which files make up the shader library and which of relief's specialization constants it
//! declares. Plain data with no dependency on the rest of the crate: `build.rs` compiles this same
//! file (`#[path]`) to embed the files, write `relief_ids.glsl` and compile the shader-library
//! example against exactly these files and nothing else.

/// The file an includer includes first.
pub const ENTRY: &str = "relief_library.glsl";

/// The generated file of specialization ids and mode values (`relief_ids.glsl`).
// Read by build.rs (and the tests); the library lists the embedded files themselves.
#[allow(dead_code)]
pub const IDS_FILE: &str = "relief_ids.glsl";

/// The library's files other than the methods (which come from the method table) and the
/// generated ids: each one's name in the library's folder and its path under `shaders/`.
// Read by build.rs, which embeds them.
#[allow(dead_code)]
pub const CORE_FILES: &[(&str, &str)] = &[
    (ENTRY, "library/relief_library.glsl"),
    ("conventions.glsl", "include/conventions.glsl"),
    ("numeric.glsl", "include/numeric.glsl"),
    ("heightfield.glsl", "include/heightfield.glsl"),
    ("pyramid.glsl", "include/pyramid.glsl"),
    ("cone.glsl", "include/cone.glsl"),
    ("shadows.glsl", "include/shadows.glsl"),
    ("relief_frame.glsl", "include/relief_frame.glsl"),
    ("curved.glsl", "include/curved.glsl"),
];

/// The specialization constants the library's files declare, by their names in relief's own
/// table (`shader_interface::SPEC_IDS`). In the library each takes the id
/// `RELIEF_SPEC_ID_BASE` plus its id in relief's table.
pub const SPEC_CONSTANTS: &[&str] = &[
    "SPEC_BUDGET_MAX_STEPS",
    "SPEC_BUDGET_REFINE_STEPS",
    "SPEC_BUDGET_LEAF_EXACT",
    "SPEC_BUDGET_EXTENT_LIMIT",
    "SPEC_SHADOW_MODE",
    "SPEC_SHADOW_STEPS",
    "SPEC_SHADOW_REACH",
    "SPEC_HARD_SHADOW_TEXELS",
    "SPEC_COUNT_FETCHES",
];

/// The first specialization id of the library's constants when the includer does not define
/// `RELIEF_SPEC_ID_BASE` (`relief_library.glsl`).
pub const DEFAULT_SPEC_ID_BASE: u32 = 100;

/// A method file's name in the library's folder, from its path under `shaders/` in the method
/// table (`methods/qdm.glsl` is `qdm.glsl`).
pub fn method_file_name(shader: &str) -> &str {
    shader.rsplit('/').next().unwrap_or(shader)
}
