//! Height maps from and to PNG files: 8- and 16-bit grey, grey + alpha, RGB and RGBA.
//!
//! Every source sample is first widened to 16 bits (8-bit `v` becomes `v * 257`, the image crate's exact
//! widening) and then divided by 65535, so an 8-bit `v` lands on exactly `v / 255` and 16-bit precision is never
//! lost. `invert` is applied on the 16-bit code (`65535 - x`), which keeps loaded heights exactly on the UNORM16
//! grid: [`Heightfield::quantized_unorm16`] of a loaded map is the map itself, so the CPU reference and the
//! GPU's `R16_UNORM` copy agree bit for bit.

use std::fmt;
use std::path::Path;
use std::str::FromStr;

use image::{DynamicImage, ImageBuffer, ImageFormat, Luma};

use super::{Heightfield, HeightfieldError};

/// Which part of an image holds the heights.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Channel {
    /// The grey value; for a colour image its luminance (the image crate's Rec. 709 weights).
    #[default]
    Luma,
    /// The red channel (the grey value for a grey image).
    R,
    /// The green channel (the grey value for a grey image).
    G,
    /// The blue channel (the grey value for a grey image).
    B,
    /// The alpha channel; an error for images without one.
    A,
}

impl Channel {
    /// Every channel, in the order their names are listed in messages.
    pub const ALL: [Channel; 5] = [
        Channel::Luma,
        Channel::R,
        Channel::G,
        Channel::B,
        Channel::A,
    ];

    /// The name used on the command line: `luma`, `r`, `g`, `b` or `a`.
    pub fn name(self) -> &'static str {
        match self {
            Channel::Luma => "luma",
            Channel::R => "r",
            Channel::G => "g",
            Channel::B => "b",
            Channel::A => "a",
        }
    }

    /// Index into an RGBA pixel, `None` for luma (which mixes channels).
    fn rgba_index(self) -> Option<usize> {
        match self {
            Channel::Luma => None,
            Channel::R => Some(0),
            Channel::G => Some(1),
            Channel::B => Some(2),
            Channel::A => Some(3),
        }
    }
}

impl fmt::Display for Channel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Channel {
    type Err = HeightfieldError;

    /// Parses a channel name exactly as [`Channel::name`] writes it.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Channel::ALL
            .into_iter()
            .find(|c| c.name() == s)
            .ok_or_else(|| HeightfieldError::UnknownChannel {
                name: s.to_owned(),
                valid: Channel::ALL.map(Channel::name).join(", "),
            })
    }
}

/// How to turn an image into heights.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct LoadOptions {
    /// Which channel holds the heights (default: luma).
    pub channel: Channel,
    /// Read the map as depth (white = low): `h = 1 - x` (default: false).
    pub invert: bool,
}

/// Deflate, PNG's only compression, expands at most 1032 times (a 258-byte match in about two
/// bits), so the pixels of `file_bytes` of PNG fill at most that many times as many bytes. The
/// decoder allocates the image its header claims before it reads the data, so without this
/// bound a 100-byte file claiming 11000 x 11000 RGBA pixels would allocate 480 MB (the `image`
/// crate's own default refuses only past 512 MiB).
fn png_limits(file_bytes: usize) -> image::Limits {
    const DEFLATE_MAX_RATIO: u64 = 1032;
    let mut limits = image::Limits::default();
    let most = DEFLATE_MAX_RATIO * file_bytes as u64 + (64 << 10);
    limits.max_alloc = Some(limits.max_alloc.map_or(most, |cap| cap.min(most)));
    limits
}

impl Heightfield {
    /// Loads a PNG height map. Errors name `path`: [`HeightfieldError::Io`] if it cannot be read,
    /// [`HeightfieldError::Decode`] if it is not a valid PNG, and those of [`Heightfield::from_dynamic_image`].
    pub fn load_png(path: &Path, opts: &LoadOptions) -> Result<Heightfield, HeightfieldError> {
        let origin = path.display().to_string();
        // Reading the bytes ourselves separates "cannot read the file" from "cannot decode it".
        let bytes = std::fs::read(path).map_err(|error| HeightfieldError::Io {
            origin: origin.clone(),
            error,
        })?;
        // A zero-byte file is the empty image users actually produce (a failed export).
        if bytes.is_empty() {
            return Err(HeightfieldError::Empty {
                origin,
                width: 0,
                height: 0,
            });
        }
        let mut reader =
            image::ImageReader::with_format(std::io::Cursor::new(&bytes), ImageFormat::Png);
        reader.limits(png_limits(bytes.len()));
        let img = reader.decode().map_err(|error| HeightfieldError::Decode {
            origin: origin.clone(),
            error,
        })?;
        Self::from_dynamic_image(&img, opts, &origin)
    }

