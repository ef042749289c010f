//! The sRGB transfer function, to compare 8-bit frames with linear values.

/// The linear value of an 8-bit sRGB channel.
pub fn decode(c: u8) -> f64 {
    let c = f64::from(c) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The 8-bit sRGB level (not rounded) of linear value `l`.
pub fn encode(l: f64) -> f64 {
    let c = if l <= 0.0031308 {
        l * 12.92
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    };
    c * 255.0
}
