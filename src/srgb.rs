//! The sRGB transfer function, both ways: the one definition every CPU path uses (texture mips
//! filtered in linear light, the PNG encoder's 16-bit frames, the shadow probe, terrain colours,
//! the level-of-detail bench). The GPU applies the same curve in hardware, on sRGB images.

/// An sRGB-encoded value in [0, 1] to linear light.
pub fn decode_f64(c: f64) -> f64 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// A linear value in [0, 1] to sRGB encoding.
pub fn encode_f64(c: f64) -> f64 {
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// [`decode_f64`] in single precision.
pub fn decode(c: f32) -> f32 {
    decode_f64(f64::from(c)) as f32
}

/// [`encode_f64`] in single precision.
pub fn encode(c: f32) -> f32 {
    encode_f64(f64::from(c)) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_two_directions_invert_each_other_and_meet_at_the_knee() {
        for k in 0..=1000 {
            let c = f64::from(k) / 1000.0;
            assert!((decode_f64(encode_f64(c)) - c).abs() < 1e-12, "{c}");
        }
        // Both pieces agree where the curve switches (continuity within the standard's rounding).
        assert!((encode_f64(0.003_130_8) - 0.040_449_936).abs() < 1e-6);
        assert!((decode_f64(0.5) - 0.214_041_14).abs() < 1e-6);
        assert_eq!(encode(1.0), 1.0);
        assert_eq!(decode(0.0), 0.0);
    }
}
