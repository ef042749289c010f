//! Ray queries (`VK_KHR_ray_query`) through the scene: its triangles in one bottom-level
//! acceleration structure, its relief triangles' prisms as boxes in another whose candidates the
//! shader resolves with the exact height-field walk, both in one top level (`traced_scene`);
//! batches of occlusion rays traced through it (`occlusion_pass`). Checked against the exact CPU
//! scene reference, whose relief solid (`shadow_reference::relief_shell`) the prism test copies.

pub mod occlusion_pass;
pub mod prism_records;
pub mod traced_scene;
