//! The binary's happy paths: render the default scene with --json, and write pyramid levels.

mod common;

use std::process::Command;

fn relief(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(args)
        .output()
        .expect("binary runs")
}

/// Renders the default scene at `width` x `height` with `method` and flags, one of which makes
/// the CLI print one JSON object; returns that object and the PNG's path.
fn render_default(
    name: &str,
    width: &str,
    height: &str,
    method: &str,
    flags: &[&str],
) -> (serde_json::Value, std::path::PathBuf) {
    let out = common::scratch_dir(name).join("frame.png");
    let mut args = vec![
        "render",
        "--out",
        out.to_str().expect("utf-8"),
        "--width",
        width,
        "--height",
        height,
        "--method",
        method,
    ];
    args.extend_from_slice(flags);
    let run = relief(&args);
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "render {flags:?} failed:\n{err}");
    let json = serde_json::from_slice(&run.stdout).expect("one JSON object");
    (json, out)
}

#[test]
fn render_default_scene_reports_passes() {
    if common::device("render_default_scene_reports_passes").is_none() {
        return;
    }
    let (report, out) = render_default("render-json", "96", "64", "qdm", &["--json"]);
    assert!(report["device"]["name"]
        .as_str()
        .is_some_and(|n| !n.is_empty()));
    let passes = report["passes"].as_array().expect("passes");
    let names: Vec<&str> = passes.iter().filter_map(|p| p["pass"].as_str()).collect();
    // QDM reads the max pyramid, so its build is a pass of its own; the default scene's bricks
    // ask for horizon AO, built once after it; its sun casts, so its shadow map comes before the
    // surface; the occluder pass bounds what the relief slab's fragments must trace.
    assert_eq!(
        names,
        ["pyramid", "ao map", "shadow maps", "occluders", "surface"]
    );
    assert!(
        passes
            .iter()
            .all(|p| p["gpu_ms"].as_f64().is_some_and(|ms| ms > 0.0)),
        "{passes:?}"
    );
    let png = image::open(&out).expect("PNG written").to_rgba8();
    assert_eq!(png.dimensions(), (96, 64));
}

#[test]
fn maps_writes_every_pyramid_level() {
    if common::device("maps_writes_every_pyramid_level").is_none() {
        return;
    }
    // maps fails when the GPU pyramid differs from the CPU builder's, under either addressing.
    for address in ["repeat", "clamp"] {
        let dir = common::scratch_dir(&format!("maps-{address}"));
        let run = relief(&[
            "maps",
            "--field",
            "fbm",
            "--size",
            "37",
            "--address",
            address,
            "--out",
            dir.to_str().expect("utf-8"),
        ]);
        assert!(
            run.status.success(),
            "maps --address {address} failed:\n{}",
            String::from_utf8_lossy(&run.stderr)
        );
        // 37 -> 18 -> 9 -> 4 -> 2 -> 1: six levels, each a PNG of the right size.
        for (k, side) in [37u32, 18, 9, 4, 2, 1].into_iter().enumerate() {
            let level = image::open(dir.join(format!("level_{k:02}.png"))).expect("level written");
            assert_eq!((level.width(), level.height()), (side, side), "level {k}");
        }
        assert!(!dir.join("level_06.png").exists());
    }
}

#[test]
fn maps_builds_the_cone_map_on_the_gpu_or_on_request_the_cpu() {
    if common::device("maps_builds_the_cone_map").is_none() {
        return;
    }
    for (on, says) in [("gpu", "built on the GPU"), ("cpu", "built on the CPU")] {
        let dir = common::scratch_dir(&format!("maps-csm-{on}"));
        let run = relief(&[
            "maps",
            "--field",
            "fbm",
            "--size",
            "37",
            "--method",
            "csm",
            "--map-on",
            on,
            "--out",
            dir.to_str().expect("utf-8"),
        ]);
        let out = String::from_utf8_lossy(&run.stdout);
        assert!(
            run.status.success(),
            "maps --map-on {on} failed:\n{}",
            String::from_utf8_lossy(&run.stderr)
        );
        assert!(out.contains(says), "{on}: {out}");
        assert!(dir.join("map.npy").exists(), "{on}: map.npy written");
    }
}

