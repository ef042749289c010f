//! Materials: glTF metallic-roughness with textures, samplers and uv transforms, plus relief.

use super::layered::Layers;
use super::lod::Lod;
use super::shading::{AoMode, ShadowSettings};
use crate::heightfield::Channel;
use crate::method::Method;

/// How a texture's texels are filtered.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Filter {
    /// The closest texel.
    Nearest,
    #[default]
    /// Bilinear between texels.
    Linear,
}

/// How a texture coordinate outside 0..1 is wrapped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Wrap {
    #[default]
    /// Tiles.
    Repeat,
    /// Tiles, every other tile mirrored.
    MirroredRepeat,
    /// Holds the edge texel beyond the edge.
    ClampToEdge,
}

/// A texture's sampler (glTF `sampler`; defaults: linear, mipmapped, repeat).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct SamplerDesc {
    /// Filter when magnified.
    pub mag: Filter,
    /// Filter when minified.
    pub min: Filter,
    /// Whether minification reads mip levels (and, when so, whether it blends between them).
    pub mipmaps: Option<Filter>,
    /// Addressing along u.
    pub wrap_u: Wrap,
    /// Addressing along v.
    pub wrap_v: Wrap,
}

impl Default for SamplerDesc {
    fn default() -> Self {
        SamplerDesc {
            mag: Filter::Linear,
            min: Filter::Linear,
            mipmaps: Some(Filter::Linear),
            wrap_u: Wrap::Repeat,
            wrap_v: Wrap::Repeat,
        }
    }
}

/// KHR_texture_transform: uv' = T * R * S * uv (glTF's order).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UvTransform {
    /// Added to the uv after scaling and rotation.
    pub offset: [f32; 2],
    /// Radians, counter-clockwise in uv space as the extension defines it.
    pub rotation: f32,
    /// Multiplies the uv first.
    pub scale: [f32; 2],
}

impl Default for UvTransform {
    fn default() -> Self {
        UvTransform {
            offset: [0.0; 2],
            rotation: 0.0,
            scale: [1.0; 2],
        }
    }
}

impl UvTransform {
    /// The two rows of the 2x3 affine matrix: uv' = (row0 . (u, v, 1), row1 . (u, v, 1)).
    pub fn rows(&self) -> [[f32; 3]; 2] {
        let (s, c) = self.rotation.sin_cos();
        let [sx, sy] = self.scale;
        let [ox, oy] = self.offset;
        [[c * sx, s * sy, ox], [-s * sx, c * sy, oy]]
    }
}

/// A material's use of one image.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TextureRef {
    /// Index into `Scene::images`.
    pub image: usize,
    /// Which texture coordinate set (0 or 1) the texture reads.
    pub tex_coord: u32,
    /// The uv transform applied before sampling.
    pub transform: UvTransform,
    /// How it is sampled.
    pub sampler: SamplerDesc,
}

/// The texture slots of a material, in the order the surface shader binds them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum TextureSlot {
    /// Base colour (albedo), sRGB.
    BaseColor,
    /// Metallic in blue, roughness in green.
    MetallicRoughness,
    /// Tangent-space normals.
    Normal,
    /// Ambient occlusion in red.
    Occlusion,
    /// Emitted light, sRGB.
    Emissive,
}

impl TextureSlot {
    /// Every slot, in the order materials bind them.
    pub const ALL: [TextureSlot; 5] = [
        TextureSlot::BaseColor,
        TextureSlot::MetallicRoughness,
        TextureSlot::Normal,
        TextureSlot::Occlusion,
        TextureSlot::Emissive,
    ];

    /// Whether texels hold colours (sRGB-encoded) rather than data.
    pub fn is_color(self) -> bool {
        matches!(self, TextureSlot::BaseColor | TextureSlot::Emissive)
    }

    /// The slot's name in messages.
    pub fn name(self) -> &'static str {
        match self {
            TextureSlot::BaseColor => "baseColor",
            TextureSlot::MetallicRoughness => "metallicRoughness",
            TextureSlot::Normal => "normal",
            TextureSlot::Occlusion => "occlusion",
            TextureSlot::Emissive => "emissive",
        }
    }
}

/// How alpha is used (glTF `alphaMode`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum AlphaMode {
    #[default]
    /// Fully opaque, alpha ignored.
    Opaque,
    /// Fragments with alpha below the cutoff are discarded.
    /// Opaque where alpha reaches `cutoff`, discarded elsewhere.
    Mask {
        /// The alpha a texel needs to be drawn.
        cutoff: f32,
    },
    /// Blended over what is behind, drawn after the opaque surfaces.
    Blend,
}

/// Where a relief material's heights come from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum HeightSource {
    /// The frame's height map: `--heightmap`, or the built-in one for the default scene.
    Frame,
    /// A texture of the scene, from the material's `extras.relief.height`.
    Texture {
        /// The height texture.
        texture: TextureRef,
        /// Which of its channels holds the heights.
        channel: Channel,
        /// Whether white is low rather than high.
        invert: bool,
    },
    /// The blend of the material's layers (`Material::layers`).
    Layers,
}

