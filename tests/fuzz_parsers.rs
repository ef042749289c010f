//! Generated bad input for every file parser relief has: structure-aware mutations of valid
//! files (cut short, bytes flipped, counts and sizes made extreme, JSON values of the wrong type,
//! NaN and infinities, deep nesting). Each parser must return an error that names the file, or
//! a value, never panic, within 10 s, holding at most 32 MiB plus 64 bytes per input byte at
//! once (`fuzz_support::bounded`). `PROPTEST_CASES=N` runs N cases a parser instead of the
//! default. The reproducers of failures found are the named tests at the end.

mod common;
mod fuzz_support;

use std::path::{Path, PathBuf};

use fuzz_support::alloc_cap::Counting;
use fuzz_support::bounded::{run_bounded, Bounds};
use fuzz_support::mutate::{apply_bytes, apply_json, byte_edits, json_edits, ByteEdit};
use fuzz_support::png_seed::{self, PngSpec};
use fuzz_support::{case_file, config, gltf_seed};
use proptest::prelude::*;
use relief::environment::Environment;
use relief::heightfield::{Generator, LoadOptions};
use relief::scene::{load_gltf, SceneOptions};
use relief::terrain::{GridOptions, Stroke, TerrainEditor};
use relief::vk::{check_pipeline_cache_header, CacheIdentity};

#[global_allocator]
static ALLOC: Counting = Counting;

/// Cases a parser runs by default.
const CASES: u32 = 300;

fn scratch(test: &str) -> PathBuf {
    common::scratch_dir(test)
}

/// Writes `bytes` to a fresh `.ext` file in `folder` and runs `parse` on it under the bounds;
/// an error must name the file. `Ok(Some(message))`: refused, as it said.
fn parse_file<T: 'static, E: std::fmt::Display + 'static>(
    folder: &Path,
    ext: &str,
    bytes: &[u8],
    parse: fn(&Path) -> Result<T, E>,
) -> Result<Option<String>, String> {
    let path = case_file(folder, ext);
    std::fs::write(&path, bytes).expect("scratch is writable");
    let name = path.file_name().unwrap().to_string_lossy().into_owned();
    let bounds = Bounds::for_input(bytes.len());
    let outcome = run_bounded(bounds, {
        let path = path.clone();
        move || parse(&path).map(drop).map_err(|e| e.to_string())
    });
    let verdict = match outcome {
        Err(broke) => Err(format!("{}: {broke}", path.display())),
        Ok(Err(message)) if !message.contains(&name) => Err(format!(
            "{}: the error does not name the file: {message}",
            path.display()
        )),
        Ok(Err(message)) => Ok(Some(message)),
        Ok(Ok(())) => Ok(None),
    };
    if verdict.is_ok() {
        let _ = std::fs::remove_file(&path);
    }
    verdict
}

fn gltf(path: &Path) -> Result<relief::scene::Scene, relief::scene::SceneError> {
    load_gltf(path, &SceneOptions::default())
}

fn hdr(path: &Path) -> Result<Environment, relief::environment::EnvironmentError> {
    Environment::load(path)
}

fn png(
    path: &Path,
) -> Result<relief::heightfield::Heightfield, relief::heightfield::HeightfieldError> {
    relief::heightfield::Heightfield::load_png(path, &LoadOptions::default())
}

/// A 16x8 environment as `Environment::save` writes it (made once: the tests run at once).
fn hdr_seed() -> Vec<u8> {
    static SEED: std::sync::OnceLock<Vec<u8>> = std::sync::OnceLock::new();
    SEED.get_or_init(|| {
        let path = scratch("hdr-seed").join("seed.hdr");
        Environment::from_fn("seed", 16, 8, |d| {
            glam::Vec3::new(d.x + 1.5, d.y + 1.5, 0.25)
        })
        .save(&path)
        .expect("saves");
        std::fs::read(&path).expect("reads back")
    })
    .clone()
}

/// The seeds load: the mutations start from valid files, so what they break is the parser's
/// business.
#[test]
fn the_seeds_are_valid() {
    let folder = scratch("seeds");
    let text = serde_json::to_vec(&gltf_seed::gltf_json()).unwrap();
    for (ext, bytes) in [("gltf", text), ("glb", gltf_seed::glb())] {
        let path = folder.join(format!("seed.{ext}"));
        std::fs::write(&path, bytes).unwrap();
        let scene = gltf(&path).unwrap_or_else(|e| panic!("the {ext} seed loads: {e}"));
        assert!(scene.materials[0].relief.is_some(), "{ext}: relief read");
        assert!(scene.camera_path.is_some(), "{ext}: camera path read");
    }
    let path = folder.join("seed.hdr");
    std::fs::write(&path, hdr_seed()).unwrap();
    hdr(&path).expect("the .hdr seed loads");
    for spec in png_seed::seeds() {
        let path = folder.join("seed.png");
        std::fs::write(&path, png_seed::png(&spec)).unwrap();
        let hf = png(&path).unwrap_or_else(|e| panic!("{spec:?} loads: {e}"));
        assert_eq!((hf.width(), hf.height()), (spec.width, spec.height));
    }
}

