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
        if let Some(encoded) = encoded_bytes(image.source(), base, buffers) {
            held_to_its_bytes(&encoded)
                .map_err(|e| format!("image {} ({name}): {e}", image.index()))?;
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

/// The image's encoded bytes, where they can be had before the gltf crate decodes them: a
/// buffer view (already checked to lie inside its buffer), a base64 data URI, or a file beside
/// the glTF. `None` leaves the image to the gltf crate and its errors.
fn encoded_bytes(
    source: gltf::image::Source,
    base: &Path,
    buffers: &[gltf::buffer::Data],
) -> Option<Vec<u8>> {
    match source {
        gltf::image::Source::View { view, .. } => {
            let data = &buffers.get(view.buffer().index())?.0;
            data.get(view.offset()..view.offset() + view.length())
                .map(<[u8]>::to_vec)
        }
        gltf::image::Source::Uri { uri, .. } => match uri.strip_prefix("data:") {
            Some(rest) => rest.split_once(";base64,").and_then(|(_, b64)| base64(b64)),
            None => std::fs::read(base.join(uri)).ok(),
        },
    }
}

/// Standard base64 (padding optional); `None` on any other character.
fn base64(text: &str) -> Option<Vec<u8>> {
    let value = |c: u8| -> Option<u32> {
        Some(match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return None,
        } as u32)
    };
    let digits = text.trim_end_matches('=').as_bytes();
    let mut out = Vec::with_capacity(digits.len() / 4 * 3 + 2);
    for group in digits.chunks(4) {
        let mut word = 0u32;
        for (k, &c) in group.iter().enumerate() {
            word |= value(c)? << (18 - 6 * k);
        }
        let bytes = word.to_be_bytes();
        out.extend_from_slice(&bytes[1..group.len()]);
    }
    Some(out)
}

/// Refuses an image whose header claims more pixel bytes than its encoded bytes can expand to.
/// The decoders allocate the whole claimed image before reading the data, so a 200-byte PNG
/// claiming 11000 x 11000 pixels would cost 480 MB before failing. Deflate (PNG) expands at
/// most 1032 times; baseline JPEG spends at least about 2 bits on each 8 x 8 block of each of
/// its components, which stays within that bound too.
fn held_to_its_bytes(encoded: &[u8]) -> Result<(), String> {
    const MAX_EXPANSION: u64 = 1032;
    let Ok(reader) = image::ImageReader::new(std::io::Cursor::new(encoded)).with_guessed_format()
    else {
        return Ok(());
    };
    // An undecodable header is the gltf crate's to report, in its words.
    let Ok(decoder) = reader.into_decoder() else {
        return Ok(());
    };
    let (width, height) = image::ImageDecoder::dimensions(&decoder);
    let claimed = image::ImageDecoder::total_bytes(&decoder);
    let most = MAX_EXPANSION * encoded.len() as u64 + (64 << 10);
    if claimed > most {
        return Err(format!(
            "its header claims {width}x{height} pixels ({claimed} bytes), more than its {} \
             encoded bytes can hold",
            encoded.len()
        ));
    }
    Ok(())
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
    fn base64_decodes_with_and_without_padding_and_refuses_other_characters() {
        assert_eq!(base64("aGVsbG8=").unwrap(), b"hello");
        assert_eq!(base64("aGVsbG8").unwrap(), b"hello");
        assert_eq!(base64("aGk=").unwrap(), b"hi");
        assert_eq!(base64("").unwrap(), b"");
        assert!(base64("aG!s").is_none());
    }

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
