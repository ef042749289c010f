//! The pass kit: what every pass folder shares and imports instead of the frame's orchestrator
//! (`frame`): the frame's formats and uniform block, the GPU height field, the depth-as-colour
//! target, a mesh's buffers and bounds, the tone curves, pass names and their timestamp scopes, the frame's timeline, and the
//! graph the frame's passes form.

pub(in crate::render) mod caster_draws;
pub(in crate::render) mod depth_as_colour;
pub(in crate::render) mod draw_push;
pub(in crate::render) mod formats;
pub(in crate::render) mod frame_timeline;
pub(in crate::render) mod frame_uniforms;
pub(in crate::render) mod gpu_heightfield;
pub(in crate::render) mod graph;
pub(in crate::render) mod hard_shadow;
pub(in crate::render) mod mesh_buffers;
pub(in crate::render) mod pass;
pub(in crate::render) mod pass_timer;
pub(in crate::render) mod render_error;
pub(in crate::render) mod set_layouts;
pub(in crate::render) mod shadow_mode_value;
pub(in crate::render) mod texture_mips;
pub(in crate::render) mod tone_curves;
