//! Cost maps (`relief render --cost-map steps|fragments`): a frame's work counters as a heat map
//! PNG, per pixel the relief steps traced or the relief fragments traced (overdraw after
//! culling), on a black-body ramp from black (none) through red and orange to white (the
//! frame's most), with the ramp itself as a colour bar down the right edge, ticked at each
//! quarter of the scale.

use std::io::Cursor;

use anyhow::Context as _;
use clap::ValueEnum;
use image::{ExtendedColorType, ImageFormat};
use relief::render::WorkCounts;

/// What a cost map shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum CostMap {
    /// Steps of every relief trace at the pixel.
    Steps,
    /// Relief fragments traced at the pixel: 1 where nothing traced is hidden.
    Fragments,
}

impl CostMap {
    /// The name in the file's: `STEM.cost-steps.png`.
    pub fn name(self) -> &'static str {
        match self {
            CostMap::Steps => "steps",
            CostMap::Fragments => "fragments",
        }
    }

    /// The per-pixel counts it draws.
    fn values(self, counts: &WorkCounts) -> &[u32] {
        match self {
            CostMap::Steps => &counts.steps,
            CostMap::Fragments => &counts.traced,
        }
    }
}

/// Width of the colour bar, with the one-pixel gap before it.
const BAR: u32 = 12;

/// The black-body ramp at `t` in 0..=1: black, red, orange, yellow, white.
fn ramp(t: f32) -> [u8; 3] {
    let t = t.clamp(0.0, 1.0);
    let channel = |start: f32| ((t - start) / (1.0 - start)).clamp(0.0, 1.0);
    let r = (t * 3.0).min(1.0);
    let g = channel(0.33).powf(0.8);
    let b = channel(0.7);
    [r, g, b].map(|c| (c * 255.0).round() as u8)
}

/// `counts` as `map`'s heat map PNG, the colour bar on the right.
pub fn cost_map_png(map: CostMap, counts: &WorkCounts) -> anyhow::Result<Vec<u8>> {
    heat_map_png(map.values(counts), counts.width, counts.height)
}

/// `values` (`w` x `h`, rows top to bottom) as a heat map PNG from 0 (black) to their largest
/// (white), the colour bar on the right.
pub fn heat_map_png(values: &[u32], w: u32, h: u32) -> anyhow::Result<Vec<u8>> {
    if values.len() != (w * h) as usize {
        anyhow::bail!("a {w}x{h} heat map from {} values", values.len());
    }
    let top = values.iter().copied().max().unwrap_or(0).max(1) as f32;
    let out_w = w + BAR;
    let mut rgb = vec![0u8; (out_w * h * 3) as usize];
    for y in 0..h {
        for x in 0..out_w {
            let colour = if x < w {
                ramp(values[(y * w + x) as usize] as f32 / top)
            } else if x == w {
                [0, 0, 0]
            } else {
                // Top of the bar the largest count, bottom none; a grey tick at each quarter.
                let t = 1.0 - y as f32 / (h.max(2) - 1) as f32;
                let quarter = (t * 4.0).round() / 4.0;
                let tick = (t - quarter).abs() * (h.max(2) - 1) as f32 <= 0.5 && x >= w + BAR - 4;
                if tick {
                    [128, 128, 128]
                } else {
                    ramp(t)
                }
            };
            let at = ((y * out_w + x) * 3) as usize;
            rgb[at..at + 3].copy_from_slice(&colour);
        }
    }
    let mut bytes = Vec::new();
    image::write_buffer_with_format(
        &mut Cursor::new(&mut bytes),
        &rgb,
        out_w,
        h,
        ExtendedColorType::Rgb8,
        ImageFormat::Png,
    )
    .context("encoding the cost map")?;
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ramp_runs_from_black_to_white_and_brightens() {
        assert_eq!(ramp(0.0), [0, 0, 0]);
        assert_eq!(ramp(1.0), [255, 255, 255]);
        let sum = |c: [u8; 3]| c.iter().map(|&v| u32::from(v)).sum::<u32>();
        let steps: Vec<u32> = (0..=20).map(|k| sum(ramp(k as f32 / 20.0))).collect();
        assert!(steps.windows(2).all(|w| w[0] < w[1]), "{steps:?}");
    }

    #[test]
    fn a_cost_map_is_the_frame_and_its_bar() {
        let counts = WorkCounts {
            width: 4,
            height: 3,
            traced: vec![0, 1, 2, 4, 0, 0, 0, 0, 1, 1, 1, 1],
            steps: vec![0; 12],
            fetches: vec![0; 12],
        };
        assert!(
            heat_map_png(&[1, 2], 3, 1).is_err(),
            "values and size disagree"
        );
        let png = cost_map_png(CostMap::Fragments, &counts).unwrap();
        let img = image::load_from_memory(&png).unwrap().to_rgb8();
        assert_eq!(img.dimensions(), (4 + BAR, 3));
        assert_eq!(img.get_pixel(0, 0).0, [0, 0, 0]);
        assert_eq!(img.get_pixel(3, 0).0, [255, 255, 255]);
        assert_eq!(img.get_pixel(2, 0).0, ramp(0.5));
    }
}
