//! `relief render --exr-out`: a frame as one OpenEXR file, the linear radiance beside the
//! surface pass's G-buffer, every channel 32 bits.

use std::path::Path;

use anyhow::Context as _;
use exr::prelude::{AnyChannel, AnyChannels, FlatSamples, Image, WritableImage};
use relief::render::FrameOutput;

/// Writes `frame`'s radiance and G-buffer (both read back) to `out`; nothing when either is
/// missing.
pub fn write_exr(frame: &FrameOutput, out: &Path) -> anyhow::Result<()> {
    let (Some(radiance), Some(g)) = (&frame.radiance, &frame.gbuffer) else {
        return Ok(());
    };
    if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let float = |name: &str, values: Vec<f32>| AnyChannel::new(name, FlatSamples::F32(values));
    let uint = |name: &str, values: Vec<u32>| AnyChannel::new(name, FlatSamples::U32(values));
    let rgba = |c: usize| radiance.iter().map(|p| p[c]).collect::<Vec<f32>>();
    let normal = |c: usize| g.normal.iter().map(|n| n[c]).collect::<Vec<f32>>();
    let uv = |c: usize| g.uv.iter().map(|t| t[c]).collect::<Vec<f32>>();
    let channels = vec![
        float("R", rgba(0)),
        float("G", rgba(1)),
        float("B", rgba(2)),
        float("A", rgba(3)),
        float("Z", g.depth.clone()),
        float("N.X", normal(0)),
        float("N.Y", normal(1)),
        float("N.Z", normal(2)),
        float("coverage", g.coverage.clone()),
        float("uv.U", uv(0)),
        float("uv.V", uv(1)),
        uint("id", g.mesh.clone()),
        uint("steps", g.steps.clone()),
    ];
    let size = (frame.width as usize, frame.height as usize);
    let image = Image::from_channels(size, AnyChannels::sort(channels.into()));
    image
        .write()
        .to_file(out)
        .with_context(|| format!("writing {}", out.display()))
}
