//! Live edits of a terrain's ground: brush strokes applied to its elevation, and only the tiles
//! whose vertices read a changed texel rebuilt (their positions and normals), so a frame after a
//! stroke re-uploads a few tiles, not the grid. The layered relief on top is unaffected: its
//! blended field, pyramid and AO live in the height uv, which the elevation does not move.

use super::brush::{Stroke, StrokeError, StrokeTarget};
use super::grid::{GridOptions, TerrainGrid};
use crate::geometry::Mesh;
use crate::heightfield::Heightfield;

/// A terrain's elevation with the grid built over it.
#[derive(Debug, Clone)]
pub struct TerrainEditor {
    elevation: Heightfield,
    grid: TerrainGrid,
    name: String,
    material: usize,
}

/// What one list of strokes changed.
#[derive(Debug, Clone)]
pub struct TerrainEdit {
    /// Strokes applied.
    pub strokes: usize,
    /// Texels the strokes' squares covered (counted once per stroke).
    pub texels: u64,
    /// The rebuilt tiles: their index among the grid's tiles (= their mesh's, in
    /// `terrain_tiles` order) and their new mesh.
    pub tiles: Vec<(usize, Mesh)>,
}

impl TerrainEditor {
    /// The editor of the grid `terrain_tiles(elevation, options, name, material)` builds.
    pub fn new(
        elevation: Heightfield,
        options: &GridOptions,
        name: &str,
        material: usize,
    ) -> TerrainEditor {
        let grid = TerrainGrid::new(elevation.width(), elevation.height(), options);
        TerrainEditor {
            elevation,
            grid,
            name: name.into(),
            material,
        }
    }

    /// The elevation as edited so far.
    pub fn elevation(&self) -> &Heightfield {
        &self.elevation
    }

    /// How many tiles the ground has.
    pub fn tile_count(&self) -> usize {
        self.grid.tile_count()
    }

    /// Applies `strokes` in order (all checked first: one bad stroke applies none) and rebuilds
    /// the tiles they touched. `paint` strokes weigh layers, not the ground, and are refused.
    pub fn apply(&mut self, strokes: &[Stroke]) -> Result<TerrainEdit, StrokeError> {
        let (w, h) = (self.elevation.width(), self.elevation.height());
        for (k, s) in strokes.iter().enumerate() {
            s.check(k, w, h)?;
            if s.paints() {
                return Err(StrokeTarget::PaintOnElevation { index: k }.into());
            }
        }
        let mut data = self.elevation.data().to_vec();
        // Each stroke's own square, so that two far-apart strokes do not rebuild what lies between.
        let mut touched = std::collections::BTreeSet::new();
        let mut texels = 0;
        for s in strokes {
            let Some(r) = s.rect(w, h) else { continue };
            for j in r.y0..=r.y1 {
                for i in r.x0..=r.x1 {
                    let t = j as usize * w as usize + i as usize;
                    data[t] = s.apply(i, j, data[t]);
                }
            }
            texels += r.texels();
            touched.extend(self.grid.tiles_reading((r.x0, r.y0), (r.x1, r.y1)));
        }
        self.elevation = Heightfield::from_valid(w, h, data);
        let tiles = touched
            .into_iter()
            .map(|k| {
                let mesh = self
                    .grid
                    .tile_mesh(&self.elevation, k, &self.name, self.material);
                (k, mesh)
            })
            .collect();
        Ok(TerrainEdit {
            strokes: strokes.len(),
            texels,
            tiles,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::heightfield::Generator;
    use crate::terrain::brush::test_stroke as stroke;
    use crate::terrain::{terrain_tiles, BrushKind};

    fn options() -> GridOptions {
        GridOptions {
            extent: 10.0,
            height: 1.0,
            tile_quads: 8,
            step: 2,
        }
    }

    #[test]
    fn rebuilt_tiles_equal_a_full_rebuild_and_the_others_are_unchanged() {
        let elevation = Generator::Fbm.generate(64, 64, 5);
        let before = terrain_tiles(&elevation, &options(), "g", 0);
        let mut editor = TerrainEditor::new(elevation, &options(), "g", 0);
        let strokes = [
            stroke(BrushKind::Raise, 10.0, 12.0, 4.0),
            stroke(BrushKind::Crater, 40.0, 50.0, 6.0),
        ];
        let edit = editor.apply(&strokes).unwrap();
        let after = terrain_tiles(editor.elevation(), &options(), "g", 0);
        let rebuilt: Vec<usize> = edit.tiles.iter().map(|(k, _)| *k).collect();
        assert!(
            !rebuilt.is_empty() && rebuilt.len() < after.len() / 2,
            "{rebuilt:?} of {}",
            after.len()
        );
        for (k, mesh) in &edit.tiles {
            assert_eq!(mesh.vertices, after[*k].vertices);
            assert_eq!(mesh.name, after[*k].name);
        }
        for k in (0..after.len()).filter(|k| !edit.tiles.iter().any(|(t, _)| t == k)) {
            assert_eq!(
                before[k].vertices, after[k].vertices,
                "tile {k} changed unrebuilt"
            );
        }
    }

    #[test]
    fn a_bad_stroke_applies_nothing() {
        let elevation = Generator::Fbm.generate(32, 32, 5);
        let mut editor = TerrainEditor::new(elevation.clone(), &options(), "g", 0);
        let strokes = [
            stroke(BrushKind::Raise, 10.0, 12.0, 4.0),
            stroke(BrushKind::Raise, f32::NAN, 12.0, 4.0),
        ];
        let err = editor.apply(&strokes).unwrap_err();
        assert!(err.to_string().contains("stroke 1: x is NaN"), "{err}");
        assert_eq!(editor.elevation(), &elevation);
        let outside = [stroke(BrushKind::Lower, 500.0, 12.0, 4.0)];
        assert!(matches!(
            editor.apply(&outside),
            Err(StrokeError::Outside { .. })
        ));
    }
}
