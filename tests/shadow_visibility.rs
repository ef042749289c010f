//! The shadow modes on the GPU against the exact visible fraction of a disk light
//! (`heightfield::visibility`), at the hits `relief trace --shadows` dumps: hard shadows agree with the
//! exact verdict, the cone mode is close at every radius and never leaks light, and no mode produces
//! NaN or a fraction outside [0, 1] for lights overhead, grazing, below the horizon or huge, on
//! degenerate fields.

mod common;

use std::sync::Arc;

use relief::bench::{ray_direction, shadow_stats, ShadowStats};
use relief::heightfield::visibility::LightDir;
use relief::heightfield::{build_method_map, Address, Generator, Heightfield};
use relief::method::Method;
use relief::render::{trace_on_gpu, HeightFormat, ShadowTrace, TraceOutput, TraceRequest};
use relief::scene::ShadowMode;
use relief::vk::Context;

const DEPTH_SCALE: f32 = 0.1;

fn trace(
    ctx: &Arc<Context>,
    hf: &Heightfield,
    depth_scale: f32,
    grid: u32,
    shadow: ShadowTrace,
) -> TraceOutput {
    let method: Method = "qdm".parse().expect("qdm is a method");
    let map = build_method_map(method, hf, Address::Repeat);
    let req = TraceRequest {
        method,
        dir: ray_direction(45.0, 10.0).map(|x| x as f32),
        depth_scale,
        grid: (grid, grid),
        budget: method.info().default_budget,
        address: Address::Repeat,
        format: HeightFormat::R16Unorm,
        map: map.as_ref().map(|(m, _)| m),
        shadow: Some(shadow),
    };
    trace_on_gpu(ctx, hf, &req).expect("trace runs")
}

fn measure(ctx: &Arc<Context>, hf: &Heightfield, mode: ShadowMode, light: LightDir) -> ShadowStats {
    let shadow = ShadowTrace::directional(
        mode,
        light.elevation_deg,
        light.azimuth_deg,
        light.radius_deg,
    );
    let out = trace(ctx, hf, DEPTH_SCALE, 32, shadow);
    let s = f64::from(DEPTH_SCALE);
    shadow_stats(hf, &out.hits, &out.visible, s, Address::Repeat, light, 8).expect("reference")
}

fn fields() -> [(&'static str, Heightfield); 2] {
    [
        (
            "fbm",
            Generator::Fbm.generate(128, 128, 1).quantized_unorm16(),
        ),
        (
            "bricks",
            Generator::Bricks.generate(128, 128, 1).quantized_unorm16(),
        ),
    ]
}

#[test]
fn hard_shadows_agree_with_the_exact_verdict() {
    let Some(ctx) = common::device("hard_shadows_agree_with_the_exact_verdict") else {
        return;
    };
    for (name, hf) in fields() {
        for elevation_deg in [5.0, 15.0, 30.0, 60.0] {
            let light = LightDir {
                elevation_deg,
                azimuth_deg: 200.0,
                radius_deg: 0.0,
            };
            let stats = measure(&ctx, &hf, ShadowMode::Hard, light);
            assert_eq!(stats.points, 1024, "{name} at {elevation_deg} deg");
            assert!(
                stats.agreement >= 0.999,
                "{name} at {elevation_deg} deg: hard shadows agree on {:.4} of points",
                stats.agreement
            );
        }
    }
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn cone_shadows_follow_the_penumbra_without_leaking() {
    let Some(ctx) = common::device("cone_shadows_follow_the_penumbra_without_leaking") else {
        return;
    };
    for (name, hf) in fields() {
        for elevation_deg in [5.0, 15.0, 30.0] {
            for radius_deg in [0.0, 2.0, 8.0] {
                let light = LightDir {
                    elevation_deg,
                    azimuth_deg: 200.0,
                    radius_deg,
                };
                let stats = measure(&ctx, &hf, ShadowMode::Cone, light);
                let what = format!("{name}, light at {elevation_deg} deg, radius {radius_deg}");
                assert_eq!(stats.bad_values, 0, "{what}");
                assert!(stats.abs_error.mean <= 0.05, "{what}: {stats:?}");
                assert!(stats.leak_rate <= 0.001, "{what}: {stats:?}");
                if radius_deg == 0.0 {
                    assert!(stats.agreement >= 0.999, "{what}: {stats:?}");
                }
            }
        }
    }
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn every_mode_stays_in_range_on_extreme_lights_and_fields() {
    let Some(ctx) = common::device("every_mode_stays_in_range_on_extreme_lights_and_fields") else {
        return;
    };
    let fields = [
        ("1x1", Heightfield::new(1, 1, vec![0.5]).expect("1x1"), 0.1),
        (
            "flat 8x8",
            Heightfield::new(8, 8, vec![0.25; 64]).expect("flat"),
            0.1,
        ),
        ("spikes", Generator::Spikes.generate(64, 64, 3), 0.5),
        (
            "bricks, depth 50",
            Generator::Bricks.generate(32, 32, 1),
            50.0,
        ),
    ];
    let lights = [
        (90.0, 0.0),
        (0.0, 0.0),
        (-10.0, 0.0),
        (0.5, 45.0),
        (45.0, 45.0),
        (30.0, 90.0),
    ];
    for (name, hf, depth_scale) in &fields {
        let flat = name.starts_with("1x1") || name.starts_with("flat");
        for mode in ShadowMode::ALL {
            for (elevation, radius) in lights {
                let shadow = ShadowTrace::directional(mode, elevation, 130.0, radius);
                let out = trace(&ctx, hf, *depth_scale, 8, shadow);
                let what = format!("{mode} on {name}, light at {elevation} deg radius {radius}");
                for &v in &out.visible {
                    assert!((0.0..=1.0).contains(&v), "{what}: visible fraction {v}");
                }
                if flat && mode.is_some() {
                    // A flat field hides exactly the part of the disk below the horizontal; hard
                    // shadows look at the disk's centre only.
                    let expected = if mode == ShadowMode::Hard || radius == 0.0 {
                        Some(if elevation > 0.0 { 1.0 } else { 0.0 })
                    } else if elevation - radius >= 0.0 {
                        Some(1.0)
                    } else if elevation + radius <= 0.0 {
                        Some(0.0)
                    } else {
                        None
                    };
                    if let Some(expected) = expected {
                        for &v in &out.visible {
                            assert!(
                                (v - expected).abs() < 1e-4,
                                "{what}: {v}, expected {expected}"
                            );
                        }
                    }
                }
            }
        }
    }
    common::assert_no_validation_errors(&ctx);
}
