//! The formats the frame's targets share, which every pass drawing into them builds its
//! pipelines for.

use ash::vk;

/// The frame's colour format: sRGB, so the hardware encodes the tone-mapping pass's linear
/// output once, on write.
pub const COLOR_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;
/// The scene's depth format.
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;
/// The scene passes' colour format: linear radiance, beyond 1 where lights are bright.
pub const HDR_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;

/// The G-buffer's attachment formats after the radiance, in location order (1 to 4): normal and
/// coverage; uv, depth, mesh and steps as integer bits; albedo and AO; motion and shadow
/// (`frame/gbuffer.rs` says what each channel holds).
pub const GBUFFER_FORMATS: [vk::Format; 4] = [
    vk::Format::R16G16B16A16_SFLOAT,
    vk::Format::R32G32B32A32_UINT,
    vk::Format::R16G16B16A16_SFLOAT,
    vk::Format::R16G16B16A16_SFLOAT,
];

/// The deferred frame's attachments after the G-buffer's, in location order (5 to 7): the
/// shaded point and its depth below the relief's top plane; shading normal, polygon plane and
/// normal (octahedral), roughness and metallic as integer bits; the height field's own shadow
/// toward the first four lights (`render/lighting` says what each holds).
pub const SHADING_INPUT_FORMATS: [vk::Format; 3] = [
    vk::Format::R32G32B32A32_SFLOAT,
    vk::Format::R32G32B32A32_UINT,
    vk::Format::R8G8B8A8_UNORM,
];

/// The G-buffer's formats followed by the shading inputs': a deferred frame's attachments after
/// the radiance.
const DEFERRED_FORMATS: [vk::Format; 7] = [
    GBUFFER_FORMATS[0],
    GBUFFER_FORMATS[1],
    GBUFFER_FORMATS[2],
    GBUFFER_FORMATS[3],
    SHADING_INPUT_FORMATS[0],
    SHADING_INPUT_FORMATS[1],
    SHADING_INPUT_FORMATS[2],
];

/// The colour formats a scene pipeline draws after the radiance: the G-buffer's and the shading
/// inputs' in a deferred frame, the G-buffer's when the frame keeps it, else none.
pub fn scene_extra_formats(gbuffer: bool, deferred: bool) -> &'static [vk::Format] {
    if deferred {
        &DEFERRED_FORMATS
    } else if gbuffer {
        &GBUFFER_FORMATS
    } else {
        &[]
    }
}
