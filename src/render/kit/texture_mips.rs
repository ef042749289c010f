//! Mip chains for material textures, built on the CPU with a 2x2 box filter (Vulkan's size rule:
//! halve, round down, at least 1). Colour textures are averaged in linear light, not in their
//! sRGB encoding, so minified textures keep their brightness.

/// Every level of `rgba` (tightly packed RGBA8 rows of `width` x `height`), level 0 first.
pub fn mip_chain(width: u32, height: u32, rgba: &[u8], srgb: bool) -> Vec<Vec<u8>> {
    let decode: Vec<f32> = (0..=255u8)
        .map(|v| {
            let c = f32::from(v) / 255.0;
            if srgb {
                crate::srgb::decode(c)
            } else {
                c
            }
        })
        .collect();
    let mut levels = vec![rgba.to_vec()];
    let (mut w, mut h) = (width as usize, height as usize);
    while w > 1 || h > 1 {
        let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
        let prev = levels.last().map(Vec::as_slice).unwrap_or_default();
        let mut next = vec![0u8; nw * nh * 4];
        for y in 0..nh {
            for x in 0..nw {
                let xs = [(2 * x).min(w - 1), (2 * x + 1).min(w - 1)];
                let ys = [(2 * y).min(h - 1), (2 * y + 1).min(h - 1)];
                for c in 0..4 {
                    // Alpha is coverage, never sRGB-encoded.
                    let linear = srgb && c < 3;
                    let mut sum = 0.0;
                    for &sy in &ys {
                        for &sx in &xs {
                            let v = prev[(sy * w + sx) * 4 + c];
                            sum += if linear {
                                decode[v as usize]
                            } else {
                                f32::from(v) / 255.0
                            };
                        }
                    }
                    let mean = sum * 0.25;
                    let encoded = if linear {
                        crate::srgb::encode(mean)
                    } else {
                        mean
                    };
                    next[(y * nw + x) * 4 + c] = (encoded * 255.0 + 0.5).clamp(0.0, 255.0) as u8;
                }
            }
        }
        levels.push(next);
        (w, h) = (nw, nh);
    }
    levels
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_follow_vulkans_rule() {
        let levels = mip_chain(5, 3, &[128; 5 * 3 * 4], false);
        let sizes: Vec<usize> = levels.iter().map(|l| l.len() / 4).collect();
        assert_eq!(sizes, vec![15, 2, 1]);
    }

    #[test]
    fn srgb_average_is_taken_in_linear_light() {
        // Black and white halves: the linear mean 0.5 encodes to sRGB 188, not 128.
        let rgba = [0, 0, 0, 255, 255, 255, 255, 255];
        let levels = mip_chain(2, 1, &rgba, true);
        assert_eq!(&levels[1][..3], &[188, 188, 188]);
        assert_eq!(levels[1][3], 255);
        let data = mip_chain(2, 1, &rgba, false);
        assert_eq!(data[1][0], 128);
    }
}
