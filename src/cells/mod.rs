//! Relief mapping on cubic cell complexes (Apaza and Andújar): a closed mesh is replaced by the grey
//! cells of an N^3 grid over its bounding cube, each carrying distance maps on its domain faces. No Vulkan here.
//!
//! Built so far: the checked closed mesh ([`mesh`]), the grid and its cells' colours ([`grid`]), the cells' face
//! configurations and their ten base cases ([`case`]), each case's projection of the cell onto its domain faces
//! with its inverse ([`projection`]), the distance maps sampled on the CPU with the overlap ratio that picks the
//! grid size ([`distance_map`]), rays marched through the complex ([`trace`]) and measured against exact
//! ray/triangle intersection ([`measure`]), the layout the GPU march reads ([`packed`]), the triangle each texel's
//! line meets ([`surface_triangles`]) with the triangles' corners the pass shades from ([`attributes`]) and the
//! surface rebuilt from the maps ([`reconstruct`]). The renderer's pass
//! that draws a complex is `render::cells_pass`.
//!
//! Units: positions are in the mesh's own units (world space for a [`SceneMesh`]); inside a cell, points are
//! cell-local in the unit cube `[0, 1]^3` and distances (map texels, march errors) are in cell sides.
//!
//! # Main types
//! - [`ClosedMesh`] (or [`SceneMesh`] for a glTF scene's meshes): the checked input; [`MeshError`] says why a
//!   mesh is refused.
//! - [`CellGrid`]: the N^3 grid over the mesh's bounding cube with each cell's [`Colour`].
//! - [`Case`], [`FaceSet`] and [`Projection`]: how a grey cell is parameterized from its internal faces.
//! - [`CellMaps`] of [`FaceMap`]s: the sampled distance maps, with the overlap ratio.
//! - [`CellComplex`]: the CPU march; [`HitAgreement`] what [`measure_hits`] found against exact intersection.
//! - [`PackedComplex`], [`surface_triangle_maps`] and [`CornerAttributes`]: the buffers the GPU pass uploads.
//!
//! # How they fit together
//! Build a [`ClosedMesh`] with [`ClosedMesh::new`] (or a [`SceneMesh`]), let [`choose_grid`] double the grid
//! until the maps' overlap ratio is low enough (or fix N with [`fixed_grid`]), which returns the [`CellGrid`] and
//! its [`CellMaps`]; march rays on the CPU with [`CellComplex::new`] and [`CellComplex::march`], check them with
//! [`measure_hits`], or hand [`PackedComplex::new`], [`surface_triangle_maps`] and [`SceneMesh::corners`] to the renderer to draw the complex on
//! the GPU. [`rebuild`] turns the maps back into triangles to inspect what they hold.

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
pub mod surface_triangles;
pub mod trace;

pub use attributes::CornerAttributes;
pub use case::{Axis, Case, Face, FaceSet};
pub use distance_map::{
    choose_grid, choose_grid_within, fixed_grid, sampled_bytes, texel_size, CellMaps, FaceMap,
    GridStop, GridTooLarge, SurfacePoint, MAP_MEMORY_LIMIT,
};
pub use grid::{CellGrid, CellIndex, Colour};
pub use measure::{compare_hits, measure_hits, parallel_rays, HitAgreement, RayOutcome};
pub use mesh::{shapes, ClosedMesh, MeshError};
pub use packed::{GreyRecord, PackedComplex};
pub use projection::{domain_faces, Image, Projection};
pub use reconstruct::{rebuild, RebuiltMesh};
pub use scene_mesh::{MeshSelection, SceneMesh};
pub use surface_triangles::{surface_triangle_maps, NO_TRIANGLE};
pub use trace::{exact_hits, CellComplex, CellHit, MarchSettings};
