//! The render outputs (AOVs) `relief render` writes beside the beauty: which layers there are,
//! their OpenEXR channels, and the 16-bit PNGs of the scalar ones. Every layer comes from the
//! surface pass's G-buffer (`GBufferChannels`); position is unprojected from the depth, and the
//! material from the object through the scene.

use std::fmt;

use clap::ValueEnum;
use exr::prelude::{AnyChannel, FlatSamples};
use relief::render::GBufferChannels;
use relief::scene::Camera;

/// One render output.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, ValueEnum)]
pub enum Layer {
    /// Z: linear view depth of the displaced hit, along the camera's axis, scene units.
    Depth,
    /// P.X, P.Y, P.Z: world position, unprojected from the depth.
    Position,
    /// N.X, N.Y, N.Z: world-space shading normal.
    Normal,
    /// uv.U, uv.V: texture coordinates (set 0) at the traced hit.
    Uv,
    /// albedo.R, albedo.G, albedo.B: linear base colour at the hit.
    Albedo,
    /// material: the glTF material index + 1 (0 where nothing was drawn).
    Material,
    /// id: the scene mesh index + 1 (0 where nothing was drawn).
    Object,
    /// steps: the view ray's steps through its height field.
    Steps,
    /// shadow: the share of the direct light no shadow blocked.
    Shadow,
    /// ao: the ambient occlusion the ambient light was darkened by.
    Ao,
    /// coverage: the share of the pixel's samples a surface covered.
    Coverage,
    /// motion.X, motion.Y: screen motion since the previous frame, pixels (x right, y down).
    Motion,
}

impl Layer {
    /// Every layer, in the order above.
    pub const ALL: [Layer; 12] = [
        Layer::Depth,
        Layer::Position,
        Layer::Normal,
        Layer::Uv,
        Layer::Albedo,
        Layer::Material,
        Layer::Object,
        Layer::Steps,
        Layer::Shadow,
        Layer::Ao,
        Layer::Coverage,
        Layer::Motion,
    ];

    /// Whether the layer is one number per pixel, written as a 16-bit PNG on request.
    pub fn scalar(self) -> bool {
        !matches!(
            self,
            Layer::Position | Layer::Normal | Layer::Uv | Layer::Albedo | Layer::Motion
        )
    }
}

impl fmt::Display for Layer {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let name = self
            .to_possible_value()
            .map(|v| v.get_name().to_owned())
            .unwrap_or_default();
        f.write_str(&name)
    }
}

/// What a frame's layers are read from.
pub struct LayerSource<'a> {
    pub gbuffer: &'a GBufferChannels,
    pub camera: &'a Camera,
    /// Each scene mesh's material index.
    pub mesh_materials: &'a [usize],
}

