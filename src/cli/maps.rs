//! `relief maps`: the max pyramid of a height map, built on the GPU, one 16-bit PNG per level;
//! with `--method`, also that method's precomputed map (cone ratios, quadric coefficients) as
//! `map.npy`, with its build time: on the GPU (every map has a GPU builder, for maps the device
//! takes) unless `--map-on cpu`. Both are built with the same addressing (`--address`, repeat by
//! default as for `render`).

use std::path::PathBuf;

use anyhow::Context as _;
use clap::Args;
use relief::bench::write_npy_f32;
use relief::heightfield::{Address, Heightfield, MaxPyramid};
use relief::method::Method;
use relief::render::{build_method_map_with, build_pyramid_on_gpu, HeightFormat, MapBuilder};

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
    /// Where to build the method's map: "gpu" (where a GPU builder exists, else the CPU) or "cpu".
    #[arg(long, value_name = "WHERE", default_value = "gpu", value_parser = ["gpu", "cpu"])]
    map_on: String,
    /// Height map addressing, for the pyramid and the method's map alike.
    #[arg(long, value_name = "repeat|clamp", default_value_t = Address::Repeat)]
    address: Address,
    /// Pick the Vulkan device whose name contains this text.
    #[arg(long, value_name = "SUBSTRING")]
    device: Option<String>,
}

fn write_method_map(
    id: &str,
    hf: &Heightfield,
    args: &MapsArgs,
    builder: MapBuilder<'_>,
) -> anyhow::Result<()> {
    let method: Method = id.parse()?;
    let out = &args.out;
    let started = std::time::Instant::now();
    let built = build_method_map_with(method, &hf.quantized_unorm16(), args.address, builder)?;
    let wall_ms = started.elapsed().as_secs_f64() * 1e3;
    let Some(map) = built else {
        println!("{method} reads no map besides the pyramid");
        return Ok(());
    };
    let path = out.join("map.npy");
    let data = &map.data;
    let shape = [
        data.height as usize,
        data.width as usize,
        data.channels as usize,
    ];
    write_npy_f32(&path, &shape, &data.texels)
        .with_context(|| format!("writing {}", path.display()))?;
    let on = if map.on == "gpu" {
        // The wall time adds the CPU's bilinear bound, the transfers and the submissions.
        format!(
            "on the GPU in {:.1} ms of GPU time ({wall_ms:.1} ms wall)",
            map.ms
        )
    } else {
        format!("on the CPU in {:.1} ms", map.ms)
    };
    println!(
        "{method} map: {}x{} x {} channels, built {} -> {}",
        data.width,
        data.height,
        data.channels,
        on,
        path.display()
    );
    Ok(())
}

pub fn run(args: &MapsArgs) -> anyhow::Result<()> {
    let (hf, source, ctx) = args.heights.load_on_device(args.device.as_deref(), false)?;
    let (levels, gpu_ms) = build_pyramid_on_gpu(&ctx, &hf, HeightFormat::R16Unorm, args.address)?;
    // The GPU pyramid is checked against the CPU builder on the same 16-bit values.
    let wrap = args.address == Address::Repeat;
    let cpu = MaxPyramid::build_bilinear_bound(&hf.quantized_unorm16(), wrap);
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
        let builder = match args.map_on.as_str() {
            "cpu" => MapBuilder::Cpu,
            _ => MapBuilder::Gpu(&ctx),
        };
        write_method_map(id, &hf, args, builder)?;
        super::check_validation(&ctx)?;
    }
    if mismatched > 0 {
        anyhow::bail!("{mismatched} GPU pyramid level(s) differ from the CPU builder");
    }
    Ok(())
}
