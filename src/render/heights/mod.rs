//! A height map's GPU side, kept across frames: its image and max pyramid, the method's
//! precomputed map, and the frame uniforms each frame slot binds with them.

pub(in crate::render) mod height_resources;
pub(in crate::render) mod method_map;