/// How a material is displaced.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Relief {
    /// Depth of height 0 below the polygon, in uv units of the height map (docs/conventions.md).
    pub depth_scale: f32,
    /// The method that traces the relief.
    pub method: Method,
    /// Iteration cap instead of the method's default.
    pub budget: Option<u32>,
    /// Where the heights come from.
    pub height: HeightSource,
    /// Self-shadowing toward lights that cast shadows.
    pub shadows: ShadowSettings,
    /// Ambient occlusion from the height field.
    pub ao: AoMode,
    /// Level of detail; `None` traces every pixel at full detail.
    pub lod: Option<Lod>,
    /// Whether the relief's outline follows the mesh's polygons or its curvature.
    pub silhouettes: Silhouettes,
    /// Whether the frame's depth holds the displaced hit's depth (what other surfaces are tested
    /// against, and what the G-buffer and an engine's passes read) or the polygon's own.
    pub write_depth: bool,
}

/// How a relief material's outline is cut.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Silhouettes {
    /// The height field hangs under each polygon's plane: every ray that meets the polygon
    /// meets the relief, and the outline is the mesh's.
    #[default]
    Flat,
    /// Curved relief (Oliveira and Policarpo 2005): the height field hangs under a quadric that
    /// follows the mesh's curvature, and a ray that leaves that shell misses, so the outline
    /// is the displaced surface's. Traced with relief mapping's linear and binary search (the
    /// other methods' acceleration structures bound straight rays only).
    Curved,
    /// Prism shells: each triangle extruded down its normals into a prism as deep as the relief
    /// and the ray walked through every prism it crosses, so the outline is the displaced
    /// surface's on open meshes too. Drawn from the prisms' faces, with relief mapping's
    /// bindings and self-shadows; the walk is the shells' own.
    Shells,
}

impl std::fmt::Display for Silhouettes {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Silhouettes::Flat => "flat",
            Silhouettes::Curved => "curved",
            Silhouettes::Shells => "shells",
        })
    }
}

impl std::str::FromStr for Silhouettes {
    type Err = String;

    fn from_str(s: &str) -> Result<Silhouettes, String> {
        match s {
            "flat" => Ok(Silhouettes::Flat),
            "curved" => Ok(Silhouettes::Curved),
            "shells" => Ok(Silhouettes::Shells),
            _ => Err(format!(
                "unknown silhouettes {s:?}: use flat, curved or shells"
            )),
        }
    }
}

impl Relief {
    /// Relief from the frame's height map with the method's own budget, hard self-shadows and no AO.
    pub fn new(depth_scale: f32, method: Method) -> Relief {
        Relief {
            write_depth: true,
            depth_scale,
            method,
            budget: None,
            height: HeightSource::Frame,
            shadows: ShadowSettings::default(),
            ao: AoMode::default(),
            lod: None,
            silhouettes: Silhouettes::Flat,
        }
    }
}

/// A surface's look: glTF metallic-roughness.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    /// The material's name in the file, for messages and for choosing materials by name.
    pub name: String,
    /// Linear RGBA factor.
    pub base_color: [f32; 4],
    /// Base colour texture, multiplied by `base_color`.
    pub base_color_texture: Option<TextureRef>,
    /// Perceptual roughness, multiplied by the texture's.
    pub roughness: f32,
    /// Metalness, multiplied by the texture's.
    pub metallic: f32,
    /// Roughness in G, metalness in B.
    pub metallic_roughness_texture: Option<TextureRef>,
    /// Tangent-space normal map.
    pub normal_texture: Option<TextureRef>,
    /// Scale of the normal map's x and y.
    pub normal_scale: f32,
    /// Occlusion in R.
    pub occlusion_texture: Option<TextureRef>,
    /// How strongly the occlusion texture darkens ambient light.
    pub occlusion_strength: f32,
    /// Linear RGB factor (KHR_materials_emissive_strength folded in).
    pub emissive: [f32; 3],
    /// Emission texture, multiplied by `emissive`.
    pub emissive_texture: Option<TextureRef>,
    /// How alpha is used.
    pub alpha_mode: AlphaMode,
    /// Whether back faces are drawn too.
    pub double_sided: bool,
    /// Relief, or `None` for a plain surface.
    pub relief: Option<Relief>,
    /// Height-blended layers, read when the relief's height source is `Layers`.
    pub layers: Option<Layers>,
}

impl Default for Material {
    fn default() -> Self {
        Material {
            name: "default".into(),
            base_color: [0.8, 0.8, 0.8, 1.0],
            base_color_texture: None,
            roughness: 0.6,
            metallic: 0.0,
            metallic_roughness_texture: None,
            normal_texture: None,
            normal_scale: 1.0,
            occlusion_texture: None,
            occlusion_strength: 1.0,
            emissive: [0.0; 3],
            emissive_texture: None,
            alpha_mode: AlphaMode::Opaque,
            double_sided: false,
            relief: None,
            layers: None,
        }
    }
}

impl Material {
    /// The texture in `slot`, if any.
    pub fn texture(&self, slot: TextureSlot) -> Option<&TextureRef> {
        match slot {
            TextureSlot::BaseColor => self.base_color_texture.as_ref(),
            TextureSlot::MetallicRoughness => self.metallic_roughness_texture.as_ref(),
            TextureSlot::Normal => self.normal_texture.as_ref(),
            TextureSlot::Occlusion => self.occlusion_texture.as_ref(),
            TextureSlot::Emissive => self.emissive_texture.as_ref(),
        }
    }
}
