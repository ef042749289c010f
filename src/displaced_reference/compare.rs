//! How close a frame of relief is to the displaced-geometry reference's frame of the same view:
//! silhouette agreement and mean colour difference, over the whole image and over the band
//! around the reference's outline, where flat relief and the truth part.

/// A frame against the reference's.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct OutlineAgreement {
    /// Intersection over union of the covered pixels (those not the background's colour).
    pub iou: f64,
    /// Mean absolute RGB channel difference over the image, in 8-bit levels.
    pub mean_difference: f64,
    /// The same over the band within two pixels of the reference's outline.
    pub band_difference: f64,
    /// Pixels in that band.
    pub band_pixels: usize,
}

/// Which pixels of `rgba` (`width` wide, RGBA8) are covered: those whose colour differs from the
/// top-left pixel's, the background in a framed view.
pub fn coverage(rgba: &[u8]) -> Vec<bool> {
    let background = rgba.get(..4).unwrap_or_default();
    rgba.chunks_exact(4).map(|p| p != background).collect()
}

/// Intersection over union of two coverage masks of one image.
pub fn iou(a: &[bool], b: &[bool]) -> f64 {
    let both = a.iter().zip(b).filter(|(x, y)| **x && **y).count();
    let either = a.iter().zip(b).filter(|(x, y)| **x || **y).count();
    both as f64 / either.max(1) as f64
}

/// Compares `image` with `reference`, both RGBA8 of `width` x `height`, the same view.
pub fn compare_with_reference(
    image: &[u8],
    reference: &[u8],
    width: u32,
    height: u32,
) -> OutlineAgreement {
    let (a, b) = (coverage(image), coverage(reference));
    let band = outline_band(&b, width as usize, height as usize, 2);
    let difference = |keep: &dyn Fn(usize) -> bool| {
        let (mut sum, mut n) = (0u64, 0u64);
        for (k, (p, q)) in image
            .chunks_exact(4)
            .zip(reference.chunks_exact(4))
            .enumerate()
        {
            if keep(k) {
                sum += (0..3).map(|c| u64::from(p[c].abs_diff(q[c]))).sum::<u64>();
                n += 3;
            }
        }
        sum as f64 / n.max(1) as f64
    };
    OutlineAgreement {
        iou: iou(&a, &b),
        mean_difference: difference(&|_| true),
        band_difference: difference(&|k| band[k]),
        band_pixels: band.iter().filter(|x| **x).count(),
    }
}

/// Pixels within `reach` pixels (a square) of a covered pixel beside an uncovered one.
fn outline_band(covered: &[bool], width: usize, height: usize, reach: usize) -> Vec<bool> {
    let at = |x: usize, y: usize| covered[y * width + x];
    let mut edge = vec![false; covered.len()];
    for y in 0..height {
        for x in 0..width {
            let c = at(x, y);
            let differs = (x > 0 && at(x - 1, y) != c)
                || (x + 1 < width && at(x + 1, y) != c)
                || (y > 0 && at(x, y - 1) != c)
                || (y + 1 < height && at(x, y + 1) != c);
            edge[y * width + x] = differs;
        }
    }
    let mut band = vec![false; covered.len()];
    for y in 0..height {
        for x in 0..width {
            if !edge[y * width + x] {
                continue;
            }
            for by in y.saturating_sub(reach)..(y + reach + 1).min(height) {
                for bx in x.saturating_sub(reach)..(x + reach + 1).min(width) {
                    band[by * width + bx] = true;
                }
            }
        }
    }
    band
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(width: usize, height: usize, covered: impl Fn(usize, usize) -> bool) -> Vec<u8> {
        let mut out = Vec::new();
        for y in 0..height {
            for x in 0..width {
                out.extend(if covered(x, y) {
                    [200, 100, 50, 255]
                } else {
                    [0, 0, 0, 255]
                });
            }
        }
        out
    }

    #[test]
    fn a_shifted_square_loses_agreement_along_its_edge() {
        let a = image(20, 20, |x, y| (5..15).contains(&x) && (5..15).contains(&y));
        let b = image(20, 20, |x, y| (6..16).contains(&x) && (5..15).contains(&y));
        let same = compare_with_reference(&a, &a, 20, 20);
        assert_eq!((same.iou, same.mean_difference), (1.0, 0.0));
        let shifted = compare_with_reference(&a, &b, 20, 20);
        assert!((shifted.iou - 90.0 / 110.0).abs() < 1e-9, "{shifted:?}");
        assert!(shifted.band_difference > shifted.mean_difference);
        // The outline ring of the 10 x 10 square, two pixels either side: at most 16 x 16 less
        // 4 x 4 (the outline's outer corners are not edge pixels, so a few corners stay out).
        assert!((200..=240).contains(&shifted.band_pixels), "{shifted:?}");
    }
}
