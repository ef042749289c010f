//! The GPU's copy of a relief triangle's frame: one record per prism, made from the CPU
//! reference's frame (the record's layout is in `shader_interface`).

pub use crate::render::shader_interface::PrismRecord;
use crate::shadow_reference::relief_shell::ShellFrame;

impl From<&ShellFrame> for PrismRecord {
    fn from(f: &ShellFrame) -> Self {
        let row = |r: [f64; 4]| r.map(|x| x as f32);
        PrismRecord {
            to_local: f.to_local.map(row),
            to_bary: [
                f.to_bary[0][0] as f32,
                f.to_bary[0][1] as f32,
                f.to_bary[1][0] as f32,
                f.to_bary[1][1] as f32,
            ],
            anchor: [
                f.anchor_uv[0] as f32,
                f.anchor_uv[1] as f32,
                f.depth_scale as f32,
                0.0,
            ],
        }
    }
}