#[test]
fn explain_prints_the_plan() {
    if common::device("explain_prints_the_plan").is_none() {
        return;
    }
    // Hard shadows and no AO: then csm needs its cone map and nothing else (the default scene's
    // cone shadows and horizon AO would read the pyramid).
    let flags = ["--explain", "--shadows", "hard", "--ao", "none"];
    let (plan, _) = render_default("explain", "64", "48", "csm", &flags);
    assert!(
        plan["device"]["name"].is_string() && plan["device"]["ray_query"].is_boolean(),
        "--explain carries the device block: {}",
        plan["device"]
    );
    // It says whether the frame traces by ray query, and why not.
    let rays = &plan["ray_queries"];
    assert_eq!(rays["available"], plan["device"]["ray_query"], "{rays}");
    assert_eq!(rays["used_by_frame"], false, "{rays}");
    assert!(
        rays["why"].as_str().is_some_and(|w| w.contains("raster")),
        "{rays}"
    );
    let shaders: Vec<&str> = plan["pipelines"]
        .as_array()
        .expect("pipelines")
        .iter()
        .filter_map(|p| p["shader"].as_str())
        .collect();
    assert_eq!(shaders, ["surface.frag:csm", "surface.frag:plain"]);
    let all_maps = plan["maps"].as_array().expect("maps");
    // The built-in sky's maps (the command line's default ambient light), then the height maps'.
    let sky = all_maps.iter().find(|m| m["kind"] == "environment maps");
    assert!(
        sky.is_some_and(|m| m["source"] == "built-in sky"),
        "{all_maps:?}"
    );
    assert_eq!(
        plan["environment"]["irradiance_size"],
        serde_json::json!([32, 16])
    );
    let maps: Vec<_> = all_maps
        .iter()
        .filter(|m| m["kind"] != "environment maps")
        .collect();
    assert_eq!(maps.len(), 1, "the cone map only: {maps:?}");
    assert_eq!(maps[0]["kind"], "cone_map");
    assert_eq!(maps[0]["size"], serde_json::json!([256, 256]));
    assert!(maps[0]["ms"].as_f64().is_some_and(|ms| ms > 0.0));
    let skipped = plan["skipped"].as_array().expect("skipped");
    for what in ["max_pyramid", "quadric_map", "relaxed_cone_map", "ao map"] {
        let entry = skipped.iter().find(|s| s["what"] == what);
        assert!(
            entry.is_some_and(|e| e["why"].as_str().is_some_and(|w| !w.is_empty())),
            "{what} skipped with a reason: {skipped:?}"
        );
    }
    assert!(plan["passes"]
        .as_array()
        .expect("passes")
        .iter()
        .any(|p| p["name"] == "surface"));
    assert_eq!(maps[0]["on"], "gpu", "csm's cone map is built on the GPU");
    assert_eq!(
        plan["created"]["compute_pipelines"], 4,
        "no pyramid for csm, only the cone map build and the sky's three kernels"
    );
    // The slab and the plain meshes, each drawn, each casting into the sun's map and each
    // bounding what lies behind it, the tone-mapping pass and the sky behind the scene.
    assert_eq!(plan["created"]["graphics_pipelines"], 8);
    let maps = plan["shadow_maps"].as_array().expect("shadow maps");
    assert_eq!(maps.len(), 1, "{maps:?}");
    assert_eq!(maps[0]["kind"], "cascades");
    assert_eq!(maps[0]["caster_meshes"].as_array().map(Vec::len), Some(4));
    // The frame's graph: its passes in recording order, each with what it reads and writes.
    let nodes = plan["graph"]["nodes"].as_array().expect("graph nodes");
    let order: Vec<&str> = nodes.iter().filter_map(|n| n["pass"].as_str()).collect();
    assert_eq!(
        order,
        [
            "shadow maps",
            "occluders",
            "surface",
            "background",
            "tone map"
        ],
        "csm without the pyramid: {nodes:?}"
    );
    let surface = nodes
        .iter()
        .find(|n| n["pass"] == "surface")
        .expect("surface");
    assert_eq!(
        surface["reads"],
        serde_json::json!(["shadow-atlas", "occluder-bounds"])
    );
    assert_eq!(nodes[0]["rate"], "when-changed");
}

