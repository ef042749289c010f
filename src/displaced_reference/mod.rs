//! The ground truth for relief on curved meshes: every relief mesh really tessellated and
//! displaced, as geometry, on the CPU, to be drawn by the plain raster pass with the same camera,
//! material (its relief taken off) and lights.
//!
//! Each relief mesh is subdivided uniformly ([`subdivide`]) until its longest edge spans at most
//! `texels_per_edge` texels of its height map, then each vertex moves down its interpolated
//! normal by the relief's depth there: `s * (1 - h)` in height-uv units, with `h` the bilinear
//! height of the unorm16 map the GPU samples and one depth unit as long in world space as the
//! surface pass makes it (the geometric mean of the world lengths of one uv unit along u and v,
//! [`crate::geometry::depth_length`]). So a depth scale means the same here as on a flat quad.
//! How fine is fine enough is measured, not assumed: the reference at `texels_per_edge` and at
//! half of it are compared (see docs/silhouettes.md).

mod compare;
mod displace;
mod subdivide;

pub use compare::{compare_with_reference, coverage, iou, OutlineAgreement};
pub use displace::displace;
pub(crate) use displace::welded_depth_lengths;
pub use subdivide::{levels_for, subdivide};

use crate::heightfield::{Address, Heightfield};
use crate::scene::{HeightLookup, MaterialHeights, MaterialHeightsError, Relief, Scene};

/// Edge length the reference subdivides to by default, in height texels.
pub const DEFAULT_TEXELS_PER_EDGE: f64 = 1.0;

/// Most triangles one displaced mesh may have (about 300 MB of vertices and indices).
pub const MAX_TRIANGLES: usize = 4 << 20;

/// What became of one relief mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct DisplacedMesh {
    /// The mesh's name.
    pub name: String,
    /// Times each triangle was split in four.
    pub levels: u32,
    /// Triangles after subdivision.
    pub triangles: usize,
    /// Its longest edge before subdivision, in height texels.
    pub longest_edge_texels: f64,
}

/// A scene whose relief meshes are displaced geometry, and what was done to each.
#[derive(Debug, Clone)]
pub struct DisplacedScene {
    /// The scene to draw: plain materials only.
    pub scene: Scene,
    /// One entry per relief mesh, in the scene's order.
    pub meshes: Vec<DisplacedMesh>,
}

/// Why the displaced reference could not be built.
#[derive(Debug, thiserror::Error)]
pub enum DisplacedReferenceError {
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
    /// The edge length asked for is not a positive number.
    #[error("the displaced reference's texels per edge must be a positive number, got {0}")]
    BadTexelsPerEdge(f64),
    /// A mesh would need more triangles than [`MAX_TRIANGLES`].
    #[error(
        "the displaced reference of mesh {mesh:?} needs {levels} subdivisions ({triangles} triangles, \
         more than {limit}) to bring its longest edge of {longest:.0} texels to {texels_per_edge}; \
         ask for longer edges"
    )]
    TooFine {
        /// The mesh's name.
        mesh: String,
        /// Subdivisions it would need.
        levels: u32,
        /// Triangles it would have.
        triangles: u128,
        /// [`MAX_TRIANGLES`].
        limit: usize,
        /// Its longest edge, in height texels.
        longest: f64,
        /// The edge length asked for.
        texels_per_edge: f64,
    },
    /// A relief material's heights could not be read.
    #[error(transparent)]
    Heights(#[from] MaterialHeightsError),
}

/// Each relief mesh of `scene` (its index) with its material's relief and heights; materials
/// reading the frame's height map read `frame_heights` with `frame_address`.
pub fn relief_lookups(
    scene: &Scene,
    frame_heights: Option<&Heightfield>,
    frame_address: Address,
) -> Result<Vec<(usize, Relief, HeightLookup)>, DisplacedReferenceError> {
    let mut heights = MaterialHeights::new(scene, frame_heights, frame_address);
    let mut out = Vec::new();
    for (index, mesh) in scene.meshes.iter().enumerate() {
        let material = scene.materials.get(mesh.material).ok_or_else(|| {
            DisplacedReferenceError::NoMaterial {
                mesh: mesh.name.clone(),
                material: mesh.material,
                count: scene.materials.len(),
            }
        })?;
        if let Some(relief) = material.relief {
            out.push((index, relief, heights.of(material, relief.height)?));
        }
    }
    Ok(out)
}

