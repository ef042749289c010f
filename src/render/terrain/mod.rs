//! Terrain editing: the blended pyramid of layered materials, elevation brush edits and layer painting with partial rebuilds.

pub(in crate::render) mod blended_pyramid_pass;
pub(in crate::render) mod elevation_editor;
pub(in crate::render) mod layer_paint;
pub(in crate::render) mod layer_set;
pub(in crate::render) mod layered_heights;