#[test]
fn explain_says_where_the_frame_is_lit_and_deferred_needs_one_sample() {
    if common::device("explain_says_where_the_frame_is_lit").is_none() {
        return;
    }
    let flags = ["--explain", "--msaa", "1", "--lighting", "deferred"];
    let (plan, _) = render_default("explain-deferred", "64", "48", "qdm", &flags);
    assert_eq!(plan["lighting"]["path"], "deferred", "{}", plan["lighting"]);
    let nodes = plan["graph"]["nodes"].as_array().expect("graph nodes");
    let lighting = nodes
        .iter()
        .find(|n| n["pass"] == "lighting")
        .expect("a lighting node");
    assert_eq!(
        lighting["reads"],
        serde_json::json!(["shadow-atlas", "g-buffer", "shading-inputs"])
    );
    // The default look draws 4 samples: forward, and --explain says what deferred would need.
    let (plan, _) = render_default("explain-forward", "64", "48", "qdm", &["--explain"]);
    assert_eq!(plan["lighting"]["path"], "forward");
    let why = plan["lighting"]["deferred_refused"].as_str().unwrap_or("");
    assert!(why.contains("--msaa 1"), "{}", plan["lighting"]);
    // Asked for with 4 samples: refused by name, nothing written.
    let out = common::scratch_dir("deferred-refused").join("frame.png");
    let run = relief(&[
        "render",
        "--width",
        "64",
        "--height",
        "48",
        "--lighting",
        "deferred",
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success(), "deferred with 4 samples ran");
    assert!(
        err.contains("--lighting deferred") && err.contains("--msaa 1"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    assert!(!out.exists(), "no frame written");
}

#[test]
fn explain_says_the_frame_traces_its_shadows_by_ray_query() {
    let out = common::scratch_dir("explain-traced").join("frame.png");
    let Some(run) = common::cli::relief_with_ray_queries(&[
        "render",
        "--width",
        "64",
        "--height",
        "48",
        "--msaa",
        "1",
        "--lighting",
        "deferred",
        "--traced-shadows",
        "--explain",
        "--out",
        out.to_str().expect("utf-8"),
    ]) else {
        return;
    };
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{err}");
    let plan: serde_json::Value = serde_json::from_slice(&run.stdout).expect("one JSON object");
    assert_eq!(
        plan["lighting"]["shadows"], "traced",
        "{}",
        plan["lighting"]
    );
    assert_eq!(plan["ray_queries"]["used_by_frame"], true);
    assert!(
        plan["shadow_maps"].as_array().is_some_and(Vec::is_empty),
        "no map is built: {}",
        plan["shadow_maps"]
    );
    let skipped = plan["skipped"].as_array().expect("skipped");
    assert!(
        skipped.iter().any(|s| s["what"] == "shadow maps"
            && s["why"].as_str().is_some_and(|w| w.contains("traced"))),
        "{skipped:?}"
    );
}

#[test]
fn a_frame_sequence_reuses_its_resources_and_reports_steady_statistics() {
    if common::device("frame_sequence_statistics").is_none() {
        return;
    }
    let run = relief(&[
        "render",
        "--width",
        "64",
        "--height",
        "36",
        "--method",
        "qdm",
        "--frames",
        "4",
        "--orbit",
        "360",
        "--no-write",
        "--json",
    ]);
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "render --frames failed:\n{err}");
    let report: serde_json::Value = serde_json::from_slice(&run.stdout).expect("one JSON object");
    assert_eq!(report["frames"], 4);
    assert!(
        report["out"].is_null(),
        "--no-write writes nothing: {report}"
    );
    let first: Vec<&str> = report["passes"]
        .as_array()
        .expect("first frame's passes")
        .iter()
        .filter_map(|p| p["pass"].as_str())
        .collect();
    assert_eq!(
        first,
        ["pyramid", "ao map", "shadow maps", "occluders", "surface"],
        "the first frame builds the pyramid and the AO map"
    );
    let steady = report["steady"].as_array().expect("steady statistics");
    let names: Vec<&str> = steady.iter().filter_map(|p| p["pass"].as_str()).collect();
    assert_eq!(
        names,
        ["shadow maps", "occluders", "surface"],
        "only the shadow maps, the occluders and the surface pass after frame 1: {steady:?}"
    );
    let surface = &steady[2];
    assert_eq!(surface["pass"], "surface");
    assert_eq!(surface["frames"], 3);
    let ms = |key: &str| surface[key].as_f64().expect(key);
    assert!(ms("min_ms") > 0.0 && ms("min_ms") <= ms("median_ms"));
    assert!(ms("median_ms") <= ms("p95_ms"), "{surface}");
    let created = &report["created_after_first_frame"];
    for (key, count) in created.as_object().expect("counts") {
        assert_eq!(count, 0, "{key} created after the first frame: {created}");
    }
    // vk counts destructions too: a sequence that keeps its resources ends with what it had
    // after its first frame, and has some.
    let alive = &report["alive"];
    assert_eq!(
        alive["after_first_frame"], alive["after_last_frame"],
        "objects alive changed over the sequence"
    );
    assert!(alive["after_last_frame"]["buffers"]
        .as_u64()
        .is_some_and(|n| n > 0));
    assert!(alive["after_last_frame"]["allocated_bytes"]
        .as_u64()
        .is_some_and(|n| n > 0));
    let device = &report["device"];
    for key in ["ray_query", "acceleration_structure"] {
        assert!(device[key].is_boolean(), "device lacks {key}: {device}");
    }
}

#[test]
fn a_frame_sequence_writes_numbered_files() {
    if common::device("frame_sequence_files").is_none() {
        return;
    }
    let dir = common::scratch_dir("frame-sequence");
    let out = dir.join("shot.png");
    let run = relief(&[
        "render",
        "--width",
        "48",
        "--height",
        "32",
        "--frames",
        "2",
        "--orbit",
        "90",
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "render --frames failed:\n{err}");
    let first = image::open(dir.join("shot_0001.png"))
        .expect("frame 1")
        .to_rgba8();
    let second = image::open(dir.join("shot_0002.png"))
        .expect("frame 2")
        .to_rgba8();
    assert_eq!(first.dimensions(), (48, 32));
    assert!(!out.exists(), "a sequence writes numbered files only");
    assert_ne!(
        first.as_raw(),
        second.as_raw(),
        "the orbit moved the camera"
    );
    assert!(
        err.contains("objects created after the first frame: none"),
        "{err}"
    );
}

#[test]
fn the_pipeline_cache_persists_between_runs_and_a_corrupt_one_is_ignored() {
    if common::device("pipeline_cache_persists").is_none() {
        return;
    }
    let dir = common::scratch_dir("pipeline-cache");
    let cache = dir.join("pipelines.bin");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "render",
            "--width",
            "32",
            "--height",
            "32",
            "--method",
            "qdm",
            "--no-write",
            "--json",
        ];
        args.extend_from_slice(extra);
        let out = relief(&args);
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(out.status.success(), "render failed:\n{err}");
        let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
        (report["pipeline_cache"].clone(), err)
    };
    let path = cache.to_str().expect("utf-8");
    let (first, _) = run(&["--pipeline-cache", path]);
    assert_eq!(first["seeded"], false, "{first}");
    // The slab (qdm) and the plain meshes, drawn, casting and bounding what lies behind them,
    // the tone-mapping pass, the pyramid build, the horizon AO build, the sky's three map
    // kernels and its background.
    assert_eq!(first["pipelines"], 13, "{first}");
    assert!(cache.exists(), "the cache was written");
    let (second, _) = run(&["--pipeline-cache", path]);
    assert_eq!(second["seeded"], true, "{second}");
    std::fs::write(&cache, b"not a pipeline cache at all, just bytes").expect("write");
    let (corrupt, err) = run(&["--pipeline-cache", path]);
    assert_eq!(corrupt["seeded"], false, "{corrupt}");
    assert!(
        err.contains("pipeline cache"),
        "a warning names the cache: {err}"
    );
    let (off, _) = run(&["--no-pipeline-cache"]);
    assert!(off["path"].is_null() && off["seeded"] == false, "{off}");
}

/// A plane whose one material carries relief from `extras.relief` (POM over a 4x4 height image),
/// written as a .gltf in `dir`.
fn plane_with_relief_extras(dir: &std::path::Path) -> std::path::PathBuf {
    let (bin, views, accessors) = common::plane_gltf::plane_buffer(None);
    let mut png = Vec::new();
    image::DynamicImage::ImageLuma8(image::GrayImage::from_fn(4, 4, |x, y| {
        image::Luma([(40 * (x + y)) as u8])
    }))
    .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
    .expect("png");
    let doc = serde_json::json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": bin.len(), "uri": format!("data:application/octet-stream;base64,{}", common::base64::base64(&bin))}],
        "bufferViews": views,
        "accessors": accessors,
        "images": [{"uri": format!("data:image/png;base64,{}", common::base64::base64(&png))}],
        "textures": [{"source": 0}],
        "materials": [{"name": "Bumps", "extras": {"relief": {"depth_scale": 0.05, "method": "pom", "height": {"index": 0}}}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "material": 0}]}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}],
    });
    let path = dir.join("plane.gltf");
    std::fs::write(&path, serde_json::to_vec(&doc).expect("json")).expect("writes");
    path
}

