//! The GPU's copy of a relief triangle's frame: one record per prism, as
//! `shaders/include/relief_prism.glsl` reads it.

use bytemuck::{Pod, Zeroable};

use crate::shadow_reference::relief_shell::ShellFrame;

/// One relief prism, 80 bytes, std430.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct PrismRecord {
    /// Rows of the affine map from a world point to (height u, height v, depth).
    pub to_local: [[f32; 4]; 3],
    /// Columns of the map from a height-uv offset to the weights of corners 1 and 2.
    pub to_bary: [f32; 4],
    /// xy: height uv of corner 0; z: the depth scale; w: unused.
    pub anchor: [f32; 4],
}

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_record_is_the_shaders_eighty_bytes() {
        assert_eq!(std::mem::size_of::<PrismRecord>(), 80);
    }
}
