//! Height fields on the CPU: the validated map itself, PNG loading and saving, synthetic generators, the
//! conservative max pyramid, the method maps (cone, quadric), the exact reference tracer with its
//! addressing modes ([`Address`], the one addressing type of the crate) and the exact shading references
//! (light visibility, ambient occlusion). No Vulkan here.
//!
//! Conventions (docs/conventions.md): heights are in [0, 1] with 1 the top plane; a W x H map stores texel
//! `(i, j)` at row-major index `j * W + i`, `i` along u (x), `j` along v (y); PNG row 0 is `j = 0`.
//!
//! Invariant of [`Heightfield`]: `width >= 1`, `height >= 1`, `data.len() == width * height` and every value is
//! finite and within [0, 1]. Every constructor checks it, so code that holds a `Heightfield` never re-checks.
//!
//! Height versus depth: a [`Heightfield`] stores *heights* (1 = the top plane, 0 = the deepest point). Tracers
//! work in *depth* measured down from the top plane, `d = s * (1 - h)` for a depth scale `s` in uv units, so
//! fields named `z` (such as [`reference::RefHit::z`]) are depths in [0, s].
//!
//! # Main types
//! - [`Heightfield`]: the validated map; load it with [`Heightfield::load_png`] (choosing a [`Channel`] through
//!   [`LoadOptions`]), build it from floats with [`Heightfield::new`] or generate one with [`Generator`].
//! - [`MaxPyramid`]: the conservative max mip chain (per coarse texel the maximum of the texels it covers).
//! - [`cone_map::ConeMap`], [`quadric_map::QuadricMap`] and their flattened GPU form [`MapData`]: the per-method
//!   precomputed maps.
//! - [`reference::trace`] with [`reference::RefRay`] and [`Address`]: the exact hit every method is measured
//!   against; [`visibility::light_visibility`] and [`ambient_occlusion`]: the exact shading references.
//! - [`HeightfieldError`]: every failure to load, build or save a map, naming where the data came from.
//!
//! # How they fit together
//! A bench loads `rock.png` with [`Heightfield::load_png`], quantizes it with
//! [`Heightfield::quantized_unorm16`] so the CPU sees what the GPU samples, uploads [`Heightfield::to_unorm16`]
//! with the levels of [`MaxPyramid::build`], builds the method's map with [`MapData::build`] for the method's
//! [`crate::method::MapKind`], and then compares each pixel's GPU hit with [`reference::trace`] on the same
//! quantized field and [`Address`]. None of this touches Vulkan, so all of it runs in plain unit tests.

pub mod ambient_occlusion;
mod cell_walk;
pub mod cone_map;
pub mod error;
pub mod load;
pub mod method_map;
pub mod pyramid;
pub mod quadric_map;
pub mod reference;
pub(crate) mod rng;
pub mod stable_quadratic;
pub mod synthetic;
#[cfg(test)]
mod test_support;
pub mod visibility;

pub use error::HeightfieldError;
pub use load::{Channel, LoadOptions};
pub use method_map::{build_method_map, MapData};
pub use pyramid::{covered_range, mip_level_count, MaxPyramid, PyramidLevel};
pub use reference::Address;
pub use synthetic::Generator;

/// The largest side, in texels, of a height field or an image relief makes: the GPU map builders
/// pack texel indices in 14 bits, and every size the command line takes is held to the same bound.
pub const MAX_SIDE: u32 = 16384;

/// The largest value of a 16-bit UNORM texel, which stands for 1.0.
const UNORM16_MAX: f32 = 65535.0;

/// A validated W x H field of heights in [0, 1], row-major with `i` along u.
#[derive(Debug, Clone, PartialEq)]
pub struct Heightfield {
    width: u32,
    height: u32,
    data: Vec<f32>,
}

