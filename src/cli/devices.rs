//! `relief devices`: every usable Vulkan device with its driver, API version, limits, ray-query
//! support, and a warning where the driver is known to leak memory every frame.

use clap::Args;
use relief::vk::{list_devices, Context, ContextOptions};

#[derive(Args)]
pub struct DevicesArgs {
    /// Print one JSON list instead of a table.
    #[arg(long)]
    json: bool,
}

pub fn run(args: &DevicesArgs) -> anyhow::Result<()> {
    let ctx = Context::new(&ContextOptions::default())?;
    let devices: Vec<_> = list_devices(ctx.instance())?
        .into_iter()
        .map(|(_, info)| info)
        .collect();
    if args.json {
        println!("{}", serde_json::to_string(&devices)?);
        return Ok(());
    }
    let yes_no = |b: bool| if b { "yes" } else { "no" };
    for (k, d) in devices.iter().enumerate() {
        println!(
            "{k}: {} [{}] driver {} | Vulkan {} | max 2D image {} | timestamps {} bits, {} ns/tick \
             | ray queries {} | acceleration structures {}",
            d.name,
            d.kind,
            d.driver.trim(),
            d.api,
            d.max_image_dimension_2d,
            d.timestamp_valid_bits,
            d.timestamp_period_ns,
            yes_no(d.ray_query),
            yes_no(d.acceleration_structure)
        );
        if let Some(why) = &d.known_frame_leak {
            println!("   warning: {why}");
        }
    }
    Ok(())
}
