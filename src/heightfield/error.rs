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
        /// Where the data came from: a file path or a description (see the module docs).
        origin: String,
        /// The I/O error the read returned.
        #[source]
        error: std::io::Error,
    },

    /// The bytes are not a decodable image (not a PNG, truncated, corrupt).
    #[error("height map \"{origin}\": not a decodable image ({error})")]
    Decode {
        /// Where the data came from: a file path or a description (see the module docs).
        origin: String,
        /// The decoder's error.
        #[source]
        error: image::ImageError,
    },

    /// Writing the map as a PNG failed.
    #[error("height map \"{origin}\": cannot write PNG ({error})")]
    Write {
        /// Where the data came from: a file path or a description (see the module docs).
        origin: String,
        /// The encoder's or file system's error.
        #[source]
        error: image::ImageError,
    },

    /// Zero width or height: a height field has at least one texel.
    #[error(
        "height map \"{origin}\": empty ({width}x{height}); a height map needs at least 1x1 texels"
    )]
    Empty {
        /// Where the data came from: a file path or a description (see the module docs).
        origin: String,
        /// Width asked for, in texels (0 if this is the empty dimension).
        width: u32,
        /// Height asked for, in texels (0 if this is the empty dimension).
        height: u32,
    },

    /// Larger than the device can hold in one 2D image (`maxImageDimension2D`).
    #[error(
        "height map \"{origin}\": {width}x{height} exceeds the device's maximum image dimension {limit}"
    )]
    TooLarge {
        /// Where the data came from: a file path or a description (see the module docs).
        origin: String,
        /// Width of the map, in texels.
        width: u32,
        /// Height of the map, in texels.
        height: u32,
        /// The largest dimension the device accepts, in texels (`maxImageDimension2D`).
        limit: u32,
    },

    /// A NaN or infinite height.
    #[error("height map \"{origin}\": value at index {index} is not finite")]
    NonFinite {
        /// Where the data came from: a file path or a description (see the module docs).
        origin: String,
        /// Row-major index (`j * width + i`) of the first non-finite value.
        index: usize,
    },

    /// A finite height outside [0, 1].
    #[error("height map \"{origin}\": value {value} at index {index} is outside [0, 1]")]
    OutOfRange {
        /// Where the data came from: a file path or a description (see the module docs).
        origin: String,
        /// Row-major index (`j * width + i`) of the first value outside [0, 1].
        index: usize,
        /// That value.
        value: f32,
    },

    /// The data does not hold exactly `width * height` values.
    #[error("height map \"{origin}\": {len} values given for {width}x{height} texels")]
    WrongLength {
        /// Where the data came from: a file path or a description (see the module docs).
        origin: String,
        /// Width given, in texels.
        width: u32,
        /// Height given, in texels.
        height: u32,
        /// Number of values given (should be `width * height`).
        len: usize,
    },

    /// A channel name that is not one of the valid ones.
    #[error("unknown height channel \"{name}\" (valid: {valid})")]
    UnknownChannel {
        /// The name that was given.
        name: String,
        /// The valid names, comma-separated, for the message.
        valid: String,
    },

    /// A synthetic generator name that is not one of the valid ones.
    #[error("unknown synthetic height map \"{name}\" (valid: {valid})")]
    UnknownGenerator {
        /// The name that was given.
        name: String,
        /// The valid generator names, comma-separated, for the message.
        valid: String,
    },

    /// The alpha channel was asked of an image that has none.
    #[error(
        "height map \"{origin}\": channel 'a' requested but the image ({color:?}) has no alpha"
    )]
    MissingChannel {
        /// Where the data came from: a file path or a description (see the module docs).
        origin: String,
        /// The image's color type as decoded, which has no alpha.
        color: ColorType,
    },
}
