//! The passes a frame can record, as one enum: the plan lists them, the renderer times them with
//! timestamp scopes, and `--explain` and the timing tables print them, all by the same names.

use serde::{Serialize, Serializer};

/// One pass of a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Pass {
    /// Builds the max pyramid of every height map a pyramid method reads (first frame only: the
    /// fields are static).
    Pyramid,
    /// Builds the texture-space AO map of every height map a material asks AO of (first frame
    /// only, after the pyramids).
    AmbientOcclusion,
    /// Renders each shadow-casting light's shadow map, relief casters traced from the light; one
    /// timestamp scope per map. Only in frames where a view moved (cascades follow the camera)
    /// or the casters changed: a still sequence renders the maps once.
    ShadowMaps,
    /// Writes, per pixel, the farthest depth the nearest opaque surface can reach (a plain
    /// mesh's own depth, the bottom of a relief slab), so relief fragments behind it skip their
    /// trace in the surface pass.
    Occluders,
    /// Draws the meshes replaced by cell complexes: each grey cell's front faces, a ray marched
    /// through the complex per fragment (Apaza and Andujar).
    Cells,
    /// Draws the scene: rasterises the meshes and traces each relief fragment's view ray.
    Surface,
    /// Rays from each relief hit toward the shadow-casting lights, traced inside the surface
    /// pass's fragments (listed for the plan; its time is part of `Surface`).
    SelfShadowRays,
    /// The sky behind the scene, drawn after the opaque surfaces where the depth test leaves
    /// pixels uncovered (inside the surface pass's rendering; its time is part of `Surface`).
    Background,
    /// The deferred frame's lighting: every pixel the surface pass drew is lit once, from the
    /// G-buffer and the shading inputs, after the scene's rendering ends (timed within the
    /// surface pass's scope).
    Lighting,
    /// Exposure and the tone curve from the linear radiance into the frame (after the surface
    /// pass's rendering ends, timed within its scope).
    ToneMap,
}

impl Pass {
    /// Every pass, in recording order.
    pub const ALL: [Pass; 10] = [
        Pass::Pyramid,
        Pass::AmbientOcclusion,
        Pass::ShadowMaps,
        Pass::Occluders,
        Pass::Cells,
        Pass::Surface,
        Pass::SelfShadowRays,
        Pass::Background,
        Pass::Lighting,
        Pass::ToneMap,
    ];

    /// The name the plan, `--explain` and the timing tables print.
    pub fn name(self) -> &'static str {
        match self {
            Pass::Pyramid => "pyramid",
            Pass::AmbientOcclusion => "ao map",
            Pass::ShadowMaps => "shadow maps",
            Pass::Occluders => "occluders",
            Pass::Cells => "cells",
            Pass::Surface => "surface",
            Pass::SelfShadowRays => "self-shadow rays",
            Pass::Background => "background",
            Pass::Lighting => "lighting",
            Pass::ToneMap => "tone map",
        }
    }

    /// Whether the pass has timestamps of its own (else it runs inside another pass).
    pub fn timed(self) -> bool {
        !matches!(
            self,
            Pass::SelfShadowRays | Pass::Background | Pass::Lighting | Pass::ToneMap
        )
    }
}

impl std::fmt::Display for Pass {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl Serialize for Pass {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_and_serialise_as_printed() {
        let mut names: Vec<&str> = Pass::ALL.iter().map(|p| p.name()).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), Pass::ALL.len());
        for pass in Pass::ALL {
            let json = serde_json::to_string(&pass).unwrap();
            assert_eq!(json, format!("\"{}\"", pass.name()));
            assert_eq!(pass.to_string(), pass.name());
        }
    }
}
