//! `relief render --terrain ... --edits strokes.json`: brush strokes applied between frames, one
//! list per frame (list k before frame k + 2; frame 1 shows the terrain as loaded). Elevation
//! strokes rebuild only the ground tiles they touched; `paint` strokes move a layer's weight and
//! rebuild only the splat texels, blended field, pyramid nodes and AO texels near them
//! (`Renderer::paint_layers`). The file is a JSON array of arrays of strokes:
//!
//! ```json
//! [ [ {"kind": "raise", "x": 512, "y": 400, "radius": 32, "strength": 0.05} ],
//!   [ {"kind": "crater", "x": 300, "y": 620, "radius": 48, "strength": 0.08},
//!     {"kind": "flatten", "x": 700, "y": 700, "radius": 64, "strength": 0.5, "target": 0.3},
//!     {"kind": "paint", "layer": 2, "x": 400, "y": 420, "radius": 40, "strength": 0.8} ] ]
//! ```
//!
//! Centres and radii are in elevation texels (a paint stroke is carried onto the splat map, its
//! radius scaled by the larger of the two axes' ratios); every stroke is checked before the
//! first frame, so a bad one stops the render naming its frame and place in the list.

use std::path::Path;
use std::time::Instant;

use anyhow::Context as _;
use relief::render::{FrameOutput, PaintReport, RenderError, Renderer};
use relief::terrain::{RuleWeights, SplatMap, Stroke, StrokeTarget, TerrainEditor};
use serde::Serialize;

/// The strokes of a render and the editor they go through.
pub struct TerrainEdits {
    editor: TerrainEditor,
    frames: Vec<Vec<Stroke>>,
    /// The layered material paint strokes weigh, and the splat size they are carried onto.
    painted: PaintedLayers,
    /// The rules that weighed the layers, to weigh again where elevation strokes move the
    /// ground; dropped (with the reason said) when the renderer cannot repaint its weights.
    rules: Option<RuleWeights>,
    path: std::path::PathBuf,
}

/// The layered material of the terrain and its splat map's size.
#[derive(Debug, Clone, Copy)]
pub struct PaintedLayers {
    pub material: usize,
    pub layers: usize,
    pub splat_size: (u32, u32),
}

impl PaintedLayers {
    pub fn of(material: usize, layers: usize, splat: &SplatMap) -> PaintedLayers {
        PaintedLayers {
            material,
            layers,
            splat_size: splat.size(),
        }
    }
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
    /// What the list's paint strokes rebuilt, if it had any.
    pub paint: Option<PaintReport>,
    /// What weighing the layers again by the rules where the ground moved rebuilt, if anything.
    pub reweighed: Option<PaintReport>,
}

