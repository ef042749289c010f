//! `relief render --exr-out` (or `--out FILE.exr`): a frame as one OpenEXR file, the linear
//! radiance beside the render outputs (`aov`), every channel 32 bits, with the camera and the
//! colour space in its header.

use std::io::Cursor;
use std::path::Path;

use anyhow::Context as _;
use exr::math::Vec2;
use exr::meta::attribute::{AttributeValue, Chromaticities, Text};
use exr::meta::header::LayerAttributes;
use exr::prelude::{AnyChannel, AnyChannels, FlatSamples, Image, WritableImage};
use glam::Mat4;
use relief::render::FrameOutput;
use relief::scene::{Camera, Projection};

use super::aov::{Layer, LayerSource};
use super::frame_files::FrameView;

/// The header attribute holding relief's own view-projection (column-major, right-handed
/// world, Vulkan clip space: y down, depth 0 to 1), beside the standard `worldToCamera`.
pub const VIEW_PROJECTION_ATTRIBUTE: &str = "reliefViewProjection";

/// Whether `path` names an OpenEXR file.
pub fn is_exr(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"))
}

/// `frame`'s radiance and the G-buffer's `layers` (both read back), seen by `camera`, as the
/// bytes of one OpenEXR file; `None` when either is missing.
pub fn encode_exr(
    frame: &FrameOutput,
    layers: &[Layer],
    view: &FrameView,
    tone_mapped: bool,
) -> anyhow::Result<Option<Vec<u8>>> {
    let (camera, mesh_materials) = (&view.camera, view.mesh_materials);
    let (Some(radiance), Some(gbuffer)) = (&frame.radiance, &frame.gbuffer) else {
        return Ok(None);
    };
    let source = LayerSource {
        gbuffer,
        camera,
        mesh_materials,
    };
    let scale = 2f32.powf(view.tone.exposure_ev);
    let beauty: Vec<[f32; 4]> = if tone_mapped {
        radiance
            .iter()
            .map(|p| {
                let [r, g, b] = view.tone.curve.apply([p[0], p[1], p[2]].map(|c| c * scale));
                [r, g, b, p[3]]
            })
            .collect()
    } else {
        radiance.clone()
    };
    let rgba = |c: usize| beauty.iter().map(|p| p[c]).collect::<Vec<f32>>();
    let mut channels: Vec<_> = ["R", "G", "B", "A"]
        .iter()
        .enumerate()
        .map(|(c, name)| AnyChannel::new(*name, FlatSamples::F32(rgba(c))))
        .collect();
    for &layer in layers {
        channels.extend(source.channels(layer));
    }
    let size = (frame.width as usize, frame.height as usize);
    let mut image = Image::from_channels(size, AnyChannels::sort(channels.into()));
    describe_camera(&mut image.layer_data.attributes, camera, frame);
    let beauty = if tone_mapped {
        format!(
            "R, G, B: tone mapped with {} at {:+} EV (display-referred, linear, not sRGB-encoded)",
            view.tone.curve, view.tone.exposure_ev
        )
    } else {
        "R, G, B: linear scene radiance, before exposure and tone mapping".to_owned()
    };
    image.layer_data.attributes.comments = Some(Text::from(beauty.as_str()));
    // The radiance is linear light in the sRGB / Rec. 709 primaries, white D65.
    image.attributes.chromaticities = Some(Chromaticities {
        red: Vec2(0.64, 0.33),
        green: Vec2(0.30, 0.60),
        blue: Vec2(0.15, 0.06),
        white: Vec2(0.3127, 0.3290),
    });
    let mut bytes = Vec::new();
    image
        .write()
        .to_buffered(Cursor::new(&mut bytes))
        .context("encoding the OpenEXR frame")?;
    Ok(Some(bytes))
}

/// The camera in the header: OpenEXR's standard attributes, and relief's own view-projection.
/// Only one attribute goes into `other`, a hash map, so that the header's bytes keep one order.
fn describe_camera(attributes: &mut LayerAttributes, camera: &Camera, frame: &FrameOutput) {
    // OpenEXR's camera space is left-handed, z forward: relief's view looks down -z. Imath
    // multiplies row vectors, so its row-major array is the column-major one of the matrix
    // that multiplies column vectors.
    let to_camera = Mat4::from_scale(glam::Vec3::new(1.0, 1.0, -1.0)) * camera.view;
    attributes.world_to_camera = Some(to_camera.to_cols_array());
    let (near, far) = camera.near_far();
    attributes.near_clip_plane = Some(near);
    attributes.far_clip_plane = Some(far);
    if let Projection::Perspective { yfov, .. } = camera.projection {
        attributes.vertical_field_of_view = Some(yfov.to_degrees());
    }
    attributes.software_name = Some(Text::from("relief"));
    let aspect = frame.width as f32 / frame.height as f32;
    attributes.other.insert(
        Text::from(VIEW_PROJECTION_ATTRIBUTE),
        AttributeValue::Matrix4x4(camera.view_projection(aspect).to_cols_array()),
    );
}
