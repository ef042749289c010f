//! `relief render --terrain ... --edits strokes.json`: brush strokes applied between frames, one
//! list per frame (list k before frame k + 2; frame 1 shows the terrain as loaded), each
//! rebuilding only the ground tiles it touched. The file is a JSON array of arrays of strokes:
//!
//! ```json
//! [ [ {"kind": "raise", "x": 512, "y": 400, "radius": 32, "strength": 0.05} ],
//!   [ {"kind": "crater", "x": 300, "y": 620, "radius": 48, "strength": 0.08},
//!     {"kind": "flatten", "x": 700, "y": 700, "radius": 64, "strength": 0.5, "target": 0.3} ] ]
//! ```
//!
//! Centres and radii are in elevation texels; every stroke is checked against the map before
//! the first frame, so a bad one stops the render naming its frame and place in the list.

use std::path::Path;
use std::time::Instant;

use anyhow::Context as _;
use relief::render::{FrameOutput, RenderError, Renderer};
use relief::terrain::{Stroke, TerrainEditor};
use serde::Serialize;

/// The strokes of a render and the editor they go through.
pub struct TerrainEdits {
    editor: TerrainEditor,
    frames: Vec<Vec<Stroke>>,
}

/// What one frame's strokes rebuilt, for `--explain` and the report.
#[derive(Debug, Clone, Serialize)]
pub struct EditRecord {
    /// 1-based, the frame drawn after the strokes.
    pub frame: u32,
    pub strokes: usize,
    pub texels: u64,
    pub tiles_rebuilt: Vec<String>,
    pub tiles_total: usize,
    /// CPU ms of applying the strokes and rebuilding the tiles' vertices.
    pub rebuild_ms: f64,
    /// CPU ms of uploading the tiles (after the frames in flight finished).
    pub upload_ms: f64,
}

impl TerrainEdits {
    /// Reads `path` and checks every stroke against `editor`'s elevation.
    pub fn load(path: &Path, editor: TerrainEditor) -> anyhow::Result<TerrainEdits> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("--edits: cannot read {}", path.display()))?;
        let frames: Vec<Vec<Stroke>> = serde_json::from_str(&text).map_err(|e| {
            anyhow::anyhow!(
                "--edits {}: {e} (expected an array of frames, each an array of strokes)",
                path.display()
            )
        })?;
        let e = editor.elevation();
        for (f, strokes) in frames.iter().enumerate() {
            for (k, s) in strokes.iter().enumerate() {
                s.check(k, e.width(), e.height()).map_err(|err| {
                    anyhow::anyhow!("--edits {}: frame list {f}: {err}", path.display())
                })?;
            }
        }
        Ok(TerrainEdits { editor, frames })
    }

    /// Frames needed to show every list (the first frame is unedited).
    pub fn frames_needed(&self) -> u32 {
        self.frames.len() as u32 + 1
    }

    /// Applies the strokes due before frame `frame` (0-based) and hands the rebuilt tiles to
    /// `renderer`; returns the frames that had to be waited for and what was rebuilt.
    pub fn before_frame(
        &mut self,
        frame: u32,
        renderer: &mut Renderer,
    ) -> anyhow::Result<(Vec<FrameOutput>, Option<EditRecord>)> {
        let Some(strokes) = (frame as usize)
            .checked_sub(1)
            .and_then(|k| self.frames.get(k))
        else {
            return Ok((Vec::new(), None));
        };
        let started = Instant::now();
        let edit = self
            .editor
            .apply(strokes)
            .with_context(|| format!("--edits: before frame {}", frame + 1))?;
        let rebuild_ms = started.elapsed().as_secs_f64() * 1e3;
        // The frames in flight still draw the old tiles: wait for them before timing the upload.
        let mut retired = renderer
            .finish()
            .map_err(|e: RenderError| anyhow::anyhow!(e))?;
        let started = Instant::now();
        let meshes: Vec<(usize, &relief::scene::Mesh)> =
            edit.tiles.iter().map(|(k, m)| (*k, m)).collect();
        retired.extend(
            renderer
                .update_meshes(&meshes)
                .map_err(|e: RenderError| anyhow::anyhow!(e))?,
        );
        let record = EditRecord {
            frame: frame + 1,
            strokes: edit.strokes,
            texels: edit.texels,
            tiles_rebuilt: edit.tiles.iter().map(|(_, m)| m.name.clone()).collect(),
            tiles_total: self.editor.tile_count(),
            rebuild_ms,
            upload_ms: started.elapsed().as_secs_f64() * 1e3,
        };
        Ok((retired, Some(record)))
    }
}
