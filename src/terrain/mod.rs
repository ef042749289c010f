//! Height-blended terrain (Drobot, section 1.7): up to four relief layers, each a height field,
//! blended per texel by weights into the one surface the methods trace. No Vulkan here.
//!
//! Which surface each blend mode defines, exactly ([`BlendMode`]): per texel of the layers, from the
//! layers' heights `h_k` and the weights `w_k` at that texel,
//!
//! - `alpha` (Listing 1.5): `sum(w_k h_k) / sum(w_k)` (0 where every weight is 0);
//! - `height` (Listing 1.6): the same surface, shaded with weights `h_k w_k / sum(h_k w_k)`, so that
//!   the higher material shows in the blend zone (sand in the cracks between stones);
//! - `height-intersect` (Listing 1.7): `max_k(w_k h_k)`, the highest weighted layer, shaded as
//!   `height`;
//!
//! then bilinear between texel centres like any height field ([`crate::heightfield`]'s conventions),
//! so the exact reference traces the blended field ([`blended_field`]) as it traces any other. A
//! layer whose weight is 1 where every other weight is 0 gives back its own heights bit for bit.
//!
//! [`tiled_stack`] puts a layered material's layers, each tiled, on the grid its blended field is
//! traced at; [`splat_from_rules`] weighs layers by altitude and slope where no splat map is painted.
//!
//! The built-in terrain scene, the tiled ground under one layered material, is built in the scene
//! module (`scene::terrain_scene`), above this one: the terrain knows meshes, not scenes.
//!
//! [`terrain_tiles`] makes the ground those layers lie on: a tiled grid mesh over an elevation
//! map.
//!
//! [`blended_pyramid`] bounds the blended surface from the layers' and the weights' max pyramids
//! without the blended field at full size: `max(x) * max(w) >= max(x * w)` (Drobot, 1.7.4) for
//! `height-intersect`, and the highest layer with any weight for the convex `alpha` blend.

mod blend;
mod blended_pyramid;
mod brush;
mod detail;
mod edit;
mod grid;
mod layers;
mod rules;
mod vertex_weights;

pub use blend::{blended_field, BlendMode};
pub use blended_pyramid::{blended_pyramid, least_sum_slack, node_bound};
pub use brush::{coarse_span, BrushKind, Stroke, StrokeError, StrokeTarget, TexelRect};
pub use detail::{tiled_stack, TiledLayer};
pub use edit::{TerrainEdit, TerrainEditor};
pub use grid::{terrain_tiles, GridOptions, TerrainGrid};
pub use layers::{LayerError, LayerStack, SplatMap, MAX_LAYERS};
pub use rules::{splat_from_rules, LayerRule, RuleWeights};
pub use vertex_weights::splat_from_vertex_colors;