    /// Converts a decoded image into heights (see the module docs for the exact mapping); `source` names the
    /// image in errors. Errors: [`HeightfieldError::Empty`] for a zero dimension,
    /// [`HeightfieldError::MissingChannel`] for alpha of an image without it.
    pub fn from_dynamic_image(
        img: &DynamicImage,
        opts: &LoadOptions,
        source: &str,
    ) -> Result<Heightfield, HeightfieldError> {
        let (width, height) = (img.width(), img.height());
        if width == 0 || height == 0 {
            return Err(HeightfieldError::Empty {
                origin: source.to_owned(),
                width,
                height,
            });
        }
        let codes = channel_codes(img, opts.channel, source)?;
        let data = codes
            .into_iter()
            .map(|x| {
                let x = if opts.invert { u16::MAX - x } else { x };
                f32::from(x) / f32::from(u16::MAX)
            })
            .collect();
        Heightfield::with_origin(width, height, data, source)
    }

    /// Writes the heights as a 16-bit grey PNG (`round(h * 65535)`); loading it back with default options
    /// gives [`Heightfield::quantized_unorm16`] of this map exactly.
    pub fn save_png16(&self, path: &Path) -> Result<(), HeightfieldError> {
        let codes = self.to_unorm16();
        let width = self.width() as usize;
        let img: ImageBuffer<Luma<u16>, Vec<u16>> =
            ImageBuffer::from_fn(self.width(), self.height(), |i, j| {
                Luma([codes[j as usize * width + i as usize]])
            });
        img.save_with_format(path, ImageFormat::Png)
            .map_err(|error| HeightfieldError::Write {
                origin: path.display().to_string(),
                error,
            })
    }
}