impl TerrainEdits {
    /// Reads `path` and checks every stroke against `editor`'s elevation, paint strokes also
    /// against `painted`'s layers and splat map.
    pub fn load(
        path: &Path,
        editor: TerrainEditor,
        painted: PaintedLayers,
        rules: Option<RuleWeights>,
    ) -> anyhow::Result<TerrainEdits> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("--edits: cannot read {}", path.display()))?;
        let frames: Vec<Vec<Stroke>> = serde_json::from_str(&text).map_err(|e| {
            anyhow::anyhow!(
                "--edits {}: {e} (expected an array of frames, each an array of strokes)",
                path.display()
            )
        })?;
        let e = editor.elevation();
        let (w, h) = (e.width(), e.height());
        let (sw, sh) = painted.splat_size;
        for (f, strokes) in frames.iter().enumerate() {
            for (k, s) in strokes.iter().enumerate() {
                let checked = s.check(k, w, h).and_then(|()| {
                    if !s.paints() {
                        return Ok(());
                    }
                    if s.layer as usize >= painted.layers {
                        return Err(StrokeTarget::Layer {
                            index: k,
                            layer: s.layer,
                            layers: painted.layers,
                        }
                        .into());
                    }
                    onto_splat(s, (w, h), painted.splat_size).check(k, sw, sh)
                });
                checked.map_err(|err| {
                    anyhow::anyhow!("--edits {}: frame list {f}: {err}", path.display())
                })?;
            }
        }
        Ok(TerrainEdits {
            editor,
            frames,
            painted,
            rules,
            path: path.to_path_buf(),
        })
    }

    /// Checks that `renderer` can paint the terrain's layers when a stroke paints them (its
    /// method reads no map built once from the whole field, no averaged pyramid). Without paint
    /// strokes a renderer that cannot repaint keeps the rules' weights as loaded, and says so.
    pub fn check_renderer(&mut self, renderer: &Renderer) -> anyhow::Result<()> {
        let repaint = renderer.layer_splat(self.painted.material).map(drop);
        if self.frames.iter().flatten().any(Stroke::paints) {
            repaint.with_context(|| format!("--edits {}", self.path.display()))?;
        } else if let (Err(why), Some(_)) = (repaint, &self.rules) {
            eprintln!("--edits: the layers' weights stay as loaded under the strokes: {why}");
            self.rules = None;
        }
        Ok(())
    }

    /// Whether the renderer must keep the blend's inputs: a stroke paints weights, or moves
    /// ground whose weights come from rules.
    pub fn needs_painter(&self) -> bool {
        let strokes = || self.frames.iter().flatten();
        strokes().any(Stroke::paints) || (self.rules.is_some() && strokes().next().is_some())
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
        let (paint, shape): (Vec<Stroke>, Vec<Stroke>) = strokes.iter().partition(|s| s.paints());
        let edit = self
            .editor
            .apply(&shape)
            .with_context(|| format!("--edits: before frame {}", frame + 1))?;
        let rebuild_ms = started.elapsed().as_secs_f64() * 1e3;
        // The frames in flight still draw the old tiles: wait for them before timing the upload.
        let mut retired = renderer
            .finish()
            .map_err(|e: RenderError| anyhow::anyhow!(e))?;
        let reweighed = self.reweigh(&shape, renderer, &mut retired)?;
        let paint = if paint.is_empty() {
            None
        } else {
            let e = self.editor.elevation();
            let on_splat: Vec<Stroke> = paint
                .iter()
                .map(|s| onto_splat(s, (e.width(), e.height()), self.painted.splat_size))
                .collect();
            let (waited, report) = renderer
                .paint_layers(self.painted.material, &on_splat)
                .with_context(|| {
                    format!(
                        "--edits {}: before frame {}",
                        self.path.display(),
                        frame + 1
                    )
                })?;
            retired.extend(waited);
            Some(report)
        };
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
            strokes: edit.strokes + paint.as_ref().map_or(0, |p| p.strokes),
            texels: edit.texels,
            tiles_rebuilt: edit.tiles.iter().map(|(_, m)| m.name.clone()).collect(),
            tiles_total: self.editor.tile_count(),
            rebuild_ms,
            upload_ms: started.elapsed().as_secs_f64() * 1e3,
            paint,
            reweighed,
        };
        Ok((retired, Some(record)))
    }

    /// Weighs the layers again by the rules where `strokes` moved the ground (not where paint
    /// strokes weighed them by hand); what that rebuilt, summed over the strokes.
    fn reweigh(
        &self,
        strokes: &[Stroke],
        renderer: &mut Renderer,
        retired: &mut Vec<FrameOutput>,
    ) -> anyhow::Result<Option<PaintReport>> {
        let Some(rules) = &self.rules else {
            return Ok(None);
        };
        let elevation = self.editor.elevation();
        let (w, h) = (elevation.width(), elevation.height());
        let mut total: Option<PaintReport> = None;
        for rect in strokes.iter().filter_map(|s| s.rect(w, h)) {
            let Some(splat_rect) = rules.splat_rect_reading(&rect, w, h) else {
                continue;
            };
            let (waited, report) = renderer
                .reweigh_layers(self.painted.material, splat_rect, |i, j| {
                    rules.weights_at(elevation, i, j)
                })
                .map_err(|e: RenderError| anyhow::anyhow!(e))?;
            retired.extend(waited);
            if let Some(r) = report {
                total.get_or_insert_with(PaintReport::default).add(&r);
            }
        }
        Ok(total)
    }
}

/// A paint stroke in elevation texels carried onto a splat map of `splat` texels over the same
/// terrain: the centre scaled per axis, the radius by the larger ratio (so that the disk covers
/// at least what it covered on the elevation).
fn onto_splat(stroke: &Stroke, (w, h): (u32, u32), (sw, sh): (u32, u32)) -> Stroke {
    let (rx, ry) = (sw as f32 / w as f32, sh as f32 / h as f32);
    Stroke {
        x: stroke.x * rx,
        y: stroke.y * ry,
        radius: stroke.radius * rx.max(ry),
        ..*stroke
    }
}
