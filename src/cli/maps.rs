//! `relief maps`: the max pyramid of a height map, built on the GPU, one 16-bit PNG per level;
//! with `--method`, also that method's precomputed map (cone ratios, quadric coefficients) as
//! `map.npy`, with its build time.

use std::path::PathBuf;

use anyhow::Context as _;
use clap::Args;
use relief::bench::write_npy_f32;
use relief::heightfield::reference::Address;
use relief::heightfield::{Heightfield, MaxPyramid};
use relief::method::{build_method_map, Method};
use relief::render::{build_pyramid_on_gpu, Addressing, HeightFormat};

use super::heightmap_args::HeightmapArgs;

#[derive(Args)]
pub struct MapsArgs {
    #[command(flatten)]
    heights: HeightmapArgs,
    /// Folder for level_00.png, level_01.png, ...
    #[arg(long)]
    out: PathBuf,
    /// Also build this method's precomputed map (see `relief methods --json`, `needs`).
    #[arg(long, value_name = "ID")]
    method: Option<String>,
    /// Pick the Vulkan device whose name contains this text.
    #[arg(long, value_name = "SUBSTRING")]
    device: Option<String>,
}

fn write_method_map(id: &str, hf: &Heightfield, out: &std::path::Path) -> anyhow::Result<()> {
    let method: Method = id.parse()?;
    let Some((map, took)) = build_method_map(method, &hf.quantized_unorm16(), Address::Repeat)
    else {
        println!("{method} reads no map besides the pyramid");
        return Ok(());
    };
    let path = out.join("map.npy");
    let shape = [
        map.height as usize,
        map.width as usize,
        map.channels as usize,
    ];
    write_npy_f32(&path, &shape, &map.texels)
        .with_context(|| format!("writing {}", path.display()))?;
    println!(
        "{method} map: {}x{} x {} channels, built on the CPU in {:.1} ms -> {}",
        map.width,
        map.height,
        map.channels,
        took.as_secs_f64() * 1e3,
        path.display()
    );
    Ok(())
}

pub fn run(args: &MapsArgs) -> anyhow::Result<()> {
    let (hf, source) = args
        .heights
        .load()?
        .ok_or_else(|| anyhow::anyhow!("give a height map: --heightmap FILE or --field NAME"))?;
    let ctx = super::open_device(args.device.as_deref(), false)?;
    hf.check_max_dimension(ctx.info().max_image_dimension_2d, &source)?;
    let (levels, gpu_ms) =
        build_pyramid_on_gpu(&ctx, &hf, HeightFormat::R16Unorm, Addressing::Clamp)?;
    // The GPU pyramid is checked against the CPU builder on the same 16-bit values.
    let cpu = MaxPyramid::build_bilinear_bound(&hf.quantized_unorm16(), false);
    let mismatched = levels
        .iter()
        .zip(cpu.levels())
        .filter(|(gpu, cpu)| gpu.as_slice() != cpu.data.as_slice())
        .count();
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    for (k, (data, level)) in levels.into_iter().zip(cpu.levels()).enumerate() {
        let path = args.out.join(format!("level_{k:02}.png"));
        Heightfield::new(level.width, level.height, data)?.save_png16(&path)?;
        println!(
            "level {k:2}: {:>5}x{:<5} {}",
            level.width,
            level.height,
            path.display()
        );
    }
    super::check_validation(&ctx)?;
    println!("pyramid build: {gpu_ms:.3} ms GPU ({source})");
    if let Some(id) = &args.method {
        write_method_map(id, &hf, &args.out)?;
    }
    if mismatched > 0 {
        anyhow::bail!("{mismatched} GPU pyramid level(s) differ from the CPU builder");
    }
    Ok(())
}