/// `scene` with every relief mesh displaced (edges of at most `texels_per_edge` height texels)
/// and every material's relief taken off. Materials reading the frame's height map read
/// `frame_heights` with `frame_address`.
pub fn displaced_scene(
    scene: &Scene,
    frame_heights: Option<&Heightfield>,
    frame_address: Address,
    texels_per_edge: f64,
) -> Result<DisplacedScene, DisplacedReferenceError> {
    if !(texels_per_edge.is_finite() && texels_per_edge > 0.0) {
        return Err(DisplacedReferenceError::BadTexelsPerEdge(texels_per_edge));
    }
    let mut out = scene.clone();
    let mut report = Vec::new();
    for (index, relief, lookup) in relief_lookups(scene, frame_heights, frame_address)? {
        let mesh = &scene.meshes[index];
        let size = [lookup.heights.width(), lookup.heights.height()];
        let (levels, longest) = levels_for(mesh, &lookup.uv, size, texels_per_edge);
        let triangles = (mesh.indices.len() / 3) as u128 * 4u128.saturating_pow(levels);
        if triangles > MAX_TRIANGLES as u128 {
            return Err(DisplacedReferenceError::TooFine {
                mesh: mesh.name.clone(),
                levels,
                triangles,
                limit: MAX_TRIANGLES,
                longest,
                texels_per_edge,
            });
        }
        out.meshes[index] = displace(&subdivide(mesh, levels), &lookup, relief.depth_scale);
        report.push(DisplacedMesh {
            name: mesh.name.clone(),
            levels,
            triangles: triangles as usize,
            longest_edge_texels: longest,
        });
    }
    for material in &mut out.materials {
        material.relief = None;
    }
    Ok(DisplacedScene {
        scene: out,
        meshes: report,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::Method;
    use crate::scene::{quad_mesh, sphere_mesh, Material, Relief};

    fn relief_scene(mesh: crate::geometry::Mesh) -> Scene {
        Scene {
            meshes: vec![mesh],
            materials: vec![Material {
                relief: Some(Relief::new(0.05, Method::QDM)),
                ..Material::default()
            }],
            ..Scene::default()
        }
    }

    #[test]
    fn relief_meshes_are_subdivided_to_the_edge_asked_for_and_lose_their_relief() {
        let heights = Heightfield::new(32, 32, vec![0.5; 32 * 32]).expect("a field");
        let scene = relief_scene(sphere_mesh("ball", 1.0, 8, 16, 0));
        let out = displaced_scene(&scene, Some(&heights), Address::Repeat, 2.0).expect("displaces");
        let m = &out.meshes[0];
        // The longest edge (a diagonal of a 2 x 4 texel cell) halves each level down to 2.
        assert!(
            m.longest_edge_texels / f64::from(1u32 << m.levels) <= 2.0,
            "{m:?}"
        );
        assert!(
            m.longest_edge_texels / f64::from(1u32 << (m.levels - 1)) > 2.0,
            "{m:?}"
        );
        assert_eq!(out.scene.meshes[0].indices.len() / 3, m.triangles);
        assert!(out.scene.materials[0].relief.is_none());
        // Half the depth of a depth unit (pi * sqrt 2 here) under the unit sphere's polygons.
        let sunk = 0.05 * 0.5 * std::f64::consts::PI * 2f64.sqrt();
        let r = glam::Vec3::from(out.scene.meshes[0].vertices[100].position).length();
        let polygon_r = 1.0; // vertices of the original sit on the unit sphere
        assert!(f64::from(r) < polygon_r - sunk * 0.9, "{r}");
    }

    #[test]
    fn bad_requests_are_refused_by_name() {
        let heights = Heightfield::new(4096, 1, vec![0.5; 4096]).expect("a field");
        let scene = relief_scene(quad_mesh("wide floor", 1.0, 1.0, 1.0, 0));
        let err = |r: Result<DisplacedScene, DisplacedReferenceError>| {
            r.expect_err("refused").to_string()
        };
        let zero = err(displaced_scene(
            &scene,
            Some(&heights),
            Address::Repeat,
            0.0,
        ));
        assert!(zero.contains("positive"), "{zero}");
        let none = err(displaced_scene(&scene, None, Address::Repeat, 1.0));
        assert!(none.contains("frame height map"), "{none}");
        let fine = err(displaced_scene(
            &scene,
            Some(&heights),
            Address::Repeat,
            0.01,
        ));
        assert!(
            fine.contains("wide floor") && fine.contains("triangles"),
            "{fine}"
        );
    }
}
