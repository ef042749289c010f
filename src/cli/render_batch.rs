//! `relief render` over several scenes, or through every camera of a scene (`--camera all`): one
//! device for the whole batch, each scene's files tagged with its name so no two collide, a
//! failing scene reported and passed over (unless `--fail-fast`), and a summary at the end. One
//! scene through one camera is not a batch: its files keep their names and its error is the run's.

use std::path::Path;
use std::sync::Arc;

use relief::vk::Context;
use serde_json::json;

use super::error_message;
use super::render::{open_device, render_scene, RenderArgs};
use super::render_frames::SceneSummary;
use super::scene_args::CameraChoice;

/// One image set of a batch: a scene through one camera, and how it went.
struct Item {
    /// The scene file and camera, as the summary names them.
    name: String,
    /// The tag in its files' names.
    tag: String,
    outcome: Result<SceneSummary, String>,
}

/// The error a batch with failed scenes ends with (exit code 1).
#[derive(Debug, thiserror::Error)]
#[error("{failed} of {total} scene(s) of the batch failed: {names}")]
pub struct BatchFailed {
    failed: usize,
    total: usize,
    names: String,
}

/// Draws what `args` asks for: one scene, or a batch.
pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    let scenes = args.scene.scene_files();
    let choice = args.scene.camera();
    let one_camera = match choice {
        Some(CameraChoice::One(k)) => Some(k),
        _ => None,
    };
    let all_cameras = choice == Some(CameraChoice::All);
    if let ([scene], false) = (scenes.as_slice(), all_cameras) {
        // Value and file errors come before the device is made, as for every command.
        let mut loaded = args.scene.load_scene(*scene, one_camera)?;
        let ctx = open_device(args)?;
        render_scene(args, &ctx, &mut loaded, &args.files)?;
        return Ok(());
    }
    let ctx = open_device(args)?;
    let tags = scene_tags(&scenes);
    let mut items = Vec::new();
    for (k, (scene, tag)) in scenes.iter().zip(&tags).enumerate() {
        let name = scene.map_or("the built-in scene".into(), |p| p.display().to_string());
        if !args.json {
            eprintln!("relief: scene {}/{}: {name}", k + 1, scenes.len());
        }
        let tag = if scenes.len() > 1 { tag.as_str() } else { "" };
        let failed = draw_scene(args, &ctx, *scene, &name, tag, all_cameras, &mut items);
        if failed && args.fail_fast() {
            break;
        }
    }
    report(args, &items, scenes.len());
    let failed: Vec<&str> = items
        .iter()
        .filter(|i| i.outcome.is_err())
        .map(|i| i.name.as_str())
        .collect();
    if failed.is_empty() {
        return Ok(());
    }
    Err(BatchFailed {
        failed: failed.len(),
        total: items.len(),
        names: failed.join(", "),
    }
    .into())
}

/// Draws `scene` through one camera, or each of its cameras; pushes an item per camera and says
/// whether any failed.
fn draw_scene(
    args: &RenderArgs,
    ctx: &Arc<Context>,
    scene: Option<&Path>,
    name: &str,
    tag: &str,
    all_cameras: bool,
    items: &mut Vec<Item>,
) -> bool {
    let one_camera = match args.scene.camera() {
        Some(CameraChoice::One(k)) => Some(k),
        _ => None,
    };
    let first = args.scene.load_scene(scene, one_camera);
    let cameras = match (&first, all_cameras) {
        (Ok(loaded), true) => loaded.cameras,
        _ => 0,
    };
    let mut loaded = Some(first);
    let mut failed = false;
    // A scene without cameras is drawn once, framed, under --camera all too.
    for k in 0..cameras.max(1) {
        let (name, tag) = if cameras == 0 {
            (name.to_owned(), tag.to_owned())
        } else {
            let camera_tag = format!("cam{k}");
            let joined = [tag, &camera_tag].join(if tag.is_empty() { "" } else { "_" });
            (format!("{name} camera {k}"), joined)
        };
        let next = loaded
            .take()
            .unwrap_or_else(|| args.scene.load_scene(scene, Some(k)));
        let outcome = next.and_then(|mut loaded| {
            let files = args.files.tagged(&tag);
            render_scene(args, ctx, &mut loaded, &files)
        });
        let outcome = outcome.map_err(|e| {
            let message = error_message(&e);
            eprintln!("relief: {name} failed: {message}");
            message
        });
        failed |= outcome.is_err();
        items.push(Item { name, tag, outcome });
        if failed && args.fail_fast() {
            break;
        }
    }
    failed
}

/// The tag of each scene's files: its file stem, or, where two stems (cleaned to letters,
/// digits, `-` and `_`) would be the same, the scene's place in the batch before every stem.
fn scene_tags(scenes: &[Option<&Path>]) -> Vec<String> {
    let stems: Vec<String> = scenes
        .iter()
        .map(|p| {
            let stem = p
                .and_then(Path::file_stem)
                .map_or("scene".into(), |s| s.to_string_lossy());
            stem.chars()
                .map(|c| {
                    if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                        c
                    } else {
                        '-'
                    }
                })
                .collect()
        })
        .collect();
    let mut sorted = stems.clone();
    sorted.sort_unstable();
    sorted.dedup();
    if sorted.len() == stems.len() {
        return stems;
    }
    let width = scenes.len().to_string().len();
    stems
        .iter()
        .enumerate()
        .map(|(k, stem)| format!("{:0width$}-{stem}", k + 1))
        .collect()
}

/// The batch's summary: a table on stderr, or one JSON object.
fn report(args: &RenderArgs, items: &[Item], scenes: usize) {
    let drawn = items.iter().filter(|i| i.outcome.is_ok()).count();
    if args.json {
        let rows: Vec<_> = items
            .iter()
            .map(|i| match &i.outcome {
                Ok(s) => json!({ "scene": i.name, "tag": i.tag, "summary": s }),
                Err(e) => json!({ "scene": i.name, "tag": i.tag, "error": e }),
            })
            .collect();
        let value = json!({ "batch": { "scenes": scenes, "drawn": drawn, "failed": items.len() - drawn, "items": rows } });
        println!("{value}");
        return;
    }
    eprintln!(
        "batch: {} image set(s) from {scenes} scene(s): {drawn} drawn, {} failed",
        items.len(),
        items.len() - drawn
    );
    let w = items.iter().map(|i| i.name.len()).max().unwrap_or(0).max(5);
    eprintln!(
        "  {:<w$} {:>7} {:>8} {:>8} {:>13}",
        "scene", "frames", "written", "skipped", "gpu_ms/frame"
    );
    for item in items {
        match &item.outcome {
            Ok(s) => eprintln!(
                "  {:<w$} {:>7} {:>8} {:>8} {:>13.3}",
                item.name, s.frames, s.written, s.skipped, s.gpu_ms_per_frame
            ),
            Err(_) => eprintln!("  {:<w$} failed (see above)", item.name),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scenes_are_tagged_by_stem_or_by_place_where_stems_repeat() {
        let a = Path::new("shots/a.gltf");
        let b = Path::new("other/b two.glb");
        assert_eq!(scene_tags(&[Some(a), Some(b)]), ["a", "b-two"]);
        let same = Path::new("other/a.glb");
        assert_eq!(
            scene_tags(&[Some(a), Some(b), Some(same)]),
            ["1-a", "2-b-two", "3-a"]
        );
    }
}