/// The bounds can fail: a panic, a hang and an allocation over the cap are each caught.
#[test]
fn the_bounds_catch_a_panic_a_hang_and_a_large_allocation() {
    // Long enough for the panic hook to print a backtrace.
    let bounds = Bounds {
        time: std::time::Duration::from_secs(10),
        bytes: 1 << 20,
    };
    let e = run_bounded(bounds, || panic!("on purpose")).unwrap_err();
    assert!(e.contains("panicked: on purpose"), "{e}");
    let short = Bounds {
        time: std::time::Duration::from_millis(200),
        ..bounds
    };
    let e = run_bounded(short, || {
        std::thread::sleep(std::time::Duration::from_secs(3))
    })
    .unwrap_err();
    assert!(e.contains("did not return"), "{e}");
    let e = run_bounded(bounds, || vec![1u8; 4 << 20].len()).unwrap_err();
    assert!(e.contains("over the cap"), "{e}");
    assert_eq!(
        run_bounded(bounds, || vec![1u8; 1 << 10].len()),
        Ok(1 << 10)
    );
}

/// Sizes a header may claim: nothing, one texel, 10^9 texels, 2^32 - 1 wide, the largest read.
const HOSTILE_SIZES: [(u32, u32); 8] = [
    (0, 0),
    (1, 1),
    (31_623, 31_623),
    (u32::MAX, 1),
    (1, u32::MAX),
    (8192, 4096),
    (65_535, 65_535),
    (16, 1_000_000),
];

/// The `.hdr` seed with its resolution line claiming `(width, height)` in one of its orientations.
fn hdr_claiming(width: u32, height: u32, orientation: usize) -> Vec<u8> {
    let seed = hdr_seed();
    let text = String::from_utf8_lossy(&seed).into_owned();
    let line = [
        "-Y {h} +X {w}",
        "+Y {h} +X {w}",
        "-Y {h} -X {w}",
        "+X {w} -Y {h}",
    ][orientation % 4]
        .replace("{h}", &height.to_string())
        .replace("{w}", &width.to_string());
    let at = text.find("-Y 8 +X 16").expect("the seed's resolution line");
    let mut out = seed[..at].to_vec();
    out.extend_from_slice(line.as_bytes());
    out.extend_from_slice(&seed[at + "-Y 8 +X 16".len()..]);
    out
}

/// The PNG of `spec` with its header rewritten (valid CRC, so the decoder believes it).
fn png_claiming(spec: &PngSpec, claimed: &PngSpec) -> Vec<u8> {
    let mut bytes = png_seed::png(spec);
    let header = png_seed::ihdr(claimed);
    bytes[8..8 + header.len()].copy_from_slice(&header);
    bytes
}

fn stroke_seed() -> serde_json::Value {
    serde_json::json!([
        [{"kind": "raise", "x": 30, "y": 20, "radius": 8, "strength": 0.05}],
        [{"kind": "crater", "x": 10, "y": 50, "radius": 12, "strength": 0.08},
         {"kind": "flatten", "x": 40, "y": 40, "radius": 16, "strength": 0.5, "target": 0.3},
         {"kind": "lower", "x": 63, "y": 0, "radius": 64, "strength": 1.0}]
    ])
}

/// What `relief render --edits` does with the file's text: parse, check every stroke against
/// the elevation, apply the elevation strokes (paint strokes go to the layers, not here).
fn apply_strokes(text: &str) -> Result<(), String> {
    let frames: Vec<Vec<Stroke>> = serde_json::from_str(text).map_err(|e| e.to_string())?;
    let elevation = Generator::Fbm.generate(64, 64, 7);
    let mut editor = TerrainEditor::new(elevation, &GridOptions::default(), "ground", 0);
    for strokes in &frames {
        for (k, s) in strokes.iter().enumerate() {
            s.check(k, 64, 64).map_err(|e| e.to_string())?;
        }
        let shape: Vec<Stroke> = strokes.iter().filter(|s| !s.paints()).copied().collect();
        editor.apply(&shape).map_err(|e| e.to_string())?;
    }
    Ok(())
}

