//! `relief trace` prints error statistics that agree with an independent recomputation from its
//! own `.npy` dump: the dump is parsed here, each ray re-traced with the reference, and the
//! statistics recomputed by this file's own code.

mod common;

use std::process::Command;

use relief::heightfield::reference::{trace, RefRay, SurfaceModel};
use relief::heightfield::Address;
use relief::heightfield::Generator;

#[test]
fn printed_errors_match_the_dump() {
    check_dump(Address::Repeat);
}

#[test]
fn printed_errors_match_the_dump_with_clamp() {
    check_dump(Address::Clamp);
}

/// Runs `relief trace --address address` and recomputes its printed statistics from its dump.
fn check_dump(address: Address) {
    let test = format!("trace-dump-{address}");
    if common::device(&test).is_none() {
        return;
    }
    let dir = common::scratch_dir(&test);
    let dump = dir.join("hits.npy");
    let (size, seed, depth) = (64u32, 5u64, 0.08f64);
    let out = Command::new(env!("CARGO_BIN_EXE_relief"))
        .args([
            "trace",
            "--field",
            "fbm",
            "--size",
            &size.to_string(),
            "--seed",
            &seed.to_string(),
        ])
        .args([
            "--method",
            "pom",
            "--angle",
            "20",
            "--azimuth",
            "40",
            "--depth-scale",
            "0.08",
            "--address",
            &address.to_string(),
        ])
        .args(["--grid", "24x16", "--dump", dump.to_str().expect("utf-8")])
        .output()
        .expect("binary runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let printed: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON line");
    let (shape, values) = common::npy::read_npy(&std::fs::read(&dump).expect("dump written"));
    assert_eq!(shape, [16, 24, 8]);

    let hf = Generator::Fbm
        .generate(size, size, seed)
        .quantized_unorm16();
    let s = f64::from(depth as f32);
    let mut errors: Vec<f64> = values
        .chunks_exact(8)
        .map(|r| {
            let r: Vec<f64> = r.iter().map(|&v| f64::from(v)).collect();
            let ray = RefRay {
                u0: r[0],
                v0: r[1],
                dx: r[2],
                dy: r[3],
                dz: r[4],
            };
            let exact = trace(&hf, &ray, s, SurfaceModel::Bilinear, address);
            // The dumped hit uv, not the z, so the uv columns are checked too.
            let (du, dv) = (r[5] - exact.u, r[6] - exact.v);
            (du * f64::from(size)).hypot(dv * f64::from(size))
        })
        .collect();
    let mean = errors.iter().sum::<f64>() / errors.len() as f64;
    errors.sort_by(f64::total_cmp);
    let max = errors[errors.len() - 1];
    let gross = errors.iter().filter(|&&e| e > 1.0).count() as f64 / errors.len() as f64;

    // The dump's hit uv was computed on the GPU in f32, the printed error from z_hit along the
    // ray: they differ by float rounding alone, measured 4.1e-8 (repeat) and 2.0e-7 (clamp) texels
    // on the mean, 3.7e-7 on the max (both), and the gross counts are equal.
    let close = |a: f64, b: f64| (a - b).abs() <= 5e-7;
    let p_mean = printed["error_texels"]["mean"].as_f64().expect("mean");
    let p_max = printed["error_texels"]["max"].as_f64().expect("max");
    let p_gross = printed["gross_rate"].as_f64().expect("gross");
    eprintln!(
        "{address}: printed - recomputed: mean {:e}, max {:e}, gross {:e}",
        p_mean - mean,
        p_max - max,
        p_gross - gross
    );
    assert!(
        close(p_mean, mean),
        "printed mean {p_mean}, recomputed {mean}"
    );
    assert!(close(p_max, max), "printed max {p_max}, recomputed {max}");
    assert_eq!(p_gross, gross, "printed gross, recomputed");
    assert_eq!(printed["nan_pixels"], 0);
    assert_eq!(printed["address"], address.to_string());
}

/// `--shadows` adds a ninth column, the visible fraction at the hit; its printed error against the
/// exact reference is recomputed here from the dump.
#[test]
fn shadow_dump_has_the_visible_fraction() {
    let test = "trace-dump-shadows";
    if common::device(test).is_none() {
        return;
    }
    let dir = common::scratch_dir(test);
    let dump = dir.join("vis.npy");
    let out = Command::new(env!("CARGO_BIN_EXE_relief"))
        .args([
            "trace", "--field", "bricks", "--size", "64", "--method", "qdm",
        ])
        .args(["--angle", "50", "--depth-scale", "0.1", "--grid", "12x10"])
        .args([
            "--shadows",
            "cone",
            "--light-elevation",
            "20",
            "--light-azimuth",
        ])
        .args(["-30", "--light-radius", "4", "--reference-samples", "6"])
        .args(["--dump", dump.to_str().expect("utf-8")])
        .output()
        .expect("binary runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let printed: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON line");
    let (shape, values) = common::npy::read_npy(&std::fs::read(&dump).expect("dump written"));
    assert_eq!(shape, [10, 12, 9]);
    let hf = Generator::Bricks.generate(64, 64, 1).quantized_unorm16();
    let light = relief::heightfield::visibility::LightDir {
        elevation_deg: 20.0,
        azimuth_deg: -30.0,
        radius_deg: 4.0,
    };
    let errors: Vec<f64> = values
        .chunks_exact(9)
        .map(|r| {
            let (u, v) = (f64::from(r[5]), f64::from(r[6]));
            let exact = relief::heightfield::visibility::light_visibility(
                &hf,
                f64::from(0.1f32),
                Address::Repeat,
                (u, v),
                light,
                6,
            )
            .expect("reference");
            assert!((0.0..=1.0).contains(&r[8]), "visible fraction {}", r[8]);
            (f64::from(r[8]) - exact.fraction).abs()
        })
        .collect();
    let mean = errors.iter().sum::<f64>() / errors.len() as f64;
    let stats = &printed["shadow"]["stats"];
    let p_mean = stats["abs_error"]["mean"].as_f64().expect("mean");
    assert!(
        (p_mean - mean).abs() < 1e-9,
        "printed {p_mean}, recomputed {mean}"
    );
    assert_eq!(printed["shadow"]["mode"], "cone");
    assert_eq!(stats["points"], 120);
}
