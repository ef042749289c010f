//! Layered relief materials (Drobot, 1.7): up to four layers, each with its own height map and,
//! optionally, albedo, normal and roughness, tiled across the material's height uv, weighed by an
//! RGBA splat map (channel k weighs layer k) and blended by a [`BlendMode`] into the one surface
//! the material's method traces. The surface each mode defines is `terrain`'s; the renderer
//! builds it, and its conservative pyramid, from what is named here.

use std::sync::Arc;

use image::{DynamicImage, ImageBuffer, Rgba};

use super::material::{SamplerDesc, TextureRef, UvTransform, Wrap};
use super::{Mesh, Scene, SceneImage};
use crate::heightfield::Channel;
use crate::terrain::{splat_from_vertex_colors, BlendMode, LayerError, MAX_LAYERS};

/// One layer of a layered material.
#[derive(Debug, Clone, PartialEq)]
pub struct MaterialLayer {
    /// For messages and `--explain`.
    pub name: String,
    /// The layer's heights.
    pub height: TextureRef,
    /// Which channel of `height` holds them.
    pub height_channel: Channel,
    /// sRGB colour; white when absent.
    pub albedo: Option<TextureRef>,
    /// Tangent-space normal (OpenGL convention, +y up the image); the height field's own when absent.
    pub normal: Option<TextureRef>,
    /// Roughness in the red channel; the material's roughness factor when absent.
    pub roughness: Option<TextureRef>,
    /// Repeats of the layer across the material's height uv (0..1).
    pub tiling: f32,
    /// The layer's heights are scaled by this (0..=1) before blending: a layer of shallower
    /// relief than the material's depth scale.
    pub depth: f32,
}

/// Where a layered material's weights come from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LayerWeights {
    /// An RGBA splat map over the height uv (channel k weighs layer k), clamped at its edges.
    Splat(TextureRef),
    /// The vertex colours of the meshes that use the material, rasterised over their first uv
    /// set into a `resolution`^2 splat map by [`bake_vertex_color_weights`] (the glTF loader
    /// does so).
    VertexColors {
        /// Side of the baked splat map, in texels.
        resolution: u32,
    },
    /// Vertex colours baked into this splat map: read like `Splat`, and the colours weigh the
    /// layers instead of tinting the material.
    BakedVertexColors(TextureRef),
}

/// A material's layers, their weights and how they blend.
#[derive(Debug, Clone, PartialEq)]
pub struct Layers {
    /// 1 to 4.
    pub layers: Vec<MaterialLayer>,
    /// Where each layer's weight comes from.
    pub weights: LayerWeights,
    /// How the layers blend.
    pub mode: BlendMode,
    /// Side of the blended height field the method traces, in texels across the height uv.
    pub resolution: u32,
}

/// Why a material's layers cannot be used. Every message is one line.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum LayersError {
    #[error("a layered material needs 1 to {MAX_LAYERS} layers, got {0}")]
    /// Not 1 to 4 layers.
    Count(usize),
    #[error("layer {layer:?}: tiling must be a finite number above 0, got {value}")]
    /// A tiling that is not a finite number above 0.
    Tiling {
        /// The layer's name.
        layer: String,
        /// Its tiling.
        value: f32,
    },
    #[error("layer {layer:?}: depth must be within 0..=1, got {value}")]
    /// A depth outside 0..=1.
    Depth {
        /// The layer's name.
        layer: String,
        /// Its depth.
        value: f32,
    },
    #[error("the blended field's resolution must be within 1..={max}, got {value}")]
    /// A blended field's side out of range.
    Resolution {
        /// The side asked for.
        value: u32,
        /// The largest side taken.
        max: u32,
    },
    #[error("its weights come from vertex colours not yet baked into a splat map (scene::bake_vertex_color_weights)")]
    /// Vertex-colour weights not yet baked into a splat map.
    Unbaked,
}

/// Largest blended field side: the CPU stack (eight f32 maps of this side: 512 MiB at 4096) and
/// the GPU build scale with its square.
pub const MAX_LAYERED_RESOLUTION: u32 = 4096;

impl Layers {
    /// The splat map the weights are read from (`None` until vertex colours are baked).
    pub fn splat(&self) -> Option<&TextureRef> {
        match &self.weights {
            LayerWeights::Splat(t) | LayerWeights::BakedVertexColors(t) => Some(t),
            LayerWeights::VertexColors { .. } => None,
        }
    }

    /// Checks the counts and numbers (texture indices are checked against the scene by the plan).
    pub fn check(&self) -> Result<(), LayersError> {
        if self.layers.is_empty() || self.layers.len() > MAX_LAYERS {
            return Err(LayersError::Count(self.layers.len()));
        }
        for l in &self.layers {
            if !(l.tiling.is_finite() && l.tiling > 0.0) {
                return Err(LayersError::Tiling {
                    layer: l.name.clone(),
                    value: l.tiling,
                });
            }
            if !(0.0..=1.0).contains(&l.depth) {
                return Err(LayersError::Depth {
                    layer: l.name.clone(),
                    value: l.depth,
                });
            }
        }
        if self.resolution == 0 || self.resolution > MAX_LAYERED_RESOLUTION {
            return Err(LayersError::Resolution {
                value: self.resolution,
                max: MAX_LAYERED_RESOLUTION,
            });
        }
        Ok(())
    }
}

/// Replaces every layered material's vertex-colour weights by a splat map rasterised from the
/// colours of the meshes that use it, added to the scene's images.
pub fn bake_vertex_color_weights(scene: &mut Scene) -> Result<(), LayerError> {
    for m in 0..scene.materials.len() {
        let Some(LayerWeights::VertexColors { resolution }) =
            scene.materials[m].layers.as_ref().map(|l| l.weights)
        else {
            continue;
        };
        let meshes: Vec<&Mesh> = scene
            .meshes
            .iter()
            .filter(|mesh| mesh.material == m)
            .collect();
        let splat = splat_from_vertex_colors(&meshes, resolution)?;
        let (w, h) = splat.size();
        let pixels = ImageBuffer::from_fn(w, h, |i, j| {
            Rgba(
                splat
                    .texel(i, j)
                    .map(|x| (x.clamp(0.0, 1.0) * 65535.0).round() as u16),
            )
        });
        scene.images.push(SceneImage {
            name: format!("vertex-colour weights of {:?}", scene.materials[m].name),
            pixels: Arc::new(DynamicImage::ImageRgba16(pixels)),
        });
        let texture = TextureRef {
            image: scene.images.len() - 1,
            tex_coord: 0,
            transform: UvTransform::default(),
            sampler: SamplerDesc {
                wrap_u: Wrap::ClampToEdge,
                wrap_v: Wrap::ClampToEdge,
                mipmaps: None,
                ..SamplerDesc::default()
            },
        };
        if let Some(layers) = scene.materials[m].layers.as_mut() {
            layers.weights = LayerWeights::BakedVertexColors(texture);
        }
    }
    Ok(())
}
