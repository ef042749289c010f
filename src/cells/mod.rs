//! Relief mapping on cubic cell complexes (Apaza and Andújar, paper 002): a closed mesh is replaced by the grey
//! cells of an N^3 grid over its bounding cube, each carrying distance maps on its domain faces. No Vulkan here.
//!
//! Built so far: the checked closed mesh ([`mesh`]), the grid and its cells' colours ([`grid`]), the cells' face
//! configurations and their ten base cases ([`case`]), each case's projection of the cell onto its domain faces
//! with its inverse ([`projection`]), the distance maps sampled on the CPU with the overlap ratio that picks the
//! grid size ([`distance_map`]), rays marched through the complex ([`trace`]) and measured against exact
//! ray/triangle intersection ([`measure`]), the layout the GPU march reads ([`packed`]), the surface's attributes on
//! the maps' texels ([`attributes`]) and the surface rebuilt from the maps ([`reconstruct`]). The renderer's pass
//! that draws a complex is `render::cells_pass`.

pub mod attributes;
pub mod case;
pub mod distance_map;
pub mod grid;
pub mod measure;
pub mod mesh;
pub mod packed;
mod parallel;
pub mod projection;
pub mod reconstruct;
pub mod scene_mesh;
pub mod trace;

pub use attributes::{attribute_maps, AttributeTexel, SurfaceAttributes};
pub use case::{Axis, Case, Face, FaceSet};
pub use distance_map::{
    choose_grid, choose_grid_within, fixed_grid, sampled_bytes, CellMaps, FaceMap, GridStop,
    GridTooLarge, SurfacePoint, MAP_MEMORY_LIMIT,
};
pub use grid::{CellGrid, CellIndex, Colour};
pub use measure::{compare_hits, measure_hits, parallel_rays, HitAgreement, RayOutcome};
pub use mesh::{shapes, ClosedMesh, MeshError};
pub use packed::{GreyRecord, PackedComplex};
pub use projection::{domain_faces, Image, Projection};
pub use reconstruct::{rebuild, RebuiltMesh};
pub use scene_mesh::{MeshSelection, SceneMesh};
pub use trace::{exact_hits, CellComplex, CellHit, MarchSettings};
