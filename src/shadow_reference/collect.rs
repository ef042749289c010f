//! Gathering the scene's occluders: every triangle in world space, classified by its material.
//!
//! - `Blend` materials cast nothing (a translucent surface's shadow is not a visibility question).
//! - `Mask` materials block as opaque, unless their alpha factor is already below the cutoff (then every texel
//!   is cut away and they cast nothing); the alpha texture is not read.
//! - Relief materials become [`ReliefShell`]s over the height map their relief reads
//!   ([`MaterialHeights`]: the frame's, or the material's texture decoded as the renderer does, quantized
//!   to unorm16 as the GPU samples it); in the flat world each shell carries a flat map instead, since only
//!   its polygon casts there.
//! - Everything else is a plain triangle, blocking from both sides.

use std::sync::Arc;

use glam::{Vec2, Vec3};

use super::relief_shell::ReliefShell;
use super::triangle::Triangle;
use super::{ReliefCasting, ShadowReferenceError};
use crate::heightfield::{Address, Heightfield};
use crate::scene::{AlphaMode, HeightLookup, HeightUv, Material, MaterialHeights, Mesh, Scene};

/// One occluder of the scene.
#[derive(Debug, Clone)]
pub(super) enum Primitive {
    Plain(Triangle),
    // Boxed: relief triangles are few, and plain ones stay small and dense.
    Relief(Box<ReliefShell>),
}

/// Every occluder of `scene`; see the module docs for the classification.
pub(super) fn collect(
    scene: &Scene,
    frame_heights: Option<&Heightfield>,
    frame_address: Address,
    casting: ReliefCasting,
) -> Result<Vec<Primitive>, ShadowReferenceError> {
    let mut heights = MaterialHeights::new(scene, frame_heights, frame_address);
    // The flat world: every relief map is one texel at the top plane.
    let flat = match casting {
        ReliefCasting::Flat => Some(Arc::new(Heightfield::new(1, 1, vec![1.0])?)),
        ReliefCasting::Displaced => None,
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
        let relief = match (material.relief, &flat) {
            (Some(relief), None) => Some((relief, heights.of(material, relief.height)?)),
            // Layers too: the flat world needs only where the polygon lies.
            (Some(relief), Some(flat)) => {
                let (address, uv) = heights
                    .placement(relief.height)
                    .unwrap_or((Address::Repeat, HeightUv::IDENTITY));
                let heights = Arc::clone(flat);
                Some((
                    relief,
                    HeightLookup {
                        heights,
                        address,
                        uv,
                    },
                ))
            }
            (None, _) => None,
        };
        for tri in mesh.indices.chunks_exact(3) {
            let corners = corners(mesh, tri);
            let shell = relief.as_ref().and_then(|(relief, lookup)| {
                let vertex = |k: usize| &mesh.vertices[tri[k] as usize];
                ReliefShell::new(
                    corners,
                    [0, 1, 2].map(|k| lookup.uv.of(vertex(k))),
                    [0, 1, 2].map(|k| Vec2::from(vertex(k).uv)),
                    relief.depth_scale,
                    Arc::clone(&lookup.heights),
                    lookup.address,
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