fn identity() -> CacheIdentity {
    CacheIdentity {
        vendor_id: 0x10005,
        device_id: 0,
        uuid: *b"relief-fuzz-uuid",
    }
}

fn cache_seed() -> Vec<u8> {
    let id = identity();
    let mut bytes = Vec::new();
    for word in [32u32, 1, id.vendor_id, id.device_id] {
        bytes.extend_from_slice(&word.to_le_bytes());
    }
    bytes.extend_from_slice(&id.uuid);
    bytes.extend_from_slice(b"the driver's own bytes follow");
    bytes
}

proptest! {
    #![proptest_config(config(CASES))]

    #[test]
    fn gltf_json_mutations_are_refused_by_name(edits in json_edits()) {
        let folder = scratch("gltf-json");
        let text = apply_json(&gltf_seed::gltf_json(), &edits);
        parse_file(&folder, "gltf", text.as_bytes(), gltf).map_err(TestCaseError::fail)?;
    }

    #[test]
    fn glb_byte_mutations_are_refused_by_name(edits in byte_edits()) {
        let folder = scratch("glb-bytes");
        let bytes = apply_bytes(&gltf_seed::glb(), &edits);
        parse_file(&folder, "glb", &bytes, gltf).map_err(TestCaseError::fail)?;
    }

    #[test]
    fn hdr_byte_mutations_are_refused_by_name(edits in byte_edits()) {
        let folder = scratch("hdr-bytes");
        let bytes = apply_bytes(&hdr_seed(), &edits);
        parse_file(&folder, "hdr", &bytes, hdr).map_err(TestCaseError::fail)?;
    }

    #[test]
    fn hdr_claimed_sizes_are_held_to_the_bytes(
        size in proptest::sample::select(HOSTILE_SIZES.to_vec()),
        orientation in 0..4usize,
        edits in proptest::collection::vec(fuzz_support::mutate::byte_edit(), 0..2),
    ) {
        let folder = scratch("hdr-sizes");
        let bytes = apply_bytes(&hdr_claiming(size.0, size.1, orientation), &edits);
        parse_file(&folder, "hdr", &bytes, hdr).map_err(TestCaseError::fail)?;
    }

    #[test]
    fn png_byte_mutations_are_refused_by_name(
        seed in proptest::sample::select(png_seed::seeds()),
        edits in byte_edits(),
    ) {
        let folder = scratch("png-bytes");
        let bytes = apply_bytes(&png_seed::png(&seed), &edits);
        parse_file(&folder, "png", &bytes, png).map_err(TestCaseError::fail)?;
    }

    #[test]
    fn png_claimed_headers_are_held_to_the_bytes(
        seed in proptest::sample::select(png_seed::seeds()),
        size in proptest::sample::select(HOSTILE_SIZES.to_vec()),
        depth in proptest::sample::select(vec![1u8, 2, 4, 8, 16, 7]),
        interlaced in any::<bool>(),
        cut in proptest::option::of(any::<usize>()),
    ) {
        let folder = scratch("png-sizes");
        let claimed = PngSpec { width: size.0, height: size.1, depth, interlaced, ..seed };
        let mut bytes = png_claiming(&seed, &claimed);
        if let Some(at) = cut {
            bytes = apply_bytes(&bytes, &[ByteEdit::Truncate(at)]);
        }
        parse_file(&folder, "png", &bytes, png).map_err(TestCaseError::fail)?;
    }

    #[test]
    fn stroke_json_mutations_are_refused_or_applied(edits in json_edits()) {
        let text = apply_json(&stroke_seed(), &edits);
        let bounds = Bounds::for_input(text.len());
        // Refused or applied, both fine: only a broken bound fails.
        let _applied = run_bounded(bounds, move || apply_strokes(&text)).map_err(TestCaseError::fail)?;
    }

    #[test]
    fn pipeline_cache_mutations_never_pass_a_damaged_header(edits in byte_edits()) {
        let seed = cache_seed();
        let bytes = apply_bytes(&seed, &edits);
        let checked = run_bounded(Bounds::for_input(bytes.len()), {
            let bytes = bytes.clone();
            move || check_pipeline_cache_header(&bytes, &identity())
        })
        .map_err(TestCaseError::fail)?;
        // The header is the first 32 bytes: it passes exactly when they are the seed's.
        let intact = bytes.len() >= 32 && bytes[..32] == seed[..32];
        prop_assert_eq!(checked.is_ok(), intact, "{:?}", checked);
    }
}

