//! Scene shadows: a shadow map for every shadow-casting light (cascades for directional lights,
//! a perspective map for spots, a cube for points), rendered each frame into one depth atlas,
//! relief materials casting their displaced surface (traced from the light with their method),
//! and read by the surface pass at each relief hit with PCSS (`shaders/include/scene_shadows.glsl`).
//!
//! - `shadow_plan`: which lights get a map, of what kind, size and filter, and who casts;
//! - `light_views`: the views' matrices (cascades fitted to the camera and texel-snapped);
//! - `frame_views`: a frame's views written into its uniforms;
//! - `shadow_atlas`: the depth image and its tiles;
//! - `shadow_pass`: the recording, one timestamp scope per map.

pub(in crate::render) mod frame_views;
pub(in crate::render) mod light_views;
pub(in crate::render) mod shadow_atlas;
pub(in crate::render) mod shadow_pass;
pub(in crate::render) mod shadow_plan;
