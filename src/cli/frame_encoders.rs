//! A read-back frame encoded as the bytes of one file: the 8-bit sRGB PNG the GPU tone mapped,
//! a 16-bit sRGB PNG tone mapped here from the linear radiance, or the radiance as a Radiance
//! `.hdr`. Encoding to memory lets every file be written whole under a temporary name first
//! (`frame_files`).

use std::io::Cursor;

use anyhow::Context as _;
use image::{ExtendedColorType, ImageFormat};
use relief::render::{FrameOutput, ToneMapping};

/// `frame`'s tone-mapped colours as an 8-bit PNG; `None` when the frame was not read back.
pub fn png8(frame: &FrameOutput) -> anyhow::Result<Option<Vec<u8>>> {
    let Some(rgba) = &frame.rgba else {
        return Ok(None);
    };
    encode(rgba, frame, ExtendedColorType::Rgba8, ImageFormat::Png).map(Some)
}

/// `frame`'s radiance tone mapped on the CPU with `tone` (the curve the GPU applies) and
/// encoded as 16-bit sRGB: the steps of an 8-bit frame are 257 times finer. `None` when the
/// radiance was not read back.
pub fn png16(frame: &FrameOutput, tone: &ToneMapping) -> anyhow::Result<Option<Vec<u8>>> {
    let Some(radiance) = &frame.radiance else {
        return Ok(None);
    };
    let scale = 2f32.powf(tone.exposure_ev);
    let texels: Vec<u16> = radiance
        .iter()
        .flat_map(|p| {
            let [r, g, b] = tone.curve.apply([p[0], p[1], p[2]].map(|c| c * scale));
            let alpha = if p[3].is_finite() {
                p[3].clamp(0.0, 1.0)
            } else {
                0.0
            };
            [encode_srgb(r), encode_srgb(g), encode_srgb(b), alpha].map(to_u16)
        })
        .collect();
    encode(
        bytemuck::cast_slice(&texels),
        frame,
        ExtendedColorType::Rgba16,
        ImageFormat::Png,
    )
    .map(Some)
}

/// `frame`'s linear radiance (RGB, alpha dropped; negative and non-finite values as 0) as a
/// Radiance `.hdr`; `None` when the radiance was not read back.
pub fn hdr(frame: &FrameOutput) -> anyhow::Result<Option<Vec<u8>>> {
    let Some(radiance) = &frame.radiance else {
        return Ok(None);
    };
    let rgb: Vec<f32> = radiance
        .iter()
        .flat_map(|p| [p[0], p[1], p[2]].map(|c| if c.is_finite() { c.max(0.0) } else { 0.0 }))
        .collect();
    encode(
        bytemuck::cast_slice(&rgb),
        frame,
        ExtendedColorType::Rgb32F,
        ImageFormat::Hdr,
    )
    .map(Some)
}

/// `width` x `height` 16-bit values as a greyscale PNG.
pub fn grey16(values: &[u16], width: u32, height: u32) -> anyhow::Result<Vec<u8>> {
    let mut bytes = Vec::new();
    image::write_buffer_with_format(
        &mut Cursor::new(&mut bytes),
        bytemuck::cast_slice(values),
        width,
        height,
        ExtendedColorType::L16,
        ImageFormat::Png,
    )
    .context("encoding a 16-bit PNG")?;
    Ok(bytes)
}

fn encode(
    texels: &[u8],
    frame: &FrameOutput,
    colour: ExtendedColorType,
    format: ImageFormat,
) -> anyhow::Result<Vec<u8>> {
    let mut bytes = Vec::new();
    image::write_buffer_with_format(
        &mut Cursor::new(&mut bytes),
        texels,
        frame.width,
        frame.height,
        colour,
        format,
    )
    .with_context(|| format!("encoding the frame as {format:?}"))?;
    Ok(bytes)
}

/// The sRGB transfer function, as the GPU applies it when it writes the 8-bit sRGB frame.
fn encode_srgb(linear: f32) -> f32 {
    relief::srgb::encode(linear.clamp(0.0, 1.0))
}

fn to_u16(v: f32) -> u16 {
    (v.clamp(0.0, 1.0) * 65535.0).round() as u16
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_srgb_curve_meets_its_ends_and_its_linear_toe() {
        assert_eq!(encode_srgb(0.0), 0.0);
        assert!((encode_srgb(1.0) - 1.0).abs() < 1e-6);
        assert!((encode_srgb(0.002) - 0.002 * 12.92).abs() < 1e-7);
        // Mid grey (18%) sits near 46% of the code range.
        assert!((encode_srgb(0.18) - 0.4614).abs() < 1e-3);
        // The two pieces meet.
        let knee = 0.003_130_8;
        assert!((encode_srgb(knee) - encode_srgb(knee + 1e-7)).abs() < 1e-5);
    }

    #[test]
    fn a_16_bit_png_decodes_to_its_values() {
        let values = [0, 1, 256, 32768, 65534, 65535];
        let bytes = grey16(&values, 3, 2).expect("encodes");
        let decoded = image::load_from_memory(&bytes)
            .expect("decodes")
            .to_luma16();
        assert_eq!(decoded.as_raw().as_slice(), &values);
    }
}
