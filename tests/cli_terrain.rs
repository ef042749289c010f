//! `relief render --terrain` through the binary: the layered plan with `--explain`, strokes
//! replayed between frames rebuilding only the tiles they touch, one-line refusals of bad edits
//! and layers, and the corpus's four ground layers over its real elevation map.

mod common;

use std::path::{Path, PathBuf};
use std::process::Output;

use common::cli::{assert_clean_failure, relief};
use relief::heightfield::Generator;
use serde_json::Value;

/// A `size`^2 fbm elevation map written as a 16-bit PNG.
fn elevation(dir: &Path, size: u32) -> PathBuf {
    let path = dir.join(format!("elevation{size}.png"));
    Generator::Fbm
        .generate(size, size, 9)
        .save_png16(&path)
        .unwrap();
    path
}

/// `relief render --terrain ELEVATION` small, with `extra`.
fn render_terrain(elevation: &Path, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "render",
        "--terrain",
        elevation.to_str().unwrap(),
        "--terrain-resolution",
        "128",
        "--out",
        out.to_str().unwrap(),
        "--width",
        "96",
        "--height",
        "64",
    ];
    args.extend_from_slice(extra);
    relief(&args)
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// `--edits FILE` with `text` written to `name` in `dir`.
fn edits(dir: &Path, name: &str, text: &str) -> Vec<String> {
    vec![
        "--edits".into(),
        write(dir, name, text).display().to_string(),
    ]
}

#[test]
fn strokes_between_frames_rebuild_only_the_tiles_they_touch() {
    if common::device("strokes_between_frames_rebuild_only_the_tiles_they_touch").is_none() {
        return;
    }
    let dir = common::scratch_dir("cli_terrain_edits");
    // 512^2 at the grid's defaults (a vertex every 4 texels, 32 quads a tile): 4x4 tiles.
    let elevation = elevation(&dir, 512);
    let strokes = write(
        &dir,
        "strokes.json",
        r#"[[{"kind": "raise", "x": 200, "y": 260, "radius": 32, "strength": 0.2}],
            [{"kind": "crater", "x": 400, "y": 320, "radius": 40, "strength": 0.2},
             {"kind": "paint", "layer": 3, "x": 300, "y": 150, "radius": 40, "strength": 0.9},
             {"kind": "flatten", "x": 160, "y": 400, "radius": 30, "strength": 0.5, "target": 0.4}]]"#,
    );
    let out = dir.join("frame.png");
    let run = render_terrain(
        &elevation,
        &out,
        &["--edits", strokes.to_str().unwrap(), "--explain"],
    );
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{err}");
    let plan: Value = serde_json::from_slice(&run.stdout).expect("one JSON object");
    assert_eq!(plan["pipelines"][0]["shader"], "surface.frag:qdm:layers");
    let kinds: Vec<&str> = plan["maps"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["kind"].as_str().unwrap())
        .collect();
    for kind in ["layer stack", "blended pyramid", "ao"] {
        assert!(kinds.contains(&kind), "{kinds:?}");
    }
    let edits = &plan["edits"];
    assert_eq!(
        edits["maps_built_once"].as_array().unwrap().len(),
        kinds.len()
    );
    let frames = edits["frames"].as_array().unwrap();
    assert_eq!(frames.len(), 2, "{edits}");
    for (f, expected_strokes) in frames.iter().zip([1, 3]) {
        assert_eq!(f["strokes"], expected_strokes);
        let rebuilt = f["tiles_rebuilt"].as_array().unwrap().len();
        let total = f["tiles_total"].as_u64().unwrap() as usize;
        assert!(rebuilt >= 1 && rebuilt < total / 2, "{f}");
    }
    // The raise moved the ground under the rules: they weighed its layers again there.
    let reweighed = &frames[0]["reweighed"];
    let again = reweighed["blended_texels"][0].as_u64().unwrap();
    assert!(again > 0 && again < 128 * 128 / 4, "{reweighed}");
    // The paint stroke re-blended a corner of the 128^2 field and its AO, not the whole.
    assert!(frames[0]["paint"].is_null(), "{}", frames[0]);
    let paint = &frames[1]["paint"];
    assert_eq!(paint["strokes"], 1, "{paint}");
    let blended = paint["blended_texels"][0].as_u64().unwrap();
    assert!(blended > 0 && blended < 128 * 128 / 4, "{paint}");
    let ao = paint["ao_texels"].as_u64().unwrap();
    assert!(ao >= blended && ao < 128 * 128, "{paint}");
    // Three frames written: the terrain as loaded, then after each list.
    for k in 1..=3 {
        assert!(dir.join(format!("frame_{k:04}.png")).exists());
    }
    let first = image::open(dir.join("frame_0001.png")).unwrap().to_rgba8();
    let last = image::open(dir.join("frame_0003.png")).unwrap().to_rgba8();
    assert_ne!(
        first.as_raw(),
        last.as_raw(),
        "the strokes changed the ground"
    );
}

