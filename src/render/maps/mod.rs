//! Offline map builders on the GPU: the max and mean pyramids, cone, relaxed cone and quadric maps, the texture-space AO map, and the search they share.

pub(in crate::render) mod ao_influence;
pub(in crate::render) mod ao_map_pass;
pub(in crate::render) mod ao_sweep;
pub(in crate::render) mod cone_map_pass;
pub(in crate::render) mod map_builder;
pub(in crate::render) mod map_builder_pass;
pub(in crate::render) mod map_search;
pub(in crate::render) mod mean_pyramid_pass;
pub(in crate::render) mod pyramid_pass;
pub(in crate::render) mod quadric_map_pass;
pub(in crate::render) mod relaxed_cone_map_pass;
