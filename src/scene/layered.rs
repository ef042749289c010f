//! Layered relief materials (paper 001, 1.7): up to four layers, each with its own height map and,
//! optionally, albedo, normal and roughness, tiled across the material's height uv, weighed by an
//! RGBA splat map (channel k weighs layer k) and blended by a [`BlendMode`] into the one surface
//! the material's method traces. The surface each mode defines is `terrain`'s; the renderer
//! builds it, and its conservative pyramid, from what is named here.

use super::material::TextureRef;
use crate::heightfield::Channel;
use crate::terrain::{BlendMode, MAX_LAYERS};

/// One layer of a layered material.
#[derive(Debug, Clone, PartialEq)]
pub struct MaterialLayer {
    /// For messages and `--explain`.
    pub name: String,
    pub height: TextureRef,
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

/// A material's layers, their weights and how they blend.
#[derive(Debug, Clone, PartialEq)]
pub struct Layers {
    /// 1 to 4.
    pub layers: Vec<MaterialLayer>,
    /// RGBA weights over the height uv, clamped at its edges.
    pub splat: TextureRef,
    pub mode: BlendMode,
    /// Side of the blended height field the method traces, in texels across the height uv.
    pub resolution: u32,
}

/// Why a material's layers cannot be used. Every message is one line.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum LayersError {
    #[error("a layered material needs 1 to {MAX_LAYERS} layers, got {0}")]
    Count(usize),
    #[error("layer {layer:?}: tiling must be a finite number above 0, got {value}")]
    Tiling { layer: String, value: f32 },
    #[error("layer {layer:?}: depth must be within 0..=1, got {value}")]
    Depth { layer: String, value: f32 },
    #[error("the blended field's resolution must be within 1..={max}, got {value}")]
    Resolution { value: u32, max: u32 },
}

/// Largest blended field side: the CPU stack and the GPU build scale with its square.
pub const MAX_LAYERED_RESOLUTION: u32 = 8192;

impl Layers {
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