#[test]
fn bad_edits_and_layers_fail_in_one_line() {
    let dir = common::scratch_dir("cli_terrain_errors");
    let elevation = elevation(&dir, 64);
    let out = dir.join("frame.png");
    let cases: Vec<(Vec<String>, Vec<&str>)> = vec![
        (
            edits(&dir, "outside.json", r#"[[{"kind": "raise", "x": 900, "y": 5, "radius": 4, "strength": 0.1}]]"#),
            vec![
                "outside.json",
                "frame list 0",
                "stroke 0",
                "misses the 64x64 map",
            ],
        ),
        (
            edits(&dir, "zero.json", r#"[[], [{"kind": "lower", "x": 5, "y": 5, "radius": 0, "strength": 0.1}]]"#),
            vec!["frame list 1", "radius 0"],
        ),
        (
            edits(&dir, "nan.json", r#"[[{"kind": "raise", "x": NaN, "y": 5, "radius": 4, "strength": 0.1}]]"#),
            vec!["nan.json", "expected an array of frames"],
        ),
        (
            edits(&dir, "unknown.json", r#"[[{"kind": "smooth", "x": 5, "y": 5, "radius": 4, "strength": 0.1}]]"#),
            vec!["unknown.json", "smooth"],
        ),
        (
            edits(&dir, "layer.json", r#"[[{"kind": "paint", "layer": 7, "x": 5, "y": 5, "radius": 4, "strength": 0.5}]]"#),
            vec!["layer.json", "stroke 0", "layer 7, but the material has 4 layers"],
        ),
        (
            [
                edits(&dir, "paint.json", r#"[[{"kind": "paint", "layer": 1, "x": 5, "y": 5, "radius": 4, "strength": 0.5}]]"#),
                vec!["--method".into(), "csm".into()],
            ]
            .concat(),
            vec!["paint.json", "cone map", "qdm"],
        ),
        (
            vec![
                "--edits".into(),
                dir.join("paint.json").display().to_string(),
                "--lod".into(),
            ],
            vec!["paint.json", "averaged pyramid", "--lod"],
        ),
        (
            vec!["--layer".into(), dir.join("nothing").display().to_string()],
            vec!["--layer", "nothing_height.png"],
        ),
        (vec!["--tiling".into(), "0".into()], vec!["--tiling"]),
    ];
    for (extra, needles) in cases {
        let extra: Vec<&str> = extra.iter().map(String::as_str).collect();
        let run = render_terrain(&elevation, &out, &extra);
        assert_clean_failure(&run, &needles);
    }
    // The terrain is its own scene: a scene file or a height map beside it is refused.
    let run = relief(&[
        "render",
        "scene.gltf",
        "--terrain",
        elevation.to_str().unwrap(),
    ]);
    common::cli::assert_usage_failure(&run, &["--terrain", "scene.gltf"]);
    let run = relief(&[
        "render",
        "--terrain",
        elevation.to_str().unwrap(),
        "--terrain-resolution",
        "100000",
    ]);
    assert_clean_failure(&run, &["--terrain-resolution", "16..=4096"]);
    let run = relief(&["render", "--terrain", "missing.png"]);
    assert_clean_failure(&run, &["--terrain", "missing.png"]);
}

#[test]
fn the_corpus_ground_layers_cover_the_corpus_elevation_map() {
    let Some(corpus) =
        common::corpus::corpus("the_corpus_ground_layers_cover_the_corpus_elevation")
    else {
        return;
    };
    if common::device("the_corpus_ground_layers_cover_the_corpus_elevation").is_none() {
        return;
    }
    let dir = common::scratch_dir("cli_terrain_corpus");
    let layers = corpus.join("terrain-layers");
    let elevation =
        corpus.join("heightmaps/vulkan-samples-assets/derived/terrain_heightmap_r16.png");
    let prefixes = [
        layers.join("hterrain-demo/sand"),
        layers.join("terrain3d/ground037"),
        layers.join("terrain3d/rock030"),
        layers.join("terrain3d/rock023"),
    ];
    let mut extra = vec!["--explain".to_owned()];
    for p in &prefixes {
        extra.push("--layer".into());
        extra.push(p.display().to_string());
    }
    let extra: Vec<&str> = extra.iter().map(String::as_str).collect();
    let out = dir.join("corpus.png");
    let run = render_terrain(&elevation, &out, &extra);
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{err}");
    let plan: Value = serde_json::from_slice(&run.stdout).unwrap();
    let source = plan["heights"][0]["source"].as_str().unwrap();
    assert!(source.starts_with("4 layers"), "{source}");
    assert_eq!(plan["pipelines"][0]["shadows"], "cone");
    // Four layers of colour: the ground is neither one flat colour nor empty.
    let image = image::open(&out).unwrap().to_rgba8();
    let distinct: std::collections::HashSet<[u8; 3]> = image
        .pixels()
        .map(|p| [p.0[0] / 16, p.0[1] / 16, p.0[2] / 16])
        .collect();
    assert!(distinct.len() > 40, "{} colours", distinct.len());
}
