//! The descriptor set layouts every pass drawing meshes shares: set 0 (the frame uniforms, the
//! height field's bindings where a pass reads them, then the scene's shadow atlas and
//! environment maps) and set 1 (a material's textures and parameters).

use std::sync::Arc;

use ash::vk;

use crate::render::shader_interface::{
    BINDING_ENV_BRDF, BINDING_ENV_IRRADIANCE, BINDING_ENV_SPECULAR, BINDING_FRAME,
    BINDING_MATERIAL_BASE_COLOR, BINDING_MATERIAL_EMISSIVE, BINDING_MATERIAL_METALLIC_ROUGHNESS,
    BINDING_MATERIAL_NORMAL, BINDING_MATERIAL_OCCLUSION, BINDING_MATERIAL_PARAMS,
    BINDING_MATERIAL_RELIEF_AO, BINDING_SHADOW_ATLAS,
};
use crate::vk::{Context, DescriptorLayout, VkResult};

/// Bit of `textures.x` and binding of the relief AO map (`SLOT_RELIEF_AO` in draw.glsl).
pub(in crate::render) const RELIEF_AO_SLOT: u32 = BINDING_MATERIAL_RELIEF_AO;
/// The bindings of the texture slots, in `TextureSlot::ALL`'s order.
pub(in crate::render) const TEXTURE_BINDINGS: [u32; 5] = [
    BINDING_MATERIAL_BASE_COLOR,
    BINDING_MATERIAL_METALLIC_ROUGHNESS,
    BINDING_MATERIAL_NORMAL,
    BINDING_MATERIAL_OCCLUSION,
    BINDING_MATERIAL_EMISSIVE,
];

/// The bindings every drawing pass's set 0 ends with: the shadow atlas and the environment's
/// three maps.
const SCENE_BINDINGS: [u32; 4] = [
    BINDING_SHADOW_ATLAS,
    BINDING_ENV_IRRADIANCE,
    BINDING_ENV_SPECULAR,
    BINDING_ENV_BRDF,
];

/// The set 0 layout of `bindings` (each a sampled texture but the frame uniforms), followed by
/// the scene's.
pub(in crate::render) fn set0_layout(
    ctx: &Arc<Context>,
    bindings: &[u32],
    name: &str,
) -> VkResult<DescriptorLayout> {
    // Compute too: the deferred frame's lighting pass binds the plain set.
    let stages = vk::ShaderStageFlags::VERTEX
        | vk::ShaderStageFlags::FRAGMENT
        | vk::ShaderStageFlags::COMPUTE;
    let all: Vec<_> = bindings
        .iter()
        .chain(&SCENE_BINDINGS)
        .map(|&b| match b {
            BINDING_FRAME => (b, vk::DescriptorType::UNIFORM_BUFFER),
            _ => (b, vk::DescriptorType::COMBINED_IMAGE_SAMPLER),
        })
        .collect();
    DescriptorLayout::new(ctx, &all, stages, name)
}

/// Set 0 of draws without relief: the frame uniforms and the scene's bindings.
pub(in crate::render) fn plain_frame_layout(ctx: &Arc<Context>) -> VkResult<DescriptorLayout> {
    set0_layout(ctx, &[BINDING_FRAME], "plain frame layout")
}

/// The layout of set 1.
pub fn material_layout(ctx: &Arc<Context>) -> VkResult<DescriptorLayout> {
    let mut bindings: Vec<(u32, vk::DescriptorType)> = TEXTURE_BINDINGS
        .iter()
        .map(|&b| (b, vk::DescriptorType::COMBINED_IMAGE_SAMPLER))
        .collect();
    bindings.push((BINDING_MATERIAL_PARAMS, vk::DescriptorType::UNIFORM_BUFFER));
    bindings.push((RELIEF_AO_SLOT, vk::DescriptorType::COMBINED_IMAGE_SAMPLER));
    let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
    DescriptorLayout::new(ctx, &bindings, stages, "material layout")
}
