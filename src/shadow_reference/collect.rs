//! Gathering the scene's occluders: every triangle in world space, classified by its material.
//!
//! - `Blend` materials cast nothing (a translucent surface's shadow is not a visibility question).
//! - `Mask` materials block as opaque, unless their alpha factor is already below the cutoff (then every texel
//!   is cut away and they cast nothing); the alpha texture is not read.
//! - Relief materials become [`ReliefShell`]s over the height map their relief reads (the frame's, or the
//!   material's texture decoded as the renderer does), quantized to unorm16 as the GPU samples it; in the flat
//!   world each shell carries a flat map instead, since only its polygon casts there.
//! - Everything else is a plain triangle, blocking from both sides.

use std::sync::Arc;

use glam::{Vec2, Vec3};

use super::relief_shell::ReliefShell;
use super::triangle::Triangle;
use super::{ReliefCasting, ShadowReferenceError};
use crate::heightfield::{Address, Channel, Heightfield, LoadOptions};
use crate::scene::{AlphaMode, HeightSource, Material, Mesh, Scene, Wrap};

/// One occluder of the scene.
#[derive(Debug, Clone)]
pub(super) enum Primitive {
    Plain(Triangle),
    // Boxed: relief triangles are few, and plain ones stay small and dense.
    Relief(Box<ReliefShell>),
}

/// Where a relief material's heights come from, to share one decoded map between materials.
#[derive(Debug, Clone, Copy, PartialEq)]
enum HeightKey {
    Frame,
    Image {
        image: usize,
        channel: Channel,
        invert: bool,
    },
}

/// The decoded, quantized height maps, each made once.
struct Heights<'a> {
    scene: &'a Scene,
    frame: Option<&'a Heightfield>,
    frame_address: Address,
    made: Vec<(HeightKey, Arc<Heightfield>)>,
    /// The map of the flat world: one texel at the top plane.
    flat: Option<Arc<Heightfield>>,
}

/// Every occluder of `scene`; see the module docs for the classification.
pub(super) fn collect(
    scene: &Scene,
    frame_heights: Option<&Heightfield>,
    frame_address: Address,
    casting: ReliefCasting,
) -> Result<Vec<Primitive>, ShadowReferenceError> {
    let mut heights = Heights {
        scene,
        frame: frame_heights,
        frame_address,
        made: Vec::new(),
        flat: match casting {
            ReliefCasting::Flat => Some(Arc::new(Heightfield::new(1, 1, vec![1.0])?)),
            ReliefCasting::Displaced => None,
        },
    };
    let mut primitives = Vec::new();
    for mesh in &scene.meshes {
        let material =
            scene
                .materials
                .get(mesh.material)
                .ok_or_else(|| ShadowReferenceError::NoMaterial {
                    mesh: mesh.name.clone(),
                    material: mesh.material,
                    count: scene.materials.len(),
                })?;
        if !casts(material) {
            continue;
        }
        let relief = match material.relief {
            Some(relief) => Some((relief, heights.of(material, relief.height)?)),
            None => None,
        };
        for tri in mesh.indices.chunks_exact(3) {
            let corners = corners(mesh, tri);
            let shell = relief.as_ref().and_then(|(relief, (hf, address, uv_map))| {
                ReliefShell::new(
                    corners,
                    uv_map.apply(mesh, tri),
                    [0, 1, 2].map(|k| Vec2::from(mesh.vertices[tri[k] as usize].uv)),
                    relief.depth_scale,
                    Arc::clone(hf),
                    *address,
                )
            });
            primitives.push(match shell {
                Some(shell) => Primitive::Relief(Box::new(shell)),
                // A relief triangle without a texture frame (degenerate uvs) can only be its polygon.
                None => Primitive::Plain(Triangle { corners }),
            });
        }
    }
    Ok(primitives)
}

fn casts(material: &Material) -> bool {
    match material.alpha_mode {
        AlphaMode::Opaque => true,
        AlphaMode::Mask { cutoff } => material.base_color[3] >= cutoff,
        AlphaMode::Blend => false,
    }
}

fn corners(mesh: &Mesh, tri: &[u32]) -> [Vec3; 3] {
    [0, 1, 2].map(|k| {
        let v = &mesh.vertices[tri[k] as usize];
        mesh.transform.transform_point3(Vec3::from(v.position))
    })
}

/// The affine map from a vertex's uv sets to its height-map uv (the height texture's set and transform).
#[derive(Debug, Clone, Copy)]
struct UvMap {
    set: u32,
    rows: [[f32; 3]; 2],
}

impl UvMap {
    fn apply(&self, mesh: &Mesh, tri: &[u32]) -> [Vec2; 3] {
        [0, 1, 2].map(|k| {
            let v = &mesh.vertices[tri[k] as usize];
            let [u, w] = if self.set == 1 { v.uv1 } else { v.uv };
            let [r0, r1] = self.rows;
            Vec2::new(r0[0] * u + r0[1] * w + r0[2], r1[0] * u + r1[1] * w + r1[2])
        })
    }
}

const IDENTITY_ROWS: [[f32; 3]; 2] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

impl Heights<'_> {
    /// The map `material`'s relief reads, its addressing, and how its uvs are found.
    fn of(
        &mut self,
        material: &Material,
        source: HeightSource,
    ) -> Result<(Arc<Heightfield>, Address, UvMap), ShadowReferenceError> {
        let (key, address, uv_map) = match source {
            HeightSource::Frame => (
                HeightKey::Frame,
                self.frame_address,
                UvMap {
                    set: 0,
                    rows: IDENTITY_ROWS,
                },
            ),
            HeightSource::Texture {
                texture,
                channel,
                invert,
            } => {
                let wraps = [texture.sampler.wrap_u, texture.sampler.wrap_v];
                // As the renderer decides: clamp on either axis clamps the map.
                let address = if wraps.contains(&Wrap::ClampToEdge) {
                    Address::Clamp
                } else {
                    Address::Repeat
                };
                let key = HeightKey::Image {
                    image: texture.image,
                    channel,
                    invert,
                };
                let uv_map = UvMap {
                    set: texture.tex_coord,
                    rows: texture.transform.rows(),
                };
                (key, address, uv_map)
            }
            HeightSource::Layers if self.flat.is_none() => {
                return Err(ShadowReferenceError::LayeredHeights {
                    material: material.name.clone(),
                })
            }
            HeightSource::Layers => (
                HeightKey::Frame,
                Address::Repeat,
                UvMap {
                    set: 0,
                    rows: IDENTITY_ROWS,
                },
            ),
        };
        if let Some(flat) = &self.flat {
            return Ok((Arc::clone(flat), address, uv_map));
        }
        Ok((self.made(material, key)?, address, uv_map))
    }

    fn made(
        &mut self,
        material: &Material,
        key: HeightKey,
    ) -> Result<Arc<Heightfield>, ShadowReferenceError> {
        if let Some((_, hf)) = self.made.iter().find(|(k, _)| *k == key) {
            return Ok(Arc::clone(hf));
        }
        let hf = match key {
            HeightKey::Frame => self
                .frame
                .ok_or_else(|| ShadowReferenceError::NoFrameHeights {
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
                        .ok_or_else(|| ShadowReferenceError::NoImage {
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