#[test]
fn method_overrides_the_methods_a_gltf_file_gives() {
    if common::device("method_overrides_the_methods_a_gltf_file_gives").is_none() {
        return;
    }
    let dir = common::scratch_dir("method-override");
    let file = plane_with_relief_extras(&dir);
    let shaders = |flags: &[&str]| -> Vec<String> {
        let mut args = vec!["render", file.to_str().expect("utf-8"), "--explain"];
        args.extend_from_slice(&["--width", "32", "--height", "24", "--no-write"]);
        args.extend_from_slice(flags);
        let run = relief(&args);
        assert!(
            run.status.success(),
            "render {flags:?} failed:\n{}",
            String::from_utf8_lossy(&run.stderr)
        );
        let plan: serde_json::Value = serde_json::from_slice(&run.stdout).expect("one JSON object");
        plan["pipelines"]
            .as_array()
            .expect("pipelines")
            .iter()
            .filter_map(|p| p["shader"].as_str().map(str::to_owned))
            .collect()
    };
    let own = shaders(&[]);
    assert!(own.iter().any(|s| s == "surface.frag:pom"), "{own:?}");
    let overridden = shaders(&["--method", "qdm"]);
    assert!(
        overridden.iter().any(|s| s == "surface.frag:qdm"),
        "{overridden:?}"
    );
    assert!(
        !overridden.iter().any(|s| s == "surface.frag:pom"),
        "--method left the file's method in place: {overridden:?}"
    );
}

