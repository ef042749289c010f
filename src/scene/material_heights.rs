//! The height map a relief material reads, decoded on the CPU the way the GPU samples it: the
//! frame's map or the material's texture (channel and inversion applied), quantized to unorm16,
//! with the addressing the renderer chooses and the map from a vertex's uv sets to height uv.
//! The CPU references (exact scene shadows, displaced geometry) read relief through this.

use std::sync::Arc;

use glam::Vec2;

use super::{HeightSource, Material, Scene, Vertex, Wrap};
use crate::heightfield::{Address, Channel, Heightfield, HeightfieldError, LoadOptions};

/// Why a relief material's heights could not be read on the CPU.
#[derive(Debug, thiserror::Error)]
pub enum MaterialHeightsError {
    /// A relief material reads the frame's height map and none was given.
    #[error("relief material {material:?} reads the frame height map, and none was given")]
    NoFrameHeights {
        /// The material's name.
        material: String,
    },
    /// A relief material's height texture names an image the scene does not have.
    #[error("relief material {material:?} reads image {image}, but the scene has {count}")]
    NoImage {
        /// The material's name.
        material: String,
        /// The image index.
        image: usize,
        /// How many images there are.
        count: usize,
    },
    /// A relief material blends layers, whose heights only the GPU builds.
    #[error("relief material {material:?} blends layers, whose heights only the GPU builds; a CPU reference cannot read them")]
    LayeredHeights {
        /// The material's name.
        material: String,
    },
    /// A height map could not be decoded.
    #[error(transparent)]
    Heights(#[from] HeightfieldError),
}

/// The affine map from a vertex's uv sets to its height-map uv: the height texture's set and
/// transform (KHR_texture_transform), identity for the frame's map.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeightUv {
    /// Which uv set (0 or 1).
    pub set: u32,
    /// Rows of the 2x3 affine transform.
    pub rows: [[f32; 3]; 2],
}

impl HeightUv {
    /// Set 0, untransformed.
    pub const IDENTITY: HeightUv = HeightUv {
        set: 0,
        rows: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
    };

    /// The height uv of `v`.
    pub fn of(&self, v: &Vertex) -> Vec2 {
        let [u, w] = if self.set == 1 { v.uv1 } else { v.uv };
        let [r0, r1] = self.rows;
        Vec2::new(r0[0] * u + r0[1] * w + r0[2], r1[0] * u + r1[1] * w + r1[2])
    }
}

/// What one relief material reads.
#[derive(Debug, Clone)]
pub struct HeightLookup {
    /// The heights, quantized to unorm16 as the GPU stores them.
    pub heights: Arc<Heightfield>,
    /// How the map continues outside [0, 1].
    pub address: Address,
    /// Where each vertex falls in it.
    pub uv: HeightUv,
}

/// Where a relief material's heights come from, so materials reading one map share it.
#[derive(Debug, Clone, Copy, PartialEq)]
enum HeightKey {
    Frame,
    Image {
        image: usize,
        channel: Channel,
        invert: bool,
    },
}

/// The decoded height maps of a scene's relief materials, each made once.
pub struct MaterialHeights<'a> {
    scene: &'a Scene,
    frame: Option<&'a Heightfield>,
    frame_address: Address,
    made: Vec<(HeightKey, Arc<Heightfield>)>,
}

impl<'a> MaterialHeights<'a> {
    /// Materials of `scene` reading the frame's map read `frame` with `frame_address`.
    pub fn new(
        scene: &'a Scene,
        frame: Option<&'a Heightfield>,
        frame_address: Address,
    ) -> MaterialHeights<'a> {
        MaterialHeights {
            scene,
            frame,
            frame_address,
            made: Vec::new(),
        }
    }

    /// The addressing and uv map of `source` without decoding anything; `None` for layers.
    pub fn placement(&self, source: HeightSource) -> Option<(Address, HeightUv)> {
        match source {
            HeightSource::Frame => Some((self.frame_address, HeightUv::IDENTITY)),
            HeightSource::Texture { texture, .. } => {
                let wraps = [texture.sampler.wrap_u, texture.sampler.wrap_v];
                // As the renderer decides: clamp on either axis clamps the map.
                let address = if wraps.contains(&Wrap::ClampToEdge) {
                    Address::Clamp
                } else {
                    Address::Repeat
                };
                let uv = HeightUv {
                    set: texture.tex_coord,
                    rows: texture.transform.rows(),
                };
                Some((address, uv))
            }
            HeightSource::Layers => None,
        }
    }

    /// The map `material` reads from `source` (its relief's height source).
    pub fn of(
        &mut self,
        material: &Material,
        source: HeightSource,
    ) -> Result<HeightLookup, MaterialHeightsError> {
        let Some((address, uv)) = self.placement(source) else {
            return Err(MaterialHeightsError::LayeredHeights {
                material: material.name.clone(),
            });
        };
        let key = match source {
            HeightSource::Texture {
                texture,
                channel,
                invert,
            } => HeightKey::Image {
                image: texture.image,
                channel,
                invert,
            },
            _ => HeightKey::Frame,
        };
        Ok(HeightLookup {
            heights: self.made(material, key)?,
            address,
            uv,
        })
    }

    fn made(
        &mut self,
        material: &Material,
        key: HeightKey,
    ) -> Result<Arc<Heightfield>, MaterialHeightsError> {
        if let Some((_, hf)) = self.made.iter().find(|(k, _)| *k == key) {
            return Ok(Arc::clone(hf));
        }
        let hf = match key {
            HeightKey::Frame => self
                .frame
                .ok_or_else(|| MaterialHeightsError::NoFrameHeights {
                    material: material.name.clone(),
                })?
                .quantized_unorm16(),
            HeightKey::Image {
                image,
                channel,
                invert,
            } => {
                let img =
                    self.scene
                        .images
                        .get(image)
                        .ok_or_else(|| MaterialHeightsError::NoImage {
                            material: material.name.clone(),
                            image,
                            count: self.scene.images.len(),
                        })?;
                let opts = LoadOptions { channel, invert };
                Heightfield::from_dynamic_image(&img.pixels, &opts, &img.name)?.quantized_unorm16()
            }
        };
        let hf = Arc::new(hf);
        self.made.push((key, Arc::clone(&hf)));
        Ok(hf)
    }
}
