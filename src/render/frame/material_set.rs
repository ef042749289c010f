//! Set 1 of the surface pass: per material, its parameter block, its five textures and the AO map
//! of its relief (the white texture fills empty slots). The block's layout is `MaterialUniform` in
//! `shader_interface`, which `shaders/include/draw.glsl` reads too.

use std::sync::Arc;

use ash::vk;

use super::scene_textures::SceneTextures;
use crate::render::kit::set_layouts::{RELIEF_AO_SLOT, TEXTURE_BINDINGS};
use crate::render::shader_interface::{
    MaterialUniform, BINDING_MATERIAL_PARAMS, SLOT_BASE_COLOR, SLOT_EMISSIVE, SLOT_HEIGHT,
    SLOT_METALLIC_ROUGHNESS, SLOT_NORMAL, SLOT_OCCLUSION,
};
use crate::scene::{AlphaMode, HeightSource, Material, SceneImage, TextureSlot, UvTransform};
use crate::vk::{
    Bind, Buffer, Context, DescriptorLayout, DescriptorPool, DescriptorSet, ImageView, Sampler,
    VkResult,
};

/// The shaders' index of a texture slot: its bit in `textures.x` and its pair of `uv_rows`.
fn slot_index(slot: TextureSlot) -> usize {
    (match slot {
        TextureSlot::BaseColor => SLOT_BASE_COLOR,
        TextureSlot::MetallicRoughness => SLOT_METALLIC_ROUGHNESS,
        TextureSlot::Normal => SLOT_NORMAL,
        TextureSlot::Occlusion => SLOT_OCCLUSION,
        TextureSlot::Emissive => SLOT_EMISSIVE,
    }) as usize
}

fn uv_rows(transform: &UvTransform, tex_coord: u32) -> [[f32; 4]; 2] {
    let [r0, r1] = transform.rows();
    [
        [r0[0], r0[1], r0[2], tex_coord as f32],
        [r1[0], r1[1], r1[2], 0.0],
    ]
}

impl MaterialUniform {
    pub fn of(material: &Material) -> MaterialUniform {
        let identity = uv_rows(&UvTransform::default(), 0);
        let mut rows = [[0.0; 4]; 12];
        let mut textures = 0u32;
        for slot in TextureSlot::ALL {
            let k = slot_index(slot);
            let pair = match material.texture(slot) {
                Some(t) => {
                    textures |= 1 << k;
                    uv_rows(&t.transform, t.tex_coord)
                }
                None => identity,
            };
            rows[2 * k] = pair[0];
            rows[2 * k + 1] = pair[1];
        }
        let height = match material.relief.map(|r| r.height) {
            Some(HeightSource::Texture { texture, .. }) => {
                uv_rows(&texture.transform, texture.tex_coord)
            }
            _ => identity,
        };
        rows[2 * SLOT_HEIGHT as usize] = height[0];
        rows[2 * SLOT_HEIGHT as usize + 1] = height[1];
        let cutoff = match material.alpha_mode {
            AlphaMode::Mask { cutoff } => cutoff,
            _ => -1.0,
        };
        let [er, eg, eb] = material.emissive;
        MaterialUniform {
            base_color: material.base_color,
            emissive: [er, eg, eb, cutoff],
            pbr: [
                material.roughness,
                material.metallic,
                material.normal_scale,
                material.occlusion_strength,
            ],
            relief: [
                material.relief.map_or(0.0, |r| r.depth_scale),
                f32::from(u8::from(material.alpha_mode == AlphaMode::Blend)),
                0.0,
                0.0,
            ],
            textures: [textures, 0, 0, 0],
            uv_rows: rows,
        }
    }
}

/// One descriptor set per drawn material, with the buffers it points at.
pub struct MaterialSets {
    _pool: DescriptorPool,
    _buffers: Vec<Buffer>,
    /// By material index; `None` for materials no mesh draws.
    sets: Vec<Option<DescriptorSet>>,
}

impl MaterialSets {
    /// Sets for the materials `drawn` marks, uploading the textures they read; `relief_ao[k]` is
    /// material k's AO map, if its relief has one.
    pub fn new(
        ctx: &Arc<Context>,
        layout: &DescriptorLayout,
        materials: &[Material],
        images: &[SceneImage],
        drawn: &[bool],
        relief_ao: &[Option<(ImageView, Sampler)>],
        textures: &mut SceneTextures,
    ) -> VkResult<MaterialSets> {
        let count = drawn.iter().filter(|d| **d).count().max(1) as u32;
        let pool = DescriptorPool::new(ctx, count, 6 * count, "material sets")?;
        let mut buffers = Vec::new();
        let mut sets = vec![None; materials.len()];
        for (index, material) in materials.iter().enumerate() {
            if !drawn.get(index).copied().unwrap_or(false) {
                continue;
            }
            let ao = relief_ao.get(index).cloned().flatten();
            let mut uniform = MaterialUniform::of(material);
            if ao.is_some() {
                uniform.textures[0] |= 1 << RELIEF_AO_SLOT;
            }
            let buffer = Buffer::with_data(
                ctx,
                bytemuck::bytes_of(&uniform),
                vk::BufferUsageFlags::UNIFORM_BUFFER,
                &format!("material {:?}", material.name),
            )?;
            let mut bound = Vec::with_capacity(6);
            for slot in TextureSlot::ALL.iter() {
                bound.push(match material.texture(*slot) {
                    Some(t) => textures.bind(images, t, slot.is_color())?,
                    None => textures.white()?,
                });
            }
            let (ao_view, ao_sampler) = match ao {
                Some(bound) => bound,
                None => textures.white()?,
            };
            let mut binds = Vec::with_capacity(7);
            for (&binding, (view, sampler)) in TEXTURE_BINDINGS.iter().zip(&bound) {
                binds.push(Bind::Texture(binding, view, sampler));
            }
            binds.push(Bind::Uniform(BINDING_MATERIAL_PARAMS, &buffer));
            binds.push(Bind::Texture(RELIEF_AO_SLOT, &ao_view, &ao_sampler));
            sets[index] = Some(pool.allocate(layout, &binds)?);
            buffers.push(buffer);
        }
        Ok(MaterialSets {
            _pool: pool,
            _buffers: buffers,
            sets,
        })
    }

    /// The set of material `index`, if it is drawn.
    pub fn set(&self, index: usize) -> Option<DescriptorSet> {
        self.sets.get(index).cloned().flatten()
    }
}