/// Runs `parse` on `bytes` as a `.ext` file and returns its refusal, failing the test if it
/// broke a bound or accepted the file.
fn refused<T: 'static, E: std::fmt::Display + 'static>(
    test: &str,
    ext: &str,
    bytes: &[u8],
    parse: fn(&Path) -> Result<T, E>,
) -> String {
    match parse_file(&scratch(test), ext, bytes, parse) {
        Err(broke) => panic!("{broke}"),
        Ok(None) => panic!("a lying {ext} file was accepted"),
        Ok(Some(message)) => message,
    }
}

// The hostile headers the parsers must refuse before they allocate what they claim.

#[test]
fn an_hdr_claiming_a_billion_texels_is_refused_within_the_cap() {
    let message = refused("hdr-billion", "hdr", &hdr_claiming(31_623, 31_623, 0), hdr);
    assert!(message.contains("31623x31623"), "{message}");
}

#[test]
fn an_hdr_claiming_8k_by_4k_over_a_few_hundred_bytes_is_refused_within_the_cap() {
    let message = refused("hdr-8k", "hdr", &hdr_claiming(8192, 4096, 0), hdr);
    assert!(
        message.contains("8192x4096") && message.contains("bytes"),
        "{message}"
    );
}

#[test]
fn a_gltf_accessor_claiming_2_to_the_32_elements_is_refused_within_the_cap() {
    for (accessor, view) in [(0, true), (1, false)] {
        let mut doc = gltf_seed::gltf_json();
        doc["accessors"][accessor]["count"] = serde_json::json!(u32::MAX);
        if !view {
            doc["accessors"][accessor]
                .as_object_mut()
                .unwrap()
                .remove("bufferView");
        }
        let text = serde_json::to_vec(&doc).unwrap();
        let message = refused("accessor-2-32", "gltf", &text, gltf);
        assert!(message.contains("4294967295"), "{message}");
    }
}

#[test]
fn a_png_height_map_claiming_65535_squared_pixels_is_refused_within_the_cap() {
    for seed in png_seed::seeds() {
        let claimed = PngSpec {
            width: 65_535,
            height: 65_535,
            ..seed
        };
        let message = refused("png-huge", "png", &png_claiming(&seed, &claimed), png);
        assert!(message.contains("png"), "{message}");
    }
}

#[test]
fn a_gltf_embedded_png_claiming_11000_squared_pixels_is_refused_within_the_cap() {
    let seed = png_seed::seeds()[3];
    let claimed = PngSpec {
        width: 11_000,
        height: 11_000,
        ..seed
    };
    let lying = png_claiming(&seed, &claimed);
    let mut doc = gltf_seed::gltf_json();
    doc["images"][0]["uri"] = serde_json::json!(format!(
        "data:image/png;base64,{}",
        common::base64::base64(&lying)
    ));
    let text = serde_json::to_vec(&doc).unwrap();
    let message = refused("embedded-png", "gltf", &text, gltf);
    assert!(message.contains("11000x11000"), "{message}");
}

// Reproducers of failures the generated cases found.

/// Found by `gltf_json_mutations_are_refused_by_name`: an accessor replaced by a number or an
/// array was taken for one with neither bufferView nor sparse, and filling in its zero buffer
/// indexed into it as an object (a panic in the prepass).
#[test]
fn an_accessor_that_is_not_an_object_is_refused_by_name() {
    for not_an_object in [
        serde_json::json!(-1),
        serde_json::json!([]),
        serde_json::json!("x"),
    ] {
        let mut doc = gltf_seed::gltf_json();
        doc["accessors"][2] = not_an_object.clone();
        let text = serde_json::to_vec(&doc).unwrap();
        let message = refused("accessor-not-object", "gltf", &text, gltf);
        assert!(
            message.to_lowercase().contains("accessor"),
            "{not_an_object}: {message}"
        );
    }
}

/// Also from the glTF cases: an all-zero accessor (no bufferView, no sparse) claiming 2^26
/// elements was given a zero buffer as a 358 MB base64 data URI before anything was read.
#[test]
fn an_all_zero_accessor_claiming_millions_of_elements_is_refused_within_the_cap() {
    let mut doc = gltf_seed::gltf_json();
    let accessor = doc["accessors"][1].as_object_mut().unwrap();
    accessor.remove("bufferView");
    accessor.insert("count".into(), serde_json::json!(1u64 << 26));
    let text = serde_json::to_vec(&doc).unwrap();
    let message = refused("zero-accessor", "gltf", &text, gltf);
    assert!(message.contains("67108864"), "{message}");
}