impl Heightfield {
    /// Builds a field from row-major heights, checking the invariant (see the module docs).
    ///
    /// Errors: [`HeightfieldError::Empty`] for a zero dimension, [`HeightfieldError::WrongLength`] when
    /// `data.len() != width * height`, [`HeightfieldError::NonFinite`] and [`HeightfieldError::OutOfRange`]
    /// naming the first offending index.
    pub fn new(width: u32, height: u32, data: Vec<f32>) -> Result<Heightfield, HeightfieldError> {
        Self::with_origin(width, height, data, "in-memory height data")
    }

    /// Like [`Heightfield::new`], with `origin` naming the data's source in any error message.
    pub fn with_origin(
        width: u32,
        height: u32,
        data: Vec<f32>,
        origin: &str,
    ) -> Result<Heightfield, HeightfieldError> {
        if width == 0 || height == 0 {
            return Err(HeightfieldError::Empty {
                origin: origin.to_owned(),
                width,
                height,
            });
        }
        let expected = (width as usize).checked_mul(height as usize);
        if expected != Some(data.len()) {
            return Err(HeightfieldError::WrongLength {
                origin: origin.to_owned(),
                width,
                height,
                len: data.len(),
            });
        }
        check_values(&data, origin)?;
        Ok(Heightfield {
            width,
            height,
            data,
        })
    }

    /// Wraps data a generator built valid by construction; checked in debug builds only.
    pub(crate) fn from_valid(width: u32, height: u32, data: Vec<f32>) -> Heightfield {
        debug_assert!(width >= 1 && height >= 1);
        debug_assert_eq!(data.len(), width as usize * height as usize);
        debug_assert!(data.iter().all(|h| (0.0..=1.0).contains(h)));
        Heightfield {
            width,
            height,
            data,
        }
    }

    /// Number of texels along u.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Number of texels along v.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// All heights, row-major: texel `(i, j)` is at `j * width + i`.
    pub fn data(&self) -> &[f32] {
        &self.data
    }

    /// `width * height`.
    pub fn texel_count(&self) -> usize {
        self.data.len()
    }

    /// The height of texel `(i, j)`.
    ///
    /// Panics if `i >= width` or `j >= height`; the check is explicit because an `i` past the row end would
    /// otherwise silently read the next row.
    pub fn get(&self, i: u32, j: u32) -> f32 {
        assert!(
            i < self.width && j < self.height,
            "texel ({i}, {j}) outside {}x{}",
            self.width,
            self.height
        );
        self.data[j as usize * self.width as usize + i as usize]
    }

    /// The same field with each value rounded to the nearest `k / 65535`, exactly what the GPU sees once the
    /// map is stored as `R16_UNORM`. Reference computations compare against this, not the raw floats.
    pub fn quantized_unorm16(&self) -> Heightfield {
        let data = self
            .data
            .iter()
            .map(|&h| f32::from(to_unorm16_value(h)) / UNORM16_MAX)
            .collect();
        Heightfield::from_valid(self.width, self.height, data)
    }

    /// The heights as 16-bit UNORM texels (`round(h * 65535)`), ready to upload as `R16_UNORM`.
    pub fn to_unorm16(&self) -> Vec<u16> {
        self.data.iter().map(|&h| to_unorm16_value(h)).collect()
    }

    /// Fails with [`HeightfieldError::TooLarge`], naming `source`, if either dimension exceeds `limit` (the
    /// device's `maxImageDimension2D`).
    pub fn check_max_dimension(&self, limit: u32, source: &str) -> Result<(), HeightfieldError> {
        if self.width > limit || self.height > limit {
            return Err(HeightfieldError::TooLarge {
                origin: source.to_owned(),
                width: self.width,
                height: self.height,
                limit,
            });
        }
        Ok(())
    }
}

/// Rounds a height in [0, 1] to the nearest 16-bit UNORM code.
fn to_unorm16_value(h: f32) -> u16 {
    // The clamp only matters for values the invariant already excludes; it keeps the cast total.
    (h.clamp(0.0, 1.0) * UNORM16_MAX).round() as u16
}