impl LayerSource<'_> {
    /// `layer`'s OpenEXR channels (32-bit float, or unsigned integer for ids and counts).
    pub fn channels(&self, layer: Layer) -> Vec<AnyChannel<FlatSamples>> {
        let g = self.gbuffer;
        let float = |name: &str, values: Vec<f32>| AnyChannel::new(name, FlatSamples::F32(values));
        let uint = |name: &str, values: Vec<u32>| AnyChannel::new(name, FlatSamples::U32(values));
        fn component<const N: usize>(values: &[[f32; N]], c: usize) -> Vec<f32> {
            values.iter().map(|v| v[c]).collect()
        }
        match layer {
            Layer::Depth => vec![float("Z", g.depth.clone())],
            Layer::Position => {
                let p = g.positions(self.camera);
                vec![
                    float("P.X", component(&p, 0)),
                    float("P.Y", component(&p, 1)),
                    float("P.Z", component(&p, 2)),
                ]
            }
            Layer::Normal => vec![
                float("N.X", component(&g.normal, 0)),
                float("N.Y", component(&g.normal, 1)),
                float("N.Z", component(&g.normal, 2)),
            ],
            Layer::Uv => vec![
                float("uv.U", component(&g.uv, 0)),
                float("uv.V", component(&g.uv, 1)),
            ],
            Layer::Albedo => vec![
                float("albedo.R", component(&g.albedo, 0)),
                float("albedo.G", component(&g.albedo, 1)),
                float("albedo.B", component(&g.albedo, 2)),
            ],
            Layer::Material => vec![uint("material", self.materials())],
            Layer::Object => vec![uint("id", g.mesh.clone())],
            Layer::Steps => vec![uint("steps", g.steps.clone())],
            Layer::Shadow => vec![float("shadow", g.shadow.clone())],
            Layer::Ao => vec![float("ao", g.ao.clone())],
            Layer::Coverage => vec![float("coverage", g.coverage.clone())],
            Layer::Motion => vec![
                float("motion.X", component(&g.motion, 0)),
                float("motion.Y", component(&g.motion, 1)),
            ],
        }
    }

    /// A scalar `layer` as 16-bit values: depth from the near plane (0) to the far one (65535,
    /// also where nothing was drawn), ids and step counts as they are (saturated at 65535), the
    /// others' 0..1 range spread over 0..65535. `None` for a layer of several channels.
    pub fn png_values(&self, layer: Layer) -> Option<Vec<u16>> {
        let g = self.gbuffer;
        let unit = |values: &[f32]| values.iter().map(|&v| unit_to_u16(v)).collect();
        let count = |values: &[u32]| values.iter().map(|&v| v.min(65535) as u16).collect();
        Some(match layer {
            Layer::Depth => {
                let (near, far) = self.camera.near_far();
                let span = (far - near).max(f32::MIN_POSITIVE);
                g.depth
                    .iter()
                    .map(|&z| {
                        unit_to_u16(if z.is_finite() {
                            (z - near) / span
                        } else {
                            1.0
                        })
                    })
                    .collect()
            }
            Layer::Material => count(&self.materials()),
            Layer::Object => count(&g.mesh),
            Layer::Steps => count(&g.steps),
            Layer::Shadow => unit(&g.shadow),
            Layer::Ao => unit(&g.ao),
            Layer::Coverage => unit(&g.coverage),
            Layer::Position | Layer::Normal | Layer::Uv | Layer::Albedo | Layer::Motion => {
                return None
            }
        })
    }

    /// Each pixel's material index + 1, 0 where nothing was drawn.
    fn materials(&self) -> Vec<u32> {
        self.gbuffer
            .mesh
            .iter()
            .map(|&id| match id.checked_sub(1) {
                Some(mesh) => self
                    .mesh_materials
                    .get(mesh as usize)
                    .map_or(0, |&m| m as u32 + 1),
                None => 0,
            })
            .collect()
    }
}

fn unit_to_u16(v: f32) -> u16 {
    let v = if v.is_finite() {
        v.clamp(0.0, 1.0)
    } else {
        0.0
    };
    (v * 65535.0).round() as u16
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn two_pixels() -> GBufferChannels {
        GBufferChannels {
            width: 2,
            height: 1,
            depth: vec![5.5, f32::INFINITY],
            normal: vec![[0.0, 0.0, 1.0], [0.0; 3]],
            coverage: vec![1.0, 0.0],
            uv: vec![[0.25, 0.5], [0.0; 2]],
            mesh: vec![2, 0],
            steps: vec![70_000, 0],
            albedo: vec![[0.5, 0.25, 1.0], [0.0; 3]],
            ao: vec![0.5, 0.0],
            shadow: vec![1.0, 0.0],
            motion: vec![[1.5, -2.0], [0.0; 2]],
        }
    }

    #[test]
    fn every_layer_has_its_channels_and_scalar_ones_their_png() {
        let g = two_pixels();
        let camera = Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 0.8, 1.0, 11.0);
        let source = LayerSource {
            gbuffer: &g,
            camera: &camera,
            mesh_materials: &[0, 3],
        };
        for layer in Layer::ALL {
            let channels = source.channels(layer);
            assert!(!channels.is_empty(), "{layer}");
            assert_eq!(
                source.png_values(layer).is_some(),
                layer.scalar(),
                "{layer}"
            );
            assert_eq!(layer.scalar(), channels.len() == 1, "{layer}");
        }
        assert_eq!(source.materials(), [4, 0]);
        // Depth 5.5 lies halfway from the near plane (1) to the far one (11).
        assert_eq!(
            source.png_values(Layer::Depth),
            Some(vec![29491, 65535]),
            "(5.5 - 1) / 10 * 65535 rounds to 29491"
        );
        assert_eq!(source.png_values(Layer::Steps), Some(vec![65535, 0]));
        assert_eq!(source.png_values(Layer::Ao), Some(vec![32768, 0]));
        assert_eq!(Layer::Motion.to_string(), "motion");
    }
}
