//! The shells of a scene's relief meshes, read as the displaced reference reads them: each relief
//! mesh's heights from its material, the frame's map for materials that name it.

use super::prism::{Shell, ShellError};
use crate::heightfield::{Address, Heightfield};
use crate::scene::{MaterialHeights, MaterialHeightsError, Scene};

/// Why a scene's shells could not be built.
#[derive(Debug, thiserror::Error)]
pub enum SceneShellsError {
    /// A mesh names a material the scene does not have.
    #[error("mesh {mesh:?} uses material {material}, but the scene has {count}")]
    NoMaterial {
        /// The mesh's name.
        mesh: String,
        /// The index it names.
        material: usize,
        /// How many materials there are.
        count: usize,
    },
    /// A relief material's heights could not be read.
    #[error(transparent)]
    Heights(#[from] MaterialHeightsError),
    /// A mesh could not be extruded.
    #[error(transparent)]
    Shell(#[from] ShellError),
}

/// One shell per relief mesh of `scene`, in the scene's order; materials reading the frame's
/// height map read `frame_heights` with `frame_address`.
pub fn scene_shells(
    scene: &Scene,
    frame_heights: Option<&Heightfield>,
    frame_address: Address,
) -> Result<Vec<Shell>, SceneShellsError> {
    let mut heights = MaterialHeights::new(scene, frame_heights, frame_address);
    let mut shells = Vec::new();
    for mesh in &scene.meshes {
        let material =
            scene
                .materials
                .get(mesh.material)
                .ok_or_else(|| SceneShellsError::NoMaterial {
                    mesh: mesh.name.clone(),
                    material: mesh.material,
                    count: scene.materials.len(),
                })?;
        let Some(relief) = material.relief else {
            continue;
        };
        let lookup = heights.of(material, relief.height)?;
        shells.push(Shell::new(mesh, &lookup, relief.depth_scale)?);
    }
    Ok(shells)
}
