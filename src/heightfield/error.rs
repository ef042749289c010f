//! Errors of the height-field module.
//!
//! Every variant that concerns one height map carries `origin`, a human-readable name of where the data came
//! from (a file path such as `"maps/rock.png"`, or a description such as `"synthetic fbm 256x256"`), and its
//! message names it, so a user who passes ten maps on the command line knows which one failed. Messages are
//! one line.
//!
//! The field is called `origin` rather than `source` because `thiserror` treats any field named `source` as
//! the underlying error, which a `String` is not.

use image::ColorType;

/// Why a height field could not be loaded, built, saved or used.
#[derive(Debug, thiserror::Error)]
pub enum HeightfieldError {
    /// The file is missing or unreadable.
    #[error("height map \"{origin}\": cannot read file ({error})")]
    Io {
        origin: String,
        #[source]
        error: std::io::Error,
    },

    /// The bytes are not a decodable image (not a PNG, truncated, corrupt).
    #[error("height map \"{origin}\": not a decodable image ({error})")]
    Decode {
        origin: String,
        #[source]
        error: image::ImageError,
    },

    /// Writing the map as a PNG failed.
    #[error("height map \"{origin}\": cannot write PNG ({error})")]
    Write {
        origin: String,
        #[source]
        error: image::ImageError,
    },

    /// Zero width or height: a height field has at least one texel.
    #[error(
        "height map \"{origin}\": empty ({width}x{height}); a height map needs at least 1x1 texels"
    )]
    Empty {
        origin: String,
        width: u32,
        height: u32,
    },

    /// Larger than the device can hold in one 2D image (`maxImageDimension2D`).
    #[error(
        "height map \"{origin}\": {width}x{height} exceeds the device's maximum image dimension {limit}"
    )]
    TooLarge {
        origin: String,
        width: u32,
        height: u32,
        limit: u32,
    },

    /// A NaN or infinite height.
    #[error("height map \"{origin}\": value at index {index} is not finite")]
    NonFinite { origin: String, index: usize },

    /// A finite height outside [0, 1].
    #[error("height map \"{origin}\": value {value} at index {index} is outside [0, 1]")]
    OutOfRange {
        origin: String,
        index: usize,
        value: f32,
    },

    /// The data does not hold exactly `width * height` values.
    #[error("height map \"{origin}\": {len} values given for {width}x{height} texels")]
    WrongLength {
        origin: String,
        width: u32,
        height: u32,
        len: usize,
    },

    /// A channel name that is not one of the valid ones.
    #[error("unknown height channel \"{name}\" (valid: {valid})")]
    UnknownChannel { name: String, valid: String },

    /// A synthetic generator name that is not one of the valid ones.
    #[error("unknown synthetic height map \"{name}\" (valid: {valid})")]
    UnknownGenerator { name: String, valid: String },

    /// The alpha channel was asked of an image that has none.
    #[error(
        "height map \"{origin}\": channel 'a' requested but the image ({color:?}) has no alpha"
    )]
    MissingChannel { origin: String, color: ColorType },
}
