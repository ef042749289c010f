//! Images of a glTF file, decoded and turned back into `image::DynamicImage`s.

use std::path::Path;
use std::sync::Arc;

use gltf::image::Format;
use image::{DynamicImage, ImageBuffer};

use super::SceneImage;

/// Decodes every image in glTF order, so texture `source` indices stay valid.
pub(super) fn load_images(
    doc: &gltf::Document,
    base: &Path,
    buffers: &[gltf::buffer::Data],
) -> Result<Vec<SceneImage>, String> {
    let mut images = Vec::new();
    for image in doc.images() {
        let name = match image.source() {
            gltf::image::Source::Uri { uri, .. } if !uri.starts_with("data:") => uri.to_owned(),
            _ => format!("embedded #{}", image.index()),
        };
        if let gltf::image::Source::View { view, .. } = image.source() {
            if view.stride().is_some() {
                return Err(format!(
                    "image {}: its bufferView has a byteStride",
                    image.index()
                ));
            }
        }
        let data = gltf::image::Data::from_source(image.source(), Some(base), buffers)
            .map_err(|e| format!("image {} ({name}): {e}", image.index()))?;
        let pixels = to_dynamic(data).ok_or_else(|| {
            format!(
                "image {} ({name}): pixel data does not match its size",
                image.index()
            )
        })?;
        images.push(SceneImage {
            name,
            pixels: Arc::new(pixels),
        });
    }
    Ok(images)
}

/// `None` when the pixel buffer is too short for the stated size (not expected from a decoder,
/// but `from_raw` checks it, so there is no panic to fear).
pub(super) fn to_dynamic(data: gltf::image::Data) -> Option<DynamicImage> {
    let (w, h, px) = (data.width, data.height, data.pixels);
    // 16- and 32-bit pixels come in native byte order (the gltf crate copies the decoder's
    // buffers byte for byte).
    let u16s = |px: &[u8]| -> Vec<u16> {
        px.chunks_exact(2)
            .map(|b| u16::from_ne_bytes([b[0], b[1]]))
            .collect()
    };
    let f32s = |px: &[u8]| -> Vec<f32> {
        px.chunks_exact(4)
            .map(|b| f32::from_ne_bytes([b[0], b[1], b[2], b[3]]))
            .collect()
    };
    Some(match data.format {
        Format::R8 => DynamicImage::ImageLuma8(ImageBuffer::from_raw(w, h, px)?),
        Format::R8G8 => DynamicImage::ImageLumaA8(ImageBuffer::from_raw(w, h, px)?),
        Format::R8G8B8 => DynamicImage::ImageRgb8(ImageBuffer::from_raw(w, h, px)?),
        Format::R8G8B8A8 => DynamicImage::ImageRgba8(ImageBuffer::from_raw(w, h, px)?),
        Format::R16 => DynamicImage::ImageLuma16(ImageBuffer::from_raw(w, h, u16s(&px))?),
        Format::R16G16 => DynamicImage::ImageLumaA16(ImageBuffer::from_raw(w, h, u16s(&px))?),
        Format::R16G16B16 => DynamicImage::ImageRgb16(ImageBuffer::from_raw(w, h, u16s(&px))?),
        Format::R16G16B16A16 => DynamicImage::ImageRgba16(ImageBuffer::from_raw(w, h, u16s(&px))?),
        Format::R32G32B32FLOAT => {
            DynamicImage::ImageRgb32F(ImageBuffer::from_raw(w, h, f32s(&px))?)
        }
        Format::R32G32B32A32FLOAT => {
            DynamicImage::ImageRgba32F(ImageBuffer::from_raw(w, h, f32s(&px))?)
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sixteen_bit_pixels_keep_their_values() {
        let px: Vec<u8> = [1000u16, 65535]
            .iter()
            .flat_map(|v| v.to_ne_bytes())
            .collect();
        let data = gltf::image::Data {
            pixels: px,
            format: Format::R16,
            width: 2,
            height: 1,
        };
        let img = to_dynamic(data).unwrap().into_luma16();
        assert_eq!(img.into_raw(), vec![1000, 65535]);
    }
}