/// The chosen channel of every pixel as 16-bit codes, row-major.
fn channel_codes(
    img: &DynamicImage,
    channel: Channel,
    source: &str,
) -> Result<Vec<u16>, HeightfieldError> {
    let Some(index) = channel.rgba_index() else {
        return Ok(img.to_luma16().into_raw());
    };
    if channel == Channel::A && !img.color().has_alpha() {
        return Err(HeightfieldError::MissingChannel {
            origin: source.to_owned(),
            color: img.color(),
        });
    }
    // Grey images expand to R = G = B = grey and opaque alpha, so r/g/b of a grey map is its grey value.
    Ok(img.to_rgba16().pixels().map(|p| p.0[index]).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::{GrayImage, Rgb, RgbImage, Rgba, RgbaImage};
    use std::path::PathBuf;
    use std::sync::atomic::{AtomicU32, Ordering};

    /// A temporary file path unique to this process and call; removed when dropped.
    struct TempFile(PathBuf);

    impl TempFile {
        fn new(name: &str) -> Self {
            static COUNTER: AtomicU32 = AtomicU32::new(0);
            let n = COUNTER.fetch_add(1, Ordering::Relaxed);
            let file = format!("relief-hf-test-{}-{n}-{name}", std::process::id());
            TempFile(std::env::temp_dir().join(file))
        }
    }

    impl Drop for TempFile {
        fn drop(&mut self) {
            // Best effort: a leftover temp file is harmless.
            let _ = std::fs::remove_file(&self.0);
        }
    }

    fn load(path: &Path, channel: Channel, invert: bool) -> Result<Heightfield, HeightfieldError> {
        Heightfield::load_png(path, &LoadOptions { channel, invert })
    }

    #[test]
    fn grey8_png_round_trips_exact_values() {
        let tmp = TempFile::new("grey8.png");
        let img = GrayImage::from_fn(5, 3, |i, j| Luma([(i * 50 + j * 3) as u8]));
        img.save(&tmp.0).expect("write test png");
        let hf = load(&tmp.0, Channel::Luma, false).expect("load");
        assert_eq!((hf.width(), hf.height()), (5, 3));
        for j in 0..3 {
            for i in 0..5 {
                let v = (i * 50 + j * 3) as f32;
                assert_eq!(hf.get(i, j), v / 255.0, "texel ({i}, {j})");
            }
        }
        // r of a grey image is its grey value.
        assert_eq!(load(&tmp.0, Channel::G, false).expect("load g"), hf);
    }

    #[test]
    fn grey16_png_round_trips_exact_values_and_save_png16() {
        let tmp = TempFile::new("grey16.png");
        let code = |i: u32, j: u32| (i * 9973 + j * 131 + 1) as u16;
        let img: ImageBuffer<Luma<u16>, Vec<u16>> =
            ImageBuffer::from_fn(7, 4, |i, j| Luma([code(i, j)]));
        img.save(&tmp.0).expect("write test png");
        let hf = load(&tmp.0, Channel::Luma, false).expect("load");
        for j in 0..4 {
            for i in 0..7 {
                assert_eq!(
                    hf.get(i, j),
                    f32::from(code(i, j)) / 65535.0,
                    "texel ({i}, {j})"
                );
            }
        }
        assert_eq!(hf.quantized_unorm16(), hf);

        let out = TempFile::new("saved16.png");
        hf.save_png16(&out.0).expect("save");
        assert_eq!(load(&out.0, Channel::Luma, false).expect("reload"), hf);
    }

    #[test]
    fn rgba_channel_pick_and_invert() {
        let tmp = TempFile::new("rgba.png");
        let px = |i: u32, j: u32| Rgba([(10 + i) as u8, (20 + j) as u8, 30, (200 + i + j) as u8]);
        RgbaImage::from_fn(4, 2, px)
            .save(&tmp.0)
            .expect("write test png");
        for (channel, index) in [
            (Channel::R, 0),
            (Channel::G, 1),
            (Channel::B, 2),
            (Channel::A, 3),
        ] {
            let hf = load(&tmp.0, channel, false).expect("load");
            let inv = load(&tmp.0, channel, true).expect("load inverted");
            for (j, i) in [(0, 0), (1, 3), (1, 1)] {
                let v = px(i, j).0[index];
                assert_eq!(hf.get(i, j), f32::from(v) / 255.0, "{channel} ({i}, {j})");
                assert_eq!(
                    inv.get(i, j),
                    f32::from(255 - v) / 255.0,
                    "{channel} inverted"
                );
            }
        }
    }

    #[test]
    fn luma_of_colour_uses_luminance() {
        let img = DynamicImage::ImageRgb8(RgbImage::from_fn(2, 1, |i, _| {
            if i == 0 {
                Rgb([255, 0, 0])
            } else {
                Rgb([0, 255, 0])
            }
        }));
        let hf = Heightfield::from_dynamic_image(&img, &LoadOptions::default(), "mem").expect("ok");
        // Rec. 709: red weighs 0.2126, green 0.7152.
        assert!((hf.get(0, 0) - 0.2126).abs() < 1e-3, "{}", hf.get(0, 0));
        assert!((hf.get(1, 0) - 0.7152).abs() < 1e-3, "{}", hf.get(1, 0));
    }

    #[test]
    fn missing_file_is_io_error_naming_the_path() {
        let tmp = TempFile::new("does-not-exist.png");
        let err = load(&tmp.0, Channel::Luma, false).unwrap_err();
        assert!(matches!(err, HeightfieldError::Io { .. }), "{err}");
        assert!(
            err.to_string().contains(&tmp.0.display().to_string()),
            "{err}"
        );
    }

    #[test]
    fn text_file_named_png_is_decode_error() {
        let tmp = TempFile::new("text.png");
        std::fs::write(&tmp.0, "this is not an image\n").expect("write text");
        let err = load(&tmp.0, Channel::Luma, false).unwrap_err();
        assert!(matches!(err, HeightfieldError::Decode { .. }), "{err}");
        assert!(err.to_string().contains("text.png"), "{err}");
    }

    #[test]
    fn alpha_of_rgb_is_missing_channel() {
        let img = DynamicImage::ImageRgb8(RgbImage::new(2, 2));
        let err = Heightfield::from_dynamic_image(
            &img,
            &LoadOptions {
                channel: Channel::A,
                invert: false,
            },
            "rgb.png",
        )
        .unwrap_err();
        assert!(
            matches!(err, HeightfieldError::MissingChannel { .. }),
            "{err}"
        );
        assert!(err.to_string().contains("rgb.png"), "{err}");
    }

    #[test]
    fn empty_image_is_empty_error() {
        let img = DynamicImage::new_luma8(0, 3);
        let err = Heightfield::from_dynamic_image(&img, &LoadOptions::default(), "e").unwrap_err();
        assert!(
            matches!(
                err,
                HeightfieldError::Empty {
                    width: 0,
                    height: 3,
                    ..
                }
            ),
            "{err}"
        );
    }

    #[test]
    fn channel_names_parse_and_display() {
        for c in Channel::ALL {
            assert_eq!(c.to_string().parse::<Channel>().expect("parse"), c);
        }
        let err = "alpha".parse::<Channel>().unwrap_err();
        assert!(matches!(err, HeightfieldError::UnknownChannel { .. }));
        assert!(err.to_string().contains("luma, r, g, b, a"), "{err}");
        assert_eq!(
            LoadOptions::default(),
            LoadOptions {
                channel: Channel::Luma,
                invert: false
            }
        );
    }
}
