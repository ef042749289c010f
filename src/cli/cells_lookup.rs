//! `relief cells`'s lookup table (`lookup.json`): for every grey cell, its grid index, its case
//! among the paper's ten, its projection, and where each of its domain faces' maps lies in the
//! atlas (`maps.png`) and in the GPU's layers. With the atlas it is the whole complex.

use std::path::Path;

use anyhow::Context as _;
use relief::cells::{Case, CellGrid, CellMaps, Projection};
use serde_json::{json, Value};

/// Columns of the atlas of `count` maps: the smallest square that holds them.
pub fn atlas_columns(count: usize) -> u32 {
    (f64::from(count.max(1) as u32).sqrt().ceil() as u32).max(1)
}

/// Writes the lookup table of `maps`, sampled on `grid`, to `path`.
pub fn write_lookup(path: &Path, grid: &CellGrid, maps: &CellMaps) -> anyhow::Result<()> {
    let columns = atlas_columns(maps.faces.len());
    let r = maps.resolution;
    let mut cells: Vec<Value> = Vec::new();
    let mut current = None;
    for (layer, map) in maps.faces.iter().enumerate() {
        if current != Some(map.cell) {
            current = Some(map.cell);
            let internal = grid.internal_faces(map.cell);
            cells.push(json!({
                "cell": map.cell,
                "case": Case::of_internal(internal).name(),
                "projection": projection(Projection::for_cell(internal)),
                "faces": [],
            }));
        }
        let layer = layer as u32;
        let entry = json!({
            "face": map.face.to_string(),
            "layer": layer,
            "atlas": [(layer % columns) * r, (layer / columns) * r],
        });
        if let Some(faces) = cells.last_mut().and_then(|c| c["faces"].as_array_mut()) {
            faces.push(entry);
        }
    }
    let table = json!({
        "grid": grid.n(),
        "origin": grid.origin(),
        "cell_size": grid.cell_size(),
        "map_resolution": r,
        "atlas_columns": columns,
        "distance_range": "cell sides, 0 at the face; maps.png stores them over sqrt(3) in 16 bits",
        "grey_cells": cells,
    });
    std::fs::write(path, serde_json::to_string_pretty(&table)?)
        .with_context(|| format!("writing {}", path.display()))
}

fn projection(p: Projection) -> Value {
    match p {
        Projection::Perspective { centre } => json!({"kind": "perspective", "centre": centre}),
        Projection::Axial { axis, point } => json!({"kind": "axial", "axis": axis, "point": point}),
        Projection::Planar { axis, offset } => {
            json!({"kind": "planar", "axis": axis, "offset": offset})
        }
        Projection::Parallel { face } => json!({"kind": "parallel", "toward": face.to_string()}),
    }
}