#[test]
fn methods_prints_the_table_and_json_carries_each_default_budget() {
    let table = relief(&["methods"]);
    assert!(table.status.success());
    let text = String::from_utf8_lossy(&table.stdout);
    let mut lines = text.lines();
    let header = lines.next().expect("a header");
    assert!(
        header.starts_with("id") && header.contains("default budget"),
        "{header}"
    );
    let ids: Vec<&str> = lines.filter_map(|l| l.split_whitespace().next()).collect();
    let known: Vec<&str> = relief::method::Method::all().map(|m| m.id()).collect();
    assert_eq!(ids, known, "one row per method, in the table's order");
    assert!(text.contains("16 + 5"), "relief's budget: {text}");
    let json = relief(&["methods", "--json"]);
    let list: serde_json::Value = serde_json::from_slice(&json.stdout).expect("JSON");
    for m in list.as_array().expect("a list") {
        let steps = m["default_budget"]["max_steps"].as_u64();
        assert!(steps.is_some_and(|n| n >= 1), "no default budget in {m}");
        assert!(m["needs"].is_array() && m["fixed_step"].is_boolean(), "{m}");
    }
}

#[test]
fn write_depth_off_reaches_every_relief_pipeline() {
    if common::device("write_depth_off_reaches_every_relief_pipeline").is_none() {
        return;
    }
    let out = common::scratch_dir("write-depth-off").join("frame.png");
    let run = relief(&[
        "render",
        "--width",
        "32",
        "--height",
        "18",
        "--explain",
        "--write-depth",
        "off",
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let plan: serde_json::Value = serde_json::from_slice(&run.stdout).expect("JSON");
    let pipelines = plan["pipelines"].as_array().expect("pipelines");
    for p in pipelines {
        let relief = p["method"].is_string();
        assert_eq!(p["write_depth"], !relief, "{p}");
    }
    assert!(pipelines.iter().any(|p| p["method"].is_string()));
}
