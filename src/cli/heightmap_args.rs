//! The height-field options shared by commands: a PNG file or a named synthetic generator.

use std::path::PathBuf;

use clap::Args;
use relief::heightfield::{Channel, Generator, Heightfield, LoadOptions, MAX_SIDE};

#[derive(Args, Debug, Clone)]
pub struct HeightmapArgs {
    /// Height map PNG (8- or 16-bit; grey, or one channel of a colour image).
    #[arg(long, value_name = "FILE", conflicts_with = "field")]
    pub heightmap: Option<PathBuf>,
    /// Which channel holds heights: luma, r, g, b or a.
    #[arg(long, default_value = "luma", value_name = "CHANNEL")]
    pub height_channel: Channel,
    /// The map stores depth (white = low): use 1 - value as height.
    #[arg(long)]
    pub invert: bool,
    /// A synthetic height field instead of a file: flat0 flat1 ramp step spikes checker noise fbm bricks.
    #[arg(long, value_name = "NAME")]
    pub field: Option<Generator>,
    /// Side of the synthetic field in texels.
    #[arg(long, default_value_t = 256, value_name = "N")]
    pub size: u32,
    /// Seed of the synthetic field.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

impl HeightmapArgs {
    /// The height field asked for (an error if none was), and a device it fits on: the commands
    /// that work on one map (`maps`, `trace`, `ao`) start this way.
    pub fn load_on_device(
        &self,
        device: Option<&str>,
        quiet: bool,
    ) -> anyhow::Result<(Heightfield, String, std::sync::Arc<relief::vk::Context>)> {
        let (hf, source) = self.load()?.ok_or_else(|| {
            anyhow::anyhow!("give a height map: --heightmap FILE or --field NAME")
        })?;
        let ctx = super::open_device(device, quiet)?;
        hf.check_max_dimension(ctx.info().max_image_dimension_2d, &source)?;
        Ok((hf, source, ctx))
    }

    /// The height field asked for, with a name for messages, or `None` if none was asked for.
    pub fn load(&self) -> anyhow::Result<Option<(Heightfield, String)>> {
        if let Some(path) = &self.heightmap {
            let opts = LoadOptions {
                channel: self.height_channel,
                invert: self.invert,
            };
            let hf = Heightfield::load_png(path, &opts)?;
            return Ok(Some((hf, path.display().to_string())));
        }
        let Some(generator) = self.field else {
            return Ok(None);
        };
        if self.size == 0 || self.size > MAX_SIDE {
            anyhow::bail!("--size {} is outside 1..={MAX_SIDE}", self.size);
        }
        let hf = generator.generate(self.size, self.size, self.seed);
        let name = format!("synthetic {} {}x{}", generator.name(), self.size, self.size);
        Ok(Some((hf, name)))
    }
}