/// Checks that every value is finite and within [0, 1], naming the first that is not.
fn check_values(data: &[f32], origin: &str) -> Result<(), HeightfieldError> {
    for (index, &value) in data.iter().enumerate() {
        if !value.is_finite() {
            return Err(HeightfieldError::NonFinite {
                origin: origin.to_owned(),
                index,
            });
        }
        if !(0.0..=1.0).contains(&value) {
            return Err(HeightfieldError::OutOfRange {
                origin: origin.to_owned(),
                index,
                value,
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn new_accepts_valid_data_and_indexes_row_major() {
        let hf = Heightfield::new(3, 2, vec![0.0, 0.1, 0.2, 0.3, 0.4, 1.0]).expect("valid");
        assert_eq!((hf.width(), hf.height(), hf.texel_count()), (3, 2, 6));
        assert_eq!(hf.get(2, 0), 0.2);
        assert_eq!(hf.get(0, 1), 0.3);
        assert_eq!(hf.get(2, 1), 1.0);
        assert_eq!(hf.data().len(), 6);
    }

    #[test]
    fn new_rejects_nan_and_infinity_with_index() {
        let err = Heightfield::new(2, 2, vec![0.0, 0.5, f32::NAN, 1.0]).unwrap_err();
        assert!(
            matches!(err, HeightfieldError::NonFinite { index: 2, .. }),
            "{err}"
        );
        let err = Heightfield::new(1, 2, vec![0.0, f32::INFINITY]).unwrap_err();
        assert!(
            matches!(err, HeightfieldError::NonFinite { index: 1, .. }),
            "{err}"
        );
    }

    #[test]
    fn new_rejects_out_of_range_wrong_length_and_empty() {
        let err = Heightfield::new(2, 1, vec![0.5, 1.0001]).unwrap_err();
        assert!(
            matches!(err, HeightfieldError::OutOfRange { index: 1, .. }),
            "{err}"
        );
        let err = Heightfield::new(2, 1, vec![-0.0001, 0.5]).unwrap_err();
        assert!(
            matches!(err, HeightfieldError::OutOfRange { index: 0, .. }),
            "{err}"
        );
        let err = Heightfield::new(2, 2, vec![0.5; 3]).unwrap_err();
        assert!(
            matches!(err, HeightfieldError::WrongLength { len: 3, .. }),
            "{err}"
        );
        let err = Heightfield::new(0, 4, vec![]).unwrap_err();
        assert!(matches!(err, HeightfieldError::Empty { .. }), "{err}");
        let err = Heightfield::with_origin(4, 0, vec![], "foo.png").unwrap_err();
        assert!(err.to_string().contains("\"foo.png\""), "{err}");
    }

    #[test]
    fn unorm16_quantization_rounds_to_nearest_code() {
        let hf = Heightfield::new(4, 1, vec![0.0, 1.0, 0.5, 1.0 / 65535.0 * 0.49]).expect("valid");
        assert_eq!(hf.to_unorm16(), vec![0, 65535, 32768, 0]);
        let q = hf.quantized_unorm16();
        assert_eq!(q.data()[2], 32768.0 / 65535.0);
        assert_eq!(q.data()[3], 0.0);
        // Quantizing twice changes nothing: the codes are fixed points.
        assert_eq!(q.quantized_unorm16(), q);
        assert_eq!(q.to_unorm16(), hf.to_unorm16());
    }

    #[test]
    fn max_dimension_check_names_the_source() {
        let hf = Heightfield::new(5, 3, vec![0.5; 15]).expect("valid");
        assert!(hf.check_max_dimension(5, "x").is_ok());
        let err = hf.check_max_dimension(4, "big.png").unwrap_err();
        assert!(matches!(
            err,
            HeightfieldError::TooLarge {
                width: 5,
                height: 3,
                limit: 4,
                ..
            }
        ));
        assert!(err.to_string().contains("big.png"), "{err}");
    }
}
