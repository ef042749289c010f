//! The shells of a scene's relief meshes, each with the heights the displaced reference reads
//! for it ([`relief_lookups`]).

use super::prism::{Shell, ShellError};
use crate::displaced_reference::{relief_lookups, DisplacedReferenceError};
use crate::heightfield::{Address, Heightfield};
use crate::scene::Scene;

/// Why a scene's shells could not be built.
#[derive(Debug, thiserror::Error)]
pub enum SceneShellsError {
    /// A relief mesh's material or heights could not be read.
    #[error(transparent)]
    Heights(#[from] DisplacedReferenceError),
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
    relief_lookups(scene, frame_heights, frame_address)?
        .into_iter()
        .map(|(index, relief, lookup)| {
            Ok(Shell::new(
                &scene.meshes[index],
                &lookup,
                relief.depth_scale,
            )?)
        })
        .collect()
}
