//! `relief render --exr-out` (or `--out FILE.exr`): a frame as one OpenEXR file, the linear
//! radiance beside the surface pass's G-buffer, every channel 32 bits, with the camera in its
//! header.

use std::path::Path;

use anyhow::Context as _;
use exr::meta::attribute::{AttributeValue, Text};
use exr::prelude::{AnyChannel, AnyChannels, FlatSamples, Image, WritableImage};
use glam::Mat4;
use relief::render::FrameOutput;
use relief::scene::Camera;

/// The header attribute holding relief's own view-projection (column-major, right-handed
/// world, Vulkan clip space: y down, depth 0 to 1), beside the standard `worldToCamera`.
pub const VIEW_PROJECTION_ATTRIBUTE: &str = "reliefViewProjection";

/// Whether `path` names an OpenEXR file.
pub fn is_exr(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"))
}

/// Writes `frame`'s radiance and G-buffer (both read back) to `out`, seen by `camera`; nothing
/// when either is missing.
pub fn write_exr(frame: &FrameOutput, out: &Path, camera: &Camera) -> anyhow::Result<()> {
    let (Some(radiance), Some(g)) = (&frame.radiance, &frame.gbuffer) else {
        return Ok(());
    };
    if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let float = |name: &str, values: Vec<f32>| AnyChannel::new(name, FlatSamples::F32(values));
    let uint = |name: &str, values: Vec<u32>| AnyChannel::new(name, FlatSamples::U32(values));
    let rgba = |c: usize| radiance.iter().map(|p| p[c]).collect::<Vec<f32>>();
    let normal = |c: usize| g.normal.iter().map(|n| n[c]).collect::<Vec<f32>>();
    let uv = |c: usize| g.uv.iter().map(|t| t[c]).collect::<Vec<f32>>();
    let positions = g.positions(camera);
    let position = |c: usize| positions.iter().map(|p| p[c]).collect::<Vec<f32>>();
    let channels = vec![
        float("R", rgba(0)),
        float("G", rgba(1)),
        float("B", rgba(2)),
        float("A", rgba(3)),
        float("Z", g.depth.clone()),
        float("P.X", position(0)),
        float("P.Y", position(1)),
        float("P.Z", position(2)),
        float("N.X", normal(0)),
        float("N.Y", normal(1)),
        float("N.Z", normal(2)),
        float("coverage", g.coverage.clone()),
        float("uv.U", uv(0)),
        float("uv.V", uv(1)),
        uint("id", g.mesh.clone()),
        uint("steps", g.steps.clone()),
    ];
    let size = (frame.width as usize, frame.height as usize);
    let mut image = Image::from_channels(size, AnyChannels::sort(channels.into()));
    let attributes = &mut image.layer_data.attributes;
    // OpenEXR's camera space is left-handed, z forward: relief's view looks down -z. Imath
    // multiplies row vectors, so its row-major array is the column-major one of the matrix
    // that multiplies column vectors.
    let to_camera = Mat4::from_scale(glam::Vec3::new(1.0, 1.0, -1.0)) * camera.view;
    attributes.world_to_camera = Some(to_camera.to_cols_array());
    let aspect = frame.width as f32 / frame.height as f32;
    attributes.other.insert(
        Text::from(VIEW_PROJECTION_ATTRIBUTE),
        AttributeValue::Matrix4x4(camera.view_projection(aspect).to_cols_array()),
    );
    image
        .write()
        .to_file(out)
        .with_context(|| format!("writing {}", out.display()))
}
