//! Reading an environment from a Radiance `.hdr` file, with errors that name the file.

use std::path::{Path, PathBuf};

use super::{Environment, MAX_RADIANCE};

/// Why an environment could not be used.
#[derive(Debug, thiserror::Error)]
pub enum EnvironmentError {
    /// The file could not be opened or decoded.
    #[error("environment {path}: {problem}")]
    File {
        /// The file.
        path: PathBuf,
        /// What went wrong, in the decoder's words.
        problem: String,
    },
    /// The image holds values a frame cannot light with.
    #[error("environment {name} {problem}")]
    Invalid {
        /// The environment's name.
        name: String,
        /// What is wrong with it.
        problem: String,
    },
}

/// The largest image read: an 8K x 4K panorama is the largest in common use.
const MAX_TEXELS: u64 = 8192 * 4096;

/// Texels a file may claim per byte it holds. Run-length encoding (Radiance's "new" RLE, the one
/// every writer since 1991 uses) spends at least 2 bytes on a run of 127 values of one of a
/// texel's 4 channels, so no scanline holds more than about 16 texels a byte; past twice that the
/// header lies, and the decoder would allocate the whole claimed image before finding the data
/// short. (Only the old RLE's repeat counts could beat it, and no current writer emits them.)
const TEXELS_PER_BYTE: u64 = 32;

impl Environment {
    /// Reads an equirectangular Radiance `.hdr` image (twice as wide as tall). Texels brighter
    /// than [`MAX_RADIANCE`] are clamped to it; NaN or negative values are refused.
    pub fn load(path: &Path) -> Result<Environment, EnvironmentError> {
        let fail = |problem: String| EnvironmentError::File {
            path: path.to_path_buf(),
            problem,
        };
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        if !ext.eq_ignore_ascii_case("hdr") {
            return Err(fail(
                "is not a Radiance .hdr file (the only environment format read)".into(),
            ));
        }
        let file = std::fs::File::open(path).map_err(|e| fail(e.to_string()))?;
        let bytes = file.metadata().map_err(|e| fail(e.to_string()))?.len();
        let decoder = image::codecs::hdr::HdrDecoder::new(std::io::BufReader::new(file))
            .map_err(|e| fail(format!("not a readable Radiance image: {e}")))?;
        let meta = decoder.metadata();
        let (width, height) = (meta.width, meta.height);
        if u64::from(width) * u64::from(height) > MAX_TEXELS {
            return Err(fail(format!(
                "is {width}x{height}, larger than the 8192x4096 read"
            )));
        }
        if u64::from(width) * u64::from(height) > TEXELS_PER_BYTE * bytes {
            return Err(fail(format!(
                "truncated or corrupt: its header claims {width}x{height} texels, more than \
                 its {bytes} bytes can hold"
            )));
        }
        let image = image::DynamicImage::from_decoder(decoder)
            .map_err(|e| fail(format!("truncated or corrupt: {e}")))?
            .into_rgb32f();
        let texels = image
            .pixels()
            .map(|p| p.0.map(|c| if c > MAX_RADIANCE { MAX_RADIANCE } else { c }))
            .collect();
        let name = path.file_name().map_or_else(
            || path.display().to_string(),
            |n| n.to_string_lossy().into(),
        );
        let env = Environment {
            name,
            width,
            height,
            texels,
        };
        env.check().map_err(|e| fail(e.to_string()))?;
        Ok(env)
    }

    /// Writes the image as a Radiance `.hdr` file (tests, `--hdr-out`'s format).
    pub fn save(&self, path: &Path) -> Result<(), EnvironmentError> {
        let fail = |problem: String| EnvironmentError::File {
            path: path.to_path_buf(),
            problem,
        };
        let file = std::fs::File::create(path).map_err(|e| fail(e.to_string()))?;
        let pixels: Vec<image::Rgb<f32>> = self.texels.iter().map(|t| image::Rgb(*t)).collect();
        image::codecs::hdr::HdrEncoder::new(std::io::BufWriter::new(file))
            .encode(&pixels, self.width as usize, self.height as usize)
            .map_err(|e| fail(e.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("relief-env-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    #[test]
    fn a_saved_environment_reads_back() {
        let env = Environment::from_fn("gradient", 16, 8, |d| glam::Vec3::splat(d.y + 1.5));
        let path = temp("gradient.hdr");
        env.save(&path).unwrap();
        let back = Environment::load(&path).unwrap();
        assert_eq!(
            (back.width, back.height, back.name.as_str()),
            (16, 8, "gradient.hdr")
        );
        for (a, b) in env.texels.iter().zip(&back.texels) {
            // RGBE keeps 8 bits of mantissa.
            assert!((a[0] - b[0]).abs() < a[0] / 64.0, "{a:?} {b:?}");
        }
    }

    #[test]
    fn malformed_and_truncated_files_get_one_clear_error() {
        let env = Environment::uniform([2.0, 1.0, 0.5]);
        let path = temp("whole.hdr");
        env.save(&path).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        let cut = temp("cut.hdr");
        std::fs::write(&cut, &bytes[..bytes.len() - 40]).unwrap();
        let err = Environment::load(&cut).unwrap_err().to_string();
        assert!(
            err.contains("cut.hdr") && err.contains("truncated"),
            "{err}"
        );
        let junk = temp("junk.hdr");
        std::fs::write(&junk, b"#?NOTRADIANCE\n\nsomething else").unwrap();
        let err = Environment::load(&junk).unwrap_err().to_string();
        assert!(
            err.contains("junk.hdr") && err.contains("not a readable"),
            "{err}"
        );
        let err = Environment::load(&temp("absent.hdr"))
            .unwrap_err()
            .to_string();
        assert!(err.contains("absent.hdr"), "{err}");
        let err = Environment::load(Path::new("sky.exr"))
            .unwrap_err()
            .to_string();
        assert!(err.contains("sky.exr") && err.contains(".hdr"), "{err}");
    }

    #[test]
    fn a_header_claiming_more_texels_than_the_file_holds_is_refused_before_decoding() {
        let path = temp("tiny-claims-8k.hdr");
        std::fs::write(
            &path,
            b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4096 +X 8192\n\x02\x02",
        )
        .unwrap();
        let err = Environment::load(&path).unwrap_err().to_string();
        assert!(
            err.contains("tiny-claims-8k.hdr")
                && err.contains("8192x4096")
                && err.contains("bytes"),
            "{err}"
        );
    }

    #[test]
    fn a_sun_brighter_than_half_floats_is_clamped() {
        let mut env = Environment::uniform([0.1; 3]);
        env.texels[3] = [1e6, 1e6, 1e6];
        let path = temp("sun.hdr");
        env.save(&path).unwrap();
        let back = Environment::load(&path).unwrap();
        assert_eq!(back.texels[3], [MAX_RADIANCE; 3]);
    }
}
